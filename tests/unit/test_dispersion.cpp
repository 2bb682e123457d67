// Dispersion (issue 11, item 5): a ray through a prism of SF11 is deviated at each
// wavelength as Snell's law with the glass's Sellmeier index says, and a dispersive
// surface keeps only the hero wavelength.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "gonio/math/frame.h"
#include "gonio/spectral_material.h"

namespace gonio {
namespace {

// Schott's Sellmeier formula n² = 1 + Σ B_i λ² / (λ² − C_i), λ in µm, with the
// catalogue's coefficients for N-SF11 (Schott optical glass data sheets; the values in
// refractiveindex.info's SCHOTT-SF catalogue entry).
double sf11_index(double nm) {
  const double B[3] = {1.73759695, 0.313747346, 1.89878101};
  const double C[3] = {0.013188707, 0.0623068142, 155.23629};
  const double l2 = (nm / 1000) * (nm / 1000);
  double n2 = 1;
  for (int i = 0; i < 3; ++i) n2 += B[i] * l2 / (l2 - C[i]);
  return std::sqrt(n2);
}

// Deviation of a prism of apex angle A for incidence θ1 on the first face (Born & Wolf,
// Principles of Optics, §4.7.2): sin θ1' = sin θ1 / n, θ2 = A − θ1', sin θ2' = n sin θ2,
// δ = θ1 + θ2' − A.
double prism_deviation(double n, double A, double theta1) {
  const double t1p = std::asin(std::sin(theta1) / n);
  const double t2 = A - t1p;
  const double t2p = std::asin(n * std::sin(t2));
  return theta1 + t2p - A;
}

Vec3 in_plane(double angle) { return {Float(std::cos(angle)), 0, Float(std::sin(angle))}; }

// The direction leaving an apex-up prism (apex angle A; faces' outward normals at
// 180° − A/2 and A/2 from +x in the xz-plane) for a ray entering the first face at θ1,
// traced by gonio's spectral dielectric at wavelength `nm`. Returns the angle between
// the incoming and outgoing directions.
double traced_deviation(const MaterialWithSpectra& glass, double nm, double A, double theta1) {
  SpectralScratch scratch;
  SampledWavelengths w = SampledWavelengths::single(Float(nm));
  const SpectralBxDF model = to_spectral(glass.bxdf, glass.spectra, w, scratch);
  const Vec3 n1 = in_plane(kPiD - A / 2), n2 = in_plane(A / 2);
  const Vec3 d_in = in_plane(-A / 2 + theta1);  // rotated from −n1 by θ1 towards the apex
  const Frame f1 = Frame::from_normal(n1), f2 = Frame::from_normal(n2);
  // u_lobe near 1 picks the refracted lobe (u_lobe < F reflects).
  const auto s1 = model.sample(normalize(f1.to_local(-d_in)), 0.9999f, 0.5f, 0.5f);
  EXPECT_TRUE(s1 && s1->lobe == Lobe::Transmission);
  if (!s1) return 0;
  const Vec3 d_inside = f1.to_world(s1->wi);
  const auto s2 = model.sample(normalize(f2.to_local(-d_inside)), 0.9999f, 0.5f, 0.5f);
  EXPECT_TRUE(s2 && s2->lobe == Lobe::Transmission);
  if (!s2) return 0;
  const Vec3 d_out = f2.to_world(s2->wi);
  return std::acos(std::clamp(double(dot(d_in, d_out)), -1.0, 1.0));
}

constexpr double kApex = 45 * kPiD / 180, kTheta1 = 50 * kPiD / 180;

TEST(Dispersion, PrismDeviationIsSnellWithTheSellmeierIndex) {
  const MaterialWithSpectra glass = parse_material_with_spectra(
      R"({"type":"dielectric","eta":{"sellmeier":{"B":[1.73759695,0.313747346,1.89878101],)"
      R"("C":[0.013188707,0.0623068142,155.23629]}}})");
  double previous = 0;
  for (const double nm : {650.0, 550.0, 450.0}) {
    const double expected = prism_deviation(sf11_index(nm), kApex, kTheta1);
    EXPECT_NEAR(traced_deviation(glass, nm, kApex, kTheta1), expected, 2e-5) << nm << " nm";
    EXPECT_GT(expected, previous + 0.005) << "blue is bent more than red";  // dispersion is visible
    previous = expected;
  }
}

TEST(Dispersion, NamedGlassFollowsItsTable) {
  // data/glasses/SF11.csv tabulates the index every ~21 nm; it and its linear interpolant
  // stay within 1.4e-4 of the N-SF11 formula at 450, 550 and 650 nm (4.3e-4 at most over
  // 400-700 nm, measured), 1.5e-4 rad of deviation here.
  const MaterialWithSpectra glass = parse_material_with_spectra(R"({"type":"dielectric","eta":"SF11"})");
  for (const double nm : {650.0, 550.0, 450.0})
    EXPECT_NEAR(traced_deviation(glass, nm, kApex, kTheta1), prism_deviation(sf11_index(nm), kApex, kTheta1), 1.5e-4)
        << nm << " nm";
}

TEST(Dispersion, DispersiveSurfaceKeepsOnlyTheHero) {
  SpectralScratch scratch;
  const MaterialWithSpectra sf11 = parse_material_with_spectra(R"({"type":"roughdielectric","eta":"SF11","alpha":0.1})");
  SampledWavelengths w = SampledWavelengths::sample_visible(0.3f);
  const Float hero = w[0], hero_pdf = w.pdf(0);
  const SpectralBxDF m = to_spectral(sf11.bxdf, sf11.spectra, w, scratch);
  EXPECT_TRUE(w.secondary_terminated());
  EXPECT_EQ(w[0], hero);
  EXPECT_FLOAT_EQ(w.pdf(0), hero_pdf / 4);  // Wilkie et al. 2014 §5: the hero's density / 4
  EXPECT_NEAR(m.relative_eta(), sf11_index(hero), 5e-4);  // the table, as above

  // A constant index is not dispersive: every wavelength goes on.
  const MaterialWithSpectra flat = parse_material_with_spectra(R"({"type":"dielectric","eta":1.5})");
  SampledWavelengths w2 = SampledWavelengths::sample_visible(0.3f);
  (void)to_spectral(flat.bxdf, flat.spectra, w2, scratch);
  EXPECT_FALSE(w2.secondary_terminated());
}

// A dispersive rough dielectric with multiple scattering: the lobe at the hero wavelength
// is the one made for the index there (F̄ from its table, every 5 nm), and an index that
// leaves the lobe's tables anywhere in the visible is refused, naming the wavelength.
TEST(Dispersion, MultiscatterLobeFollowsTheHeroIndex) {
  const MaterialWithSpectra glass = parse_material_with_spectra(
      R"({"type":"roughdielectric","alpha":0.3,"multiscatter":true,"eta":{"sellmeier":{"B":[1.73759695,0.313747346,)"
      R"(1.89878101],"C":[0.013188707,0.0623068142,155.23629]}}})");
  SpectralScratch scratch;
  for (const double nm : {452.5, 587.0, 701.0}) {
    SampledWavelengths w = SampledWavelengths::single(Float(nm));
    const SpectralBxDF m = to_spectral(glass.bxdf, glass.spectra, w, scratch);
    const auto* rd = std::get_if<RoughDielectricBxDFT<SampledSpectrum>>(&m.models());
    ASSERT_TRUE(rd && rd->multiscatter);
    const Float n = Float(sf11_index(nm));
    EXPECT_NEAR(rd->eta, n, 2e-6);
    const DielectricMultiscatterLobe direct = DielectricMultiscatterLobe::make(rd->distribution, n);
    EXPECT_NEAR(rd->multiscatter->fbar_out, direct.fbar_out, 2e-5) << nm;
    EXPECT_NEAR(rd->multiscatter->t_out, direct.t_out, 2e-5) << nm;
    EXPECT_NEAR(rd->multiscatter->t_in, direct.t_in, 2e-5) << nm;
  }
  try {
    (void)parse_material_with_spectra(
        R"({"type":"roughdielectric","alpha":0.3,"multiscatter":true,"eta":{"spectrum":[[360,5],[830,1.5]]}})");
    ADD_FAILURE() << "an index of 5 at 360 nm was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at 360 nm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gonio
