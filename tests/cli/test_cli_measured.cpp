// `gonio tabulate` and `measured` materials through the tool (issue 12, SPEC §2-3): a
// written table is read back by eval/sample/albedo; what a table cannot hold and bad
// files get exit 2 and one line naming the problem.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../merl_files.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

namespace mf = gonio_test_merl;

std::string measured(const std::string& path) { return R"({"type":"measured","file":")" + path + R"("})"; }

TEST(CliTabulate, WritesATableThatEvaluatesAsTheModel) {
  const mf::TempTable table(mf::temp_path("cli_tab"));
  const std::string model = R"({"type":"roughconductor","alpha":0.3,"fresnel":"schlick","f0":[0.9,0.6,0.3]})";
  const json out = run_one({"tabulate", "--bsdf", model, "-o", table.path});
  EXPECT_EQ(out.at("entries").get<long>(), 1458000);
  EXPECT_EQ(std::filesystem::file_size(table.path), 12u + 3u * 1458000u * 8u);
  // At a bin centre (i, j, k) = (40, 30, 60): f of the model, from the file.
  const double th = mf::theta_h(40), td = mf::theta_d(30), pd = mf::phi_d(60);
  const double h[3] = {std::sin(th), 0, std::cos(th)}, t[3] = {std::cos(th), 0, -std::sin(th)}, b[3] = {0, 1, 0};
  double wi[3], wo[3];
  for (int c = 0; c < 3; ++c) wi[c] = std::cos(td) * h[c] + std::sin(td) * (std::cos(pd) * t[c] + std::sin(pd) * b[c]);
  const double hd = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
  for (int c = 0; c < 3; ++c) wo[c] = 2 * hd * h[c] - wi[c];
  const std::string line = fmt(wo[0]) + " " + fmt(wo[1]) + " " + fmt(wo[2]) + " " + fmt(wi[0]) + " " + fmt(wi[1]) + " " +
                           fmt(wi[2]) + "\n";
  const json a = run_one({"eval", "--bsdf", model}, line), m = run_one({"eval", "--bsdf", measured(table.path)}, line);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(color3(m["f"])[c], color3(a["f"])[c], 2e-4 * color3(a["f"])[c]);
}

TEST(CliTabulate, RefusesWhatATableCannotHold) {
  const std::string out = mf::temp_path("cli_refused");
  expect_bad_input(run_gonio({"tabulate", "--bsdf", R"({"type":"ward","kd":0.1,"ks":0.2,"alpha":[0.1,0.3]})", "-o", out}),
                   {"anisotropic"});
  expect_bad_input(run_gonio({"tabulate", "--bsdf", R"({"type":"mirror"})", "-o", out}), {"delta"});
  EXPECT_FALSE(std::filesystem::exists(out));
  expect_bad_input(run_gonio({"tabulate", "--bsdf", R"({"type":"diffuse"})", "-o", "/nonexistent-dir/t.binary"}),
                   {"/nonexistent-dir/t.binary"});
}

TEST(CliMeasured, EvalSampleAlbedoOnALambertTable) {
  const std::string m = measured(mf::lambert_table());
  const json e = run_one({"eval", "--bsdf", m}, "0.3 0.1 0.9 -0.2 0.3 0.8\n");
  EXPECT_NEAR(color3(e["f"])[0], 0.5 / mf::kPi, 1e-6);
  const json s = run_one({"sample", "--bsdf", m}, "0.3 0.1 0.9 0.5 0.3 0.7\n");
  // weight = f cos θi / pdf, f = 0.5/π (the sampling density only approximates f cos θi)
  const double wz = s["wi"][2].get<double>(), pdf = s["pdf"].get<double>();
  EXPECT_NEAR(color3(s["weight"])[0], 0.5 / mf::kPi * wz / pdf, 1e-5);
  EXPECT_NEAR(color3(s["weight"])[0], 0.5, 0.05);
  const json a = run_one({"albedo", "--bsdf", m, "--theta", "30", "--samples", "20000"});
  EXPECT_NEAR(color3(a["reflectance"])[0], 0.5, 5 * color3(a["stderr_reflectance"])[0] + 1e-6);
}

TEST(CliMeasured, BadTablesGetOneLineNamingTheFile) {
  const auto good = mf::table_bytes([](int, int, int, int) { return 0.1; });
  const mf::TempTable truncated(mf::temp_path("cli_truncated")), header(mf::temp_path("cli_header"));
  mf::write_bytes(truncated.path, std::vector<unsigned char>(good.begin(), good.begin() + 1000));
  auto h = good;
  h[0] = 91;
  mf::write_bytes(header.path, h);
  for (const auto& [path, what] : {std::pair{truncated.path, "truncated"}, std::pair{header.path, "header"}})
    expect_bad_input(run_gonio({"eval", "--bsdf", measured(path)}, "0 0 1 0 0 1\n"), {path, what});
  expect_bad_input(run_gonio({"eval", "--bsdf", measured("no-such-table.binary")}, "0 0 1 0 0 1\n"),
                   {"no-such-table.binary"});
}

// Issue 39: entries that are finite doubles but whose f = stored × scale overflows a float
// (or exceeds the documented bound, 1e30 1/sr: MerlTable::kMaxValue) were accepted, and
// eval printed an internal error at those bins. Every command that reads a table refuses
// it with one line naming the file and the entry; nothing is written.
const std::string& absurd_table() {  // entry (3, 4, 5): red 1e42 1/sr; the rest 0.1
  static const mf::TempTable table(mf::temp_path("cli_absurd"));
  static const bool written = (mf::write_bytes(table.path, mf::table_bytes([](int i, int j, int k, int c) {
                                 return i == 3 && j == 4 && k == 5 && c == 0 ? 1e42 : 0.1;
                               })),
                               true);
  (void)written;
  return table.path;
}

TEST(CliMeasured, EntriesBeyondTheBoundAreRefusedByEveryCommand) {
  const std::string& path = absurd_table();
  const std::string m = measured(path);
  const std::initializer_list<std::string> names = {path, "(3, 4, 5)", "channel r", "1e+30"};
  expect_bad_input(run_gonio({"eval", "--bsdf", m}, "0 0 1 0 0 1\n"), names);
  expect_bad_input(run_gonio({"sample", "--bsdf", m}, "0 0 1 0.5 0.5 0.5\n"), names);
  expect_bad_input(run_gonio({"albedo", "--bsdf", m, "--theta", "30", "--samples", "100"}), names);
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse"},)" + m + "]}"},
                             "0 0 1 0 0 1\n"),
                   names);
  const std::string out = mf::temp_path("cli_absurd_out");
  expect_bad_input(run_gonio({"tabulate", "--bsdf", m, "-o", out}), names);
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CliMeasured, EntriesBeyondTheBoundAreRefusedByFitSliceAndRender) {
  const std::string& path = absurd_table();
  const std::initializer_list<std::string> names = {path, "(3, 4, 5)", "channel r", "1e+30"};
  expect_bad_input(run_gonio({"fit", "--data", path, "--model", "roughconductor"}), names);
  const std::string png = mf::temp_path("cli_absurd_png") + ".png";
  expect_bad_input(run_gonio({"slice", "--data", path, "-o", png}), names);
  const TempFile scene(R"({"camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov": 40, "width": 8, "height": 8},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": )" + measured(path) + R"(}],
    "environment": {"radiance": 1}})");
  expect_bad_input(run_gonio({"render", scene.path(), "-o", png, "--spp", "1"}), {path, "(3, 4, 5)"});
  EXPECT_FALSE(std::filesystem::exists(png));
}

// Blue 1e300 and green 5e41 (finite doubles both), written in turn over one entry of a
// good table: each named with its channel (green is read before blue, channel-major).
TEST(CliMeasured, EntriesBeyondTheBoundAreNamedInEveryChannel) {
  const mf::TempTable table(mf::temp_path("cli_absurd_channels"));
  mf::write_bytes(table.path, mf::table_bytes([](int, int, int, int) { return 0.1; }));
  for (const auto& [f, channel] : {std::pair{1e300, 2}, std::pair{5e41, 1}}) {
    const std::size_t entry = 179 + 16200 * 80;  // (80, 0, 179)
    const double stored = f / mf::kScale[channel];
    std::fstream file(table.path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(12 + 8 * (std::size_t(channel) * mf::kN + entry)));
    file.write(reinterpret_cast<const char*>(&stored), 8);  // little-endian hosts
    file.close();
    expect_bad_input(run_gonio({"eval", "--bsdf", measured(table.path)}, "0 0 1 0 0 1\n"),
                     {table.path, "(80, 0, 179)", std::string("channel ") + "rgb"[channel], "1e+30"});
  }
}

// At the bound itself a table is read, gives finite values where the commands look (an
// albedo is a mean of sample weights up to 31.4 f), and `tabulate` writes it back as a
// table gonio reads again.
TEST(CliMeasured, EntriesAtTheBoundAreReadAndWrittenBack) {
  const mf::TempTable table(mf::temp_path("cli_bound")), copy(mf::temp_path("cli_bound_copy"));
  mf::write_bytes(table.path, mf::table_bytes([](int, int, int, int) { return 1e30; }));
  const std::string m = measured(table.path);
  const json e = run_one({"eval", "--bsdf", m}, "0.3 0.1 0.9 -0.2 0.3 0.8\n");
  EXPECT_NEAR(color3(e["f"])[0], 1e30, 1e24);
  const json a = run_one({"albedo", "--bsdf", m, "--theta", "60", "--samples", "1000"});
  EXPECT_NEAR(color3(a["reflectance"])[1], 1e30 * mf::kPi, 0.1 * 1e30 * mf::kPi);
  run_one({"tabulate", "--bsdf", m, "-o", copy.path});
  const json back = run_one({"eval", "--bsdf", measured(copy.path)}, "0.3 0.1 0.9 -0.2 0.3 0.8\n");
  EXPECT_NEAR(color3(back["f"])[0], 1e30, 1e24);
}

}  // namespace
}  // namespace gonio_cli_test
