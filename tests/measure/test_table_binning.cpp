// The table mode's float binning (merl_bin_of, merl_bins.h) against the double path
// (merl.h half_diff with std::atan2, then merl_bin): the same bin for all but a tiny
// fraction of pairs, and then a neighbouring one (float rounding at a bin edge).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "../unit/test_scale.h"
#include "gonio/math/constants.h"
#include "gonio/measure/merl_bins.h"
#include "gonio/merl.h"
#include "gonio/rng.h"

namespace gonio::measure {
namespace {

Vec3 uniform_hemisphere(Pcg32& rng) {  // cos θ uniform in (0, 1]
  const double c = 1 - rng.next_double(), phi = 2 * kPiD * rng.next_double();
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  return Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(c)};
}

TEST(MeasureTableBinning, FloatBinsMatchTheDoublePathUpToEdgeRounding) {
  Pcg32 rng(11, 3);
  const int n = gonio::test::scaled(400000, 40000);
  int differ = 0;
  for (int q = 0; q < n; ++q) {
    Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
    if (q % 4 == 0) wo = Vec3{-wi.x, -wi.y, wi.z};  // mirror pairs: θh = 0, the sqrt axis' finest bins
    if (q % 4 == 1) wo = Vec3{Float(0.999 * wi.x), wi.y, wi.z + Float(1e-3)};  // near-retro: θd ≈ 0
    if (!(wo.z > 0)) continue;
    const HalfDiff hd = half_diff(wo, wi);
    const MerlBin d = merl_bin(hd.theta_h, hd.theta_d, hd.phi_d);
    const MerlBin f = merl_bin_of(wo, wi);
    if (d.i == f.i && d.j == f.j && d.k == f.k) continue;
    ++differ;
    // A neighbour only (φd's bins 0 and 179 meet at the fold).
    const int dk = std::abs(d.k - f.k);
    EXPECT_LE(std::abs(d.i - f.i), 1) << q;
    EXPECT_LE(std::abs(d.j - f.j), 1) << q;
    EXPECT_TRUE(dk <= 1 || dk == MerlTable::kPhiD - 1) << q << ": k " << d.k << " vs " << f.k;
  }
  EXPECT_LE(differ, n / 10000) << differ << " of " << n;
  RecordProperty("differ", differ);
  std::printf("float vs double bins: %d of %d pairs differ\n", differ, n);
}

}  // namespace
}  // namespace gonio::measure
