// The spectral layer (include/gonio/spectrum/, docs/spectral.md) against expectations
// computed here: the CIE tables and the glass data read from data/ by this file's own
// reader, XYZ by this file's own trapezoid quadrature, the sRGB matrix of IEC 61966-2-1
// written out here, Planck's law and Wien's displacement law, the Sellmeier formula with
// Schott's published BK7 coefficients, the closed-form density of the wavelength sampler.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "../data_csv.h"
#include "gonio/error.h"
#include "gonio/rng.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/csv.h"
#include "gonio/spectrum/glasses.h"
#include "gonio/spectrum/spectrum.h"

namespace gonio {
namespace {

// ---------------------------------------------------------------------------------------
// Independent references

using gonio_test_data::read_data;

struct Reference {
  std::vector<double> x, y, z, d65;  // at 360 + k nm, k = 0..470
  double y_int = 0, y_d65 = 0;       // Σ h ȳ, Σ h ȳ D65
  Reference() {
    for (const auto& r : read_data("cie/cie1931_2deg_cmf.csv")) {
      x.push_back(r[1]);
      y.push_back(r[2]);
      z.push_back(r[3]);
    }
    const auto d = read_data("cie/cie_illuminant_d65.csv");
    for (int k = 0; k <= 470; ++k) {
      const double nm = 360 + k;
      for (size_t i = 0; i + 1 < d.size(); ++i)
        if (d[i][0] <= nm && nm <= d[i + 1][0]) {
          d65.push_back(d[i][1] + (nm - d[i][0]) / (d[i + 1][0] - d[i][0]) * (d[i + 1][1] - d[i][1]));
          break;
        }
    }
    for (int k = 0; k <= 470; ++k) {
      y_int += h(k) * y[size_t(k)];
      y_d65 += h(k) * y[size_t(k)] * d65[size_t(k)];
    }
  }
  static double h(int k) { return (k == 0 || k == 470) ? 0.5 : 1.0; }
  // XYZ of a reflectance under D65 (white has Y = 1).
  template <typename Fn>
  std::array<double, 3> reflectance_xyz(Fn&& s) const {
    std::array<double, 3> c{};
    for (int k = 0; k <= 470; ++k) {
      const double w = h(k) * s(360.0 + k) * d65[size_t(k)] / y_d65;
      c[0] += w * x[size_t(k)], c[1] += w * y[size_t(k)], c[2] += w * z[size_t(k)];
    }
    return c;
  }
  // XYZ of an emission (constant 1 has Y = 1).
  template <typename Fn>
  std::array<double, 3> emission_xyz(Fn&& s) const {
    std::array<double, 3> c{};
    for (int k = 0; k <= 470; ++k) {
      const double w = h(k) * s(360.0 + k) / y_int;
      c[0] += w * x[size_t(k)], c[1] += w * y[size_t(k)], c[2] += w * z[size_t(k)];
    }
    return c;
  }
};

const Reference& ref() {
  static const Reference r;
  return r;
}

// IEC 61966-2-1 XYZ → linear sRGB.
std::array<double, 3> to_srgb(const std::array<double, 3>& c) {
  return {3.2406 * c[0] - 1.5372 * c[1] - 0.4986 * c[2], -0.9689 * c[0] + 1.8758 * c[1] + 0.0415 * c[2],
          0.0557 * c[0] - 0.2040 * c[1] + 1.0570 * c[2]};
}

// Planck's law, up to a constant factor: λ⁻⁵ / (exp(hc / λkT) − 1), λ in nm.
double planck_shape(double nm, double kelvin) {
  const double c2 = 6.62607015e-34 * 299792458.0 / 1.380649e-23;  // hc/k, m·K
  return std::pow(nm, -5) / std::expm1(c2 / (nm * 1e-9 * kelvin));
}

// ---------------------------------------------------------------------------------------
// Tables

TEST(SpectrumTables, CmfAndD65MatchTheCsv) {
  const auto& r = ref();
  ASSERT_EQ(r.x.size(), 471u);
  for (int k = 0; k <= 470; k += 7) {
    const XYZ c = cie_xyz_bar(Float(360 + k));
    EXPECT_NEAR(c.x, r.x[size_t(k)], 1e-6 * (1 + r.x[size_t(k)]));
    EXPECT_NEAR(c.y, r.y[size_t(k)], 1e-6 * (1 + r.y[size_t(k)]));
    EXPECT_NEAR(c.z, r.z[size_t(k)], 1e-6 * (1 + r.z[size_t(k)]));
  }
  EXPECT_NEAR(cie_y_integral(), r.y_int, 1e-9 * r.y_int);
  // D65 normalised to luminance 1, and its shape that of the table.
  const auto w = r.emission_xyz([](double nm) { return d65(Float(nm)); });
  EXPECT_NEAR(w[1], 1.0, 1e-5);
  EXPECT_NEAR(d65(560) / d65(500), r.d65[200] / r.d65[140], 1e-5);
  // D65's white point, and linear sRGB (1, 1, 1) for it.
  EXPECT_NEAR(w[0], 0.9505, 1e-3);
  EXPECT_NEAR(w[2], 1.089, 1e-3);
  const auto rgb = to_srgb(w);
  for (double v : rgb) EXPECT_NEAR(v, 1.0, 1e-3);
}

TEST(SpectrumTables, ColourSpaceMatrices) {
  const Color white = xyz_to_linear_srgb({0.9505f, 1.0f, 1.0890f});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(white[i], 1.0, 1e-3);
  const Color c(0.2f, 0.7f, 0.1f);
  const Color back = xyz_to_linear_srgb(linear_srgb_to_xyz(c));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], c[i], 1e-6);
  // sRGB green's luminance (IEC 61966-2-1: Y = 0.7152 G).
  EXPECT_NEAR(linear_srgb_to_xyz(Color(0, 1, 0)).y, 0.7152, 2e-4);
}

// ---------------------------------------------------------------------------------------
// RGB → spectrum

TEST(RgbToSpectrum, ReflectanceRoundTripOverTheSrgbCube) {
  const auto& r = ref();
  double worst = 0;
  std::array<double, 3> worst_rgb{};
  double lo = 1, hi = 0;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (int k = 0; k < 16; ++k) {
        const std::array<double, 3> in{i / 15.0, j / 15.0, k / 15.0};
        const RgbAlbedoSpectrum s{Float(in[0]), Float(in[1]), Float(in[2])};
        const auto out = to_srgb(r.reflectance_xyz([&](double nm) {
          const double v = s.eval(Float(nm));
          lo = std::min(lo, v), hi = std::max(hi, v);
          return v;
        }));
        for (int c = 0; c < 3; ++c)
          if (std::abs(out[size_t(c)] - in[size_t(c)]) > worst) worst = std::abs(out[size_t(c)] - in[size_t(c)]), worst_rgb = in;
      }
  EXPECT_LE(worst, 2e-3) << "at rgb " << worst_rgb[0] << " " << worst_rgb[1] << " " << worst_rgb[2];
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
  std::printf("reflectance round trip over 16^3: max abs error %.3g at (%g, %g, %g)\n", worst, worst_rgb[0],
              worst_rgb[1], worst_rgb[2]);
}

TEST(RgbToSpectrum, ReflectanceIsBoundedEverywhere) {
  Pcg32 rng(7);
  for (int n = 0; n < 2000; ++n) {
    const RgbAlbedoSpectrum s(rng.next_float(), rng.next_float(), rng.next_float());
    for (int k = 0; k <= 470; k += 3) {
      const Float v = s.eval(Float(360 + k));
      ASSERT_TRUE(v >= 0 && v <= 1) << v;
    }
  }
  // Greys are exactly constant, black and white exactly 0 and 1.
  EXPECT_EQ(RgbAlbedoSpectrum(0, 0, 0).eval(500), 0);
  EXPECT_EQ(RgbAlbedoSpectrum(1, 1, 1).eval(700), 1);
  EXPECT_NEAR(RgbAlbedoSpectrum(0.3f, 0.3f, 0.3f).eval(420), 0.3, 1e-6);
}

TEST(RgbToSpectrum, WhiteEmissionStaysWhite) {
  const auto& r = ref();
  for (const Float m : {1.0f, 0.25f, 40.0f}) {
    const RgbIlluminantSpectrum e(m, m, m);
    const auto rgb = to_srgb(r.emission_xyz([&](double nm) { return e.eval(Float(nm)); }));
    for (double v : rgb) EXPECT_NEAR(v / m, 1.0, 1e-3) << "m = " << m;
  }
}

TEST(RgbToSpectrum, EmissionRoundTrip) {
  const auto& r = ref();
  for (const auto& in : std::vector<std::array<double, 3>>{{5, 2, 0.5}, {0, 3, 0}, {0.1, 0.2, 0.9}, {0, 0, 0}}) {
    const RgbIlluminantSpectrum e{Float(in[0]), Float(in[1]), Float(in[2])};
    const auto out = to_srgb(r.emission_xyz([&](double nm) { return e.eval(Float(nm)); }));
    const double m = std::max({in[0], in[1], in[2], 1e-30});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[size_t(c)] / m, in[size_t(c)] / m, 2e-3);
  }
}

TEST(RgbToSpectrum, HostileInputsGiveFiniteSpectra) {
  const Float nan = std::nanf(""), inf = std::numeric_limits<Float>::infinity();
  const SigmoidPolynomial p = rgb_to_sigmoid_polynomial(nan, inf, -1);
  for (const Float l : {360.0f, 555.0f, 830.0f, -5.0f, 1e30f, nan}) EXPECT_TRUE(std::isfinite(p.eval(l))) << l;
  // Every kind of spectrum stays finite at hostile wavelengths.
  const std::vector<Spectrum> all = {ConstantSpectrum{0.5f}, PiecewiseLinearSpectrum::from_points({{400, 1}, {500, 2}}, "t"),
                                     BlackbodySpectrum(3000), D65Spectrum{2}, *named_glass("SF11"),
                                     SellmeierSpectrum({1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}),
                                     RgbAlbedoSpectrum(0.9f, 0.1f, 0.4f), RgbIlluminantSpectrum(3, 1, 0)};
  for (const auto& s : all)
    for (const Float l : {-1e30f, -5.0f, 0.0f, 1e-30f, 359.0f, 831.0f, 1e30f, inf, -inf, nan})
      EXPECT_TRUE(std::isfinite(s.eval(l))) << l << " variant " << s.variant().index();
  EXPECT_THROW(RgbAlbedoSpectrum(1.5f, 0, 0), InputError);
  EXPECT_THROW(RgbAlbedoSpectrum(nan, 0, 0), InputError);
  EXPECT_THROW(RgbIlluminantSpectrum(-1, 0, 0), InputError);
  EXPECT_THROW(RgbIlluminantSpectrum(inf, 0, 0), InputError);
}

// ---------------------------------------------------------------------------------------
// Blackbody, D65, glasses, Sellmeier

TEST(Blackbody, WienPeakAndPlanckRatios) {
  for (const double t : {4000.0, 5000.0, 6000.0, 7000.0}) {
    const BlackbodySpectrum b(t);
    double best = 0, peak = 0;
    for (double nm = 360; nm <= 830; nm += 0.05) {
      const double v = b.eval(Float(nm));
      if (v > best) best = v, peak = nm;
    }
    EXPECT_NEAR(peak, 2.897771955e6 / t, 0.2) << t << " K";
    EXPECT_NEAR(b.eval(450) / b.eval(650), planck_shape(450, t) / planck_shape(650, t),
                1e-5 * planck_shape(450, t) / planck_shape(650, t));
    // Luminance 1.
    EXPECT_NEAR(ref().emission_xyz([&](double nm) { return b.eval(Float(nm)); })[1], 1.0, 1e-4) << t << " K";
  }
  // Extreme but valid temperatures stay finite.
  for (const double t : {BlackbodySpectrum::kMinKelvin, BlackbodySpectrum::kMaxKelvin}) {
    const BlackbodySpectrum b(t);
    for (int nm = 360; nm <= 830; nm += 10) EXPECT_TRUE(std::isfinite(b.eval(Float(nm))) && b.eval(Float(nm)) >= 0);
  }
  EXPECT_THROW(BlackbodySpectrum(-5), InputError);
  EXPECT_THROW(BlackbodySpectrum(0), InputError);
  EXPECT_THROW(BlackbodySpectrum(std::nan("")), InputError);
}

TEST(Sellmeier, Bk7MatchesTheSchottTable) {
  const SellmeierSpectrum bk7({1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653});
  const auto rows = read_data("glasses/BK7.csv");
  ASSERT_GT(rows.size(), 20u);
  for (const auto& row : rows) {
    EXPECT_NEAR(bk7.index(row[0]), row[1], 1e-4) << row[0] << " nm";
    if (row[0] >= 360 && row[0] <= 830) {
      EXPECT_NEAR(bk7.eval(Float(row[0])), row[1], 1e-4) << row[0] << " nm";
    }
  }
  // A pole inside the visible range, and non-finite coefficients, are refused.
  EXPECT_THROW(SellmeierSpectrum({1, 0, 0}, {0.25, 0, 0}), InputError);  // pole at 500 nm
  EXPECT_THROW(SellmeierSpectrum({std::nan(""), 0, 0}, {0, 0, 0}), InputError);
  EXPECT_THROW(SellmeierSpectrum({1, 0, 0}, {-1, 0, 0}), InputError);
}

TEST(Glasses, InterpolateTheirCsvLinearly) {
  EXPECT_EQ(named_glass_names().size(), 7u);
  for (const char* name : {"BK7", "SF11", "BAF10", "FK51A", "LASF9", "SF10", "SF5"}) {
    const auto g = named_glass(name);
    ASSERT_TRUE(g) << name;
    const auto rows = read_data(std::string("glasses/") + name + ".csv");
    for (size_t i = 0; i + 1 < rows.size(); ++i) {
      EXPECT_NEAR(g->eval(Float(rows[i][0])), rows[i][1], 1e-6);
      const double mid = (rows[i][0] + rows[i + 1][0]) / 2;
      EXPECT_NEAR(g->eval(Float(mid)), (rows[i][1] + rows[i + 1][1]) / 2, 1e-6);
    }
  }
  EXPECT_FALSE(named_glass("bk7"));
}

// ---------------------------------------------------------------------------------------
// Wavelength sampling

double pdf_formula(double nm) {
  const double a = 0.0072, norm = std::tanh(a * (830 - 538)) - std::tanh(a * (360 - 538));
  const double c = std::cosh(a * (nm - 538));
  return a / (c * c) / norm;
}

// ∫_{360}^{λ} p by Simpson's rule on the code's own pdf.
double cdf_by_quadrature(double lambda) {
  const int n = 2000;
  const double h = (lambda - 360) / n;
  double s = visible_wavelength_pdf(360) + visible_wavelength_pdf(Float(lambda));
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4 : 2) * visible_wavelength_pdf(Float(360 + i * h));
  return s * h / 3;
}

TEST(Wavelengths, DensityIntegratesToOneAndIsTheDocumentedOne) {
  EXPECT_NEAR(cdf_by_quadrature(830), 1.0, 1e-5);
  for (double nm = 360; nm <= 830; nm += 17) EXPECT_NEAR(visible_wavelength_pdf(Float(nm)), pdf_formula(nm), 1e-6 * pdf_formula(nm) + 1e-9);
  EXPECT_EQ(visible_wavelength_pdf(359), 0);
  EXPECT_EQ(visible_wavelength_pdf(831), 0);
  EXPECT_NEAR(visible_density::kT0, std::tanh(0.0072 * (360 - 538)), 1e-7);
  EXPECT_NEAR(visible_density::kT1, std::tanh(0.0072 * (830 - 538)), 1e-7);
}

TEST(Wavelengths, FourWavelengthsAreQuarterSpacedInCdfSpace) {
  for (const Float u : {0.0f, 0.1f, 0.37f, 0.6f, 0.999f}) {
    const auto w = SampledWavelengths::sample_visible(u);
    for (int j = 0; j < 4; ++j) {
      EXPECT_TRUE(w[j] >= 360 && w[j] <= 830);
      EXPECT_NEAR(w.pdf(j), pdf_formula(w[j]), 1e-6);
      double expected = u + j / 4.0;
      expected -= std::floor(expected);
      EXPECT_NEAR(cdf_by_quadrature(w[j]), expected, 2e-5) << "u " << u << " j " << j;
    }
  }
  // Hostile u: clamped, finite.
  for (const Float u : {-1.0f, 1.0f, 7.0f, std::nanf("")}) {
    const auto w = SampledWavelengths::sample_visible(u);
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(w[j]) && w.pdf(j) > 0);
  }
}

// The renderer's sRGB-response density, derived here from its definition: per 1 nm bin,
// ‖(r̄, ḡ, b̄)‖^½ at the bin's centre, with the XYZ → linear-sRGB matrix of IEC
// 61966-2-1:1999 §5.2 written out again, normalised over the 470 bins.
struct ResponseDensity {
  std::vector<double> pdf, cdf;
  ResponseDensity() : pdf(470), cdf(471, 0.0) {
    const double m[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    double sum = 0;
    for (int i = 0; i < 470; ++i) {
      const XYZ c = cie_xyz_bar(Float(360.5 + i));
      double n2 = 0;
      for (const auto& row : m) {
        const double v = row[0] * c.x + row[1] * c.y + row[2] * c.z;
        n2 += v * v;
      }
      pdf[size_t(i)] = std::pow(n2, 0.25);
      sum += pdf[size_t(i)];
    }
    for (int i = 0; i < 470; ++i) pdf[size_t(i)] /= sum, cdf[size_t(i) + 1] = cdf[size_t(i)] + pdf[size_t(i)];
  }
  double at(double nm) const { return pdf[size_t(std::min(int(nm - 360), 469))]; }
  double cdf_at(double nm) const {
    const int i = std::min(int(nm - 360), 469);
    return cdf[size_t(i)] + pdf[size_t(i)] * (nm - 360 - i);
  }
};

TEST(Wavelengths, ResponseDensityIsTheDocumentedOne) {
  const ResponseDensity d;
  double integral = 0;
  for (int i = 0; i < 470; ++i) {
    const double p = response_wavelength_pdf(Float(360.5 + i));
    integral += p;  // bins of 1 nm
    EXPECT_NEAR(p, d.pdf[size_t(i)], 2e-5 * d.pdf[size_t(i)]) << 360 + i << " nm";
  }
  EXPECT_NEAR(integral, 1.0, 1e-6);
  EXPECT_EQ(response_wavelength_pdf(359.9f), 0);
  EXPECT_EQ(response_wavelength_pdf(830.1f), 0);
  EXPECT_EQ(response_wavelength_pdf(std::nanf("")), 0);
  // It follows all three channels: the blue (450 nm) and red (610 nm) peaks are sampled at
  // least half as densely as the green one, unlike the visible density's blue end.
  EXPECT_GT(response_wavelength_pdf(450) / response_wavelength_pdf(545), 0.5);
  EXPECT_GT(response_wavelength_pdf(610) / response_wavelength_pdf(545), 0.5);
}

TEST(Wavelengths, ResponseWavelengthsAreQuarterSpacedInCdfSpace) {
  const ResponseDensity d;
  for (const Float u : {0.0f, 0.1f, 0.37f, 0.6f, 0.9999f}) {
    const auto w = SampledWavelengths::sample_response(u);
    for (int j = 0; j < 4; ++j) {
      EXPECT_TRUE(w[j] >= 360 && w[j] <= 830);
      EXPECT_NEAR(w.pdf(j), d.at(w[j]), 2e-5 * d.at(w[j])) << "u " << u << " j " << j;
      double expected = u + j / 4.0;
      expected -= std::floor(expected);
      EXPECT_NEAR(d.cdf_at(w[j]), expected, 2e-5) << "u " << u << " j " << j;
    }
  }
  for (const Float u : {-1.0f, 1.0f, 7.0f, std::nanf("")}) {
    const auto w = SampledWavelengths::sample_response(u);
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(w[j]) && w.pdf(j) > 0);
  }
}

// The inverse CDF everywhere: at the start, middle and end of each of the guide table's
// 1,024 intervals of u, the drawn λ sits at u of the test's CDF.
TEST(Wavelengths, ResponseInverseHoldsOverTheWholeRange) {
  const ResponseDensity d;
  for (int k = 0; k < 1024; ++k)
    for (const double f : {0.0, 0.5, 0.999}) {
      const double u = (k + f) / 1024;
      Float pdf = 0;
      const Float lambda = sample_response_wavelength(Float(u), pdf);
      ASSERT_NEAR(d.cdf_at(lambda), u, 2e-5) << "u " << u;
      ASSERT_NEAR(pdf, d.at(lambda), 2e-5 * d.at(lambda)) << "u " << u;
    }
}

// Both densities' estimators: the visible one (tests, the reference) and the renderer's.
SampledWavelengths draw(bool response, Float u) {
  return response ? SampledWavelengths::sample_response(u) : SampledWavelengths::sample_visible(u);
}

void expect_y_integral_converges(bool response) {
  const auto& r = ref();
  Pcg32 rng(11);
  const int n = 200000;
  double sum = 0, sum2 = 0, sum_t = 0, sum_t2 = 0;
  for (int i = 0; i < n; ++i) {
    auto w = draw(response, rng.next_float());
    double e = 0;
    for (int j = 0; j < 4; ++j) e += cie_xyz_bar(w[j]).y / w.pdf(j) / 4;
    sum += e, sum2 += e * e;
    // With the secondaries terminated: to_xyz of a flat spectrum 1 still has mean Y = 1.
    w.terminate_secondary();
    EXPECT_TRUE(w.secondary_terminated());
    const double y = to_xyz(SampledSpectrum(1), w).y;
    sum_t += y, sum_t2 += y * y;
  }
  const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, r.y_int, 4 * se + 1e-3) << "σ = " << se;
  const double mt = sum_t / n, st = std::sqrt((sum_t2 / n - mt * mt) / n);
  EXPECT_NEAR(mt, 1.0, 4 * st) << "σ = " << st;
  std::printf("%s density: ∫ȳ: estimate %.5f ± %.5f, quadrature %.5f; terminated: %.5f ± %.5f\n",
              response ? "response" : "visible", mean, se, r.y_int, mt, st);
}

TEST(Wavelengths, EstimatorOfTheYIntegralConverges) { expect_y_integral_converges(false); }
TEST(Wavelengths, ResponseEstimatorOfTheYIntegralConverges) { expect_y_integral_converges(true); }

void expect_reflectance_under_d65_converges(bool response) {
  const auto& r = ref();
  const RgbAlbedoSpectrum s(0.8f, 0.3f, 0.1f);
  const auto expected = r.reflectance_xyz([&](double nm) { return s.eval(Float(nm)); });
  Pcg32 rng(3);
  const int n = 100000;
  double m[3] = {}, m2[3] = {};
  for (int i = 0; i < n; ++i) {
    const auto w = draw(response, rng.next_float());
    const XYZ c = to_xyz(s.eval(w) * d65(w), w);
    const double v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; ++k) m[k] += v[k], m2[k] += v[k] * v[k];
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = m[k] / n, se = std::sqrt((m2[k] / n - mean * mean) / n);
    EXPECT_NEAR(mean, expected[size_t(k)], 4 * se) << k;
  }
}

TEST(Wavelengths, ToXyzConvergesToTheQuadratureOfAReflectanceUnderD65) { expect_reflectance_under_d65_converges(false); }
TEST(Wavelengths, ResponseToXyzConvergesToTheQuadratureOfAReflectanceUnderD65) {
  expect_reflectance_under_d65_converges(true);
}

// ---------------------------------------------------------------------------------------
// Piecewise-linear spectra and bad inputs

TEST(PiecewiseLinear, InterpolatesAndHoldsItsEnds) {
  const auto s = PiecewiseLinearSpectrum::from_points({{400, 0.2}, {500, 0.6}, {700, 0.4}}, "test");
  EXPECT_NEAR(s.eval(450), 0.4, 1e-6);
  EXPECT_NEAR(s.eval(600), 0.5, 1e-6);
  EXPECT_EQ(s.eval(360), Float(0.2));
  EXPECT_EQ(s.eval(830), Float(0.4));
  const Spectrum any = s;
  const auto w = SampledWavelengths::sample_visible(0.3f);
  for (int j = 0; j < 4; ++j) EXPECT_EQ(any.eval(w)[j], s.eval(w[j]));
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PiecewiseLinear, BadInputsAreClearErrors) {
  EXPECT_NE(message_of([] { PiecewiseLinearSpectrum::from_points({{-5, 1}}, "reflectance"); }).find("positive"),
            std::string::npos);
  const std::string m = message_of([] { PiecewiseLinearSpectrum::from_points({{400, 1}, {600, 1}, {500, 1}}, "reflectance"); });
  EXPECT_NE(m.find("increase"), std::string::npos) << m;
  EXPECT_NE(m.find("point 3"), std::string::npos) << m;
  EXPECT_NE(message_of([] { PiecewiseLinearSpectrum::from_points({}, "x"); }).find("at least one"), std::string::npos);
  // Malformed CSV: the message names file:line.
  const std::string bad = "# comment\nlambda_nm,value\n400,0.5\n500,abc\n";
  const std::string e1 = message_of([&] { PiecewiseLinearSpectrum::from_csv_text(bad, "my.csv"); });
  EXPECT_NE(e1.find("my.csv:4:"), std::string::npos) << e1;
  const std::string e2 = message_of([] { PiecewiseLinearSpectrum::from_csv_text("400,0.5\n\n390,0.1\n", "s.csv"); });
  EXPECT_NE(e2.find("s.csv:3:"), std::string::npos) << e2;
  EXPECT_NE(e2.find("increase"), std::string::npos) << e2;
  const std::string e3 = message_of([] { PiecewiseLinearSpectrum::from_csv_text("400,0.5,7\n", "t.csv"); });
  EXPECT_NE(e3.find("t.csv:1:"), std::string::npos) << e3;
  const std::string e4 = message_of([] { PiecewiseLinearSpectrum::from_csv_text("# nothing\n", "e.csv"); });
  EXPECT_NE(e4.find("e.csv"), std::string::npos) << e4;
  const std::string e5 = message_of([] { PiecewiseLinearSpectrum::from_csv_text("400,nan\n", "n.csv"); });
  EXPECT_NE(e5.find("n.csv:1:"), std::string::npos) << e5;
  // A file on disk: its path in the message; a missing file is named too.
  const std::string path = ::testing::TempDir() + "gonio_spectrum_test.csv";
  {
    std::ofstream f(path);
    f << "# nm, value\n400 0.1\n500 0.2\n600 -\n";
  }
  const std::string e6 = message_of([&] { PiecewiseLinearSpectrum::from_csv_file(path); });
  EXPECT_NE(e6.find(path + ":4:"), std::string::npos) << e6;
  std::remove(path.c_str());
  EXPECT_NE(message_of([&] { PiecewiseLinearSpectrum::from_csv_file(path); }).find(path), std::string::npos);
  // Whitespace-separated and commented files are fine.
  const auto ok = PiecewiseLinearSpectrum::from_csv_text("400 0.1 # first\n\n500\t0.3\n", "ok");
  EXPECT_NEAR(ok.eval(450), 0.2, 1e-6);
}

}  // namespace
}  // namespace gonio
