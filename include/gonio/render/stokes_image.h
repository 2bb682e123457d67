#pragma once
// What a polarized render's Stokes images show (issue 15): the degree and angle of linear
// polarization per pixel, and a false-colour picture of both.
//
// Of the luminance Stokes vector (Y of each of S0..S3, BT.709 weights):
//   DoLP = √(S1² + S2²) / S0 in [0, 1],
//   AoLP = ½ atan2(S2, S1) in [0°, 180°), counter-clockwise from the image's +x axis
//          (SPEC §1: Q = S1 = I_x − I_y, y up).

#include "gonio/render/image.h"
#include "gonio/render/renderer.h"

namespace gonio::render {

struct LinearPolarization {
  double dolp = 0;      // 0 where S0 ≤ 0
  double aolp_deg = 0;  // 0 where the light is unpolarized
};

LinearPolarization linear_polarization(const StokesImages& s, int x, int y);

// The false-colour image of `gonio render --dop`: hue the AoLP (red 0°, green 60°,
// blue 120°, back to red at 180°: the angle is periodic), brightness the DoLP (black for
// unpolarized light, full for DoLP ≥ 1), as linear RGB for write_png with ToneMap::Clamp
// and no exposure (colormap.h), so that the PNG holds the HSV codes.
Image dop_image(const StokesImages& s);

}  // namespace gonio::render
