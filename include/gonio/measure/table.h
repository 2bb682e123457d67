#pragma once
// The MERL table mode of the instrument (SPEC §3 `gonio measure -o OUT.binary`): an
// isotropic surface measured over all pairs of directions at once.
//
// Estimator. Each ray draws its incidence ωi from p(ωi), a random φi (which averages the
// realisation's residual anisotropy) and θi from an even mixture of the hemisphere's
// solid angle and the 90 one-degree bands of θi (a band chosen uniformly, then a
// direction uniform in solid angle within it): p(ωi) = 1/(4π) + 1/(180 Ω_b) on band b of
// solid angle Ω_b. On the hemisphere alone the band next to the normal would get
// 1 − cos 1° = 1.5 × 10⁻⁴ of the rays, and its albedo the noise of a few; now every band
// gets at least 1/180 of them. The ray enters the patch at a uniform point and is
// traced; a ray that leaves upwards along ωo with power w scores w / (p(ωi) cos θo) in
// the bin B of (ωi, ωo). For a fixed ωi the expected power leaving into dωo is
// f(ωi, ωo) cos θo dωo per unit incident power (the gantry's f = dL/dE), so over the N
// rays
//   E[Σ w / (p(ωi) cos θo) · 1_B] / N = ∫∫_B f dωi dωo,
// and dividing by the bin's measure M_B = ∫∫_B dωi dωo (merl_bins.h, both directions
// above the horizon) gives the bin average of f:
//   f_B = Σ_{rays in B} w / (p(ωi) cos θo) / (N · M_B).
// A bin no ray reached is written as missing (negative), as is a bin wholly below the
// horizon. The directional albedo is also estimated per 1° band of θi (the mean of w
// over that band's rays, which are uniform in solid angle within the band) with its
// standard error.

#include <cstdint>
#include <vector>

#include "gonio/color.h"
#include "gonio/measure/instrument.h"
#include "gonio/measure/microsurface.h"
#include "gonio/merl.h"

namespace gonio::measure {

struct AlbedoBand {
  double theta_lo = 0, theta_hi = 0;  // degrees
  std::uint64_t rays = 0;
  Color albedo, stderr_albedo;
};

struct TableReading {
  MerlTable table;
  // The standard error of each filled entry's f (1/sr), rgb interleaved like table.rgb
  // (0 for a missing entry): from the per-ray variance of the scores, as the gantry's.
  std::vector<float> stderr_f;
  RayCounts counts;
  std::uint64_t filled = 0;   // bins with at least one ray
  std::uint64_t missing = 0;  // bins written as missing (no ray, or below the horizon)
  std::vector<AlbedoBand> bands;  // 90 bands of 1° in θi
};

TableReading measure_table(const Microsurface& surface, const RunOptions& options);

}  // namespace gonio::measure
