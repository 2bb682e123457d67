// Frames, spherical helpers and sampling warps: orthonormality, round trips, and each
// warp's distribution against its analytic CDF (Kolmogorov–Smirnov statistic).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "gonio/math/cdf_guide.h"
#include "gonio/math/degrees.h"
#include "gonio/math/fast_acos.h"
#include "gonio/math/fast_atan.h"
#include "gonio/math/frame.h"
#include "gonio/math/select.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/rng.h"
#include "test_scale.h"

namespace gonio {
namespace {

void expect_orthonormal(const Frame& f) {
  EXPECT_NEAR(length(f.s), 1, 1e-6);
  EXPECT_NEAR(length(f.t), 1, 1e-6);
  EXPECT_NEAR(length(f.n), 1, 1e-6);
  EXPECT_NEAR(dot(f.s, f.t), 0, 1e-6);
  EXPECT_NEAR(dot(f.s, f.n), 0, 1e-6);
  EXPECT_NEAR(dot(f.t, f.n), 0, 1e-6);
  // Right-handed: T = N × S (SPEC §1).
  EXPECT_NEAR(length(f.t - cross(f.n, f.s)), 0, 1e-6);
}

TEST(Frame, FromNormalIsOrthonormalForEveryNormal) {
  Pcg32 rng(11);
  std::vector<Vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0},
                               normalize(Vec3{1e-8f, 0, -1}), normalize(Vec3{0, 1e-8f, 1})};
  for (int i = 0; i < 1000; ++i) normals.push_back(square_to_uniform_sphere(rng.next_float(), rng.next_float()));
  for (const Vec3& n : normals) {
    const Frame f = Frame::from_normal(n);
    expect_orthonormal(f);
    const Vec3 v = normalize(Vec3{0.3f, -0.5f, 0.8f});
    EXPECT_NEAR(length(f.to_world(f.to_local(v)) - v), 0, 1e-6);
    EXPECT_NEAR(f.to_local(n).z, 1, 1e-6);
  }
}

TEST(Frame, TangentSetsTheDirectionOfAnisotropy) {
  const Frame f = Frame::from_normal_tangent(Vec3{0, 0, 2}, Vec3{1, 1, 0.5f});
  expect_orthonormal(f);
  EXPECT_NEAR(length(f.s - normalize(Vec3{1, 1, 0})), 0, 1e-6);
  // A tangent along the normal, or zero, falls back to some valid frame.
  expect_orthonormal(Frame::from_normal_tangent(Vec3{0, 0, 1}, Vec3{0, 0, 3}));
  expect_orthonormal(Frame::from_normal_tangent(Vec3{0, 1, 0}, Vec3{}));
  // A zero normal gives the canonical frame rather than NaN.
  expect_orthonormal(Frame::from_normal_tangent(Vec3{}, Vec3{1, 0, 0}));
}

TEST(Spherical, AnglesRoundTrip) {
  for (float th = 0.05f; th < 3.1f; th += 0.3f)
    for (float ph = 0.1f; ph < 6.2f; ph += 0.7f) {
      const Vec3 w = direction_from_angles(th, ph);
      EXPECT_NEAR(std::acos(cos_theta(w)), th, 1e-5);
      EXPECT_NEAR(phi(w), ph, 1e-5);
      EXPECT_NEAR(cos_phi(w), std::cos(ph), 1e-5);
      EXPECT_NEAR(sin_phi(w), std::sin(ph), 1e-5);
    }
  // At the pole φ is undefined: helpers stay finite.
  EXPECT_TRUE(std::isfinite(cos_phi(Vec3{0, 0, 1})) && std::isfinite(sin_phi(Vec3{0, 0, 1})));
  EXPECT_EQ(sin2_theta(Vec3{0, 0, 1.0000001f}), 0.f);
}

// Largest gap between the empirical CDF of xs and `cdf`.
double ks_statistic(std::vector<double> xs, const std::function<double(double)>& cdf) {
  std::sort(xs.begin(), xs.end());
  double d = 0;
  const double n = double(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) {
    const double c = cdf(xs[i]);
    d = std::max({d, std::abs(c - i / n), std::abs(c - (i + 1) / n)});
  }
  return d;
}

// Critical value of the KS statistic at significance 1e-4: sqrt(−ln(α/2)/2) / sqrt(n).
double ks_threshold(size_t n) { return std::sqrt(-std::log(0.5e-4) / 2) / std::sqrt(double(n)); }

template <typename Warp>
std::vector<Vec3> draw(Warp&& warp, size_t n, std::uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<Vec3> v(n);
  for (auto& w : v) w = warp(rng.next_float(), rng.next_float());
  return v;
}

TEST(Warp, CosineHemisphere) {
  const size_t n = test::scaled(200000);
  const auto ws = draw(square_to_cosine_hemisphere, n, 1);
  std::vector<double> z2, ph;
  for (const auto& w : ws) {
    ASSERT_NEAR(length(w), 1, 1e-5);
    ASSERT_GE(w.z, 0);
    z2.push_back(double(w.z) * w.z);  // cos²θ is uniform for density cos θ / π
    ph.push_back(phi(w));
  }
  EXPECT_LT(ks_statistic(z2, [](double x) { return x; }), ks_threshold(n));
  EXPECT_LT(ks_statistic(ph, [](double x) { return x / (2 * kPiD); }), ks_threshold(n));
  EXPECT_FLOAT_EQ(cosine_hemisphere_pdf(0.5f), 0.5f / float(kPiD));
  EXPECT_EQ(cosine_hemisphere_pdf(-0.5f), 0.f);
}

TEST(Warp, UniformHemisphereSphereAndCone) {
  const size_t n = test::scaled(200000);
  std::vector<double> zh, zs, zc;
  for (const auto& w : draw(square_to_uniform_hemisphere, n, 2)) zh.push_back(w.z);
  for (const auto& w : draw(square_to_uniform_sphere, n, 3)) zs.push_back(w.z);
  const float cmax = 0.8f;
  for (const auto& w : draw([&](Float a, Float b) { return square_to_uniform_cone(a, b, cmax); }, n, 4))
    zc.push_back(w.z);
  // z is uniform on [0,1], [−1,1] and [cos θmax, 1] respectively (Archimedes).
  EXPECT_LT(ks_statistic(zh, [](double x) { return x; }), ks_threshold(n));
  EXPECT_LT(ks_statistic(zs, [](double x) { return (x + 1) / 2; }), ks_threshold(n));
  EXPECT_LT(ks_statistic(zc, [&](double x) { return (x - cmax) / (1 - cmax); }), ks_threshold(n));
  EXPECT_FLOAT_EQ(uniform_hemisphere_pdf(), 1 / (2 * float(kPiD)));
  EXPECT_FLOAT_EQ(uniform_sphere_pdf(), 1 / (4 * float(kPiD)));
  EXPECT_FLOAT_EQ(uniform_cone_pdf(cmax), 1 / (2 * float(kPiD) * (1 - cmax)));
}

TEST(Warp, ConcentricDiskIsUniform) {
  const size_t n = test::scaled(200000);
  Pcg32 rng(5);
  std::vector<double> r2, ang;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 d = square_to_concentric_disk(rng.next_float(), rng.next_float());
    r2.push_back(double(d.x) * d.x + double(d.y) * d.y);
    ang.push_back(std::atan2(d.y, d.x));
  }
  EXPECT_LT(ks_statistic(r2, [](double x) { return x; }), ks_threshold(n));
  EXPECT_LT(ks_statistic(ang, [](double x) { return (x + kPiD) / (2 * kPiD); }), ks_threshold(n));
  EXPECT_LE(*std::max_element(r2.begin(), r2.end()), 1.0 + 1e-6);
}

TEST(Rng, DeterministicAndInRange) {
  Pcg32 a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    const float x = a.next_float();
    EXPECT_EQ(x, b.next_float());
    differs |= x != c.next_float();
    EXPECT_GE(x, 0.f);
    EXPECT_LT(x, 1.f);
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace gonio

namespace gonio {
namespace {
TEST(Select, SinCosPolynomialsMatchLibm) {
  double worst = 0;
  for (int i = 0; i <= 100000; ++i) {
    const Float u = Float(i) / 100000;
    const SinCos sc = sincos_2pi(u);
    worst = std::max({worst, std::abs(double(sc.cos) - std::cos(2 * kPiD * u)),
                      std::abs(double(sc.sin) - std::sin(2 * kPiD * u))});
  }
  EXPECT_LT(worst, 2e-7);
  EXPECT_EQ(select(true, 1.f, 2.f), 1.f);
  EXPECT_EQ(select(false, 1.f, 2.f), 2.f);
  EXPECT_EQ(keep_if(false, 3.f), 0.f);
}
}  // namespace
}  // namespace gonio

namespace gonio {
namespace {
// A&S 4.4.46's acos (√(1 − x) times acos_poly, as EON's albedo uses it) against libm on
// [0, 1]: its bound 2e-8 rad plus float rounding; the 4-lane form lane for lane the scalar.
TEST(FastAcos, MatchesLibmOnTheUnitInterval) {
  double worst = 0;
  for (int i = 0; i <= 100000; ++i) {
    const Float x = Float(i / 100000.0);
    const Float got = std::sqrt(1 - x) * detail::acos_poly(x);
    worst = std::max(worst, std::abs(double(got) - std::acos(double(x))));
    const Float4 v = detail::acos_poly(Float4{x, x, x, x});
    EXPECT_EQ(v[2], detail::acos_poly(x));
  }
  EXPECT_LT(worst, 4e-7);
}

// fast_atan2 against libm over every octant (A&S 4.4.49's bound, 2e-8 rad, plus float
// rounding), and
// std::atan2's conventions at the special values.
TEST(FastAtan, MatchesLibmInEveryOctantAndAtSpecialValues) {
  double worst = 0;
  for (int i = 0; i < 36000; ++i) {
    const double a = (i + 0.37) * (2 * kPiD / 36000) - kPiD;
    for (const double r : {1e-3, 1.0, 7e5}) {
      const Float x = Float(r * std::cos(a)), y = Float(r * std::sin(a));
      worst = std::max(worst, std::abs(double(fast_atan2(y, x)) - std::atan2(double(y), double(x))));
    }
  }
  EXPECT_LT(worst, 5e-7);
  EXPECT_EQ(fast_atan2(0.f, 0.f), 0.f);
  EXPECT_EQ(fast_atan2(0.f, 1.f), 0.f);
  EXPECT_NEAR(fast_atan2(0.f, -1.f), kPi, 1e-6);
  EXPECT_NEAR(fast_atan2(-0.f, -1.f), -kPi, 1e-6);
  EXPECT_NEAR(fast_atan2(1.f, 0.f), kPi / 2, 1e-6);
  EXPECT_NEAR(fast_atan2(-1.f, 0.f), -kPi / 2, 1e-6);
  EXPECT_NEAR(fast_atan2(1.f, 1.f), kPi / 4, 1e-6);
  EXPECT_TRUE(std::isnan(fast_atan2(std::nanf(""), 1.f)));
  EXPECT_TRUE(std::isnan(fast_atan2(1.f, std::nanf(""))));
}

// The four-lane fast_atan2 (the measured model's lookup) is bit for bit the scalar one in
// every lane: random arguments of every sign and scale, and the special values.
TEST(FastAtan, FourLanesAreTheScalarBitForBit) {
  std::vector<Float> values = {0.f, -0.f, 1.f, -1.f, 1e-30f, -1e-40f, 3e38f, INFINITY, -INFINITY, NAN};
  Pcg32 rng(3);
  for (int i = 0; i < 4000; ++i) values.push_back((rng.next_float() * 2 - 1) * std::pow(10.f, float(int(rng.next_u32() % 13) - 6)));
  int compared = 0;
  for (std::size_t a = 0; a + 3 < values.size(); a += 3)
    for (std::size_t b = 0; b + 3 < values.size(); b += 97) {
      const Float4 y = {values[a], values[a + 1], values[a + 2], values[a + 3]};
      const Float4 x = {values[b], values[b + 1], values[b + 2], values[b + 3]};
      const Float4 r = fast_atan2(y, x);
      for (int lane = 0; lane < 4; ++lane) {
        const Float want = fast_atan2(y[lane], x[lane]), got = r[lane];
        ASSERT_EQ(std::memcmp(&want, &got, sizeof want), 0) << y[lane] << " " << x[lane] << ": " << got << " vs " << want;
        ++compared;
      }
    }
  EXPECT_GT(compared, 100000);
}

// The interval a CDF search must return, by counting instead of searching: the number of
// entries cdf[1 .. n] at or below u (upper_bound's position less one), at most n − 1.
int counted_interval(const std::vector<float>& cdf, Float u) {
  const int n = int(cdf.size()) - 1;
  int below = 0;
  for (int j = 1; j <= n; ++j) below += cdf[std::size_t(j)] <= u ? 1 : 0;
  return std::min(below, n - 1);
}

// The guided search (the measured model's sampler) and the binary one return the same
// interval as the count for every u in [0, 1]: random CDFs with empty intervals at the
// ends and inside, a CDF whose mass is all in one interval, and u at every entry, a float
// step either side of it, at the guide's step boundaries and at random.
template <int N, int G>
void expect_guided_search_exact() {
  const int n = N;
  Pcg32 rng(11 + std::uint64_t(n));
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<double> mass(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) mass[std::size_t(i)] = rng.next_float() < 0.3f ? 0.0 : std::pow(double(rng.next_float()), 6);
    if (trial % 4 == 0) {  // empty ends
      mass.front() = 0;
      mass[1] = 0;
      mass.back() = 0;
    }
    if (trial % 4 == 1) {  // all the mass in one interval
      std::fill(mass.begin(), mass.end(), 0.0);
      mass[rng.next_u32() % std::uint32_t(n)] = 1;
    }
    double total = 0;
    for (double m : mass) total += m;
    if (!(total > 0)) {
      mass[0] = 1;
      total = 1;
    }
    std::vector<float> cdf(std::size_t(n) + 1, 0.0f);
    double run = 0;
    for (int i = 0; i < n; ++i) {
      run += mass[std::size_t(i)];
      cdf[std::size_t(i) + 1] = float(run / total);
    }
    cdf[std::size_t(n)] = 1;
    std::vector<std::uint8_t> guide(G);
    build_cdf_guide<N, G>(cdf.data(), guide.data());
    std::vector<Float> us = {0.0f, kOneMinusEpsilon, 1.0f};
    for (float c : cdf) us.insert(us.end(), {c, std::nextafter(c, 0.0f), std::nextafter(c, 1.0f)});
    for (int g = 0; g <= G; ++g) us.insert(us.end(), {Float(g) / G, std::nextafter(Float(g) / G, 0.0f)});
    for (int i = 0; i < 2000; ++i) us.push_back(rng.next_float());
    for (Float u : us) {
      if (!(u >= 0 && u <= 1)) continue;
      const int want = counted_interval(cdf, u);
      const int guided = cdf_interval_guided<N, G>(cdf.data(), guide.data(), u);
      ASSERT_EQ(guided, want) << "n " << n << " trial " << trial << " u " << u;
      ASSERT_EQ(cdf_interval(cdf.data(), n, u), want) << "n " << n << " u " << u;
    }
    const int at_nan = cdf_interval_guided<N, G>(cdf.data(), guide.data(), std::nanf(""));
    const int above = cdf_interval_guided<N, G>(cdf.data(), guide.data(), 1.5f);
    EXPECT_EQ(at_nan, n - 1);
    EXPECT_EQ(above, n - 1);
    const int below = cdf_interval_guided<N, G>(cdf.data(), guide.data(), -0.5f);
    EXPECT_TRUE(below >= 0 && below < n);
  }
}
TEST(CdfGuide, GuidedSearchFindsTheBinarySearchesInterval) {
  expect_guided_search_exact<64, 128>();
  expect_guided_search_exact<32, 64>();
  expect_guided_search_exact<32, 8>();  // fewer steps than intervals: longer walks, same answers
}
}  // namespace
}  // namespace gonio

// cos_degrees: exact at the angles whose cosines are 0, ½ and 1 (and the correctly rounded
// √3/2 at 30°, below the true value, so that 1 − cos² rounds to ¼ or above), and within an
// ulp of the cosine elsewhere, over several turns and both signs.
TEST(Degrees, CosineIsExactWhereItCanBe) {
  EXPECT_EQ(gonio::cos_degrees(0), 1.0);
  EXPECT_EQ(gonio::cos_degrees(60), 0.5);
  EXPECT_EQ(gonio::cos_degrees(-60), 0.5);
  EXPECT_EQ(gonio::cos_degrees(120), -0.5);
  EXPECT_EQ(gonio::cos_degrees(300), 0.5);
  EXPECT_EQ(gonio::cos_degrees(90), 0.0);
  EXPECT_FALSE(std::signbit(gonio::cos_degrees(90)));
  EXPECT_EQ(gonio::cos_degrees(180), -1.0);
  EXPECT_EQ(gonio::cos_degrees(360 * 7), 1.0);
  EXPECT_EQ(gonio::cos_degrees(30), 0.8660254037844386);  // √3/2 = 0.86602540378443864676…
  // The reference in x87 long double (64-bit mantissa): the radian angle of −740° has an
  // error of 1e-15 in double, far above the one ulp (1.1e-16 near 1) allowed here.
  const long double pi = 3.141592653589793238462643383279502884L;
  for (int i = -2000; i <= 2000; ++i) {
    const double deg = i * 0.37;
    EXPECT_NEAR(gonio::cos_degrees(deg), double(std::cos(static_cast<long double>(deg) * pi / 180)), 1.2e-16) << deg;
  }
}
