// `gonio render --polarized` as a user runs it (issue 15): the EXR's Stokes layers are the
// library's images, --polarizer and the scene's polarizer agree, --dop writes its picture,
// and every misuse is one line with exit 2.

#include <algorithm>
#include <filesystem>
#include <string>

#include "../cli/run_gonio.h"
#include "gonio/render/image.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"
#include "scratch_dir.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;
using gonio::test::ScratchDir;
namespace render = gonio::render;

// Rough gold and glass on a plastic floor: polarized at one bounce and more.
std::string scene_text(const std::string& render_extra = "", const std::string& camera_extra = "") {
  return R"({"camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "width": 20, "height": 12)" + camera_extra + R"(},
    "render": {"spp": 2, "seed": 5)" + render_extra + R"(},
    "shapes": [
      {"type": "quad", "corner": [-3, 0, -3], "edge1": [0, 0, 6], "edge2": [6, 0, 0], "material": {"type": "plastic", "eta": 1.5}},
      {"type": "sphere", "center": [-0.6, 0.5, 0], "radius": 0.5, "material": {"type": "roughconductor", "material": "Au", "alpha": 0.2}},
      {"type": "sphere", "center": [0.6, 0.5, 0], "radius": 0.5, "material": {"type": "dielectric", "eta": 1.5}}
    ],
    "lights": [{"type": "point", "position": [1, 3, 2], "intensity": 10}],
    "environment": {"radiance": 0.5}})";
}

render::StokesImages library_render(const std::string& text) {
  render::Scene scene = render::parse_scene(text, "test", "");
  render::StokesImages s;
  render::render(scene, {}, nullptr, &s);
  return s;
}

bool same_pixels(const render::Image& a, const render::Image& b) {
  if (a.width() != b.width() || a.height() != b.height()) return false;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c)
        if (a.at(x, y)[c] != b.at(x, y)[c]) return false;
  return true;
}

TEST(PolarizedRenderCli, ExrHoldsTheFourStokesLayers) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", scene_text());
  const std::string out = dir.path("p.exr");
  const RunResult r = run_gonio({"render", scene, "--polarized", "-o", out, "--threads", "1"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.err.find("(polarized)"), std::string::npos) << r.err;
  const render::StokesImages want = library_render(scene_text(R"(, "polarized": true)"));
  const char* names[4] = {"S0", "S1", "S2", "S3"};
  for (int k = 0; k < 4; ++k) {
    const render::Image layer = render::read_exr_layer(out, names[k]);
    EXPECT_TRUE(same_pixels(layer, want[size_t(k)])) << names[k];
  }
  // S1 and S2 are not copies of each other or of S0 (a swapped or repeated layer would be).
  EXPECT_FALSE(same_pixels(want[1], want[2]));
  EXPECT_FALSE(same_pixels(want[0], want[1]));
}

TEST(PolarizedRenderCli, PolarizerOptionEqualsTheScenesPolarizerAndDopIsWritten) {
  ScratchDir dir;
  const std::string plain = dir.file("s.json", scene_text(R"(, "polarized": true)"));
  const std::string with = dir.file("p.json", scene_text(R"(, "polarized": true)", R"(, "polarizer": 30)"));
  const RunResult a = run_gonio({"render", plain, "--polarizer", "30", "-o", dir.path("a.exr"), "--dop", dir.path("a.png")});
  ASSERT_EQ(a.status, 0) << describe(a);
  EXPECT_EQ(a.out, dir.path("a.exr") + "\n" + dir.path("a.png") + "\n");
  const RunResult b = run_gonio({"render", with, "-o", dir.path("b.exr")});
  ASSERT_EQ(b.status, 0) << describe(b);
  EXPECT_TRUE(same_pixels(render::read_exr_layer(dir.path("a.exr"), "S0"), render::read_exr_layer(dir.path("b.exr"), "S0")));
  // The picture of a fully polarized image (everything went through the polarizer) is
  // bright everywhere the image is not black.
  const render::Image dop = render::read_image(dir.path("a.png"));
  EXPECT_GT(dop.average().max_component(), 0.05);
}

TEST(PolarizedRenderCli, MisuseIsOneLineAndExit2) {
  ScratchDir dir;
  const std::string plain = dir.file("s.json", scene_text());
  const std::string filtered = dir.file("f.json", scene_text("", R"(, "polarizer": 10)"));
  const std::string marble = dir.file("m.json", R"({"camera": {"width": 8, "height": 8},
    "shapes": [{"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": {"type": "subsurface", "eta": 1.3, "albedo": 0.9, "mfp": 0.1}}]})");
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {{"render", plain, "-o", dir.path("x.png"), "--dop", dir.path("d.png")}, {"--dop", "polarized"}},
      {{"render", plain, "--polarized", "-o", dir.path("x.png"), "--dop", dir.path("d.exr")}, {"--dop", ".png"}},
      {{"render", plain, "--polarized", "-o", dir.path("x.png"), "--polarizer", "400"}, {"--polarizer", "400"}},
      {{"render", plain, "-o", dir.path("x.png"), "--polarizer", "20"}, {"polarizer", "polarized"}},
      {{"render", filtered, "-o", dir.path("x.png")}, {"f.json", "/camera/polarizer", "polarized"}},
      {{"render", marble, "--polarized", "-o", dir.path("x.png")}, {"polarized", "subsurface"}},
  };
  for (const Case& c : cases) {
    const RunResult r = run_gonio(c.args);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    for (const std::string& m : c.mentions) EXPECT_NE(r.err.find(m), std::string::npos) << m << ": " << describe(r);
    EXPECT_FALSE(fs::exists(dir.path("x.png")));
  }
}

}  // namespace
}  // namespace gonio_cli_test
