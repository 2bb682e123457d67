// The random walk (random_walk.h) and the slab estimator (slab_walk.h) against physics
// derived independently of them: Chandrasekhar's H-function for the index-matched
// half-space, Beer–Lambert for a slab that only absorbs.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "../test_common.h"
#include "gonio/bxdf/dielectric.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/random_walk.h"
#include "gonio/subsurface/slab_walk.h"
#include "chandrasekhar_h.h"
#include "test_scale.h"

namespace gonio {
namespace {

using test::chandrasekhar_h;

// ∫₀¹ H dμ, for the moment identity.
double h_moment0(double albedo) {
  std::vector<double> x, w;
  gauss_legendre(24, 0, 1, x, w);
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += w[i] * chandrasekhar_h(albedo, x[i]);
  return s;
}

TEST(SubsurfaceWalk, HFunctionMatchesChandrasekhar) {
  // Chandrasekhar 1960, Table XI (conservative isotropic scattering): H(1) = 2.9078.
  EXPECT_NEAR(chandrasekhar_h(1.0, 1.0), 2.9078, 1e-3);
  // The zeroth moment: ∫₀¹ H dμ = (2/ϖ)(1 − √(1 − ϖ)) (Chandrasekhar 1960, ch. V).
  for (double a : {0.5, 0.9, 0.99}) EXPECT_NEAR(h_moment0(a), 2 / a * (1 - std::sqrt(1 - a)), 1e-6) << a;
}

Subsurface grey_medium(double albedo, double eta, double g = 0) {
  Subsurface s;
  s.eta = Float(eta);
  DielectricBxDF b;
  b.eta = Float(eta);
  s.boundary = b;
  s.medium.sigma_s = Color(Float(albedo));
  s.medium.sigma_a = Color(Float(1 - albedo));
  s.medium.g = Float(g);
  return s;
}

// η = 1, g = 0: the albedo of a half-space for light incident along μ0 is
// 1 − H(μ0) √(1 − ϖ) (Chandrasekhar 1960, ch. V; the plane albedo). One chromatic medium
// holds the three albedos, each channel with its own σt, so the spectral MIS of the walk
// (distances drawn with one channel's σt, weighted for all) is tested too: Rd does not
// depend on σt, only on ϖ.
TEST(SubsurfaceWalk, IndexMatchedHalfSpaceMatchesHFunction) {
  const double albedo[3] = {0.5, 0.9, 0.99}, sigma_t[3] = {1, 2, 0.5};
  Subsurface s = grey_medium(0.5, 1.0);
  for (int c = 0; c < 3; ++c) {
    s.medium.sigma_s[c] = Float(albedo[c] * sigma_t[c]);
    s.medium.sigma_a[c] = Float((1 - albedo[c]) * sigma_t[c]);
  }
  const SlabResult r = slab_random_walk(s, test::scaled(200000, 20000), 7, 2);
  for (int c = 0; c < 3; ++c) {
    const double expected = 1 - chandrasekhar_h(albedo[c], 1.0) * std::sqrt(1 - albedo[c]);
    EXPECT_GT(r.stderr_[c], 0);
    EXPECT_NEAR(r.Rd[c], expected, 3 * r.stderr_[c]) << "albedo " << albedo[c];
  }
}

// Near and at ϖ = 1 the walks grow long (a conservative half-space returns a path after n
// events with probability ~ n^{−3/2}): the 0.6 % of paths still inside after kMaxWalkSteps
// are counted by their escape probability (DipoleEscape). The H-function holds at every ϖ;
// at ϖ = 1 every path comes back, and with equal channels its weight stays exactly 1.
TEST(SubsurfaceWalk, ConservativeHalfSpaceReturnsEverything) {
  const double albedo[3] = {1, 0.99999, 0.9999};
  Subsurface s = grey_medium(1, 1.0);
  for (int c = 0; c < 3; ++c) {
    s.medium.sigma_s[c] = Float(albedo[c]);
    s.medium.sigma_a[c] = Float(1 - albedo[c]);
  }
  const SlabResult r = slab_random_walk(s, test::scaled(100000, 20000), 11, 2);
  for (int c = 0; c < 3; ++c) {
    const double expected = 1 - chandrasekhar_h(albedo[c], 1.0) * std::sqrt(1 - albedo[c]);
    EXPECT_NEAR(r.Rd[c], expected, 4 * r.stderr_[c] + 2e-5) << "albedo " << albedo[c];
  }
  const SlabResult grey = slab_random_walk(grey_medium(1, 1.0), test::scaled(20000, 8192), 12, 2);
  EXPECT_EQ(grey.Rd, Color(1));
  // With a boundary, all of the light that enters, 1 − F(0) (Hecht's normal incidence).
  const double eta = 1.5, f0 = (eta - 1) * (eta - 1) / ((eta + 1) * (eta + 1));
  const SlabResult glass = slab_random_walk(grey_medium(1, eta), test::scaled(20000, 8192), 13, 2);
  EXPECT_NEAR(glass.Rd[0], 1 - f0, 4 * glass.stderr_[0]);
}

// Blocks have their own streams and are summed in order: the same bits for 1 and 3
// threads (and another seed gives another estimate).
TEST(SubsurfaceWalk, SlabEstimateDoesNotDependOnTheThreadCount) {
  const Subsurface s = grey_medium(0.7, 1.33, 0.3);
  const std::uint64_t n = 3 * kSlabBlock + 17;
  const SlabResult a = slab_random_walk(s, n, 9, 1), b = slab_random_walk(s, n, 9, 3);
  EXPECT_EQ(a.Rd, b.Rd);
  EXPECT_EQ(a.stderr_, b.stderr_);
  ASSERT_EQ(a.profile.size(), b.profile.size());
  for (size_t i = 0; i < a.profile.size(); ++i) EXPECT_EQ(a.profile[i].value, b.profile[i].value) << i;
  EXPECT_NE(slab_random_walk(s, n, 10, 1).Rd, a.Rd);
}

// --- An analog Monte Carlo written here from the papers --------------------------------
// Photons in double precision: exponential free flights (σt = 1), absorption with
// probability 1 − ϖ at each collision, HG directions by rejection from the phase
// function itself (Henyey & Greenstein 1941, eq. 3: no inverse CDF), and at the surface
// the Fresnel reflectance in its angle form (Hecht, Optics, eqs. 4.42–4.43:
// Rs = sin²(θi − θt)/sin²(θi + θt), Rp = tan²(θi − θt)/tan²(θi + θt)) deciding reflection.

struct D3 {
  double x, y, z;
};

double fresnel_angle_form(double cos_i, double n_i, double n_t) {
  const double sin_i = std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
  const double sin_t = n_i / n_t * sin_i;
  if (sin_t >= 1) return 1;
  if (sin_i < 1e-9) return std::pow((n_i - n_t) / (n_i + n_t), 2);  // normal incidence
  const double ti = std::asin(sin_i), tt = std::asin(sin_t);
  const double rs = std::pow(std::sin(ti - tt) / std::sin(ti + tt), 2);
  const double rp = std::pow(std::tan(ti - tt) / std::tan(ti + tt), 2);
  return (rs + rp) / 2;
}

// A direction at angle acos(mu) from d, azimuth phi (any perpendicular pair).
D3 rotate(const D3& d, double mu, double phi) {
  const D3 a = std::abs(d.x) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0};
  D3 u{a.y * d.z - a.z * d.y, a.z * d.x - a.x * d.z, a.x * d.y - a.y * d.x};
  const double lu = std::sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
  u = {u.x / lu, u.y / lu, u.z / lu};
  const D3 v{d.y * u.z - d.z * u.y, d.z * u.x - d.x * u.z, d.x * u.y - d.y * u.x};
  const double st = std::sqrt(std::max(0.0, 1 - mu * mu));
  return {st * (std::cos(phi) * u.x + std::sin(phi) * v.x) + mu * d.x,
          st * (std::cos(phi) * u.y + std::sin(phi) * v.y) + mu * d.y,
          st * (std::cos(phi) * u.z + std::sin(phi) * v.z) + mu * d.z};
}

// Rd of the half-space for normal incidence: fraction of incident photons that leave.
std::pair<double, double> analog_slab_rd(double albedo, double g, double eta, std::uint64_t n, std::uint64_t seed) {
  Pcg32 rng(seed, 99);
  const double pmax = (1 - g * g) / (2 * std::pow(1 - std::abs(g), 3));  // p(μ) at μ = ±1
  double sum = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    if (rng.next_double() < fresnel_angle_form(1, 1, eta)) continue;  // first-surface reflection
    D3 p{0, 0, 0}, d{0, 0, -1};
    for (int events = 0; events < 100000; ++events) {
      const double t = -std::log(1 - rng.next_double());
      if (d.z > 0 && p.z + t * d.z >= 0) {  // reaches the surface
        const double s = -p.z / d.z;
        p = {p.x + s * d.x, p.y + s * d.y, 0};
        if (rng.next_double() >= fresnel_angle_form(d.z, eta, 1)) {
          sum += 1;
          break;
        }
        d.z = -d.z;  // mirror reflection back inside
        continue;
      }
      p = {p.x + t * d.x, p.y + t * d.y, p.z + t * d.z};
      if (rng.next_double() >= albedo) break;  // absorbed
      double mu = 0;
      for (;;) {
        mu = 2 * rng.next_double() - 1;
        const double pdf = (1 - g * g) / (2 * std::pow(1 + g * g - 2 * g * mu, 1.5));
        if (rng.next_double() * pmax < pdf) break;
      }
      d = rotate(d, mu, 2 * kPiD * rng.next_double());
    }
  }
  const double mean = sum / double(n);
  return {mean, std::sqrt(mean * (1 - mean) / double(n - 1))};
}

// g ≠ 0 and η = 1.33 (Fresnel entry loss, internal and total internal reflection).
TEST(SubsurfaceWalk, AnisotropicMismatchedSlabMatchesAnalogMonteCarlo) {
  struct Case {
    double albedo, g, eta;
  };
  for (const Case c : {Case{0.9, 0.5, 1.33}, Case{0.95, -0.3, 1.0}, Case{0.8, 0.0, 1.5}}) {
    const std::uint64_t n = test::scaled(60000, 8000);
    const auto [ref, ref_se] = analog_slab_rd(c.albedo, c.g, c.eta, n, 11);
    const SlabResult r = slab_random_walk(grey_medium(c.albedo, c.eta, c.g), n, 5, 2);
    const double tol = 3 * std::sqrt(ref_se * ref_se + double(r.stderr_[0]) * r.stderr_[0]);
    EXPECT_NEAR(r.Rd[0], ref, tol) << "albedo " << c.albedo << " g " << c.g << " eta " << c.eta;
  }
}

// σs = 0: what crosses a slab of thickness L along cos θ is e^{−σa L / cos θ} per
// channel (Beer–Lambert), through walk_to_boundary with a two-plane boundary.
struct TwoPlanes {
  struct Hit {
    Float t = 0;
    bool bottom = false;
  };
  Float depth = 1;  // the slab is −depth ≤ z ≤ 0
  bool nearest(const Vec3& o, const Vec3& d, Hit& hit) const {
    if (d.z > 0) {
      hit = {-o.z / d.z, false};
      return true;
    }
    if (d.z < 0) {
      hit = {(-depth - o.z) / d.z, true};
      return true;
    }
    return false;
  }
};

TEST(SubsurfaceWalk, AbsorbingSlabFollowsBeerLambert) {
  Medium m;
  m.sigma_s = Color(0);
  m.sigma_a = Color(0.5f, 1.0f, 2.0f);
  const TwoPlanes slab{1.5f};
  for (double cos_theta : {1.0, 0.6}) {
    const Vec3 d = normalize(Vec3{Float(std::sqrt(1 - cos_theta * cos_theta)), 0, Float(-cos_theta)});
    Pcg32 rng(3, 4);
    const std::uint64_t n = test::scaled(100000, 10000);
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    for (std::uint64_t i = 0; i < n; ++i) {
      Color beta(1);
      TwoPlanes::Hit hit;
      if (!walk_to_boundary(m, slab, Vec3{0, 0, 0}, d, beta, rng, hit)) continue;
      ASSERT_TRUE(hit.bottom);
      ASSERT_NEAR(hit.t, 1.5 / cos_theta, 1e-5);
      for (int c = 0; c < 3; ++c) {
        sum[c] += beta[c];
        sum2[c] += double(beta[c]) * beta[c];
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / double(n), se = std::sqrt((sum2[c] / double(n) - mean * mean) / double(n - 1));
      const double expected = std::exp(-double(m.sigma_a[c]) * 1.5 / cos_theta);
      EXPECT_NEAR(mean, expected, 3 * se + 1e-6) << "channel " << c << " cos " << cos_theta;
    }
  }
}

// Without absorption a scattering event and a boundary crossing each weigh exactly 1 in
// every channel (σs e^{−σt t} / (σt e^{−σt t}) and e^{−σt t} / e^{−σt t}), whatever the
// rounding of the channel probabilities β_k / Σ β: a returned weight of 1 − 6e-8 or a path
// dropped by Russian roulette (which only a weight below 1 calls) is rounding bias.
TEST(SubsurfaceWalk, ConservativeWeightsStayExactlyOne) {
  const Medium m = grey_medium(1, 1.0).medium;
  const TwoPlanes slab{2.0f};
  Pcg32 rng(6, 1);
  for (int i = 0; i < 20000; ++i) {
    Color beta(1);
    TwoPlanes::Hit hit;
    ASSERT_TRUE(walk_to_boundary(m, slab, Vec3{0, 0, -1}, Vec3{0, 0, -1}, beta, rng, hit)) << "path " << i;
    ASSERT_EQ(beta, Color(1)) << "path " << i;
  }
}

// DipoleEscape against the walk itself: the share of an isotropic point source at depth z
// in an index-matched half-space that reaches the surface, at ϖ = 0.999 (the tail is for
// ϖ ≥ 0.9999, where ϖ^65536 is not negligible). Diffusion holds deep down: its decay
// σtr = √(σa/D) is within 0.1 % of the transport eigenvalue there, and it was measured
// 0.7 % and 1.1 % above the walk at depths 8 and 20 (10 % at ϖ = 0.99, depth 20, where
// the tail never serves). At σa = 0 it is 1 at any depth.
TEST(SubsurfaceWalk, DipoleEscapeMatchesPointSourcesDeepInside) {
  for (const double eta : {1.0, 1.33, 1.5})
    for (const Float depth : {0.0f, 30.0f, 1e4f}) EXPECT_EQ(DipoleEscape(grey_medium(1, eta).medium, Float(eta))(depth), Color(1));
  {
    const double albedo = 0.999;
    const Medium m = grey_medium(albedo, 1.0).medium;
    const DipoleEscape escape(m, 1);
    const TwoPlanes half_space{1e30f};  // a bottom no walk reaches
    for (const double depth : {8.0, 20.0}) {
      Pcg32 rng(5, std::uint64_t(depth));
      const std::uint64_t n = test::scaled(40000, 10000);
      double sum = 0, sum2 = 0;
      for (std::uint64_t i = 0; i < n; ++i) {
        const Float u = 2 * rng.next_float() - 1, phi = Float(2 * kPiD) * rng.next_float();
        const Float r = std::sqrt(std::max(Float(0), 1 - u * u));
        Color beta(1);
        TwoPlanes::Hit hit;
        if (!walk_to_boundary(m, half_space, Vec3{0, 0, Float(-depth)}, Vec3{r * std::cos(phi), r * std::sin(phi), u},
                              beta, rng, hit))
          continue;
        sum += beta[0];
        sum2 += double(beta[0]) * beta[0];
      }
      const double mean = sum / double(n), se = std::sqrt((sum2 / double(n) - mean * mean) / double(n - 1));
      EXPECT_NEAR(escape(Float(depth))[0], mean, 0.03 * mean + 4 * se) << "albedo " << albedo << " depth " << depth;
    }
  }
}

}  // namespace
}  // namespace gonio
