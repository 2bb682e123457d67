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

// Issue 39: media so thin that a transport mean free path 1/σt′ overflows a float gave
// infinite radii (exit 3, "a non-finite value reached the output"); they are refused with
// the documented range (σt′ = σa + (1 − g) σs is 0 or at least 1e-15 per unit), by either
// method and whichever coefficient is tiny. At the bound the answer is finite.
TEST(CliSubsurface, TinyMediaAreRefusedWithTheirRange) {
  for (const char* method : {"randomwalk", "diffusion"})
    for (const std::string medium : {R"("sigma_s":1e-38,"sigma_a":1e-38)", R"("sigma_s":2e-38,"sigma_a":2e-38)",
                                     R"("sigma_s":1e-38,"sigma_a":0)", R"("sigma_s":0,"sigma_a":2e-38)",
                                     R"("sigma_s":[1,1,1e-20],"sigma_a":0)", R"("sigma_s":1e-9,"sigma_a":0,"g":0.9999999)"}) {
      const std::string bsdf = R"({"type":"subsurface",)" + medium + R"(,"method":")" + method + R"("})";
      expect_bad_input(run_gonio({"subsurface", "--bsdf", bsdf, "--samples", "4000"}), {"transport coefficient", "1e-15"});
    }
  for (const char* method : {"randomwalk", "diffusion"}) {
    const std::string bsdf = R"({"type":"subsurface","sigma_s":[1e-15,1,0],"sigma_a":0,"method":")" + std::string(method) + R"("})";
    const json out = run_one({"subsurface", "--bsdf", bsdf, "--samples", "500"});
    const auto rd = color3(out["Rd"]);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(rd[c])) << out.dump();
    EXPECT_EQ(rd[2], 0);  // a clear channel (σt′ = 0) returns nothing
  }
}

// Issue 39: Rd never exceeds what crosses the boundary, 1 − F(0) with
// F(0) = ((η − 1)/(η + 1))² (Fresnel at normal incidence, computed here), by either method,
// over single-scattering albedos up to 1 (σa = 0), g and η. Photon beam diffusion reported
// 1.0119 at η = 1.33 without absorption; its profile is now divided by its total where that
// exceeds what entered (docs/subsurface.md), so a medium without absorption returns at most
// 1 − F(0) and, the exact answer being 1 − F(0), not much less (PBD: 0.96 of it at g = 0.7). The walk is exact: only its
// noise may cross the bound.
void expect_rd_within_what_enters(double eta, const std::string& medium, const char* method, const char* samples,
                                  bool conservative) {
  const std::string bsdf = R"({"type":"subsurface","eta":)" + fmt(eta) + "," + medium + R"(,"method":")" + method + R"("})";
  const json out = run_one({"subsurface", "--bsdf", bsdf, "--samples", samples});
  const double f0 = std::pow((eta - 1) / (eta + 1), 2);
  const auto rd = color3(out["Rd"]), se = color3(out["stderr"]);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(rd[c], (1 - f0) * (1 + 1e-6) + 4 * se[c]) << bsdf << " " << out["Rd"].dump();
    EXPECT_GE(rd[c], conservative ? 0.9 * (1 - f0) - 4 * se[c] : 0.0) << bsdf << " " << out["Rd"].dump();
  }
}

TEST(CliSubsurface, DiffusionRdNeverExceedsWhatEnters) {
  for (const double eta : {1.0, 1.33, 1.5, 2.5}) {
    expect_rd_within_what_enters(eta, R"("sigma_s":1,"sigma_a":0)", "diffusion", "1", true);
    expect_rd_within_what_enters(eta, R"("sigma_s":1,"sigma_a":0,"g":0.7)", "diffusion", "1", true);
    expect_rd_within_what_enters(eta, R"("sigma_s":0.999,"sigma_a":0.001)", "diffusion", "1", false);
  }
  // The reported case: the artist's albedo just below 1 (ϖ = 1 after the inversion).
  expect_rd_within_what_enters(1.33, R"("albedo":0.999999,"mfp":1)", "diffusion", "1", true);
}

TEST(CliSubsurface, RandomWalkRdNeverExceedsWhatEnters) {
  for (const double eta : {1.33, 2.5}) {
    expect_rd_within_what_enters(eta, R"("sigma_s":1,"sigma_a":0)", "randomwalk", "400", true);
    expect_rd_within_what_enters(eta, R"("sigma_s":1,"sigma_a":0,"g":0.7)", "randomwalk", "400", true);
  }
}

}  // namespace
}  // namespace gonio_cli_test
