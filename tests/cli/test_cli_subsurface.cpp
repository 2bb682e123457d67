// gonio subsurface (SPEC §3): one JSON line with Rd, stderr and the profile; --help; bad
// media are one line with exit 2. The physics is tested at library level
// (tests/unit/test_subsurface_*.cpp); here only the command.

#include <cmath>
#include <string>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

const char* kMilk = R"({"type":"subsurface","albedo":[0.9,0.6,0.3],"mfp":1})";

TEST(CliSubsurface, PrintsOneLineWithRdStderrAndProfile) {
  const RunResult r = run_gonio({"subsurface", "--bsdf", kMilk, "--samples", "3000", "--seed", "3"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 1u) << r.out;
  const json j = json::parse(lines[0]);
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 3u) << lines[0];
  const auto rd = color3(j.at("Rd")), se = color3(j.at("stderr"));
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(rd[size_t(c)], 0);
    EXPECT_LT(rd[size_t(c)], 1);
    EXPECT_GT(se[size_t(c)], 0);
  }
  // A redder medium: the albedo's order is kept.
  EXPECT_GT(rd[0], rd[1]);
  EXPECT_GT(rd[1], rd[2]);
  const json& profile = j.at("profile");
  ASSERT_TRUE(profile.is_array());
  EXPECT_EQ(profile.size(), 40u);
  double last_r = 0;
  for (const json& p : profile) {
    ASSERT_TRUE(p.is_array() && p.size() == 2) << p.dump();
    const double radius = p[0].get<double>();
    EXPECT_GT(radius, last_r);
    last_r = radius;
    const auto v = color3(p[1]);
    for (double x : v) EXPECT_TRUE(std::isfinite(x) && x >= 0) << p.dump();
  }
  // Deterministic for a seed.
  const RunResult again = run_gonio({"subsurface", "--bsdf", kMilk, "--samples", "3000", "--seed", "3"});
  EXPECT_EQ(again.out, r.out);
}

// "method": "diffusion" answers from the profile: the same line, a zero standard error.
TEST(CliSubsurface, DiffusionMethodPrintsTheSameLine) {
  const RunResult r =
      run_gonio({"subsurface", "--bsdf", R"({"type":"subsurface","medium":"skin1","method":"diffusion"})"});
  ASSERT_EQ(r.status, 0) << describe(r);
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 1u) << r.out;
  const json j = json::parse(lines[0]);
  EXPECT_EQ(j.size(), 3u) << lines[0];
  for (double x : color3(j.at("stderr"))) EXPECT_EQ(x, 0);
  for (double x : color3(j.at("Rd"))) EXPECT_TRUE(x > 0 && x < 1) << lines[0];
  EXPECT_EQ(j.at("profile").size(), 40u);
}

TEST(CliSubsurface, ReadsAFileAndPrintsHelp) {
  TempFile f(R"({"type":"subsurface","medium":"ketchup","scale":0.1})");
  const RunResult r = run_gonio({"subsurface", "--bsdf", "@" + f.path(), "--samples", "500"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(split_lines(r.out).size(), 1u);
  const RunResult h = run_gonio({"subsurface", "--help"});
  EXPECT_EQ(h.status, 0);
  for (const char* m : {"--bsdf", "--samples", "--seed"}) EXPECT_TRUE(contains_ci(h.out, m)) << h.out;
}

TEST(CliSubsurface, BadInputIsOneLineExitTwo) {
  expect_bad_input(run_gonio({"subsurface", "--bsdf", R"({"type":"subsurface","sigma_s":-1,"sigma_a":0})"}),
                   {"sigma_s", "-1"});
  expect_bad_input(run_gonio({"subsurface", "--bsdf", R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"g":1.5})"}),
                   {"g", "1.5"});
  expect_bad_input(run_gonio({"subsurface", "--bsdf", R"({"type":"subsurface","medium":"jade"})"}),
                   {"medium", "jade", "marble"});
  expect_bad_input(run_gonio({"subsurface", "--bsdf", R"({"type":"subsurface","albedo":1.2,"mfp":1})"}),
                   {"albedo", "1.2"});
  expect_bad_input(run_gonio({"subsurface", "--bsdf", R"({"type":"diffuse"})"}), {"subsurface", "diffuse"});
  expect_bad_input(run_gonio({"subsurface", "--bsdf", "{"}));
  expect_bad_input(run_gonio({"subsurface", "--bsdf", kMilk, "--samples", "0"}), {"--samples"});
  expect_bad_input(run_gonio({"subsurface"}), {"--bsdf"});
}

}  // namespace
}  // namespace gonio_cli_test
