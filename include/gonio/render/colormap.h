#pragma once
// The colour maps of gonio's figures, defined in sRGB code values (what a PNG holds) and
// returned as linear RGB for an Image written with write_png(…, {0, ToneMap::Clamp}), so
// that the file holds the codes below exactly (to 8-bit rounding).

#include "gonio/color.h"

namespace gonio::render {

// Sequential map for t in [0, 1] (clamped): from near-black violet through red and
// orange to pale yellow. Its luminance increases strictly with t, so brighter means more.
Color sequential_colormap(double t);
// Diverging map for t in [−1, 1] (clamped): blue at −1, near-white at 0, red at +1; the
// luminance falls symmetrically away from 0.
Color diverging_colormap(double t);

// Linear RGB of sRGB code values in [0, 1].
Color from_srgb(double r, double g, double b);

// Relative luminance of linear sRGB (ITU-R BT.709 primaries: Y = 0.2126 R + 0.7152 G +
// 0.0722 B).
inline double luminance(const Color& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

}  // namespace gonio::render
