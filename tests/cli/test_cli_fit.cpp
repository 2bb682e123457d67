// gonio fit as a user runs it (SPEC §3): one JSON line whose material `gonio eval` takes,
// and the error contract (exit 2, one line) for a bad model, file or --init. The fit
// itself is tested in tests/unit/test_fit.cpp; here a table is written once, in a
// temporary directory, from a known GGX material (gonio's model at each bin's centre).

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "gonio/material.h"
#include "gonio/merl.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;

class FitTable {
 public:
  FitTable() {
    dir_ = fs::temp_directory_path() / ("gonio_cli_fit_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const gonio::BxDF m =
        gonio::parse_material(R"({"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":[0.9,0.6,0.3]})");
    gonio::MerlTable t;
    // Only the entries the fit reads at --stride 9 (θd 4, 13, ...; φd 9, 27, ...) are
    // measured: cheap to make, and the full table's error is over these.
    for (int i = 0; i < 90; ++i)
      for (int j = 0; j < 90; ++j)
        for (int k = 0; k < 180; ++k) {
          const auto [wo, wi] = gonio::merl_directions(gonio::merl_theta_h(i), gonio::merl_theta_d(j), gonio::merl_phi_d(k));
          if (j % 9 == 4 && k % 18 == 9 && wo.z > 0 && wi.z > 0) t.set(i, j, k, m.f(wo, wi));
          else t.set_missing(i, j, k);
        }
    path_ = (dir_ / "ggx.binary").string();
    gonio::write_merl(path_, t);
  }
  ~FitTable() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  fs::path dir_;
  std::string path_;
};

const FitTable& table() {
  static const FitTable t;
  return t;
}

TEST(CliFit, PrintsOneLineWithAMaterialThatEvalTakes) {
  const RunResult r = run_gonio({"fit", "--data", table().path(), "--model", "roughconductor", "--stride", "9"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 1u) << r.out;
  // The keys in SPEC §3's order.
  EXPECT_EQ(lines[0].rfind("{\"material\":{", 0), 0u) << lines[0];
  const json out = json::parse(lines[0]);
  ASSERT_EQ(out.size(), 5u) << lines[0];
  EXPECT_EQ(out.at("metric"), "log");
  EXPECT_TRUE(out.at("error").is_number() && out["error"].get<double>() >= 0 && out["error"].get<double>() < 1e-3);
  EXPECT_TRUE(out.at("evaluations").is_number_integer() && out["evaluations"].get<long long>() > 0);
  EXPECT_TRUE(out.at("seconds").is_number() && out["seconds"].get<double>() >= 0);
  const json& m = out.at("material");
  EXPECT_EQ(m.at("type"), "roughconductor");
  EXPECT_NEAR(m.at("alpha").get<double>(), 0.2, 0.002);
  // The material is valid --bsdf input: gonio eval gives its f, GGX's at the peak.
  const RunResult e = run_gonio({"eval", "--bsdf", m.dump()}, "0 0 1 0 0 1\n");
  ASSERT_EQ(e.status, 0) << describe(e);
  const json f = json::parse(split_lines(e.out).at(0));
  const gonio::BxDF truth =
      gonio::parse_material(R"({"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":[0.9,0.6,0.3]})");
  const gonio::Color expected = truth.f(gonio::Vec3{0, 0, 1}, gonio::Vec3{0, 0, 1});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(f["f"][c].get<double>(), expected[c], 0.02 * expected[c]);
}

TEST(CliFit, MetricNganIsReported) {
  const RunResult r = run_gonio({"fit", "--data", table().path(), "--model", "orennayar", "--metric", "ngan",
                                 "--stride", "9"});
  ASSERT_EQ(r.status, 0) << describe(r);
  const json out = json::parse(split_lines(r.out).at(0));
  EXPECT_EQ(out.at("metric"), "ngan");
  EXPECT_EQ(out.at("material").at("type"), "orennayar");
}

TEST(CliFit, BadInputIsExitTwoWithOneLine) {
  const std::string data = table().path();
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "lambert"}), {"lambert"});
  expect_bad_input(run_gonio({"fit", "--data", data + ".missing", "--model", "ward"}), {"ggx.binary.missing"});
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "ward", "--init", "{\"kd\":"}), {"--init"});
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "ward", "--init", R"({"type":"phong"})"}),
                   {"--init", "type"});
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "roughconductor", "--init", R"({"alpha":-0.1})"}),
                   {"--init", "alpha"});
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "ward", "--metric", "l2"}), {"--metric"});
  expect_bad_input(run_gonio({"fit", "--data", data, "--model", "roughconductor", "--distribution", "phong"}),
                   {"--distribution"});
  expect_bad_input(run_gonio({"fit", "--model", "ward"}), {"--data"});
  // Not a MERL table: the reader's error, naming the file.
  TempFile junk("not a table", "gonio_cli_fit_junk");
  expect_bad_input(run_gonio({"fit", "--data", junk.path(), "--model", "ward"}), {junk.path()});
}

TEST(CliFit, FailedFitIsOneLineWithoutTheSolverLog) {
  // Entries of 1e300 (a float's infinity once scaled) among those the fit reads: every
  // start fails in Ceres's first iteration, which logged "WARNING: Logging before
  // InitGoogleLogging() ..." and "trust_region_minimizer.cc:71] Terminating: ..." before
  // gonio's own line.
  std::ifstream in(table().path(), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 12 + 3 * 1458000 * sizeof(double));
  const double huge = 1e300;
  for (int i = 0; i < 90; ++i)  // (θh i, θd 4, φd 9), read at --stride 9
    std::memcpy(&bytes[12 + 8 * size_t(9 + 180 * 4 + 16200 * i)], &huge, sizeof huge);
  const TempFile huge_table(bytes, "gonio_cli_fit_huge");
  const RunResult r = run_gonio({"fit", "--data", huge_table.path(), "--model", "phong", "--stride", "9"});
  expect_bad_input(r, {});
  EXPECT_EQ(r.err.find("InitGoogleLogging"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Terminating"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gonio_cli_test
