// RGL .bsdf materials (issue 59; Dupuy & Jakob 2018): the bilinear conditional warps
// (density against frequency by χ², integral 1, inverse round trip), the tables gonio
// writes read back (round trip against the model that wrote them, held to bounds), the
// model's pdf against its sampling, and malformed files refused naming the field.
//
// Independence: the warps' expected bin masses are integrated here from the bilinear
// interpolant written out in this file (not the class's eval), and the round trip
// compares with gonio's analytic models, which their own tests hold to closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "gonio/error.h"
#include "gonio/io/tensor_file.h"
#include "gonio/material.h"
#include "gonio/math/bilinear_warp.h"
#include "gonio/rgl/data.h"
#include "gonio/rgl/write.h"
#include "test_scale.h"

namespace gonio {
namespace {

// The bilinear interpolant of a ny×nx grid on [0,1]², written out independently.
double rgl_bilerp(const std::vector<float>& v, int nx, int ny, double x, double y) {
  const double gx = x * (nx - 1), gy = y * (ny - 1);
  const int i = std::min(int(gx), nx - 2), j = std::min(int(gy), ny - 2);
  const double s = gx - i, t = gy - j;
  auto at = [&](int a, int b) { return double(v[std::size_t(b * nx + a)]); };
  return (1 - t) * ((1 - s) * at(i, j) + s * at(i + 1, j)) + t * ((1 - s) * at(i, j + 1) + s * at(i + 1, j + 1));
}

// χ² of `n` warped samples against the masses of a bins×bins histogram of `density`
// (integrated by a 6×6 midpoint rule per bin); returns the statistic per degree of freedom.
template <typename Sample, typename Density>
double rgl_chi2(Sample&& sample, Density&& density, int n, int bins, std::uint32_t seed) {
  std::vector<double> obs(std::size_t(bins * bins), 0), exp(std::size_t(bins * bins), 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  for (int k = 0; k < n; ++k) {
    const auto [x, y] = sample(u(rng), u(rng));
    const int bx = std::min(int(x * bins), bins - 1), by = std::min(int(y * bins), bins - 1);
    obs[std::size_t(by * bins + bx)] += 1;
  }
  double total = 0;
  for (int by = 0; by < bins; ++by)
    for (int bx = 0; bx < bins; ++bx) {
      double m = 0;
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b) m += density((bx + (a + 0.5) / 6) / bins, (by + (b + 0.5) / 6) / bins);
      m /= 36.0 * bins * bins;
      exp[std::size_t(by * bins + bx)] = m * n;
      total += m;
    }
  EXPECT_NEAR(total, 1.0, 2e-3);
  double chi = 0;
  int dof = 0;
  for (std::size_t k = 0; k < obs.size(); ++k) {
    if (exp[k] < 5) continue;
    chi += (obs[k] - exp[k]) * (obs[k] - exp[k]) / exp[k];
    ++dof;
  }
  return chi / std::max(dof - 1, 1);
}

std::vector<float> rgl_random_grid(int nx, int ny, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.05f, 1);
  std::vector<float> v(std::size_t(nx * ny));
  for (float& x : v) x = u(rng);
  v[3] = 0;  // a zero node: the warp must step over it
  return v;
}

TEST(RglWarp, DensityMatchesFrequencyAndIntegratesToOne) {
  const int nx = 7, ny = 5;
  const std::vector<float> raw = rgl_random_grid(nx, ny, 3);
  const BilinearWarp2D w(nx, ny, raw, {}, true, true);
  BilinearWarp2D::Slices s = w.locate(nullptr);
  // The raw interpolant's integral (exact for a bilinear patch: the mean of its corners).
  double integral = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
      integral += 0.25 * (raw[std::size_t(j * nx + i)] + raw[std::size_t(j * nx + i + 1)] +
                          raw[std::size_t((j + 1) * nx + i)] + raw[std::size_t((j + 1) * nx + i + 1)]);
  integral /= (nx - 1) * (ny - 1);
  auto density = [&](double x, double y) { return rgl_bilerp(raw, nx, ny, x, y) / integral; };
  const int n = int(test::scaled(40000, 4000));
  const double chi = rgl_chi2(
      [&](float a, float b) {
        const auto r = w.sample(a, b, s);
        return std::pair{double(r.x), double(r.y)};
      },
      density, n, 12, 11);
  EXPECT_LT(chi, 1.6);
  // eval is the normalized density; sample's pdf is eval at its point; invert undoes sample.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  double worst_pdf = 0, worst_inv = 0;
  for (int k = 0; k < 2000; ++k) {
    const float a = u(rng), b = u(rng);
    const auto r = w.sample(a, b, s);
    worst_pdf = std::max(worst_pdf, std::abs(r.pdf - density(r.x, r.y)) / density(r.x, r.y));
    worst_pdf = std::max(worst_pdf, double(std::abs(w.eval(r.x, r.y, s) - r.pdf) / r.pdf));
    const auto inv = w.invert(r.x, r.y, s);
    worst_inv = std::max({worst_inv, double(std::abs(inv.x - a)), double(std::abs(inv.y - b))});
  }
  EXPECT_LT(worst_pdf, 1e-4);
  EXPECT_LT(worst_inv, 2e-4);
}

TEST(RglWarp, ConditionalWarpInterpolatesNormalizedSlices) {
  // Two parameters (3 × 2 values): at an in-between point the density is the blend of the
  // four normalized neighbour slices, sampled in proportion.
  const int nx = 6, ny = 4;
  std::vector<float> data;
  std::vector<std::vector<float>> slices;
  for (int k = 0; k < 6; ++k) {
    slices.push_back(rgl_random_grid(nx, ny, 100 + std::uint32_t(k)));
    data.insert(data.end(), slices.back().begin(), slices.back().end());
  }
  const BilinearWarp2D w(nx, ny, data, {{0.f, 1.f, 3.f}, {-1.f, 1.f}}, true, true);
  const float p[2] = {2.5f, 0.f};  // between values 1 and 3 (3/4), between −1 and 1 (1/2)
  const BilinearWarp2D::Slices s = w.locate(p);
  ASSERT_EQ(s.count, 4);
  auto mass = [&](const std::vector<float>& v) {
    double m = 0;
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        m += 0.25 * (v[std::size_t(j * nx + i)] + v[std::size_t(j * nx + i + 1)] + v[std::size_t((j + 1) * nx + i)] +
                     v[std::size_t((j + 1) * nx + i + 1)]);
    return m / ((nx - 1) * (ny - 1));
  };
  // Slice index = i0 * 2 + i1; weights (1/4, 3/4) × (1/2, 1/2).
  auto density = [&](double x, double y) {
    const double w0[3] = {0, 0.25, 0.75};
    double d = 0;
    for (int a = 1; a < 3; ++a)
      for (int b = 0; b < 2; ++b) {
        const auto& v = slices[std::size_t(a * 2 + b)];
        d += w0[a] * 0.5 * rgl_bilerp(v, nx, ny, x, y) / mass(v);
      }
    return d;
  };
  const int n = int(test::scaled(40000, 4000));
  const double chi = rgl_chi2(
      [&](float a, float b) {
        const auto r = w.sample(a, b, s);
        return std::pair{double(r.x), double(r.y)};
      },
      density, n, 10, 17);
  EXPECT_LT(chi, 1.6);
  EXPECT_NEAR(w.eval(0.3f, 0.6f, s), density(0.3, 0.6), 1e-5 * density(0.3, 0.6));
}

RglData rgl_roundtrip(const std::string& json, RglWriteOptions opt) {
  const BxDF m = parse_material(json);
  const std::vector<std::uint8_t> bytes = tabulate_rgl(m, opt);
  return parse_rgl(TensorFile::parse(bytes, "mem.bsdf"));
}

// Relative RMS of f·cos over the hemisphere of wi at θo (uniform-area Fibonacci points),
// the written file against the model.
double rgl_rel_rms(const BxDF& model, const BxDF& table, double theta_o_deg, double phi_o = 0.3) {
  const double t = theta_o_deg * 3.14159265358979 / 180;
  const Vec3 wo{Float(std::sin(t) * std::cos(phi_o)), Float(std::sin(t) * std::sin(phi_o)), Float(std::cos(t))};
  double num = 0, den = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const double z = (k + 0.5) / n, r = std::sqrt(1 - z * z), ph = k * 2.39996322972865;
    const Vec3 wi{Float(r * std::cos(ph)), Float(r * std::sin(ph)), Float(z)};
    const double a = model.f(wo, wi).average() * z, b = table.f(wo, wi).average() * z;
    num += (a - b) * (a - b);
    den += a * a;
  }
  return std::sqrt(num / den);
}

TEST(RglRoundTrip, GgxConductorAndDiffuseReadBackWithinBounds) {
  RglWriteOptions opt;
  opt.n_theta_i = 10;
  opt.n_ndf = 48;
  opt.n_sample = 24;
  opt.wavelengths = {400, 500, 600, 700};
  for (const auto& [json, bound] : std::vector<std::pair<std::string, double>>{
           {R"({"type":"roughconductor","alpha":0.4,"material":"Au"})", 0.08},
           {R"({"type":"diffuse","reflectance":[0.7,0.5,0.3]})", 0.03}}) {
    const BxDF model = parse_material(json);
    auto data = std::make_shared<const RglData>(rgl_roundtrip(json, opt));
    const BxDF table = RglBxDF::make(data);
    for (const double th : {0.0, 30.0, 60.0}) {
      const double e = rgl_rel_rms(model, table, th);
      EXPECT_LT(e, bound) << json << " at " << th;
      std::printf("rgl round trip %s at %g deg: %.4f\n", json.c_str(), th, e);
    }
  }
}

TEST(RglModel, PdfIntegratesToOneAndMatchesSampling) {
  RglWriteOptions opt;
  opt.n_theta_i = 8;
  opt.n_ndf = 32;
  opt.n_sample = 16;
  opt.wavelengths = {450, 550, 650};
  auto data = std::make_shared<const RglData>(rgl_roundtrip(R"({"type":"roughconductor","alpha":0.3,"material":"Al"})", opt));
  const RglBxDF m = RglBxDF::make(data);
  const Vec3 wo{0.5f, 0.1f, std::sqrt(1 - 0.26f)};
  // ∫ pdf dω over the sphere by a Fibonacci rule: 1 minus what falls below the horizon.
  double integral = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double z = (k + 0.5) / n, r = std::sqrt(1 - z * z), ph = k * 2.39996322972865;
    integral += m.pdf(wo, Vec3{Float(r * std::cos(ph)), Float(r * std::sin(ph)), Float(z)}, TransportMode::Radiance);
  }
  integral *= 2 * 3.14159265358979 / n;
  // The fraction of samples that come back: the same quantity counted by sampling.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0, 1);
  int ok = 0;
  const int ns = 20000;
  double worst = 0;
  for (int k = 0; k < ns; ++k) {
    const auto s = m.sample(wo, 0.5f, u(rng), u(rng), TransportMode::Radiance);
    if (!s) continue;
    ++ok;
    worst = std::max(worst, double(std::abs(s->pdf - m.pdf(wo, s->wi, TransportMode::Radiance)) / s->pdf));
  }
  EXPECT_NEAR(integral, double(ok) / ns, 0.02);
  EXPECT_GT(integral, 0.9);
  EXPECT_LT(integral, 1.01);
  EXPECT_EQ(worst, 0.0);
}

TEST(RglModel, BoundedAtTheHorizonAndReciprocal) {
  // The interpolated f·cos does not vanish at the horizon: f is read from the side of the
  // larger cosine (bxdf/rgl.h), so it stays bounded, the albedo at grazing stays below 1,
  // and f is reciprocal. A plain value(wo, wi)/cos θi gave f = 1e27 and an albedo of 17.
  RglWriteOptions opt;
  opt.n_theta_i = 8;
  opt.n_ndf = 32;
  opt.n_sample = 16;
  opt.wavelengths = {450, 550, 650};
  auto data = std::make_shared<const RglData>(rgl_roundtrip(R"({"type":"roughconductor","alpha":0.4,"material":"Au"})", opt));
  const RglBxDF m = RglBxDF::make(data);
  const Color f = m.f(Vec3{0, 0, 1}, Vec3{0.9998f, 0.02f, 1e-30f}, TransportMode::Radiance);
  EXPECT_TRUE(std::isfinite(f.max_component()) && f.max_component() < 1) << f.max_component();
  const Vec3 grazing{std::sqrt(1 - 0.0017f * 0.0017f), 0, 0.0017f};
  double albedo = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    const double z = (k + 0.5) / n, r = std::sqrt(1 - z * z), ph = k * 2.39996322972865;
    const Vec3 wi{Float(r * std::cos(ph)), Float(r * std::sin(ph)), Float(z)};
    albedo += m.f(grazing, wi, TransportMode::Radiance).max_component() * z;
  }
  albedo *= 2 * 3.14159265358979 / n;
  EXPECT_LT(albedo, 1.0);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    Vec3 a{u(rng), u(rng), std::abs(u(rng)) + 0.01f}, b{u(rng), u(rng), std::abs(u(rng)) + 0.01f};
    a = normalize(a);
    b = normalize(b);
    const Color x = m.f(a, b, TransportMode::Radiance), y = m.f(b, a, TransportMode::Radiance);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(x[c], y[c]);
  }
}

TEST(RglFile, RefusesInconsistentShapesNamingTheField) {
  RglWriteOptions opt;
  opt.n_theta_i = 3;
  opt.n_ndf = 8;
  opt.n_sample = 4;
  opt.wavelengths = {500, 600};
  const BxDF m = parse_material(R"({"type":"diffuse"})");
  const TensorFile tf = TensorFile::parse(tabulate_rgl(m, opt), "x.bsdf");
  auto message = [](std::vector<TensorField> fields) {
    try {
      (void)parse_rgl(TensorFile::parse(encode_tensor_file(fields), "x.bsdf"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(tf.fields()), "");
  {
    auto f = tf.fields();
    std::erase_if(f, [](const TensorField& x) { return x.name == "vndf"; });
    EXPECT_EQ(message(f), "x.bsdf: field 'vndf' is missing");
  }
  {
    auto f = tf.fields();
    for (auto& x : f)
      if (x.name == "theta_i") x = float_field("theta_i", {2}, std::vector<float>{0.f, 1.f});
    EXPECT_NE(message(f).find("field 'vndf': shape [1, 3, 8, 8] does not start with [phi_i, theta_i] = [1, 2]"),
              std::string::npos)
        << message(f);
  }
  {
    auto f = tf.fields();
    for (auto& x : f)
      if (x.name == "luminance") x.data[0] = 0, x.data[1] = 0, x.data[2] = 0xc0, x.data[3] = 0x7f;  // quiet NaN
    EXPECT_NE(message(f).find("field 'luminance': value nan at index 0"), std::string::npos) << message(f);
  }
  {
    auto f = tf.fields();
    for (auto& x : f)
      if (x.name == "rgb") x.shape[2] = 2, x.data.resize(x.data.size() / 3 * 2);
    EXPECT_NE(message(f).find("field 'rgb': shape [1, 3, 2, 4, 4], expected [1, 3, 3, 4, 4]"), std::string::npos)
        << message(f);
  }
  {
    auto f = tf.fields();
    for (auto& x : f)
      if (x.name == "jacobian") x.dtype = TensorDtype::Int8;
    EXPECT_EQ(message(f), "x.bsdf: field 'jacobian': dtype int8, expected uint8");
  }
}

}  // namespace
}  // namespace gonio
