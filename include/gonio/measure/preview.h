#pragma once
// A picture of a microsurface for `gonio measure --preview FILE`: the height field seen
// from above, each facet shaded as a Lambertian surface under a fixed distant light from
// the upper left, optionally tinted by height (blue low, warm high).

#include <string>

#include "gonio/measure/heightfield.h"

namespace gonio::measure {

struct PreviewOptions {
  bool tint_by_height = true;
  int max_side = 1024;  // the image is at most max_side² pixels whatever n is
};

// The side in pixels of the preview of an n × n field: n · ⌊max_side / n⌋ (whole pixels
// per cell) when n ≤ max_side, else n / ⌈n / max_side⌉ (rounded down; whole cells per
// pixel, averaged).
int preview_side(int n, int max_side = 1024);

// Writes the preview as an 8-bit sRGB PNG (render/image.h). Throws InputError naming the
// path when it cannot be written.
void write_surface_preview(const HeightField& field, const std::string& path, const PreviewOptions& options = {});

}  // namespace gonio::measure
