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
// read 580 ρ/π at θh ≈ 0.03°). So an entry is estimated from its bin alone when
//   - by the geometry: a Lambertian sample (any albedo) would send it at least K
//     (default 25) of the N rays, by a lower bound on N ∫∫_B p(ωi) cos θo/π (table.cpp,
//     reference_rays); or
//   - by the pilot: a separate run of N/4 rays of their own (their own random streams,
//     independent of the estimate's N) gave it an effective number of rays
//     n = (Σs)²/Σs² of its scores s with 4 (n − 3√n) ≥ K — the count K expected even
//     three deviations below what the pilot saw (this writes where a surface sends far
//     more rays than a Lambertian would, as a glossy peak);
// and is estimated from its own rays alone (its "own" entry). Both decisions are
// independent of the N rays of the estimate, so every own entry is an unbiased estimate
// of its bin's average f. With ~25 rays of roughly equal score, an entry's relative
// standard error is ~20%; each entry's own standard error is computed from the per-ray
// variance of the scores (stderr_f), and the reading counts the entries above 1%, 5% and
// 20%. The pilot's rays cost a quarter more tracing and enter nothing but those decisions.
//
// Pooled entries. Every other bin above the horizon is filled too (issue 55: a table with
// holes renders darker than its surface, the measured model reading a hole as 0). Its
// estimate is the same sum over a region R of bins around it,
//   f_R = Σ_{rays in R} w / (p(ωi) cos θo) / (N · Σ_{B in R} M_B),
// the unbiased average of f over R, with R the first region of a fixed sequence that
// passes the same two tests (the geometric bound and the pilot, summed over R): first
// windows of φd around the bin (±1, 2, 4, … 64 bins, then the whole row of 180), then
// boxes of whole φd rows, ±d bins in θh and θd (d = 1, 2, 3, 4, 6, 8, … 90). φd first:
// where bins are small (θh near 0, where φd does not change the pair's geometry, and
// near the horizon) f varies least along it. R depends on the geometry and the pilot
// only, so f_R is unbiased for R's average; it differs from the bin's own average by f's
// variation across R (a bias no standard error shows). `support` says how many bins
// each entry pooled (1: its own), and stderr_f is the standard error of f_R.
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

// The rays an entry's bin, or the region it pools (above), must expect by the geometry
// or by the pilot (the default of TableOptions and of `gonio measure --min-rays`). 0
// estimates every bin above the horizon from its own rays alone.
inline constexpr double kTableMinExpectedRays = 25;
// The rays of a table at `gonio measure -o`'s default: enough that most bins at mid
// angles are their own (a Lambertian sends a typical one ~5 × 10⁻⁷ of the rays), and
// within the 10 minutes of issue 55 on 2 cores (docs/gonioreflectometer.md).
inline constexpr std::uint64_t kTableDefaultSamples = 200'000'000;

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
  // The bins each entry's estimate pooled (above): 1 for an own entry, 0 below the horizon.
  std::vector<std::uint32_t> support;
  std::uint64_t filled = 0;       // own entries (measured zeros included)
  std::uint64_t filled_by_pilot = 0;  // of those, written by the pilot's rule alone
  std::uint64_t pooled = 0;       // entries estimated over a region of bins (above)
  std::uint64_t zero = 0;         // own or pooled entries written as 0 (no ray of the estimate reached them)
  std::uint64_t missing = 0;      // entries written as missing: wholly below the horizon
  // Of the written non-zero entries (own and pooled), the fraction whose relative standard error (largest
  // over the channels) exceeds 1%, 5% and 20% (kTableErrorLevels).
  double fraction_above[3] = {0, 0, 0};
  std::vector<AlbedoBand> bands;  // 90 bands of 1° in θi
};

TableReading measure_table(const Microsurface& surface, const RunOptions& options,
                           const TableOptions& table = {});

// The pilot's rays for a table of `samples` rays: a quarter of them, at least one.
std::uint64_t table_pilot_rays(std::uint64_t samples);

}  // namespace gonio::measure
