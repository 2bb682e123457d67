#pragma once
// The 4-D measure ∫∫ dωi dωo of each bin of a MERL table (merl.h), over the part of the
// bin where both directions are above the horizon: what a measured BRDF's bin average is
// taken against (table.h).
//
// Derivation. Rusinkiewicz 1998 (§3) writes a pair (ωi, ωo) as the half vector ωh and the
// difference vector ωd (ωi seen from the half vector's frame). For fixed ωh, ωi is a
// rotation of ωd, so dωi = dωd; for fixed ωi, ωo = 2 (ωi·ωh) ωh − ωi, whose Jacobian is
// dωo = 4 (ωi·ωh) dωh (Torrance & Sparrow 1967; Walter et al. 2007 eq. 14). Hence
//   dωi dωo = 4 cos θd dωh dωd = 4 cos θd sin θd sin θh dθh dφh dθd dφd.
// An isotropic table integrates φh over [0, 2π), and its φd bin [k°, k+1°) also holds the
// swapped pairs at φd + 180° (reciprocity folds them together; swapping keeps both
// directions' heights), which doubles it:
//   M(i, j, k) = 16π ∫θh∫θd∫φd sin θh cos θd sin θd · V dθh dθd dφd.
// Both directions are above the horizon where
//   cos θh cos θd ∓ sin θh sin θd cos φd > 0  ⇔  tan θh tan θd |cos φd| < 1
// (the z of ωi and ωo, merl_directions), which V (0 or 1) tests. Bins wholly inside take
// the closed form 16π (cos θh0 − cos θh1) (sin² θd1 − sin² θd0)/2 · Δφd; bins the horizon
// cuts take the φd part in closed form and (θh, θd) by a 16 × 16 midpoint rule.
// The measures of all bins sum to (2π)², the measure of two hemispheres. (gonio fit's
// merl_entry_weight, include/gonio/fit/metric.h, is the same Jacobian taken at the bin's
// centre, up to a constant, for weighting a fit; an estimator needs the exact measure of
// the part above the horizon, hence this integral.)

#include <vector>

#include "gonio/math/vec3.h"

namespace gonio::measure {

// M(i, j, k) in sr², for every entry of MerlTable (index MerlTable::index(i, j, k)).
// Computed once and cached (about 0.3 s); thread-safe.
const std::vector<double>& merl_bin_measures();

// The table entry (i, j, k) of a pair of directions above the horizon, from its
// half/difference angles (merl.h half_diff: θh, θd in [0, π/2], φd folded in [0, π)).
struct MerlBin {
  int i, j, k;
};
MerlBin merl_bin(double theta_h, double theta_d, double phi_d);
// The same from the pair of directions (both z > 0), in float with the polynomial atan2
// (math/fast_atan.h) for the table mode's hot loop: the angles differ from merl.h's double
// half_diff by float rounding, so a pair within ~1e-6 rad of a bin edge may fall in the
// neighbouring bin (6 of 400,000 pairs, tests/measure/test_table_binning.cpp) — far
// below the noise of any table, and a pair's bin is still a fixed function of the pair.
MerlBin merl_bin_of(const Vec3& wo, const Vec3& wi);

}  // namespace gonio::measure
