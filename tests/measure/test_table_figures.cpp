// The figures of docs/gonioreflectometer.md ("Every entry filled") that need a full-size
// table: skipped unless the table is named in the environment, as the docs' commands do.
//   GONIO_PEAK_TABLE=peak.binary GONIO_PEAK_STDERR=peak.err.binary
//     build/bin/gonio_measure_tests --gtest_filter='MeasureTableFigure.*'
// (GONIO_PEAK_ALPHA gives α, default 0.1; GONIO_PEAK_SUPPORT, the --support-table, splits
// the count between own and pooled entries.)
// A Gaussian mirror surface's table, first bounce (`--max-bounces 1`), against the
// single-scattering Smith–Beckmann model (smith_beckmann_model.h), entry by entry where
// both directions of the bin's centre are within 60° of the normal and the model is in
// the peak (its bin average at least 1/sr): the model averaged over each bin (4 × 4 × 4
// midpoints in θh, θd, φd, weighted by the bin's measure density sin θh cos θd sin θd,
// merl_bins.h) against the entry, within max(3σ, 2%).
// σ is the standard error the model predicts for the entry (Pearson's form): the entry's own
// estimate σ̂ (from its rays' scores) scaled by √(model/f). A bin's estimate is a sum of
// rays of about equal score, so σ̂ ∝ √n while f ∝ n: where fewer rays than expected
// arrived, σ̂ is too small and (f − model)/σ̂ too negative (Neyman's form; the own
// entries beyond 3σ were 536 low against 189 high). Two figures, because 3σ is a
// per-entry bound: among 3 × 10⁵ entries chance alone puts 0.27% beyond it, so the test
// asks (1) that no more lie beyond 3σ than chance and the pooled regions' spread allow,
// and (2) that every entry lie within the bound a table of that many entries needs,
// max(z_N σ, 2%), z_N the two-sided Gaussian quantile at a 1% family-wise rate
// (Bonferroni: 2 Q(z_N) = 0.01 / N, z_N = 5.5 for N = 3 × 10⁵).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "gonio/math/constants.h"
#include "gonio/merl.h"
#include "smith_beckmann_model.h"

namespace gonio::measure {
namespace {

using namespace smith_beckmann;

// The pair of a (θh, θd, φd) (Rusinkiewicz 1998): ωd rotated to the half vector (θh, 0).
void pair_of(double th, double td, double pd, V& wi, V& wo) {
  const V d = dir(td, pd);
  wi = V{d.x * std::cos(th) + d.z * std::sin(th), d.y, -d.x * std::sin(th) + d.z * std::cos(th)};
  const V h = dir(th, 0);
  const double c = wi.x * h.x + wi.y * h.y + wi.z * h.z;
  wo = V{2 * c * h.x - wi.x, 2 * c * h.y - wi.y, 2 * c * h.z - wi.z};
}

double theta_h_edge(double i) { return std::pow(i / 90, 2) * kPiD / 2; }

// The z with 2 Q(z) = p, Q the Gaussian upper tail (bisection on erfc: p down to 1e-300).
double two_sided_quantile(double p) {
  double lo = 0, hi = 40;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return hi;
}

TEST(MeasureTableFigure, PeakAgainstSmithBeckmann) {
  const char* table_path = std::getenv("GONIO_PEAK_TABLE");
  const char* stderr_path = std::getenv("GONIO_PEAK_STDERR");
  if (!table_path || !stderr_path) GTEST_SKIP() << "set GONIO_PEAK_TABLE and GONIO_PEAK_STDERR";
  const char* alpha_text = std::getenv("GONIO_PEAK_ALPHA");
  const double alpha = alpha_text ? std::atof(alpha_text) : 0.1;
  const MerlTable t = read_merl(table_path), e = read_merl(stderr_path);
  const char* support_path = std::getenv("GONIO_PEAK_SUPPORT");
  const MerlTable support = support_path ? read_merl(support_path) : MerlTable{};
  std::size_t entries = 0, within = 0, pooled = 0, pooled_within = 0;
  double chi2 = 0, ratio_sum = 0, worst = 0, worst_z = 0, worst_z_beyond_floor = 0;
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        V wi, wo;
        pair_of(std::pow((i + 0.5) / 90, 2) * kPiD / 2, (j + 0.5) * kPiD / 180, (k + 0.5) * kPiD / 180, wi, wo);
        if (wi.z < 0.5 || wo.z < 0.5) continue;  // θi or θo beyond 60° at the centre
        constexpr int Q = 4;
        double num = 0, den = 0;
        for (int a = 0; a < Q; ++a)
          for (int b = 0; b < Q; ++b)
            for (int c = 0; c < Q; ++c) {
              const double th = theta_h_edge(i + (a + 0.5) / Q), td = (j + (b + 0.5) / Q) * kPiD / 180;
              const double pd = (k + (c + 0.5) / Q) * kPiD / 180;
              // dθh in equal steps of the index: dθh/du ∝ u, u = 90 √(θh/(π/2)).
              const double w = std::sin(th) * std::cos(td) * std::sin(td) * (i + (a + 0.5) / Q);
              V a_i, a_o;
              pair_of(th, td, pd, a_i, a_o);
              num += w * model_f(a_i, a_o, alpha, Masking::HeightCorrelated);
              den += w;
            }
        const double model = num / den;
        if (model < 1) continue;
        ASSERT_TRUE(t.measured(i, j, k)) << i << " " << j << " " << k;
        const double f = t.at(i, j, k)[1], own_se = e.at(i, j, k)[1];
        const double se = f > 0 ? own_se * std::sqrt(model / f) : own_se;  // Pearson (above)
        ++entries;
        const double dev = std::abs(f - model);
        const bool ok = dev <= std::max(3 * se, 0.02 * model);
        within += ok;
        if (support_path && support.at(i, j, k)[0] > 1.5f) ++pooled, pooled_within += ok;
        if (se > 0) chi2 += dev * dev / (se * se);
        ratio_sum += f / model;
        worst = std::max(worst, dev / std::max(3 * se, 0.02 * model));
        worst_z = std::max(worst_z, se > 0 ? dev / se : (dev > 0.02 * model ? HUGE_VAL : 0.0));
        if (dev > 0.02 * model) worst_z_beyond_floor = std::max(worst_z_beyond_floor, se > 0 ? dev / se : HUGE_VAL);
      }
  ASSERT_GT(entries, 0u);
  std::printf("peak entries %zu: within max(3 sigma, 2%%) %.4f; mean f/model %.4f; chi2/entry %.3f; worst %.2f x bound\n",
              entries, double(within) / double(entries), ratio_sum / double(entries), chi2 / double(entries), worst);
  if (support_path)
    std::printf("of them pooled %zu, within %zu; own %zu, within %zu\n", pooled, pooled_within, entries - pooled,
                within - pooled_within);
  const double z_family = two_sided_quantile(0.01 / double(entries));
  std::printf("largest |f - model| / sigma %.2f (beyond the 2%% floor: %.2f); the bound for %zu entries at a 1%% "
              "family-wise rate: %.2f sigma\n",
              worst_z, worst_z_beyond_floor, entries, z_family);
  EXPECT_GE(double(within) / double(entries), 0.99);
  // (2) above: every entry within max(z_N σ, 2%).
  EXPECT_LE(worst_z_beyond_floor, z_family);
  if (support_path) {
    // (1) above: the own entries beyond 3σ at most about chance's 0.27% (0.5%: the scores
    // are not Gaussian at 25 rays); the pooled ones also carry their region's spread.
    EXPECT_LE(double(entries - pooled - (within - pooled_within)) / double(entries - pooled), 0.005);
    EXPECT_LE(double(pooled - pooled_within) / double(pooled), 0.02);
  }
}

}  // namespace
}  // namespace gonio::measure
