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
// This sum is unbiased for every bin, including the bins no ray reached (their estimate
// is 0). What must not depend on the rays it averages is the choice of the entries that
// are written: writing a bin only when some ray reached it keeps, in bins whose expected
// count is below one, exactly the lucky estimates, each far too high (a flat Lambertian
// read 580 ρ/π at θh ≈ 0.03°). So an entry is written (measured zeros as zeros) when
//   - by the geometry: a Lambertian sample (any albedo) would send it at least K
//     (default 25) of the N rays, by a lower bound on N ∫∫_B p(ωi) cos θo/π (table.cpp,
//     reference_rays); or
//   - by the pilot: a separate run of N/4 rays of their own (their own random streams,
//     independent of the estimate's N) gave it an effective number of rays
//     n = (Σs)²/Σs² of its scores s with 4 (n − 3√n) ≥ K — the count K expected even
//     three deviations below what the pilot saw (this writes where a surface sends far
//     more rays than a Lambertian would, as a glossy peak);
// and is written as missing (negative) otherwise, or when the bin lies wholly below the
// horizon. Both decisions are independent of the N rays of the estimate, so every written
// entry is an unbiased estimate of its bin's average f. With ~25 rays of roughly equal
// score, an entry's relative standard error is ~20%; each entry's own standard error is
// computed from the per-ray variance of the scores (stderr_f), and the reading counts the
// entries above 1%, 5% and 20%. The pilot's rays cost a quarter more tracing and enter
// nothing but that decision.
//
// The directional albedo is also estimated per 1° band of θi (the mean of w over that
// band's rays, which are uniform in solid angle within the band) with its standard
// error.

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

// The written-entry rule (above): the rays an entry must expect, by the geometry or by
// the pilot, to be written (the default of TableOptions and of `gonio measure
// --min-rays`). 0 writes every bin above the horizon.
inline constexpr double kTableMinExpectedRays = 25;

struct TableOptions {
  double min_expected_rays = kTableMinExpectedRays;
};
// The relative standard errors the reading counts entries above.
inline constexpr double kTableErrorLevels[3] = {0.01, 0.05, 0.20};

struct TableReading {
  MerlTable table;
  // The standard error of each written entry's f (1/sr), rgb interleaved like table.rgb
  // (0 for a missing entry): from the per-ray variance of the scores, as the gantry's.
  std::vector<float> stderr_f;
  RayCounts counts;               // the estimate's N rays (not the pilot's)
  std::uint64_t pilot_rays = 0;   // the pilot's rays, traced in addition to the N
  std::uint64_t filled = 0;       // entries written (measured zeros included)
  std::uint64_t filled_by_pilot = 0;  // of those, written by the pilot's rule alone
  std::uint64_t zero = 0;         // of those, written as 0 (no ray of the estimate reached them)
  std::uint64_t missing = 0;      // entries written as missing (see the rule), or below the horizon
  // Of the written non-zero entries, the fraction whose relative standard error (largest
  // over the channels) exceeds 1%, 5% and 20% (kTableErrorLevels).
  double fraction_above[3] = {0, 0, 0};
  std::vector<AlbedoBand> bands;  // 90 bands of 1° in θi
};

TableReading measure_table(const Microsurface& surface, const RunOptions& options,
                           const TableOptions& table = {});

// The pilot's rays for a table of `samples` rays: a quarter of them, at least one.
std::uint64_t table_pilot_rays(std::uint64_t samples);

}  // namespace gonio::measure
