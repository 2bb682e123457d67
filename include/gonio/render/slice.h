#pragma once
// The θh × θd slice of a BRDF (Disney's BRDF Explorer's image view): f over the
// Rusinkiewicz half angle θh and difference angle θd, both 0..90°, at one difference
// azimuth φd (90° by default) and half azimuth φh = 0, as a figure with labelled axes and
// a colour bar. With a second material, the figure shows both on one colour scale and
// their relative difference on a diverging map.
//
// What a pixel shows: the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (colormap.h) of the
// RGB f in 1/sr at the pixel centre's (θh, θd, φd), directions by merl_directions
// (merl.h), coloured on a log scale by sequential_colormap; a pixel where wo or wi lies on
// or below the horizon is kSliceHorizon grey. Layout of a panel: θh from 0° at the left
// to 90° at the right (linear in θh, or in √θh like the MERL bins), θd from 0° at the
// bottom to 90° at the top.

#include <optional>
#include <utility>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/math/constants.h"
#include "gonio/render/image.h"

namespace gonio::render {

enum class ThetaHAxis { Linear, Sqrt };

struct SliceOptions {
  int size = 180;                                // side of a panel, pixels: 16 to 2048
  double phi_d = kPiD / 2;                       // radians, [0, π]
  ThetaHAxis theta_h_axis = ThetaHAxis::Linear;  // Sqrt: u = √(θh / 90°), MERL's bin spacing
  // The log colour scale of f (1/sr); both 0: automatic (whole decades around the values
  // from their 1st to their 99th percentile, at most kMaxDecades; values beyond take the
  // colours of the ends).
  double lo = 0, hi = 0;
  // Half-width of the difference scale; 0: automatic (the smallest of 1%, 2%, 5%, 10%, …,
  // 100% that holds every difference; beyond 100% the colours saturate).
  double diff_range = 0;
};
inline constexpr int kMinSliceSize = 16, kMaxSliceSize = 2048;
inline constexpr int kMaxDecades = 5;
inline constexpr double kLowPercentile = 0.01, kHighPercentile = 0.99;

struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
};

struct SliceFigure {
  Image image;
  // The panels: f of the first material, then (with a second) f of the second and the
  // relative difference (f2 − f1) / f1.
  std::vector<Rect> panels;
  // The log colour bar of f: row r from the top shows t = 1 − (r + ½)/height, the value
  // lo · (hi/lo)^t.
  Rect bar;
  double lo = 0, hi = 0;
  // The difference bar (with a second material): row r shows t = 1 − 2 (r + ½)/height in
  // [−1, 1], the relative difference t · diff_range.
  std::optional<Rect> diff_bar;
  double diff_range = 0;
};

// sRGB code values of the figure's fixed colours.
inline constexpr double kSliceHorizon[3] = {0.55, 0.55, 0.55};  // wo or wi below the horizon
inline constexpr double kSliceBackground[3] = {1, 1, 1};
inline constexpr double kSliceInk[3] = {0, 0, 0};  // text, ticks, frames

// θh in radians at horizontal position u in [0, 1] of a panel (0 left, 1 right).
double slice_theta_h(double u, ThetaHAxis axis);

// The values a panel shows, before any colour: the luminance of f (1/sr) at each pixel
// centre, size × size, row 0 at the top (θd = 90°), kSliceBelowHorizon where wo or wi is
// not above the surface. make_slice draws these; `gonio explore` serves them. The options'
// size and phi_d must be in range (make_slice checks them).
inline constexpr double kSliceBelowHorizon = -1;
std::vector<double> slice_values(const BxDF& bxdf, const SliceOptions& options);
// make_slice's automatic log scale [lo, hi] for these panels' values: whole decades around
// their 1st to 99th percentile. Throws InputError when no value is > 0.
std::pair<double, double> slice_auto_scale(const std::vector<std::vector<double>>& values);

// The figure of `a` (and, when `b` is not null, of `b` and their difference). Throws
// InputError when the options are out of range, or when f is 0 at every pixel and the
// scale is automatic (a specular material has no finite f to show).
SliceFigure make_slice(const BxDF& a, const BxDF* b, const SliceOptions& options = {});

}  // namespace gonio::render
