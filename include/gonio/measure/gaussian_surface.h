#pragma once
// A Gaussian random microsurface (issue 13, SPEC §3 surface type "gaussian"): a stationary
// Gaussian random height field made by spectral synthesis, whose facet slopes follow the
// Beckmann distribution with roughness (alpha_x, alpha_y). A Gaussian process has
// Gaussian slopes, and Beckmann's slope distribution is the normal one with variance
// α²/2 per axis (Walter et al. 2007 eq. 28; Heitz 2014 §5.1): the RMS forward-difference
// slope of the triangulation (heightfield.h) along x is set to alpha_x/√2 exactly, and
// along y to alpha_y/√2 exactly, for the realised field (not only in expectation).

#include <cstdint>

#include "gonio/measure/heightfield.h"

namespace gonio::measure {

struct GaussianSurfaceParams {
  double alpha_x = 0.3, alpha_y = 0.3;  // Beckmann roughness per axis, each in (0, 2]
  // Correlation length ℓ of C(r) = σ² exp(−r²/ℓ²), in units of the patch side; for an
  // anisotropic surface the geometric mean of the lengths along x and y. ≤ 0: the default.
  double correlation = 0;
  int resolution = 512;  // n, samples per side, in [kMinResolution, kMaxResolution]
  double size = 1.0;     // side of the patch; heights scale with it (slopes do not)
  std::uint64_t seed = 1;

  static constexpr int kMinResolution = 16;
  // 2048² floats are 16 MiB; the synthesis needs about 4 × that again, briefly.
  static constexpr int kMaxResolution = 2048;
  // The correlation length must span at least this many grid cells, at most half the patch.
  static constexpr double kMinCorrelationCells = 2;
  static constexpr double kMaxCorrelation = 0.5;
};

// The default correlation length for n samples per side: 1/32 of the patch (32 correlation
// lengths across it, 16 grid cells per length at the default n = 512), but never fewer
// than 8 grid cells (8/n for n < 256, where the patch then holds n/8 lengths).
double default_gaussian_correlation(int resolution);

// The correlation lengths along x and y before the balancing of the axes (which moves
// them by a few percent): ℓ·√(alpha_y/alpha_x) and ℓ·√(alpha_x/alpha_y), ℓ the
// correlation (or its default). Each must lie in [kMinCorrelationCells / n, kMaxCorrelation].
struct CorrelationLengths {
  double x = 0, y = 0;
};
CorrelationLengths nominal_correlation_lengths(const GaussianSurfaceParams& params);

// The height field. Throws std::invalid_argument for parameters outside the ranges above
// (parse_surface checks them first and reports them as InputError). Deterministic for a
// given seed and parameters.
HeightField gaussian_height_field(const GaussianSurfaceParams& params);

}  // namespace gonio::measure
