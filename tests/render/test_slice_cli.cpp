// `gonio slice` as a user runs it: the PNG it writes holds the figure make_slice draws
// (to 8-bit rounding), --compare takes JSON, @file or a MERL file, and bad arguments get
// exit 2 and one line.

#include <filesystem>
#include <string>

#include "../cli/run_gonio.h"
#include "gonio/material.h"
#include "gonio/merl.h"
#include "gonio/render/image.h"
#include "gonio/render/slice.h"
#include "scratch_dir.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;
using gonio::test::ScratchDir;

const char* kDiffuse = R"({"type":"diffuse","reflectance":[0.2,0.5,0.8]})";

TEST(SliceCli, WritesTheFigureAsPngAndPrintsThePath) {
  ScratchDir dir;
  const std::string out = dir.path("s.PNG");
  const RunResult r = run_gonio({"slice", "--bsdf", kDiffuse, "-o", out, "--size", "32", "--compare",
                                 R"({"type":"diffuse","reflectance":0.4})"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.out, out + "\n");
  // The file holds the figure's sRGB codes: compare with the library's image, encoded.
  gonio::render::SliceOptions o;
  o.size = 32;
  const auto a = gonio::parse_material(kDiffuse), b = gonio::parse_material(R"({"type":"diffuse","reflectance":0.4})");
  const gonio::render::SliceFigure fig = gonio::render::make_slice(a, &b, o);
  const gonio::render::Image png = gonio::render::read_image(out, /*srgb=*/false);
  ASSERT_EQ(png.width(), fig.image.width());
  ASSERT_EQ(png.height(), fig.image.height());
  for (const auto& p : fig.panels) {
    const int x = p.x + p.width / 2, y = p.y + p.height / 2;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(png.at(x, y)[c], gonio::render::srgb_encode(fig.image.at(x, y)[c]), 0.5 / 255 + 1e-6);
  }
}

TEST(SliceCli, CompareTakesAJsonFileOrAMerlTable) {
  ScratchDir dir;
  const std::string json = dir.file("m.json", kDiffuse);
  RunResult r = run_gonio({"slice", "--bsdf", kDiffuse, "--compare", "@" + json, "-o", dir.path("a.png"), "--size", "16"});
  EXPECT_EQ(r.status, 0) << describe(r);
  // A MERL table of the Lambertian f = ρ/π at every entry: as --data and as --compare (a
  // file with the MERL header) it is the measured material of that file, whose
  // interpolation of a constant table is that constant: zero difference to the diffuse
  // material, on the ±1% scale.
  gonio::MerlTable table;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < gonio::MerlTable::kThetaH; ++i)
    for (int j = 0; j < gonio::MerlTable::kThetaD; ++j)
      for (int k = 0; k < gonio::MerlTable::kPhiD; ++k)
        table.set(i, j, k, gonio::Color(float(0.2 / pi), float(0.5 / pi), float(0.8 / pi)));
  const std::string merl = dir.path("t.binary");
  gonio::write_merl(merl, table);
  for (const bool as_data : {true, false}) {
    const std::string out = dir.path(as_data ? "data.png" : "compare.png");
    r = as_data ? run_gonio({"slice", "--data", merl, "--compare", kDiffuse, "-o", out, "--size", "16"})
                : run_gonio({"slice", "--bsdf", kDiffuse, "--compare", merl, "-o", out, "--size", "16"});
    ASSERT_EQ(r.status, 0) << describe(r);
    // The layout of the same figure drawn in-process (two equal materials: equal ticks).
    gonio::render::SliceOptions o;
    o.size = 16;
    const auto d = gonio::parse_material(kDiffuse);
    const gonio::render::SliceFigure fig = gonio::render::make_slice(d, &d, o);
    const gonio::render::Image png = gonio::render::read_image(out, /*srgb=*/false);
    ASSERT_EQ(png.width(), fig.image.width());
    const gonio::render::Rect& p = fig.panels[2];
    for (int y = p.y; y < p.y + p.height; ++y)
      for (int x = p.x; x < p.x + p.width; ++x)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(png.at(x, y)[c], 242 / 255.0, 1.01 / 255) << x << " " << y;  // 0.95
  }
  // --data names a MERL table; a text file is refused with its name.
  r = run_gonio({"slice", "--data", json, "-o", dir.path("c.png")});
  expect_bad_input(r, {"m.json"});
}

TEST(SliceCli, BadArgumentsExitTwoWithOneLine) {
  ScratchDir dir;
  const std::string png = dir.path("x.png");
  const std::string text = dir.file("notes.txt", "hello");
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {{"slice", "-o", png}, {"--bsdf", "--data"}},
      {{"slice", "--bsdf", kDiffuse, "--data", "t.binary", "-o", png}, {"--data"}},
      {{"slice", "--bsdf", kDiffuse}, {"--output"}},
      {{"slice", "--bsdf", kDiffuse, "-o", dir.path("x.jpg")}, {"x.jpg", ".png"}},
      {{"slice", "--bsdf", kDiffuse, "-o", dir.path("no/such/dir/x.png")}, {"x.png"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--size", "8"}, {"--size"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--phi-d", "200"}, {"--phi-d", "200"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--range", "1", "0.1"}, {"--range"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--diff-range", "-1"}, {"--diff-range"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--compare", dir.path("missing.binary")}, {"--compare", "missing.binary"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--compare", text}, {"--compare", "notes.txt", "MERL"}},
      {{"slice", "--bsdf", kDiffuse, "-o", png, "--compare", R"({"type":"diffuse")"}, {"--compare"}},
      {{"slice", "--bsdf", R"({"type":"mirror"})", "-o", png}, {"specular"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args.back());
    const RunResult r = run_gonio(c.args);
    expect_bad_input(r);
    for (const auto& m : c.mentions) EXPECT_TRUE(contains_ci(r.err, m)) << m << "\n" << describe(r);
  }
  EXPECT_FALSE(fs::exists(png));  // no failed run left an image behind
}

}  // namespace
}  // namespace gonio_cli_test
