#pragma once
// The deterministic microsurfaces of `gonio measure` (SPEC §3 surface types "flat",
// "vgroove", "image"). Each is a HeightField (heightfield.h): periodic, triangulated two
// triangles per cell. Heights are in the unit of `size`.

#include <string>

#include "gonio/measure/heightfield.h"

namespace gonio::measure {

// One cell of height 0: the flat sample of the instrument's calibration.
HeightField flat_height_field(double size = 1.0);

// Symmetric V-grooves running along y: z depends on x only, rising with slope tan(angle)
// over one cell and falling over the next, so that valleys (even i) and ridges (odd i)
// lie exactly on grid lines and every facet's normal is (∓sin angle, 0, cos angle).
// n = 2 · grooves. angle in degrees, in (0, 90); grooves in [1, kMaxGrooves].
inline constexpr int kMaxGrooves = 1024;
HeightField vgroove_height_field(double angle_deg, int grooves, double size = 1.0);

// Heights from an image: z = height · size · value, value the texel's first channel (R;
// the gray channel of a gray PNG, Y of a luminance-only EXR). PNG codes are read as
// linear data (code / (2^bits − 1)), not sRGB-decoded. The image must be square with a
// side of at most kMaxImageSide; texel (x, row r) — row 0 at the top — becomes grid
// sample (i, j) = (x, side − 1 − r), so that y points up the image. The field is periodic,
// as every HeightField: the last column meets the first (a seam if the image does not tile).
// Throws InputError naming the file when it cannot be read or has the wrong shape.
inline constexpr int kMaxImageSide = 2048;
HeightField image_height_field(const std::string& path, double height, double size = 1.0);

}  // namespace gonio::measure
