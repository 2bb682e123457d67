// gonio measure on the command line: bad input exits 2 with one line; a small gantry run
// prints one JSON object whose fields the documentation describes; a table run writes a
// MERL file that read_merl accepts.
#include <gtest/gtest.h>

#include <filesystem>

#include "../cli/run_gonio.h"
#include "gonio/measure/merl_bins.h"
#include "gonio/merl/coverage.h"
#include "gonio/merl.h"

namespace {

using namespace gonio_cli_test;

// The one JSON object on stdout (stderr carries the progress lines).
json run_object(const std::vector<std::string>& args) {
  const RunResult r = run_gonio(args);
  EXPECT_EQ(r.status, 0) << describe(r);
  const auto lines = split_lines(r.out);
  EXPECT_EQ(lines.size(), 1u) << describe(r);
  return lines.empty() ? json::object() : json::parse(lines.front());
}

const std::string kFlat = R"({"type":"flat","material":{"type":"diffuse","reflectance":0.5}})";

// A few representative cases (each starts a process; the parsers' own tests cover the
// rest in-process, and CLI11's ranges are shared with every command).
TEST(MeasureCli, BadInputExitsTwoWithOneLine) {
  const std::string tmp = (std::filesystem::temp_directory_path() / "gonio_measure_cli.binary").string();
  expect_bad_input(run_gonio({"measure", "--surface", R"({"type":"flat"})", "-o", tmp}), {"material"});
  expect_bad_input(run_gonio({"measure", "--surface", R"({"type":"cube","material":{"type":"diffuse"}})", "-o", tmp}),
                   {"cube"});
  expect_bad_input(run_gonio({"measure", "--surface", "@/nonexistent/s.json", "-o", tmp}), {"--surface"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat}), {"-o"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "-o", "/nonexistent/dir/t.binary"}), {"-o"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--samples", "0", "-o", tmp}), {"--samples"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--gantry", R"({"theta_o":90})"}), {"--gantry"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--gantry", R"({"theta_o":[10]})", "-o", tmp}), {"-o"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--preview", "/tmp/x.txt"}), {"--preview"});
  // The table's own options: a range, and only with -o, never onto the table itself.
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "-o", tmp, "--min-rays", "-1"}), {"--min-rays"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "-o", tmp, "--min-rays", "2.5"}), {"--min-rays"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--gantry", R"({"theta_o":[10]})", "--min-rays", "3"}),
                   {"--min-rays", "-o"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "--gantry", R"({"theta_o":[10]})", "--stderr-table",
                              tmp + ".e"}),
                   {"--stderr-table", "-o"});
  expect_bad_input(run_gonio({"measure", "--surface", kFlat, "-o", tmp, "--stderr-table", tmp}), {"--stderr-table"});
  EXPECT_FALSE(std::filesystem::exists(tmp));
  EXPECT_FALSE(std::filesystem::exists(tmp + ".e"));
}

TEST(MeasureCli, GantryPrintsOneObject) {
  const json j = run_object({"measure", "--surface", kFlat, "--samples", "20000", "--seed", "3", "--gantry",
                          R"({"theta_i":[0,40],"theta_o":{"from":10,"to":70,"count":3},"phi_o":[0,180],"aperture":8})"});
  ASSERT_EQ(j["mode"], "gantry");
  ASSERT_EQ(j["incidences"].size(), 2u);
  EXPECT_EQ(j["rays_per_incidence"], 10000);
  for (const json& inc : j["incidences"]) {
    EXPECT_NEAR(color3(inc["albedo"])[0], 0.5, 1e-6);
    EXPECT_EQ(inc["rays"]["launched"], 10000);
    ASSERT_EQ(inc["detectors"].size(), 6u);
    for (const json& d : inc["detectors"]) {
      const double f = color3(d["f"])[1], se = color3(d["stderr"])[1];
      EXPECT_NEAR(f, 0.5 / kPi, 5 * se) << d.dump();
      EXPECT_GT(d["hits"].get<double>(), 0);
    }
  }
}

TEST(MeasureCli, TableWritesAMerlFile) {
  const std::string out = (std::filesystem::temp_directory_path() / "gonio_measure_cli_ok.binary").string();
  const std::string err = out + ".stderr";
  const json j = run_object({"measure", "--surface", kFlat, "-o", out, "--samples", "20000", "--threads", "1",
                             "--min-rays", "0", "--stderr-table", err});
  EXPECT_EQ(j["mode"], "table");
  EXPECT_EQ(j["rays"]["launched"], 20000);
  EXPECT_EQ(j["pilot_rays"], 5000);
  EXPECT_EQ(j["min_expected_rays"], 0);
  // Every bin of positive measure is its own.
  EXPECT_EQ(j["filled"].get<double>() + j["missing"].get<double>(), 1458000);
  EXPECT_EQ(j["pooled"], 0);
  EXPECT_GT(j["filled"].get<double>(), 1000);
  // Every written entry of so few rays is noisier than 1% and 5%.
  EXPECT_EQ(j["relative_stderr_above"]["0.01"], 1);
  EXPECT_EQ(j["relative_stderr_above"]["0.05"], 1);
  const double above20 = j["relative_stderr_above"]["0.2"].get<double>();
  EXPECT_GT(above20, 0);
  EXPECT_LE(above20, 1);
  // The standard errors' file: missing exactly where the table is, non-negative elsewhere.
  const gonio::MerlTable e = gonio::read_merl(err);
  std::filesystem::remove(err);
  const gonio::MerlTable t = gonio::read_merl(out);
  std::size_t measured = 0;
  for (int i = 0; i < 90; ++i)
    for (int jj = 0; jj < 90; ++jj)
      for (int k = 0; k < 180; ++k) {
        measured += t.measured(i, jj, k);
        ASSERT_EQ(t.measured(i, jj, k), e.measured(i, jj, k));
      }
  EXPECT_EQ(double(measured), j["filled"].get<double>() + j["pooled"].get<double>());
  std::filesystem::remove(out);
}

// Issue 55: with the default --min-rays every entry above the horizon is written (the
// sparse ones pooled from a region of bins, --support-table saying how many), and the
// measured model reads the table without a warning.
TEST(MeasureCli, TableFillsEveryEntryAboveTheHorizon) {
  const std::string out = (std::filesystem::temp_directory_path() / "gonio_measure_cli_full.binary").string();
  const std::string sup = out + ".support";
  const json j = run_object({"measure", "--surface", kFlat, "-o", out, "--samples", "20000", "--threads", "1",
                             "--support-table", sup});
  EXPECT_EQ(j["filled"].get<double>() + j["pooled"].get<double>() + j["missing"].get<double>(), 1458000);
  EXPECT_GT(j["pooled"].get<double>(), 1e6);  // 20,000 rays: nearly every bin pooled
  const gonio::MerlTable t = gonio::read_merl(out), s = gonio::read_merl(sup);
  std::filesystem::remove(sup);
  const std::vector<double>& m = gonio::measure::merl_bin_measures();
  std::size_t above = 0, wide = 0;
  for (int i = 0; i < 90; ++i)
    for (int jj = 0; jj < 90; ++jj)
      for (int k = 0; k < 180; ++k) {
        // Every bin some part of which is above the horizon (positive measure), which
        // includes every bin whose centre is (merl/coverage.h).
        const bool up = m[gonio::MerlTable::index(i, jj, k)] > 0;
        ASSERT_EQ(t.measured(i, jj, k), up) << i << " " << jj << " " << k;
        if (gonio::merl_entry_above_horizon(i, jj, k)) {
          ASSERT_TRUE(up);
        }
        above += up;
        if (!up) continue;
        ASSERT_GE(s.at(i, jj, k)[0], 1.0f);
        wide += s.at(i, jj, k)[0] > 1;
      }
  EXPECT_EQ(double(wide), j["pooled"].get<double>());
  EXPECT_EQ(double(above), j["filled"].get<double>() + j["pooled"].get<double>());
  const std::string bsdf = R"({"type":"measured","file":")" + out + R"("})";
  const RunResult a = run_gonio({"albedo", "--bsdf", bsdf, "--theta", "30", "--samples", "4096"});
  EXPECT_EQ(a.status, 0) << describe(a);
  EXPECT_EQ(a.err.find("missing"), std::string::npos) << a.err;
  EXPECT_EQ(gonio::merl_missing_fraction(t), 0);
  std::filesystem::remove(out);
}

// A table with holes above the horizon says so: one line on stderr with the missing
// fraction when the model reads it, and a coverage row in `gonio check` (a warning, not a
// failure; the validator's run makes this test take ~5 s). Here every θd ≥ 45° entry is
// missing: the fraction of the entries whose centre pair is above the horizon, counted
// here from the pair's directions (merl.h merl_directions, both z > 0).
TEST(MeasureCli, MissingEntriesAreReportedNotReadAsZeroSilently) {
  gonio::MerlTable t;
  double above = 0, gone = 0;
  for (int i = 0; i < 90; ++i)
    for (int jj = 0; jj < 90; ++jj)
      for (int k = 0; k < 180; ++k) {
        const auto [wo, wi] = gonio::merl_directions(gonio::merl_theta_h(i), gonio::merl_theta_d(jj), gonio::merl_phi_d(k));
        const bool up = wo.z > 0 && wi.z > 0;
        above += up;
        if (jj >= 45) {
          t.set_missing(i, jj, k);
          gone += up;
        } else {
          t.set(i, jj, k, gonio::Color(0.1f));
        }
      }
  const std::string path = (std::filesystem::temp_directory_path() / "gonio_measure_cli_holes.binary").string();
  gonio::write_merl(path, t);
  const std::string bsdf = R"({"type":"measured","file":")" + path + R"("})";
  const RunResult a = run_gonio({"albedo", "--bsdf", bsdf, "--theta", "30", "--samples", "4096"});
  EXPECT_EQ(a.status, 0) << describe(a);
  const auto lines = split_lines(a.err);
  ASSERT_EQ(lines.size(), 1u) << a.err;
  EXPECT_NE(lines[0].find("missing"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find(path), std::string::npos) << lines[0];
  // The percentage printed (3 significant digits) against the count here.
  const std::size_t pct = lines[0].find('%');
  ASSERT_NE(pct, std::string::npos);
  const std::size_t start = lines[0].rfind(' ', pct) + 1;
  EXPECT_NEAR(std::stod(lines[0].substr(start, pct - start)), 100 * gone / above, 0.2) << lines[0];
  // The validator takes ~5 s of one core on a MERL table; more time is allowed on a
  // loaded machine than run_gonio's default 30 s.
  const RunResult checked = run_gonio({"check", "--bsdf", bsdf, "--json"}, "", 180);
  ASSERT_EQ(checked.status, 0) << describe(checked);
  const json c = json::parse(checked.out);
  bool reported = false;
  for (const json& p : c["properties"])
    if (p["name"] == "coverage") {
      reported = true;
      EXPECT_NEAR(p["figure"].get<double>(), gone / above, 2e-3) << p.dump();
      EXPECT_EQ(p["warning"], true);
    }
  EXPECT_TRUE(reported);
  std::filesystem::remove(path);
}

}  // namespace
