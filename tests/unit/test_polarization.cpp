// Polarization (issue 15): the complex Fresnel amplitudes against gonio's scalar Fresnel
// and the test's own Born & Wolf formulas, Brewster's angle, the retardance of total
// internal reflection against its closed form, Cloude's realizability criterion for every
// Mueller matrix gonio makes, the unpolarized value as M00 for 10⁶ random cases,
// reciprocity in Mueller form, and two mirror reflections in perpendicular planes against
// the hand-multiplied product with the frame rotation.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

#include "gonio/fresnel_amplitudes.h"
#include "gonio/material.h"
#include "gonio/math/frame.h"
#include "gonio/math/warp.h"
#include "gonio/polarization/interface.h"
#include "gonio/polarization/polarized_bxdf.h"
#include "gonio/rng.h"
#include "gonio/spectral_material.h"
#include "test_scale.h"

namespace {

using namespace gonio;
using cx = std::complex<double>;
using M4 = std::array<std::array<double, 4>, 4>;

// --- The test's own Fresnel (Born & Wolf, Principles of Optics, §1.5.2 eqs. 20–21, in
// cos form; complex index for a conductor, §14.2; p along k × s for every wave) ---------
struct Amp {
  cx rs, rp;
};
Amp bw_fresnel(double cos_i, cx n) {
  const double sin2 = 1 - cos_i * cos_i;
  // cos θt = sqrt(1 − sin²θi / n²), principal root; for a real index under total internal
  // reflection the root with Im > 0, whose transmitted wave decays away from the interface
  // under e^{−iωt} (the imaginary part's zero is made +0 so that std::sqrt picks it).
  cx z = 1.0 - sin2 / (n * n);
  if (z.imag() == 0) z = cx(z.real(), 0.0);
  const cx cos_t = std::sqrt(z);
  return {(cos_i - n * cos_t) / (cos_i + n * cos_t), (n * cos_i - cos_t) / (n * cos_i + cos_t)};
}
// Mueller matrix of Jones diag(a, b) with S = (|Es|²+|Ep|², |Es|²−|Ep|², 2Re(Es Ep*), 2Im(Es Ep*)),
// written out from that definition.
M4 jones_diag_mueller(cx a, cx b) {
  const double A = (std::norm(a) + std::norm(b)) / 2, B = (std::norm(a) - std::norm(b)) / 2;
  const cx z = a * std::conj(b);
  return {{{A, B, 0, 0}, {B, A, 0, 0}, {0, 0, z.real(), -z.imag()}, {0, 0, z.imag(), z.real()}}};
}
M4 mul(const M4& a, const M4& b) {
  M4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}
template <typename T>
M4 to_m4(const MuellerT<T>& m) {
  M4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i][j] = double(m(i, j));
  return r;
}
template <typename C>
M4 channel(const MuellerT<C>& m, int ch) {
  M4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i][j] = double(m(i, j)[ch]);
  return r;
}
double max_abs_diff(const M4& a, const M4& b) {
  double e = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) e = std::max(e, std::abs(a[i][j] - b[i][j]));
  return e;
}

// --- Cloude's criterion (Cloude 1986, "Group theory and polarisation algebra", Optik 75):
// M is physically realizable (a sum of pure Jones systems) iff its coherency matrix is
// positive semidefinite. With c = (Es Es*, Es Ep*, Ep Es*, Ep Ep*) the Stokes vector is
// S = A c, A = [[1,0,0,1],[1,0,0,−1],[0,1,1,0],[0,−i,i,0]] (from the definition above); for
// a Jones matrix J, N = A⁻¹ M A = J ⊗ J*, N[(ab),(cd)] = J_ac J*_bd, whose realignment
// H[(ac),(bd)] = N[(ab),(cd)] = vec(J) vec(J)^H is PSD, and so is any sum of them. ---
using C4 = std::array<std::array<cx, 4>, 4>;
C4 coherency(const M4& m) {
  const cx i(0, 1);
  const C4 A = {{{1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0}, {0, -i, i, 0}}};
  // A⁻¹ (A A⁻¹ = 1, checked by hand): rows (c0, c1, c2, c3) from (S0..S3).
  const C4 Ainv = {{{0.5, 0.5, 0, 0}, {0, 0, 0.5, 0.5 * i}, {0, 0, 0.5, -0.5 * i}, {0.5, -0.5, 0, 0}}};
  C4 t{}, n{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k) t[r][c] += m[r][k] * A[k][c];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k) n[r][c] += Ainv[r][k] * t[k][c];
  C4 h{};
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) h[2 * a + c][2 * b + d] = n[2 * a + b][2 * c + d];
  return h;
}
// Smallest eigenvalue of a Hermitian 4×4 matrix, through its real symmetric 8×8 form
// [[Re, −Im], [Im, Re]] (each eigenvalue twice) and cyclic Jacobi rotations.
double min_eigenvalue(const C4& h) {
  double a[8][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      a[r][c] = a[r + 4][c + 4] = h[r][c].real();
      a[r][c + 4] = -h[r][c].imag();
      a[r + 4][c] = h[r][c].imag();
    }
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0;
    for (int p = 0; p < 8; ++p)
      for (int q = p + 1; q < 8; ++q) off += a[p][q] * a[p][q];
    if (off < 1e-30) break;
    for (int p = 0; p < 8; ++p)
      for (int q = p + 1; q < 8; ++q) {
        if (std::abs(a[p][q]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 8; ++k) {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 8; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
      }
  }
  double m = a[0][0];
  for (int k = 1; k < 8; ++k) m = std::min(m, a[k][k]);
  return m;
}
// Realizable within rounding: λ_min ≥ −tol · M00 (the trace of H is M00).
bool realizable(const M4& m, double tol = 1e-5) {
  return min_eigenvalue(coherency(m)) >= -tol * std::max(std::abs(m[0][0]), 1e-30);
}

TEST(Polarization, CloudeCriterionSeparatesRealizableMatrices) {
  // Realizable: identity, a depolarizer, an ideal polarizer, a mirror's diag(1, 1, −1, −1).
  M4 id{}, dep{}, mirror{};
  for (int k = 0; k < 4; ++k) id[k][k] = 1, mirror[k][k] = k < 2 ? 1 : -1;
  dep[0][0] = 1;
  EXPECT_TRUE(realizable(id));
  EXPECT_TRUE(realizable(dep));
  EXPECT_TRUE(realizable(mirror));
  EXPECT_TRUE(realizable(to_m4(mueller_linear_polarizer(0.3))));
  EXPECT_TRUE(realizable(to_m4(mueller_retarder(0.4, 1.1))));
  // Not realizable: diag(1, 1, 1, −1) (a handedness flip without the mirror's U flip) and a
  // diattenuation beyond 1.
  M4 bad = id;
  bad[3][3] = -1;
  EXPECT_FALSE(realizable(bad));
  M4 over{};
  over[0][0] = over[1][1] = 1;
  over[0][1] = over[1][0] = 1.2;
  EXPECT_FALSE(realizable(over));
}

// --- Amplitudes ---------------------------------------------------------------------

TEST(Polarization, AmplitudeReflectancesEqualScalarFresnel) {
  // |r_s|², |r_p|² of the complex amplitudes against fresnel.h's scalar reflectances, and
  // the amplitudes against the test's own formula, over 10⁶ random cases: dielectrics from
  // either side (total internal reflection included), conductors.
  std::mt19937_64 gen(15);
  std::uniform_real_distribution<double> u(0, 1);
  const std::uint64_t n = gonio::test::scaled(1'000'000, 20'000);
  double worst_r = 0, worst_amp = 0;
  std::string worst_case;
  for (std::uint64_t i = 0; i < n; ++i) {
    const double cos_i = (i % 3 == 2 ? 1 : (u(gen) < 0.5 ? -1 : 1)) * u(gen);
    const bool conductor = i % 3 == 2;
    const double eta = std::exp((u(gen) - 0.5) * 4);  // 0.14 .. 7.4
    const double k = conductor ? 8 * u(gen) : 0;
    const auto a = conductor ? fresnel_conductor_amplitudes(cos_i, eta, k) : fresnel_dielectric_amplitudes(cos_i, eta);
    const auto t = conductor ? fresnel_conductor_terms(cos_i, eta, k) : fresnel_dielectric_terms(cos_i, eta);
    worst_r = std::max({worst_r, std::abs(std::norm(a.rs) - t.rs), std::abs(std::norm(a.rp) - t.rp)});
    // The test's formula, from the side the light arrives at.
    const double c = std::abs(cos_i);
    const cx index = conductor ? cx(eta, k) : cx(cos_i < 0 ? 1 / eta : eta, 0);
    if (c > 1e-6) {
      const Amp b = bw_fresnel(c, index);
      const double e = std::max(std::abs(a.rs - b.rs), std::abs(a.rp - b.rp));
      if (e > worst_amp) {
        worst_amp = e;
        worst_case = "cos_i " + std::to_string(cos_i) + " eta " + std::to_string(eta) + " k " + std::to_string(k);
      }
    }
  }
  EXPECT_LT(worst_r, 1e-12);
  EXPECT_LT(worst_amp, 1e-9) << worst_case;
}

TEST(Polarization, DielectricTransmissionAmplitudesConserveEnergy) {
  // T_s = n_t cos θt / (n_i cos θi) |t_s|² = 1 − R_s, and likewise for p (Hecht eq. 4.64).
  for (double eta : {1.5, 0.7, 2.4})
    for (double th = 0; th < 89.9; th += 7.3) {
      const auto a = fresnel_dielectric_amplitudes(std::cos(th * kPiD / 180), eta);
      if (a.tir) continue;
      EXPECT_NEAR(a.t_factor * std::norm(a.ts), 1 - a.Rs, 1e-12);
      EXPECT_NEAR(a.t_factor * std::norm(a.tp), 1 - a.Rp, 1e-12);
    }
}

TEST(Polarization, BrewsterReflectionIsPurelyS) {
  // At tan θB = η, r_p = 0: unpolarized light reflects fully polarized, along s
  // (Q = +I in gonio's convention, SPEC §1).
  const double eta = 1.5, theta = std::atan(eta);
  const auto m = dielectric_reflection_mueller(std::cos(theta), eta);
  const auto s = m.apply({1, 0, 0, 0});
  const double dop = std::sqrt(s[1] * s[1] + s[2] * s[2] + s[3] * s[3]) / s[0];
  EXPECT_NEAR(dop, 1, 1e-12);
  EXPECT_NEAR(s[1] / s[0], 1, 1e-12);
  // Away from Brewster's angle it is partial.
  const auto s40 = dielectric_reflection_mueller(std::cos(40 * kPiD / 180), eta).apply({1, 0, 0, 0});
  EXPECT_LT(s40[1] / s40[0], 0.95);
}

TEST(Polarization, TotalInternalReflectionRetardanceMatchesClosedForm) {
  // Glass to air, n = 1/1.5: beyond the critical angle |r_s| = |r_p| = 1 and the phase
  // difference δ = φ_s − φ_p obeys tan(δ/2) = cos θ √(sin²θ − n²) / sin²θ (Born & Wolf
  // §1.5.4, eq. 60). In the Mueller matrix M22 = cos δ, M32 = sin δ.
  const double n = 1 / 1.5;
  const double crit = std::asin(n);
  int count = 0;
  for (double th = crit + 1e-4; th < kPiD / 2; th += 0.01) {
    const auto m = dielectric_reflection_mueller(std::cos(th), n);
    const double delta = std::atan2(m(3, 2), m(2, 2));
    const double s2 = std::sin(th) * std::sin(th);
    const double expected = std::cos(th) * std::sqrt(s2 - n * n) / s2;
    EXPECT_NEAR(std::tan(delta / 2), expected, 1e-9) << "theta " << th;
    EXPECT_NEAR(m(0, 0), 1, 1e-15);
    EXPECT_NEAR(m(0, 1), 0, 1e-15);
    ++count;
  }
  EXPECT_GT(count, 30);
  // Fresnel's rhomb: in glass of n = 1.51 two reflections at 54.6° give δ ≈ 90° in all, 45°
  // each (Born & Wolf §1.5.4).
  const auto m = dielectric_reflection_mueller(std::cos(54.6 * kPiD / 180), 1 / 1.51);
  EXPECT_NEAR(std::atan2(m(3, 2), m(2, 2)) * 180 / kPiD, 45, 0.3);
}

TEST(Polarization, InterfaceMatricesAreRealizableAndMatchTheJonesForm) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(0, 1);
  const std::uint64_t n = gonio::test::scaled(20'000, 2'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const double c = u(gen), eta = std::exp((u(gen) - 0.5) * 4), k = 5 * u(gen);
    const auto r = to_m4(dielectric_reflection_mueller(c, eta));
    const auto t = to_m4(dielectric_transmission_mueller(c, eta));
    const auto m = to_m4(mueller_reflection(fresnel_conductor_amplitudes(c, eta, k)));
    ASSERT_TRUE(realizable(r)) << c << " " << eta;
    ASSERT_TRUE(realizable(t)) << c << " " << eta;
    ASSERT_TRUE(realizable(m)) << c << " " << eta << " " << k;
    const Amp b = bw_fresnel(c, cx(eta, k));
    ASSERT_LT(max_abs_diff(m, jones_diag_mueller(b.rs, b.rp)), 1e-9);
    // Reflected plus transmitted power, per polarization, is the incident power.
    ASSERT_NEAR(r[0][0] + t[0][0], 1, 1e-12);
    ASSERT_NEAR(r[0][1] + t[0][1], 0, 1e-12);
  }
}

TEST(Polarization, RotationPolarizerRetarder) {
  // Turning a frame by π changes nothing; by α then β is by α + β.
  EXPECT_LT(max_abs_diff(to_m4(mueller_rotation(kPiD)), to_m4(mueller_rotation(0.0))), 1e-12);
  EXPECT_LT(max_abs_diff(to_m4(mueller_rotation(0.3) * mueller_rotation(0.5)), to_m4(mueller_rotation(0.8))), 1e-12);
  // Malus's law: s-polarized light through a polarizer at θ keeps cos²θ.
  for (double th : {0.0, 0.4, 1.0, kPiD / 2}) {
    const auto s = mueller_linear_polarizer(th).apply({1, 1, 0, 0});
    EXPECT_NEAR(s[0], std::cos(th) * std::cos(th), 1e-12);
  }
  // A quarter-wave plate with its fast axis at 45° turns s-linear light circular, V = +1
  // (right-handed in Born & Wolf's sense for the slow component delayed by +90°).
  const auto q = mueller_retarder(kPiD / 4, kPiD / 2).apply({1, 1, 0, 0});
  EXPECT_NEAR(q[0], 1, 1e-12);
  EXPECT_NEAR(q[1], 0, 1e-12);
  EXPECT_NEAR(q[2], 0, 1e-12);
  EXPECT_NEAR(q[3], 1, 1e-12);
  // A half-wave plate at θ turns s-linear light to linear at 2θ.
  const auto h = mueller_retarder(0.3, kPiD).apply({1, 1, 0, 0});
  EXPECT_NEAR(h[1], std::cos(1.2), 1e-12);
  EXPECT_NEAR(h[2], std::sin(1.2), 1e-12);
}

// --- Polarized BSDFs ------------------------------------------------------------------

const std::vector<std::string>& polarizing_materials() {
  static const std::vector<std::string> m = {
      R"({"type":"conductor","material":"Au"})",
      R"({"type":"conductor","fresnel":"schlick","f0":[0.9,0.6,0.3]})",
      R"({"type":"dielectric","eta":1.5})",
      R"({"type":"dielectric","eta":0.7})",
      R"({"type":"thindielectric","eta":1.5})",
      R"({"type":"thindielectric","eta":0.6})",
      R"({"type":"thindielectric","thin_film":{"thickness":400,"eta":1.33}})",
      R"({"type":"dielectric","eta":1.5,"thin_film":{"thickness":300,"eta":1.9}})",
      R"({"type":"conductor","material":"Au","thin_film":{"thickness":250,"eta":1.5}})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":1.5,"thin_film":{"thickness":500,"eta":1.38}})",
      R"({"type":"roughconductor","alpha":0.3,"material":"Cu","thin_film":{"thickness":150,"eta":2}})",
      R"({"type":"roughconductor","alpha":0.3,"material":"Cu"})",
      R"({"type":"roughconductor","alpha":0.4,"eta":[0.2,0.9,1.1],"k":[3,2.5,2],"multiscatter":true})",
      R"({"type":"roughconductor","alpha":[0.1,0.5],"material":"Ag"})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":1.5})",
      R"({"type":"roughdielectric","alpha":0.6,"eta":0.8,"distribution":"beckmann"})",
      R"({"type":"plastic","eta":1.5,"reflectance":[0.2,0.5,0.8]})",
      R"({"type":"plastic","eta":1.6,"reflectance":0.5,"alpha":0.2})",
      R"({"type":"diffuse","reflectance":0.4})",
  };
  return m;
}

Vec3 random_direction(Pcg32& rng) { return square_to_uniform_sphere(rng.next_float(), rng.next_float()); }

TEST(Polarization, M00IsTheUnpolarizedValueExactly) {
  // 10⁶ random evaluations and samples over the models: M00 of eval equals f bit for bit,
  // the pdf too; samples give the same wi, pdf and M00 = weight.
  const std::uint64_t total = gonio::test::scaled(1'000'000, 20'000);
  const auto& mats = polarizing_materials();
  const std::uint64_t per = total / (2 * mats.size()) + 1;
  for (const auto& text : mats) {
    const BxDF b = parse_material(text);
    const PolarizedBxDF p(b);
    EXPECT_EQ(p.polarizing(), b.name() != "diffuse") << text;
    Pcg32 rng(3, 5);
    std::uint64_t mismatches = 0, nonzero = 0;
    for (std::uint64_t i = 0; i < per; ++i) {
      const Vec3 wo = random_direction(rng);
      Vec3 wi = random_direction(rng);
      const auto mode = (i & 2) ? TransportMode::Importance : TransportMode::Radiance;
      if (i & 1)
        if (auto s = b.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), mode); s && !s->delta) wi = s->wi;
      const auto e = b.eval(wo, wi, mode);
      const auto pe = p.eval(wo, wi, mode);
      if (!(pe.f.m00() == e.f) || pe.pdf != e.pdf) ++mismatches;
      if (!e.f.is_black()) ++nonzero;
      const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
      const auto s = b.sample(wo, u0, u1, u2, mode);
      const auto ps = p.sample(wo, u0, u1, u2, mode);
      if (bool(s) != bool(ps)) {
        ++mismatches;
      } else if (s) {
        if (!(ps->weight.m00() == s->weight) || ps->pdf != s->pdf || ps->wi.x != s->wi.x || ps->wi.y != s->wi.y ||
            ps->wi.z != s->wi.z || ps->delta != s->delta || ps->lobe != s->lobe)
          ++mismatches;
      }
    }
    EXPECT_EQ(mismatches, 0u) << text;
    if (!is_delta_only(b.flags())) {
      EXPECT_GT(nonzero, per / 10) << text;
    }
  }
}

// Grazing and tangent directions, down to the smallest subnormal cosine, above and below:
// every entry of every matrix finite (a shape whose M00 underflows must not give an
// infinite scale), M00 still the unpolarized value.
TEST(Polarization, TinyCosinesGiveFiniteMatrices) {
  const float tiny[] = {1e-45f, 1e-40f, 1e-38f, 1e-30f, 1e-20f, 1e-8f, 0.0f};
  std::vector<Vec3> dirs;
  for (float z : tiny)
    for (float sign : {1.0f, -1.0f})
      for (float phi : {0.0f, 0.7f, 2.0f, 4.1f}) {
        const float r = std::sqrt(1 - z * z);
        dirs.push_back({r * std::cos(phi), r * std::sin(phi), sign * z});
      }
  dirs.push_back({0, 0, 1});
  dirs.push_back({0.6f, 0, 0.8f});
  dirs.push_back({0, -0.6f, -0.8f});
  for (const auto& text : polarizing_materials()) {
    const BxDF b = parse_material(text);
    const PolarizedBxDF p(b);
    std::uint64_t bad = 0;
    for (const Vec3& wo : dirs)
      for (const Vec3& wi : dirs)
        for (const auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
          const auto pe = p.eval(wo, wi, mode);
          if (!pe.f.is_finite() || !std::isfinite(pe.pdf) || !(pe.f.m00() == b.eval(wo, wi, mode).f)) ++bad;
        }
    for (const Vec3& wo : dirs)
      for (float u : {0.0f, 0.3f, 0.999999f})
        if (const auto s = p.sample(wo, u, u, 1 - u)) {
          if (!s->weight.is_finite()) ++bad;
        }
    EXPECT_EQ(bad, 0u) << text;
  }
}

TEST(Polarization, EveryBsdfMuellerMatrixIsRealizable) {
  // Cloude's criterion for eval values and sample weights of every model, every channel.
  const std::uint64_t per = gonio::test::scaled(1'500, 300);
  for (const auto& text : polarizing_materials()) {
    const BxDF b = parse_material(text);
    const PolarizedBxDF p(b);
    Pcg32 rng(11, 2);
    double worst = 0;
    std::string worst_case;
    std::uint64_t polarized = 0;
    for (std::uint64_t i = 0; i < per; ++i) {
      const Vec3 wo = random_direction(rng);
      std::vector<MuellerT<Color>> ms;
      if (auto s = p.sample(wo, rng.next_float(), rng.next_float(), rng.next_float())) {
        ms.push_back(s->weight);
        ms.push_back(p.eval(wo, s->wi).f);
      }
      ms.push_back(p.eval(wo, random_direction(rng)).f);
      for (const auto& m : ms)
        for (int ch = 0; ch < 3; ++ch) {
          const M4 c = channel(m, ch);
          if (!(c[0][0] > 0)) continue;
          const double ev = min_eigenvalue(coherency(c)) / c[0][0];
          if (ev < worst) {
            worst = ev;
            std::string d;
            for (int x = 0; x < 4; ++x)
              for (int y = 0; y < 4; ++y) d += std::to_string(c[x][y] / c[0][0]) + (y == 3 ? "\n" : " ");
            worst_case = "wo " + std::to_string(wo.x) + " " + std::to_string(wo.y) + " " + std::to_string(wo.z) + "\n" + d;
          }
          if (std::abs(c[0][1]) + std::abs(c[2][2] - c[0][0]) > 1e-3 * c[0][0]) ++polarized;
        }
    }
    EXPECT_GT(worst, -1e-5) << text << "\n" << worst_case;
    if (p.polarizing()) {
      EXPECT_GT(polarized, 0u) << text;
    }
  }
}

TEST(Polarization, MuellerReciprocity) {
  // M(wo, wi)/n_wo² = Q M(wi, wo)ᵀ Q / n_wi², Q = diag(1, 1, −1, 1) (radiance mode; the
  // scalar form is SPEC §1's).
  const std::uint64_t per = gonio::test::scaled(20'000, 2'000);
  for (const auto& text : polarizing_materials()) {
    const BxDF b = parse_material(text);
    if (is_delta_only(b.flags())) continue;
    const PolarizedBxDF p(b);
    const Float eta = b.relative_eta();
    Pcg32 rng(5, 9);
    double worst = 0;
    for (std::uint64_t i = 0; i < per; ++i) {
      const Vec3 wo = random_direction(rng);
      Vec3 wi = random_direction(rng);
      if (i & 1)
        if (auto s = b.sample(wo, rng.next_float(), rng.next_float(), rng.next_float()); s && !s->delta) wi = s->wi;
      const double no = wo.z > 0 ? 1 : eta, ni = wi.z > 0 ? 1 : eta;
      const auto a = p.eval(wo, wi).f, r = p.eval(wi, wo).f;
      for (int ch = 0; ch < 3; ++ch) {
        const M4 ma = channel(a, ch), mr = channel(r, ch);
        const double scale = std::max(ma[0][0], 1e-6);
        for (int x = 0; x < 4; ++x)
          for (int y = 0; y < 4; ++y) {
            const double q = (x == 2 ? -1 : 1) * (y == 2 ? -1 : 1);
            worst = std::max(worst, std::abs(ma[x][y] / (no * no) - q * mr[y][x] / (ni * ni)) / (scale / (no * no)));
          }
      }
    }
    EXPECT_LT(worst, 2e-3) << text;
  }
}

TEST(Polarization, TwoMirrorsInPerpendicularPlanesMatchTheHandProduct) {
  // A gold mirror (one channel's index) reflects a beam at θ1 in the xz plane; a second
  // mirror, tilted so that its plane of incidence is perpendicular to the first, reflects
  // it at θ2. gonio's two Mueller matrices, each in its mirror's local frames, chained
  // through the turn between the frames the beam has after the first and before the second
  // (computed here from the frame convention, s = ẑ × w / |ẑ × w| in each local frame),
  // must equal M_F(θ2) R(90°) M_F(θ1) with the test's own Fresnel and R(90°) =
  // diag(1, −1, −1, 1) (a quarter turn of the frame; its sign does not matter).
  const double eta = 0.27, k = 2.78;  // about gold at 600 nm
  const BxDF mirror = parse_material(R"({"type":"conductor","eta":0.27,"k":2.78})");
  const PolarizedBxDF pol(mirror);
  const double th1 = 50 * kPiD / 180, th2 = 30 * kPiD / 180;
  const Vec3 z{0, 0, 1};
  auto s_axis = [&](const Vec3& w) { return normalize(cross(z, w)); };
  // First reflection (mirror 1's local frame = world): incident along d0, out along d1.
  const Vec3 d1{Float(std::sin(th1)), 0, Float(std::cos(th1))};
  const auto s1 = pol.sample(d1, 0.5f, 0.5f, 0.5f);
  ASSERT_TRUE(s1 && s1->delta);
  // Second mirror: normal n2 = cos θ2 (−d1) + sin θ2 ŷ, so that its plane of incidence holds
  // d1 and ŷ, perpendicular to the xz plane.
  const Vec3 n2 = normalize(-d1 * Float(std::cos(th2)) + Vec3{0, 1, 0} * Float(std::sin(th2)));
  const Vec3 d2 = d1 - n2 * (2 * dot(d1, n2));
  const Frame f2 = Frame::from_normal(n2);
  auto local2 = [&](const Vec3& w) { return Vec3{dot(w, f2.s), dot(w, f2.t), dot(w, f2.n)}; };
  auto world2 = [&](const Vec3& v) { return f2.s * v.x + f2.t * v.y + f2.n * v.z; };
  const Vec3 wo2 = local2(d2);
  const auto s2 = pol.sample(wo2, 0.5f, 0.5f, 0.5f);
  ASSERT_TRUE(s2 && s2->delta);
  ASSERT_NEAR(double(dot(world2(s2->wi), -d1)), 1, 1e-5);
  // The beam along d1 leaves mirror 1 in frame A and enters mirror 2 in frame B.
  const Vec3 a = s_axis(d1), b = world2(s_axis(s2->wi));
  const double c = dot(a, b), s = dot(b, cross(d1, a));
  const double c2 = c * c - s * s, sn2 = 2 * s * c;
  M4 turn{};
  turn[0][0] = turn[3][3] = 1;
  turn[1][1] = turn[2][2] = c2;
  turn[1][2] = sn2;
  turn[2][1] = -sn2;
  EXPECT_NEAR(c2, -1, 1e-5);  // the planes are perpendicular: a quarter turn
  const M4 chained = mul(channel(s2->weight, 0), mul(turn, channel(s1->weight, 0)));
  const Amp f1 = bw_fresnel(std::cos(th1), cx(eta, k)), f2a = bw_fresnel(std::cos(th2), cx(eta, k));
  const M4 r90 = {{{1, 0, 0, 0}, {0, -1, 0, 0}, {0, 0, -1, 0}, {0, 0, 0, 1}}};
  const M4 expected = mul(jones_diag_mueller(f2a.rs, f2a.rp), mul(r90, jones_diag_mueller(f1.rs, f1.rp)));
  EXPECT_LT(max_abs_diff(chained, expected), 2e-5);
  // Without the turn the product differs: the frames matter.
  const M4 unturned = mul(jones_diag_mueller(f2a.rs, f2a.rp), jones_diag_mueller(f1.rs, f1.rp));
  EXPECT_GT(max_abs_diff(unturned, expected), 0.05);
}

TEST(Polarization, PlasticBaseIsPolarizedByTheCoat) {
  // The smooth plastic's base seen through its coat: unpolarized light from wi leaves at wo
  // with Q/I = τ(wo) = (T_s − T_p)/(T_s + T_p), and the response to s-polarized light at wi
  // is 1 + τ(wi), τ from the test's own Fresnel (T = 1 − |r|²).
  const BxDF b = parse_material(R"({"type":"plastic","eta":1.5,"reflectance":0.8})");
  const PolarizedBxDF p(b);
  auto tau = [](double cos_t) {
    const Amp a = bw_fresnel(cos_t, 1.5);
    const double ts = 1 - std::norm(a.rs), tp = 1 - std::norm(a.rp);
    return (ts - tp) / (ts + tp);
  };
  const double to = 80 * kPiD / 180, ti = 60 * kPiD / 180;
  const Vec3 wo{Float(std::sin(to)), 0, Float(std::cos(to))}, wi{0, Float(std::sin(ti)), Float(std::cos(ti))};
  const M4 m = channel(p.eval(wo, wi).f, 0);
  EXPECT_NEAR(m[1][0] / m[0][0], tau(std::cos(to)), 1e-5);
  EXPECT_NEAR(m[0][1] / m[0][0], tau(std::cos(ti)), 1e-5);
  EXPECT_LT(m[1][0], 0);  // p-polarized: the coat lets more p through
  EXPECT_EQ(m[2][2], 0);  // the base forgets the rest
}

TEST(Polarization, SpectralModelsPolarizeToo) {
  // The same templates at the 4 wavelengths of a path: M00 is the spectral f.
  const BxDF rgb = parse_material(R"({"type":"roughconductor","alpha":0.2,"material":"Au"})");
  const auto m = parse_material_with_spectra(R"({"type":"roughconductor","alpha":0.2,"material":"Au"})");
  SampledWavelengths w = SampledWavelengths::sample_visible(0.3f);
  SpectralScratch scratch;
  const SpectralBxDF sb = to_spectral(m.bxdf, m.spectra, w, scratch);
  const PolarizedSpectralBxDF p(sb);
  const Vec3 wo = normalize(Vec3{0.3f, 0.1f, 0.9f}), wi = normalize(Vec3{-0.5f, 0.2f, 0.8f});
  EXPECT_TRUE(p.eval(wo, wi).f.m00() == sb.eval(wo, wi).f);
  EXPECT_NE(p.eval(wo, wi).f(0, 1)[0], 0.0f);
  (void)rgb;
}

}  // namespace
