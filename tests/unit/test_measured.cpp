// Measured BRDFs (issue 12): the MERL format byte for byte, the half/difference angles,
// interpolation, sampling and the validator on `measured` materials.
//
// Independence: tables are written by the tests' own writer (tests/merl_files.h), the
// angles are recomputed here from Rusinkiewicz's frames, the expected interpolation is
// written out here, and the GGX model the tabulation is compared with is the closed form
// below (Walter et al. 2007 eq. 33 for D; Heitz 2014 eqs. 72 and 99 for Λ and G2;
// Schlick 1994 for F), not gonio's.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <random>
#include <string>

#include "../merl_files.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/measured_data.h"
#include "gonio/merl.h"
#include "gonio/spectral_material.h"
#include "gonio/tabulate.h"
#include "gonio/validate.h"
#include "test_scale.h"

namespace gonio {
namespace {

namespace mf = gonio_test_merl;

struct D3 {
  double x, y, z;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(double s, D3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 unit(D3 a) { return (1 / std::sqrt(dot(a, a))) * a; }
Vec3 to_vec(D3 a) { return {Float(a.x), Float(a.y), Float(a.z)}; }

// The pair of directions of (θh, θd, φd) with φh = 0, from Rusinkiewicz's frame of the half
// vector: h = (sin θh, 0, cos θh), t = (cos θh, 0, −sin θh), b = (0, 1, 0);
// wi = cos θd h + sin θd (cos φd t + sin φd b), wo its mirror image through h.
std::pair<D3, D3> directions(double th, double td, double pd) {
  const D3 h{std::sin(th), 0, std::cos(th)}, t{std::cos(th), 0, -std::sin(th)}, b{0, 1, 0};
  const D3 wi = std::cos(td) * h + std::sin(td) * (std::cos(pd) * t + std::sin(pd) * b);
  const D3 wo = (2 * dot(wi, h)) * h + (-1.0) * wi;
  return {wo, wi};
}

// GGX with Schlick's Fresnel, height-correlated Smith, in double.
double ggx_f(D3 wo, D3 wi, double alpha, double f0) {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const D3 h = unit(wo + wi);
  const double a2 = alpha * alpha, c2 = h.z * h.z;
  const double d = a2 / (kPiD * std::pow(c2 * (a2 - 1) + 1, 2));
  auto lambda = [&](D3 w) {
    const double t2 = (1 - w.z * w.z) / (w.z * w.z);
    return (std::sqrt(1 + a2 * t2) - 1) / 2;
  };
  const double g2 = 1 / (1 + lambda(wo) + lambda(wi));
  const double f = f0 + (1 - f0) * std::pow(1 - dot(wo, h), 5);
  return d * g2 * f / (4 * wo.z * wi.z);
}
constexpr const char* kGgxMaterial = R"({"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":0.8})";

// A table of gonio's tabulation of kGgxMaterial, written by gonio, once per process.
const std::string& ggx_table_path() {
  static const mf::TempTable table(mf::temp_path("ggx"));
  static const bool written = (write_merl(table.path, tabulate(parse_material(kGgxMaterial))), true);
  (void)written;
  return table.path;
}
BxDF measured(const std::string& path) {
  return parse_material(R"({"type":"measured","file":")" + path + R"("})");
}

// --- the format ------------------------------------------------------------------------

double pattern(int i, int j, int k, int c) { return (1 + i + 0.5 * j + 0.25 * k) * (c + 1) * 1e-3; }

TEST(MerlFormat, ReadsTheBytesAsSpecified) {
  const mf::TempTable file(mf::temp_path("pattern"));
  mf::write_bytes(file.path, mf::table_bytes([](int i, int j, int k, int c) {
    if (i == 3 && j == 4 && k == 5 && c == 1) return -1.0;  // one channel unmeasured
    if (i == 89 && j == 0 && k == 0) return -1.0;
    return pattern(i, j, k, c);
  }));
  const MerlTable t = read_merl(file.path);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        if ((i == 3 && j == 4 && k == 5) || (i == 89 && j == 0 && k == 0)) {
          EXPECT_FALSE(t.measured(i, j, k)) << i << " " << j << " " << k;
          continue;
        }
        const Color f = t.at(i, j, k);
        for (int c = 0; c < 3; ++c) {
          const double want = pattern(i, j, k, c) / mf::kScale[c] * mf::kScale[c];
          ASSERT_NEAR(f[c], want, 1e-7 * want) << i << " " << j << " " << k << " channel " << c;
        }
      }
}

TEST(MerlFormat, WritesTheSameBytes) {
  MerlTable t;
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) t.set(i, j, k, Color(1.0f / 64));  // exact in float and double
  t.set_missing(7, 8, 9);
  const mf::TempTable file(mf::temp_path("written"));
  write_merl(file.path, t);
  std::ifstream in(file.path, std::ios::binary);
  const std::vector<unsigned char> got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto want = mf::table_bytes([](int i, int j, int k, int) { return i == 7 && j == 8 && k == 9 ? -1.0 : 1.0 / 64; });
  ASSERT_EQ(got.size(), want.size());
  EXPECT_TRUE(got == want);
}

// Each bad file gets one line naming the file and the problem.
TEST(MerlFormat, RejectsBadFilesWithOneLine) {
  const auto good = mf::table_bytes([](int, int, int, int) { return 0.1; });
  struct Case {
    std::string name, expect;
    std::vector<unsigned char> bytes;
  };
  std::vector<Case> cases;
  cases.push_back({"truncated", "truncated", std::vector<unsigned char>(good.begin(), good.end() - 8)});
  cases.push_back({"header_only", "truncated", std::vector<unsigned char>(good.begin(), good.begin() + 12)});
  cases.push_back({"empty", "header", {}});
  auto header = good;
  header[8] = 90;  // 90 x 90 x 90
  cases.push_back({"wrong_header", "90 x 90 x 90", header});
  auto longer = good;
  longer.push_back(0);
  cases.push_back({"too_long", "longer", longer});
  auto nan = good;
  const double q = std::nan("");
  std::memcpy(&nan[12 + 8 * 1000], &q, 8);
  cases.push_back({"nan", "nan", nan});
  for (const auto& c : cases) {
    const mf::TempTable file(mf::temp_path("bad_" + c.name));
    mf::write_bytes(file.path, c.bytes);
    try {
      read_merl(file.path);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file.path), std::string::npos) << c.name << ": " << msg;
      EXPECT_NE(msg.find(c.expect), std::string::npos) << c.name << ": " << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << c.name << ": " << msg;
    }
  }
  EXPECT_THROW(read_merl(mf::temp_path("does_not_exist")), InputError);
  EXPECT_THROW(read_merl(std::filesystem::temp_directory_path().string()), InputError);
  // Through the material parser, the message also names the type.
  try {
    measured(mf::temp_path("does_not_exist"));
    ADD_FAILURE() << "missing file accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("measured: "), std::string::npos) << e.what();
  }
}

// Issue 39: the bound MerlTable::kMaxValue = 1e30 1/sr on f. In memory (parse_merl, the
// bytes of a file): an entry just above it is refused naming entry and channel, one at it is
// held; a negative entry of any size is "not measured". write_merl refuses to write what
// the reader would refuse, so that every table gonio writes reads back.
TEST(MerlFormat, ValuesAboveTheBoundAreNeitherReadNorWritten) {
  auto bytes = mf::table_bytes([](int, int, int, int) { return 0.1; });
  const auto store = [&bytes](int channel, std::size_t entry, double f) {
    const double stored = f / mf::kScale[channel];
    std::memcpy(&bytes[12 + 8 * (std::size_t(channel) * mf::kN + entry)], &stored, 8);
  };
  store(2, 7, 1e30);        // at the bound
  store(0, 8, -1e300);      // not measured, however large
  const MerlTable at = parse_merl(bytes, "t.binary");
  EXPECT_EQ(at.rgb[3 * 7 + 2], 1e30f);
  EXPECT_EQ(at.rgb[3 * 8 + 0], MerlTable::kMissing);
  store(1, 9, 1.0001e30);   // just above it
  try {
    parse_merl(bytes, "t.binary");
    ADD_FAILURE() << "1.0001e30 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.binary: MERL entry (0, 0, 9) of channel g"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1e+30"), std::string::npos) << e.what();
  }
  MerlTable t;
  t.rgb[3 * 5 + 1] = 1e30f;
  const mf::TempTable file(mf::temp_path("bound_write"));
  write_merl(file.path, t);
  EXPECT_EQ(read_merl(file.path).rgb[3 * 5 + 1], 1e30f);
  for (const float bad : {1.0001e30f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    t.rgb[3 * 6 + 2] = bad;
    EXPECT_THROW(write_merl(file.path, t), InputError) << bad;
    EXPECT_EQ(read_merl(file.path).rgb[3 * 5 + 1], 1e30f);  // the file is left as it was
  }
}

// --- half/difference angles ----------------------------------------------------------

TEST(HalfDiff, MatchesRusinkiewiczFramesAndFoldsByReciprocity) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 2000; ++n) {
    const double th = u(rng) * kPiD / 2 * 0.95, td = u(rng) * kPiD / 2 * 0.95, pd = u(rng) * 2 * kPiD;
    const auto [wo, wi] = directions(th, td, pd);
    const HalfDiff a = half_diff(to_vec(wo), to_vec(wi));
    EXPECT_NEAR(a.theta_h, th, 2e-6);
    EXPECT_NEAR(a.theta_d, td, 2e-6);
    EXPECT_GE(a.phi_d, 0);  // folded into [0, π) (SPEC §2)
    EXPECT_LT(a.phi_d, kPiD);
    const double folded = std::fmod(pd, kPiD);
    const double dphi = std::abs(a.phi_d - folded);
    EXPECT_LT(std::min(dphi, kPiD - dphi), 1e-4 / std::max(std::sin(td), 1e-3)) << th << " " << td << " " << pd;
    // Swapping the directions adds π to φd: the same folded entry.
    const HalfDiff b = half_diff(to_vec(wi), to_vec(wo));
    const double dswap = std::abs(a.phi_d - b.phi_d);
    EXPECT_LT(std::min(dswap, kPiD - dswap), 1e-4 / std::max(std::sin(td), 1e-3));
    // merl_directions is the inverse.
    const auto [o2, i2] = merl_directions(th, td, pd);
    EXPECT_NEAR(o2.x, wo.x, 1e-6);
    EXPECT_NEAR(o2.z, wo.z, 1e-6);
    EXPECT_NEAR(i2.y, wi.y, 1e-6);
    EXPECT_NEAR(i2.z, wi.z, 1e-6);
  }
}

// --- evaluation --------------------------------------------------------------------------

// A table written from GGX reads back to GGX at the bin centres, within float rounding.
TEST(Measured, ReadsBackTheTabulatedModelAtBinCentres) {
  const BxDF m = measured(ggx_table_path());
  std::mt19937 rng(5);
  int checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const int i = int(rng() % 90), j = int(rng() % 90), k = int(rng() % 180);
    const auto [wo, wi] = directions(mf::theta_h(i), mf::theta_d(j), mf::phi_d(k));
    if (wo.z < 0.05 || wi.z < 0.05) continue;
    const double want = ggx_f(wo, wi, 0.2, 0.8);
    const Color got = m.f(to_vec(wo), to_vec(wi));
    ASSERT_NEAR(got[0], want, 2e-4 * want + 1e-6) << i << " " << j << " " << k;
    ++checked;
  }
  EXPECT_GT(checked, 10000);
}

// The expected value of the scheme of measured_data.h, written out: trilinear in
// u = 90 √(θh/(π/2)) − ½, v = θd/1° − ½ (both clamped to the outermost centres) and
// w = φd/1° − ½ (periodic, 180), measured neighbours only.
double interpolate(const std::function<double(int, int, int)>& g, double th, double td, double pd) {
  auto clamp_axis = [](double c, int n, int& i0, double& t) {
    c = std::min(std::max(c, 0.0), double(n - 1));
    i0 = std::min(int(c), n - 2);
    t = c - i0;
  };
  int i0, j0;
  double ti, tj;
  clamp_axis(90 * std::sqrt(th / (kPiD / 2)) - 0.5, 90, i0, ti);
  clamp_axis(td * 180 / kPiD - 0.5, 90, j0, tj);
  double w = pd * 180 / kPiD - 0.5;
  w -= 180 * std::floor(w / 180);
  const int k0 = std::min(int(w), 179), k1 = (k0 + 1) % 180;
  const double tk = w - k0;
  double acc = 0, sum = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        const double v = g(i0 + a, j0 + b, c ? k1 : k0);
        if (v < 0) continue;
        const double wt = (a ? ti : 1 - ti) * (b ? tj : 1 - tj) * (c ? tk : 1 - tk);
        acc += wt * v, sum += wt;
      }
  return sum > 0 ? acc / sum : 0;
}

double smooth(int i, int j, int k) { return 1 + 0.01 * i + 0.02 * j + 0.3 * std::cos(2 * kPiD * (k + 0.5) / 180); }
double holes(int i, int j, int k) { return (k % 2 == 1 || (i == 40 && j == 40)) ? -1.0 : smooth(i, j, k); }

TEST(Measured, InterpolatesTrilinearlyInTheTableCoordinatesWithEdgesAndHoles) {
  for (auto* g : {&smooth, &holes}) {
    const mf::TempTable file(mf::temp_path(g == &smooth ? "smooth" : "holes"));
    mf::write_bytes(file.path, mf::table_bytes([g](int i, int j, int k, int) { return (*g)(i, j, k); }));
    const BxDF m = measured(file.path);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (int n = 0; n < 4000; ++n) {
      // Edges included: θh below the first centre, θd beyond the last, φd across the seam.
      double th = u(rng) * kPiD / 2 * 0.9, td = u(rng) * kPiD / 2, pd = u(rng) * 2 * kPiD;
      if (n % 4 == 1) th = u(rng) * 4e-5;
      if (n % 4 == 2) td = (89.5 + 0.5 * u(rng)) * kPiD / 180;
      if (n % 4 == 3) pd = (u(rng) - 0.5) * 0.02;
      const auto [wo, wi] = directions(th, td, pd);
      if (wo.z < 1e-3 || wi.z < 1e-3) continue;
      const double want = interpolate(*g, th, td, pd);
      const Color got = m.f(to_vec(wo), to_vec(wi));
      ASSERT_NEAR(got[1], want, 2e-4 * want) << th << " " << td << " " << pd;
    }
    // The table's far corner, past the last θh and θd centres: both coordinates clamped
    // to the last centre, the value that of the last entries, interpolated along φd.
    int corner_points = 0;
    for (const double th_deg : {89.2, 89.9})
      for (const double td_deg : {89.6, 89.95})
        for (const double pd_deg : {90.0, 45.0, 1.0}) {
          const double th = th_deg * kPiD / 180, td = td_deg * kPiD / 180, pd = pd_deg * kPiD / 180;
          const auto [wo, wi] = directions(th, td, pd);
          if (!(wo.z > 0 && wi.z > 0)) continue;
          const double want = interpolate(*g, th, td, pd);
          EXPECT_NEAR(m.f(to_vec(wo), to_vec(wi))[1], want, 2e-4 * want) << th_deg << " " << td_deg << " " << pd_deg;
          ++corner_points;
        }
    EXPECT_GE(corner_points, 4);
    if (g == &holes) {
      // All eight neighbours of the point between centres (40, 40) and (41, 41) at an odd k
      // and its even neighbour: (40, 40, ·) is missing, the others not.
      const auto [wo, wi] = directions(std::pow(41.0 / 90, 2) * kPiD / 2, 41.0 * kPiD / 180, 20.7 * kPiD / 180);
      EXPECT_NEAR(m.f(to_vec(wo), to_vec(wi))[0], interpolate(holes, std::pow(41.0 / 90, 2) * kPiD / 2, 41.0 * kPiD / 180,
                                                               20.7 * kPiD / 180),
                  1e-4);
    }
  }
  // All neighbours missing: 0.
  const mf::TempTable empty(mf::temp_path("empty"));
  mf::write_bytes(empty.path, mf::table_bytes([](int, int, int, int) { return -1.0; }));
  const BxDF m = measured(empty.path);
  const Vec3 w = normalize(Vec3{0.3f, 0.2f, 1});
  EXPECT_EQ(m.f(w, w)[0], 0);
  EXPECT_EQ(m.pdf(w, w), cosine_hemisphere_pdf(w.z));  // no table: cosine sampling
}

// Between bin centres, the interpolated GGX table stays within the error bound of
// trilinear interpolation, (1/8) Σ_axes h² |∂²f/∂x²| (the second differences of the closed
// form over the cell, taken at its corners; Burden & Faires, linear interpolation error).
TEST(Measured, BetweenBinsWithinTheInterpolationError) {
  const BxDF m = measured(ggx_table_path());
  auto f_at = [](int i, int j, int k) {
    const auto [wo, wi] = directions(mf::theta_h(i), mf::theta_d(j), mf::phi_d((k + 180) % 180));
    return ggx_f(wo, wi, 0.2, 0.8);
  };
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0, 1);
  int checked = 0;
  for (int n = 0; n < 3000; ++n) {
    const double uc = 1 + u(rng) * 80, vc = 1 + u(rng) * 60, wc = u(rng) * 179;
    const double th = std::pow((uc + 0.5) / 90, 2) * kPiD / 2, td = (vc + 0.5) * kPiD / 180, pd = (wc + 0.5) * kPiD / 180;
    const auto [wo, wi] = directions(th, td, pd);
    if (wo.z < 0.1 || wi.z < 0.1) continue;
    const int i0 = int(uc), j0 = int(vc), k0 = int(wc);
    double bound = 0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const int i = i0 + a, j = j0 + b, k = k0 + c;
          if (i + 1 > 89 || j + 1 > 89) continue;
          const double f0 = f_at(i, j, k);
          const double d2 = std::abs(f_at(i + 1, j, k) - 2 * f0 + f_at(i - 1, j, k)) +
                            std::abs(f_at(i, j + 1, k) - 2 * f0 + f_at(i, j - 1, k)) +
                            std::abs(f_at(i, j, k + 1) - 2 * f0 + f_at(i, j, k - 1));
          bound = std::max(bound, d2 / 8);
        }
    const double want = ggx_f(wo, wi, 0.2, 0.8);
    const double got = m.f(to_vec(wo), to_vec(wi))[0];
    // Twice the bound: the second differences estimate the curvature over the cell.
    ASSERT_LE(std::abs(got - want), 2 * bound + 2e-4 * want + 1e-6) << th << " " << td << " " << pd;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(Measured, ReflectsOnBothSidesAndNeverAcross) {
  const BxDF m = measured(ggx_table_path());
  const Vec3 wo = normalize(Vec3{0.3f, 0.1f, 0.8f}), wi = normalize(Vec3{-0.2f, 0.3f, 0.9f});
  const Vec3 wo_b{wo.x, wo.y, -wo.z}, wi_b{wi.x, wi.y, -wi.z};
  EXPECT_EQ(m.f(wo, wi)[0], m.f(wo_b, wi_b)[0]);
  EXPECT_EQ(m.pdf(wo, wi), m.pdf(wo_b, wi_b));
  EXPECT_EQ(m.f(wo, wi_b)[0], 0);
  EXPECT_EQ(m.pdf(wo, wi_b), 0);
  for (float u : {0.05f, 0.5f, 0.95f}) {
    const auto s = m.sample(wo_b, u, 0.3f, 0.6f);
    ASSERT_TRUE(s);
    EXPECT_LT(s->wi.z, 0);
  }
}

// eval computes f and the pdf together (their arctangents in one vector): it must give
// f() and pdf() bit for bit, at random pairs, near normal and grazing incidence, for
// directions off unit length, and f and pdf must stay finite and non-negative.
TEST(Measured, EvalIsFAndPdfBitForBit) {
  const BxDF m = measured(ggx_table_path());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  auto direction = [&](int kind) {
    Vec3 w = square_to_uniform_hemisphere(u(rng), u(rng));
    if (kind == 1) w = normalize(Vec3{w.x, w.y, w.z * 1e-4f});   // grazing
    if (kind == 2) w = normalize(Vec3{w.x * 1e-4f, w.y * 1e-4f, w.z});  // near the normal
    if (kind == 3) w = Vec3{w.x * 1.001f, w.y * 0.999f, w.z * 1.0005f};  // off unit length
    return w;
  };
  for (int n = 0; n < 20000; ++n) {
    const Vec3 wo = direction(n % 4), wi = direction((n / 4) % 4);
    const BSDFEval e = m.eval(wo, wi);
    const Color f = m.f(wo, wi);
    const Float p = m.pdf(wo, wi);
    for (int c = 0; c < 3; ++c) {
      const Float a = e.f[c], b = f[c];
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << n << " channel " << c << ": " << a << " vs " << b;
    }
    ASSERT_EQ(std::memcmp(&e.pdf, &p, sizeof p), 0) << n;
    ASSERT_TRUE(f.is_finite() && f.min_component() >= 0 && std::isfinite(p) && p >= 0) << n;
  }
}

// --- tabulation ----------------------------------------------------------------------

TEST(Tabulate, RefusesWhatATableCannotHold) {
  EXPECT_THROW(tabulate(parse_material(R"({"type":"roughconductor","alpha":[0.1,0.3],"material":"Au"})")), InputError);
  EXPECT_THROW(tabulate(parse_material(R"({"type":"conductor","material":"Au"})")), InputError);
  EXPECT_THROW(tabulate(parse_material(R"({"type":"plastic"})")), InputError);  // smooth coat: a delta lobe
  // Below-horizon centres are written as not measured; the rest as f.
  const MerlTable t = tabulate(parse_material(R"({"type":"diffuse","reflectance":0.5})"));
  const auto [wo, wi] = directions(mf::theta_h(89), mf::theta_d(80), mf::phi_d(0));
  ASSERT_TRUE(wo.z < 0 || wi.z < 0);
  EXPECT_FALSE(t.measured(89, 80, 0));
  EXPECT_NEAR(t.at(10, 10, 10)[0], 0.5 / kPiD, 1e-7);
}

// --- sampling ----------------------------------------------------------------------

// The validator's properties (chi2, pdf_integral, consistency, energy, reciprocity,
// weights, ...) hold on a glossy and a diffuse table. A tenth of the validator's default
// counts: the measured model is the slowest to sample.
TEST(Measured, ValidatorPasses) {
  ValidationOptions o;
  o.scale = double(test::scaled(100000, 1)) / 1e6;
  for (const std::string& path : {ggx_table_path(), gonio_test_merl::lambert_table()}) {
    const ValidationReport r = validate(measured(path), o);
    for (const auto& p : r.properties) EXPECT_TRUE(p.pass) << path << ": " << p.name << ": " << p.detail;
  }
}

// Issue 12: the tabulated sampling must cut the variance of cosine-weighted sampling at
// least tenfold on a glossy table. The estimator is of the directional albedo (channel 0).
TEST(Measured, SamplingCutsTheVarianceOfCosineSamplingTenfold) {
  const mf::TempTable file(mf::temp_path("glossy"));
  write_merl(file.path, tabulate(parse_material(R"({"type":"roughconductor","alpha":0.1,"fresnel":"schlick","f0":0.9})")));
  const BxDF m = measured(file.path);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0, 0.99999f);
  const std::uint64_t n = test::scaled(200000, 20000);
  for (double theta_deg : {0.0, 30.0, 60.0}) {
    const double t = theta_deg * kPiD / 180;
    const Vec3 wo{Float(std::sin(t)), 0, Float(std::cos(t))};
    double s1 = 0, s2 = 0, c1 = 0, c2 = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
      const auto s = m.sample(wo, u(rng), u(rng), u(rng));
      const double w = s ? s->weight[0] : 0;
      s1 += w, s2 += w * w;
      const Vec3 wi = square_to_cosine_hemisphere(u(rng), u(rng));
      const double wc = wi.z > 0 ? m.f(wo, wi)[0] * kPiD : 0;  // f cos / (cos/π)
      c1 += wc, c2 += wc * wc;
    }
    const double var_model = s2 / double(n) - std::pow(s1 / double(n), 2);
    const double var_cos = c2 / double(n) - std::pow(c1 / double(n), 2);
    EXPECT_GT(var_cos / var_model, 10) << "theta " << theta_deg << ": variance " << var_model << " vs cosine " << var_cos;
  }
}

// --- spectral mode -------------------------------------------------------------------

TEST(Measured, SpectralValueOfAGreyTableIsItsValueAtEveryWavelength) {
  const MaterialWithSpectra m =
      parse_material_with_spectra(R"({"type":"measured","file":")" + gonio_test_merl::lambert_table() + R"("})");
  SpectralScratch scratch;
  const Vec3 wo = normalize(Vec3{0.3f, 0.1f, 0.8f}), wi = normalize(Vec3{-0.2f, 0.3f, 0.9f});
  for (Float lambda : {380.0f, 550.0f, 700.0f}) {
    SampledWavelengths w = SampledWavelengths::single(lambda);
    const SpectralBxDF s = to_spectral(m.bxdf, m.spectra, w, scratch);
    EXPECT_NEAR(s.f(wo, wi)[0], 0.5 / kPiD, 1e-5) << lambda;
  }
}

}  // namespace
}  // namespace gonio
