// gonio/batch.h: the batch loops give what one call per element gives, and user
// directions are normalised without overflow, underflow or NaN.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "gonio/batch.h"
#include "gonio/material.h"
#include "gonio/rng.h"

namespace {

using namespace gonio;

TEST(Batch, UnitDirectionScalesExtremeComponents) {
  // (3, 4, 0)/5 at every scale: the squares of 3e300 overflow and those of 3e-320 vanish.
  for (double s : {1.0, 3e300, 1e-300, 1e-310, 1.7e308}) {
    const auto w = unit_direction(0.6 * s, 0.8 * s, 0);
    ASSERT_TRUE(w) << s;
    EXPECT_FLOAT_EQ(w->x, 0.6f) << s;
    EXPECT_FLOAT_EQ(w->y, 0.8f) << s;
    EXPECT_EQ(w->z, 0.0f) << s;
  }
  EXPECT_FALSE(unit_direction(0, 0, 0));
  EXPECT_FALSE(unit_direction(0, -0.0, 0));
  EXPECT_FALSE(unit_direction(std::numeric_limits<double>::infinity(), 0, 1));
  EXPECT_FALSE(unit_direction(std::nan(""), 0, 1));
  // A NaN after the first component, on the plain and on the scaled path.
  for (double s : {1.0, 1e-300, 1e300}) {
    EXPECT_FALSE(unit_direction(0, std::nan("") * s, s)) << s;
    EXPECT_FALSE(unit_direction(s, 0, std::nan(""))) << s;
    EXPECT_FALSE(unit_direction(s, std::nan(""), std::numeric_limits<double>::infinity())) << s;
  }
  const double one[3] = {0, 0, 1};
  Vec3 wa, wb;
  // The pair too, on its plain path (s = 1) and on the one-at-a-time path of rows that
  // need scaling (s = 1e-300, 1e300: there the largest component is all a test on the
  // rows' maxima sees, and a NaN after it once came back as a direction).
  for (double s : {1.0, 1e-300, 1e300}) {
    const double nan_y[3] = {s, std::nan(""), 0}, nan_z[3] = {s, 0, std::nan("")};
    EXPECT_FALSE(unit_direction_pair(nan_y, one, wa, wb)) << s;
    EXPECT_FALSE(unit_direction_pair(one, nan_z, wa, wb)) << s;
  }
}

TEST(Batch, PairEqualsTwoSingles) {
  Pcg32 rng(5, 0);
  for (int i = 0; i < 20000; ++i) {
    // Components over 40 decades, some rows far from unit length.
    auto c = [&] { return (rng.next_float() - 0.5) * std::pow(10.0, 40 * (rng.next_float() - 0.5)); };
    const double a[3] = {c(), c(), c()}, b[3] = {c(), c(), c()};
    Vec3 wa, wb;
    ASSERT_TRUE(unit_direction_pair(a, b, wa, wb));
    EXPECT_EQ(wa, *unit_direction(a[0], a[1], a[2]));
    EXPECT_EQ(wb, *unit_direction(b[0], b[1], b[2]));
  }
  const double zero[3] = {0, 0, 0}, one[3] = {0, 0, 1};
  Vec3 wa, wb;
  EXPECT_FALSE(unit_direction_pair(zero, one, wa, wb));
  EXPECT_FALSE(unit_direction_pair(one, zero, wa, wb));
}

// unit_direction_rows (four rows at a time on AVX2) gives each row bit for bit what
// unit_direction gives it, over 40 decades of scale, with rows that need the scaled path,
// zero rows and NaN components scattered among them, and a row count that is not a
// multiple of four; it reports a refused pair. Both the dispatching function and, where
// the processor has it, the AVX2 loop itself.
TEST(Batch, RowsEqualOneRowAtATime) {
  Pcg32 rng(12, 0);
  const std::size_t n = 4099;
  std::vector<double> a(3 * n), b(3 * n);
  auto c = [&] { return (rng.next_float() - 0.5) * std::pow(10.0, 40 * (rng.next_float() - 0.5)); };
  for (double& x : a) x = c();
  for (double& x : b) x = c();
  const std::size_t tiny = 1001, huge = 2002;  // rows for the scaled path, inside the AVX2 groups
  const double tiny_row[3] = {3e-310, -4e-310, 1e-311}, huge_row[3] = {1e305, 2e305, -3e305};
  std::copy(tiny_row, tiny_row + 3, a.begin() + 3 * tiny);
  std::copy(huge_row, huge_row + 3, b.begin() + 3 * huge);
  auto run = [&](auto rows, std::size_t count, const char* which) {
    std::vector<Vec3> wa(count), wb(count);
    const bool ok = rows(a.data(), b.data(), count, wa.data(), wb.data());
    bool every = true;
    for (std::size_t j = 0; j < count; ++j) {
      const auto ua = unit_direction(a[3 * j], a[3 * j + 1], a[3 * j + 2]);
      const auto ub = unit_direction(b[3 * j], b[3 * j + 1], b[3 * j + 2]);
      every = every && ua && ub;
      if (!ua || !ub) continue;
      ASSERT_EQ(std::memcmp(&wa[j], &*ua, sizeof(Vec3)), 0) << which << " row " << j;
      ASSERT_EQ(std::memcmp(&wb[j], &*ub, sizeof(Vec3)), 0) << which << " row " << j;
    }
    EXPECT_EQ(ok, every) << which;
  };
  auto dispatching = [](const double* pa, const double* pb, std::size_t m, Vec3* oa, Vec3* ob) {
    return unit_direction_rows(pa, pb, m, oa, ob);
  };
  run(dispatching, n, "unit_direction_rows");
#ifdef GONIO_BATCH_AVX2
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2");
  auto vector_loop = [](const double* pa, const double* pb, std::size_t m, Vec3* oa, Vec3* ob) {
    bool ok = true;
    EXPECT_EQ(batch_detail::unit_direction_rows_avx2(pa, pb, m, oa, ob, ok), m);
    return ok;
  };
  if (avx2) run(vector_loop, n - 3, "unit_direction_rows_avx2");  // a multiple of four
#endif
  // Bad rows: a zero, and NaNs after the first component; each refused.
  for (std::size_t bad : {std::size_t(5), std::size_t(2050), n - 1}) {
    const std::vector<double> keep_a = a, keep_b = b;
    for (std::size_t which = 0; which < 3; ++which) {
      a = keep_a;
      b = keep_b;
      double* row = (which == 1 ? b.data() : a.data()) + 3 * bad;
      if (which == 0) row[0] = row[1] = row[2] = 0;
      else row[which] = std::nan("");
      run(dispatching, n, "a bad row");
#ifdef GONIO_BATCH_AVX2
      if (avx2) run(vector_loop, n - 3, "a bad row, AVX2");
#endif
    }
    a = keep_a;
    b = keep_b;
  }
}

TEST(Batch, EvalPdfSampleEqualOneCallPerElement) {
  for (const char* text : {R"({"type":"diffuse","reflectance":[0.2,0.5,0.8]})",
                           R"({"type":"roughdielectric","eta":1.5,"alpha":0.3})",
                           R"({"type":"blend","weight":0.4,"bsdfs":[{"type":"dielectric"},{"type":"plastic","alpha":0.2}]})"}) {
    const BxDF bxdf = parse_material(text);
    Pcg32 rng(9, 1);
    const size_t n = 3000;
    std::vector<Vec3> wo(n), wi(n);
    std::vector<SampleUniforms> u(n);
    for (size_t i = 0; i < n; ++i) {
      wo[i] = *unit_direction(rng.next_float() - 0.5, rng.next_float() - 0.5, rng.next_float() - 0.3);
      wi[i] = *unit_direction(rng.next_float() - 0.5, rng.next_float() - 0.5, rng.next_float() - 0.5);
      u[i] = {rng.next_float(), rng.next_float(), rng.next_float()};
    }
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      std::vector<Color> f(n), weight(n);
      std::vector<Float> pdf(n), pdf2(n), spdf(n);
      std::vector<Vec3> swi(n);
      std::vector<std::uint8_t> delta(n);
      std::vector<BatchLobe> lobe(n);
      eval_batch<Color>(bxdf, wo, wi, mode, f, pdf);
      pdf_batch<Color>(bxdf, wo, wi, mode, pdf2);
      sample_batch<Color>(bxdf, wo, u, mode, {swi, weight, spdf, delta, lobe});
      for (size_t i = 0; i < n; ++i) {
        const BSDFEval e = bxdf.eval(wo[i], wi[i], mode);
        ASSERT_EQ(f[i], e.f) << text << " " << i;
        ASSERT_EQ(pdf[i], e.pdf) << text << " " << i;
        ASSERT_EQ(pdf2[i], bxdf.pdf(wo[i], wi[i], mode)) << text << " " << i;
        const auto s = bxdf.sample(wo[i], u[i].lobe, u[i].u1, u[i].u2, mode);
        ASSERT_EQ(lobe[i] != BatchLobe::None, bool(s)) << text << " " << i;
        if (!s) {
          EXPECT_EQ(swi[i], Vec3{});
          EXPECT_TRUE(weight[i].is_black());
          continue;
        }
        ASSERT_EQ(swi[i], s->wi);
        ASSERT_EQ(weight[i], s->weight);
        ASSERT_EQ(spdf[i], s->pdf);
        ASSERT_EQ(delta[i] != 0, s->delta);
        ASSERT_EQ(lobe[i], s->lobe == Lobe::Reflection ? BatchLobe::Reflection : BatchLobe::Transmission);
      }
    }
  }
}

TEST(Batch, MismatchedLengthsThrow) {
  const BxDF bxdf = parse_material(R"({"type":"diffuse"})");
  std::vector<Vec3> wo(3), wi(2);
  std::vector<Color> f(3);
  std::vector<Float> pdf(3);
  EXPECT_THROW(eval_batch<Color>(bxdf, wo, wi, TransportMode::Radiance, f, pdf), std::invalid_argument);
}

}  // namespace
