// The CLI conveniences of issue 10 (SPEC §3 additions): fresnel --theta-range and
// --material, albedo --theta-range, sample --count/--seed, and --bsdf @file saying why a
// file cannot be used. Each is checked against runs of the plain form at the same inputs,
// or against values computed here.

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gonio/metals.h"
#include "gonio/rng.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

// Every line of a --theta-range run is the line of the --theta run at its angle, byte for byte.
void expect_range_equals_single_runs(const std::vector<std::string>& base, const std::vector<std::string>& range,
                                     const std::vector<double>& angles) {
  std::vector<std::string> args = base;
  args.insert(args.end(), range.begin(), range.end());
  const RunResult r = run_gonio(args);
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), angles.size()) << r.out;
  for (size_t i = 0; i < angles.size(); ++i) {
    std::vector<std::string> single = base;
    single.insert(single.end(), {"--theta", fmt(angles[i])});
    const RunResult s = run_gonio(single);
    ASSERT_EQ(s.status, 0) << describe(s);
    EXPECT_EQ(lines[i] + "\n", s.out) << "angle " << angles[i];
  }
}

TEST(CliFresnelRange, LinesEqualSingleAngleRuns) {
  // 0, 15, ..., 90: both ends included, evenly spaced.
  expect_range_equals_single_runs({"fresnel", "--eta", "1.5", "--schlick"}, {"--theta-range", "0", "90", "7"},
                                  {0, 15, 30, 45, 60, 75, 90});
  // Descending, a conductor, and an index below 1 (total internal reflection past 41.8°).
  expect_range_equals_single_runs({"fresnel", "--eta", "0.2", "--k", "3"}, {"--theta-range", "80", "20", "4"},
                                  {80, 60, 40, 20});
  expect_range_equals_single_runs({"fresnel", "--eta", "0.6667"}, {"--theta-range", "30", "50", "5"},
                                  {30, 35, 40, 45, 50});
  // COUNT 1: FROM alone.
  expect_range_equals_single_runs({"fresnel", "--eta", "1.33"}, {"--theta-range", "30", "60", "1"}, {30});
}

TEST(CliFresnelRange, BadRangesAreOneLineErrors) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta-range", "0", "95", "3"}), {"--theta-range", "95"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta-range", "-1", "10", "3"}), {"--theta-range", "-1"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta-range", "0", "90", "0"}), {"COUNT", "0"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta-range", "0", "90", "2.5"}), {"COUNT", "2.5"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta-range", "0", "90"}), {"--theta-range"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "10", "--theta-range", "0", "90", "3"}),
                   {"--theta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5"}), {"--theta"});
}

// --material Au: each channel equals --eta/--k at the metal's index for that channel (the
// RGB-mode index of SPEC §2, which gonio's tables hold).
TEST(CliFresnelMaterial, MetalChannelsEqualTheirIndex) {
  const auto au = gonio::named_metal("Au");
  ASSERT_TRUE(au);
  for (const char* theta : {"0", "45", "80"}) {
    const json m = run_one({"fresnel", "--material", "Au", "--theta", theta, "--schlick"});
    for (int c = 0; c < 3; ++c) {
      const json one = run_one({"fresnel", "--eta", fmt(au->eta[c]), "--k", fmt(au->k[c]), "--theta", theta, "--schlick"});
      for (const char* key : {"Rs", "Rp", "R", "T", "schlick"}) {
        ASSERT_TRUE(m[key].is_array() && m[key].size() == 3) << m.dump();
        EXPECT_EQ(m[key][size_t(c)], one[key]) << key << " channel " << c << " at " << theta;
      }
      EXPECT_TRUE(m["cos_t"][size_t(c)].is_null()) << m.dump();  // a conductor refracts nothing
    }
  }
  // A range of angles with a named metal: one line per angle.
  const RunResult r = run_gonio({"fresnel", "--material", "Cu", "--theta-range", "0", "90", "10"});
  EXPECT_EQ(parse_json_lines(r).size(), 10u) << describe(r);
}

// --material METAL at 0°: R per channel is the colour (linear sRGB, D65, CIE 1931 2°) of
// the metal's measured reflectance spectrum, capped at 0.999 (docs/spectral.md, "Named metals in RGB mode"), as
// tests/reference/models_reference.py computes it (metal_reflectance_rgb), not gonio. The
// constants are floats: 1e-6.
TEST(CliFresnelMaterial, MetalNormalIncidenceIsTheColourOfTheSpectrum) {
  struct Case {
    const char* name;
    double r[3];
  };
  const Case cases[] = {
      {"Au", {0.999000000, 0.782537045, 0.343359374}},   {"Ag", {0.971517445, 0.960016165, 0.915152749}},
      {"Cu", {0.955338540, 0.637667351, 0.538080668}},   {"Al", {0.913176893, 0.921572356, 0.924295352}},
      {"CuZn", {0.909675595, 0.778324856, 0.422773529}},
  };
  for (const Case& c : cases) {
    const json m = run_one({"fresnel", "--material", c.name, "--theta", "0"});
    ASSERT_TRUE(m["R"].is_array() && m["R"].size() == 3) << m.dump();
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(m["R"][i].get<double>(), c.r[i], 1e-6) << c.name << " channel " << i;
      EXPECT_NEAR(m["T"][i].get<double>(), 1 - c.r[i], 1e-6) << c.name << " channel " << i;
    }
  }
}

// A named glass: R at normal incidence ((n - 1)/(n + 1))² with n from BK7's Sellmeier
// formula (Schott's coefficients, written here) at 650, 550, 450 nm; the table gonio reads
// is interpolated linearly, within 1e-4 of the formula.
// (R = 0.0426 at n = 1.5185: an error of 1e-4 in n would change R by 1.3e-5.)
TEST(CliFresnelMaterial, GlassChannelsFollowSellmeier) {
  const double B[3] = {1.03961212, 0.231792344, 1.01046945}, C[3] = {0.00600069867, 0.0200179144, 103.560653};
  const json m = run_one({"fresnel", "--material", "BK7", "--theta", "0"});
  const double nm[3] = {650, 550, 450};
  for (int c = 0; c < 3; ++c) {
    const double l2 = (nm[c] / 1000) * (nm[c] / 1000);
    double n2 = 1;
    for (int i = 0; i < 3; ++i) n2 += B[i] * l2 / (l2 - C[i]);
    const double n = std::sqrt(n2);
    ASSERT_TRUE(m["R"].is_array()) << m.dump();
    // The index gonio used, from R = ((n - 1)/(n + 1))².
    const double s = std::sqrt(m["R"][size_t(c)].get<double>());
    EXPECT_NEAR((1 + s) / (1 - s), n, 1e-4) << "channel " << c;
    EXPECT_NEAR(m["cos_t"][size_t(c)].get<double>(), 1.0, 1e-12);
  }
  // Dispersion: blue bends more than red.
  EXPECT_GT(m["R"][2].get<double>(), m["R"][0].get<double>());
}

TEST(CliFresnelMaterial, Errors) {
  expect_bad_input(run_gonio({"fresnel", "--material", "Unobtainium", "--theta", "0"}), {"Unobtainium", "Au", "BK7"});
  expect_bad_input(run_gonio({"fresnel", "--material", "Au", "--eta", "1.5", "--theta", "0"}), {"--eta"});
  expect_bad_input(run_gonio({"fresnel", "--material", "Au", "--k", "1", "--theta", "0"}), {"--k"});
}

TEST(CliAlbedoRange, LinesEqualSingleAngleRuns) {
  // Monte Carlo (a rough conductor) and closed form (a dielectric); each angle uses the seed.
  expect_range_equals_single_runs(
      {"albedo", "--bsdf", R"({"type":"roughconductor","alpha":0.3,"material":"Au"})", "--samples", "4096", "--seed", "5"},
      {"--theta-range", "0", "80", "5"}, {0, 20, 40, 60, 80});
  expect_range_equals_single_runs({"albedo", "--bsdf", R"({"type":"dielectric"})", "--inside", "--phi", "30"},
                                  {"--theta-range", "10", "70", "3"}, {10, 40, 70});
  expect_bad_input(run_gonio({"albedo", "--bsdf", R"({"type":"diffuse"})", "--hemispherical", "--theta-range", "0", "9", "2"}),
                   {"--hemispherical"});
  expect_bad_input(run_gonio({"albedo", "--bsdf", R"({"type":"diffuse"})", "--theta-range", "0", "91", "2"}),
                   {"--theta-range", "91"});
}

// sample --count: N samples per 'wo' line from gonio's own u's.
TEST(CliSampleCount, ReproducibleUnitDirectionsUniformU) {
  const std::vector<std::string> args = {"sample", "--bsdf", R"({"type":"diffuse","reflectance":[0.2,0.4,0.6]})",
                                         "--count", "2000", "--seed", "7"};
  const std::string wo = "0 0 1\n0.5 0 1\n";
  const RunResult a = run_gonio(args, wo), b = run_gonio(args, wo);
  ASSERT_EQ(a.status, 0) << describe(a);
  EXPECT_EQ(a.out, b.out) << "not reproducible for a fixed seed";
  std::vector<std::string> other = args;
  other.back() = "8";
  EXPECT_NE(run_gonio(other, wo).out, a.out) << "the seed changes nothing";
  const auto lines = parse_json_lines(a);
  ASSERT_EQ(lines.size(), 4000u);
  // Lambert samples cos θ with density 2 cos θ: cos²θ is uniform on [0, 1] (mean 1/2,
  // standard deviation of the mean sqrt(1/12/4000) = 0.0046).
  double sum_z2 = 0;
  for (const auto& s : lines) {
    const auto w = color3(s["wi"]);
    EXPECT_NEAR(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], 1.0, 1e-6) << s.dump();
    EXPECT_GT(w[2], 0) << s.dump();
    const auto weight = color3(s["weight"]);
    EXPECT_NEAR(weight[0], 0.2, 1e-6);
    EXPECT_NEAR(weight[2], 0.6, 1e-6);
    sum_z2 += w[2] * w[2];
  }
  EXPECT_NEAR(sum_z2 / 4000, 0.5, 5 * 0.0046);
}

// --count on line i draws (u0, u1, u2) from PCG32 (O'Neill 2014) with the seed and stream i:
// the same samples as the plain form fed those u's.
TEST(CliSampleCount, EqualsThePlainFormWithPcg32Numbers) {
  const std::string bsdf = R"({"type":"roughdielectric","alpha":0.3,"eta":1.5})";
  const std::string wo = "0.3 0 1\n-0.2 0.1 -1\n";
  const RunResult counted = run_gonio({"sample", "--bsdf", bsdf, "--count", "50", "--seed", "11"}, wo);
  ASSERT_EQ(counted.status, 0) << describe(counted);
  std::string plain_in;
  const char* wos[2] = {"0.3 0 1", "-0.2 0.1 -1"};
  for (std::uint64_t line = 0; line < 2; ++line) {
    gonio::Pcg32 rng(11, line);
    for (int n = 0; n < 50; ++n) {
      const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
      plain_in += std::string(wos[line]) + " " + fmt(u0) + " " + fmt(u1) + " " + fmt(u2) + "\n";
    }
  }
  const RunResult plain = run_gonio({"sample", "--bsdf", bsdf}, plain_in);
  ASSERT_EQ(plain.status, 0) << describe(plain);
  EXPECT_EQ(counted.out, plain.out);
}

TEST(CliSampleCount, Errors) {
  const std::string d = R"({"type":"diffuse"})";
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--count", "3"}, "0 0 1 0.5 0.5 0.5\n"),
                   {"stdin line 1", "expected 3 numbers", "got more"});
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--count", "3"}, "0 0 1\n0 0\n"), {"stdin line 2", "got 2"});
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--count", "3"}, "0 0 0\n"), {"stdin line 1", "zero"});
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--count", "0"}, "0 0 1\n"), {"--count"});
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--count", "x"}, "0 0 1\n"), {"--count"});
  expect_bad_input(run_gonio({"sample", "--bsdf", d, "--seed", "3"}, "0 0 1 0.5 0.5 0.5\n"), {"--seed", "--count"});
  // Without --count a line needs its u's.
  expect_bad_input(run_gonio({"sample", "--bsdf", d}, "0 0 1\n"), {"stdin line 1", "expected 6 numbers"});
}

// --bsdf @file says why the file cannot be used.
TEST(CliBsdfFile, SaysWhy) {
  const std::string dir = std::filesystem::temp_directory_path() / ("gonio_cli_bsdf_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string missing = dir + "/missing.json";
  expect_bad_input(run_gonio({"eval", "--bsdf", "@" + missing}, "0 0 1 0 0 1\n"), {"--bsdf", missing, "file not found"});
  expect_bad_input(run_gonio({"eval", "--bsdf", "@" + dir}, "0 0 1 0 0 1\n"), {"--bsdf", dir, "is a directory"});
  // A readable file works, a path through a regular file is not found.
  const std::string good = dir + "/good.json";
  { std::ofstream(good) << R"({"type":"diffuse"})"; }
  EXPECT_EQ(run_gonio({"eval", "--bsdf", "@" + good}, "0 0 1 0 0 1\n").status, 0);
  expect_bad_input(run_gonio({"eval", "--bsdf", "@" + good + "/x.json"}, "0 0 1 0 0 1\n"), {"--bsdf", "good.json/x.json"});
  // Unreadable: only testable without root's override of file permissions.
  const std::string locked = dir + "/locked.json";
  { std::ofstream(locked) << R"({"type":"diffuse"})"; }
  ::chmod(locked.c_str(), 0);
  if (::geteuid() != 0)
    expect_bad_input(run_gonio({"eval", "--bsdf", "@" + locked}, "0 0 1 0 0 1\n"), {"--bsdf", locked, "not readable"});
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gonio_cli_test
