// The MERL table mode: the bin measures (checked by Monte Carlo against uniformly drawn
// pairs of directions) and the fill of a flat Lambertian (ρ/π within the noise).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../unit/test_scale.h"
#include "gonio/material.h"
#include "gonio/measure/merl_bins.h"
#include "gonio/measure/table.h"
#include "gonio/merl.h"
#include "gonio/rng.h"
#include "surfaces_for_tests.h"

namespace gonio::measure {
namespace {

constexpr int kGi = 9, kGj = 9, kGk = 6;  // coarse groups of 10 x 10 x 30 bins
int group(int i, int j, int k) { return (i / 10) + kGi * ((j / 10) + kGj * (k / 30)); }

TEST(MerlBins, MeasuresSumToTwoHemispheres) {
  const std::vector<double>& m = merl_bin_measures();
  double total = 0;
  for (const double v : m) {
    ASSERT_GE(v, 0);
    total += v;
  }
  EXPECT_NEAR(total / (4 * kPiD * kPiD), 1, 1e-4);
}

// Pairs (ωi, ωo) drawn uniformly on two hemispheres (density 1/(2π)²) land in a group of
// bins with probability M_group / (2π)²; the group index is computed here from the
// half/difference angles with the table's bin edges (SPEC §2).
TEST(MerlBins, MeasuresMatchUniformPairsOfDirections) {
  const std::vector<double>& m = merl_bin_measures();
  std::vector<double> expect(kGi * kGj * kGk, 0.0), got(kGi * kGj * kGk, 0.0);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) expect[group(i, j, k)] += m[MerlTable::index(i, j, k)] / (4 * kPiD * kPiD);
  const std::uint64_t n = gonio::test::scaled(2000000, 300000);
  Pcg32 rng(1);
  auto uniform = [&] {
    const double c = 1 - rng.next_double(), phi = 2 * kPiD * rng.next_double(), s = std::sqrt(1 - c * c);
    return Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(c)};
  };
  for (std::uint64_t r = 0; r < n; ++r) {
    const Vec3 wi = uniform(), wo = uniform();
    const HalfDiff hd = half_diff(wo, wi);
    const int i = std::min(89, int(std::sqrt(hd.theta_h / (kPiD / 2)) * 90));
    const int j = std::min(89, int(hd.theta_d / (kPiD / 2) * 90));
    const int k = std::min(179, int(hd.phi_d / kPiD * 180));
    got[group(i, j, k)] += 1;
  }
  double chi2 = 0;
  int dof = 0;
  for (std::size_t g = 0; g < got.size(); ++g) {
    const double e = expect[g] * double(n);
    if (e < 20) {
      EXPECT_LT(got[g], e + 10 * std::sqrt(e) + 10) << "group " << g;
      continue;
    }
    chi2 += (got[g] - e) * (got[g] - e) / e;
    ++dof;
  }
  ASSERT_GT(dof, 200);
  // χ²/dof of a few hundred degrees of freedom: 1 ± 0.1 (one sigma).
  EXPECT_LT(chi2 / dof, 1.4) << "dof " << dof;
}

// A flat Lambertian's table is ρ/π: group sums Σ f_B M_B (missing bins count 0, an
// unbiased estimate of ∫∫ f) against ρ/π M_group, χ² with the bins' standard errors,
// away from the horizon (where the 1/cos θo scores have no finite variance).
TEST(MeasureTable, FlatLambertianFillsRhoOverPi) {
  const Microsurface s(testsurf::flat_field(), parse_material(R"({"type":"diffuse","reflectance":0.6})"));
  RunOptions o;
  o.samples = gonio::test::scaled(1500000, 600000);
  o.seed = 2;
  const TableReading r = measure_table(s, o);
  const std::vector<double>& m = merl_bin_measures();
  // Every ray reflects (a Lambert sample exactly at the horizon, probability ~1e-7, is
  // the model's "no sample").
  EXPECT_EQ(r.counts.up + r.counts.absorbed, r.counts.launched);
  EXPECT_LE(r.counts.absorbed, r.counts.launched / 100000);
  std::vector<double> sum(kGi * kGj * kGk, 0.0), var(sum.size(), 0.0), meas(sum.size(), 0.0);
  std::vector<bool> near_horizon(sum.size(), false);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        const std::size_t e = MerlTable::index(i, j, k);
        const int g = group(i, j, k);
        // Bin's far corner: both directions at least ~25° above the horizon.
        const double th = std::pow((i + 1) / 90.0, 2) * kPiD / 2, td = (j + 1) * kPiD / 180;
        if (th + td > 65 * kPiD / 180) near_horizon[g] = true;
        meas[g] += m[e];
        if (!r.table.measured(i, j, k)) continue;
        sum[g] += r.table.rgb[3 * e + 1] * m[e];
        var[g] += std::pow(double(r.stderr_f[3 * e + 1]) * m[e], 2);
      }
  double chi2 = 0;
  int dof = 0;
  for (std::size_t g = 0; g < sum.size(); ++g) {
    if (near_horizon[g] || !(var[g] > 0)) continue;
    const double z = (sum[g] - 0.6 / kPiD * meas[g]) / std::sqrt(var[g]);
    EXPECT_LT(std::abs(z), 5) << "group " << g;
    chi2 += z * z;
    ++dof;
  }
  ASSERT_GT(dof, 40);
  EXPECT_LT(chi2 / dof, 1.6) << "dof " << dof;
  EXPECT_GT(chi2 / dof, 0.5) << "dof " << dof;
  // The albedo per θi band is ρ (every ray reflects with weight ρ).
  for (const AlbedoBand& b : r.bands) EXPECT_NEAR(b.albedo[1], 0.6, 1e-3) << b.theta_lo;
}

// Unpolarised Fresnel reflectance of glass (n = 1.5) from air at cos θi = c (Born & Wolf
// §1.5.2: r_s = (c − n c_t)/(c + n c_t), r_p = (n c − c_t)/(n c + c_t)).
double glass_reflectance_from_air(double c) {
  const double n = 1.5, ct = std::sqrt(1 - (1 - c * c) / (n * n));
  const double rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
  return (rs * rs + rp * rp) / 2;
}

// The incidences (table.h): every 1° band of θi gets N (1/180 + (cos b° − cos (b+1)°)/2)
// rays, and its albedo is the band's solid-angle mean of what the surface reflects: here
// a flat glass, F averaged over the band (Simpson's rule in cos θi).
TEST(MeasureTable, EveryBandOfIncidenceGetsItsShareOfRaysAndItsFresnelMean) {
  const Microsurface s(testsurf::flat_field(), parse_material(R"({"type":"dielectric","eta":1.5})"));
  RunOptions o;
  o.samples = gonio::test::scaled(400000, 100000);
  o.seed = 5;
  const TableReading r = measure_table(s, o);
  ASSERT_EQ(r.bands.size(), 90u);
  const double n = double(o.samples);
  for (int b = 0; b < 90; ++b) {
    const double c0 = std::cos(b * kPiD / 180), c1 = std::cos((b + 1) * kPiD / 180);
    const double p = 1.0 / 180 + (c0 - c1) / 2, expected = n * p;
    EXPECT_NEAR(double(r.bands[b].rays), expected, 5 * std::sqrt(expected * (1 - p))) << "band " << b;
  }
  for (int b : {0, 1, 20, 45, 70}) {
    const double c0 = std::cos(b * kPiD / 180), c1 = std::cos((b + 1) * kPiD / 180);
    double mean = 0;
    const int m = 64;
    for (int q = 0; q <= m; ++q) {
      const double w = q == 0 || q == m ? 1 : q % 2 ? 4 : 2;
      mean += w * glass_reflectance_from_air(c1 + (c0 - c1) * q / m);
    }
    mean /= 3.0 * m;
    const AlbedoBand& a = r.bands[b];
    ASSERT_GT(a.stderr_albedo[1], 0) << "band " << b;
    EXPECT_NEAR(a.albedo[1], mean, 4 * a.stderr_albedo[1]) << "band " << b;
    // A binary event per ray: the standard error is that of a proportion over the band's
    // rays, itself estimated from about rays · F reflections (relative noise ~ 1/(2√that)).
    const double expected_se = std::sqrt(mean * (1 - mean) / double(a.rays));
    EXPECT_NEAR(a.stderr_albedo[1], expected_se, expected_se * 1.5 / std::sqrt(double(a.rays) * mean))
        << "band " << b;
  }
}

TEST(MeasureTable, SameBitsWhateverTheThreadCount) {
  const Microsurface s(testsurf::eggcrate_field(16, 2), parse_material(R"({"type":"diffuse","reflectance":0.7})"));
  RunOptions o;
  o.samples = 40000;
  o.threads = 1;
  const TableReading a = measure_table(s, o);
  o.threads = 2;
  const TableReading b = measure_table(s, o);
  EXPECT_TRUE(a.table.rgb == b.table.rgb);
  EXPECT_TRUE(a.stderr_f == b.stderr_f);
  EXPECT_EQ(a.counts.segments, b.counts.segments);
}

}  // namespace
}  // namespace gonio::measure
