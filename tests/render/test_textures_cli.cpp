// `gonio render` with bad textures (docs/scene-format.md, "Textures"): exit 2 and one
// line naming the file, the JSON path, the image and the problem.

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../cli/run_gonio.h"
#include "scratch_dir.h"
#include "gonio/render/image.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;

using gonio::test::ScratchDir;

// A scene with one quad whose material is `material`.
std::string quad_scene(const std::string& material) {
  return R"({"camera": {"position": [0, 2, 0.1], "look_at": [0, 0, 0], "width": 8, "height": 8},
    "shapes": [{"type": "quad", "corner": [-1, 0, -1], "edge1": [0, 0, 2], "edge2": [2, 0, 0], "material": )" +
         material + R"(}],
    "lights": [{"type": "point", "position": [0, 1, 0], "intensity": 2}]})";
}

TEST(TexturesCli, GoodTexturesRender) {
  ScratchDir dir;
  gonio::render::Image rough(4, 4);
  for (auto y = 0; y < 4; ++y)
    for (auto x = 0; x < 4; ++x) rough.at(x, y) = gonio::Color(gonio::Float(0.1 + 0.05 * (x + y)));
  gonio::render::write_exr(rough, dir.path("rough.exr"));
  const std::string scene = dir.file("s.json", quad_scene(R"({"type": "roughconductor", "material": "Au",
      "alpha": {"texture": "rough.exr", "uv_scale": [2, 3]}, "multiscatter": true})"));
  const RunResult r = run_gonio({"render", scene, "-o", dir.path("x.exr"), "--spp", "2"});
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_TRUE(fs::exists(dir.path("x.exr")));
}

struct BadTexture {
  const char* name;
  std::string material;
  std::vector<std::string> mentions;
};

TEST(TexturesCli, BadTextureInputIsOneLineAndExit2) {
  const std::vector<BadTexture> cases = {
      {"texel out of range", R"({"type": "roughconductor", "material": "Au", "alpha": {"texture": "rough.exr"}})",
       {"s.json", "/shapes/0/material/alpha", "rough.exr", "texel (3, 4)", "value 0 is out of range", "alpha must be > 0"}},
      {"texel out of range in an alpha entry", R"({"type": "ward", "kd": 0.2, "ks": 0.2, "alpha": [0.1, {"texture": "rough.exr"}]})",
       {"/shapes/0/material/alpha/1", "rough.exr", "texel (3, 4)"}},
      {"colour texel out of range", R"({"type": "diffuse", "reflectance": {"texture": "bright.exr"}})",
       {"/shapes/0/material/reflectance", "bright.exr", "texel (1, 0)", "reflectance must be in [0, 1]"}},
      {"missing image", R"({"type": "diffuse", "reflectance": {"texture": "wood.png"}})",
       {"/shapes/0/material/reflectance/texture", "wood.png"}},
      {"corrupt image", R"({"type": "diffuse", "reflectance": {"texture": "corrupt.png"}})",
       {"/shapes/0/material/reflectance/texture", "corrupt.png"}},
      {"unknown field", R"({"type": "diffuse", "reflectance": {"checker": [0.1, 0.2], "scale": 2}})",
       {"/shapes/0/material/reflectance", "unknown field", "scale"}},
      {"not textureable", R"({"type": "roughconductor", "material": "Au", "alpha": 0.1, "fresnel": {"checker": [0.1, 0.2]}})",
       {"/shapes/0/material/fresnel", "cannot be a texture"}},
      {"dielectric index", R"({"type": "dielectric", "eta": {"checker": [1.3, 1.5]}})",
       {"/shapes/0/material/eta", "cannot be a texture"}},
      {"checker out of range", R"({"type": "diffuse", "reflectance": {"checker": [0.5, [0.2, 1.2, 0.3]]}})",
       {"/shapes/0/material/reflectance/checker/1", "out of range", "reflectance"}},
      {"checker of colours for a number", R"({"type": "orennayar", "sigma": {"checker": [10, [1, 2, 3]]}})",
       {"/shapes/0/material/sigma/checker/1", "must be a number"}},
      {"kd + ks", R"({"type": "phong", "kd": {"checker": [0.2, 0.7]}, "ks": {"checker": [0.5, 0.1]}, "exponent": 10})",
       {"/shapes/0/material/kd/checker/1", "kd + ks", "with ks at its largest value 0.5"}},
      {"both kinds", R"({"type": "diffuse", "reflectance": {"checker": [0.1, 0.2], "texture": "a.png"}})",
       {"/shapes/0/material/reflectance", "exactly one"}},
      {"uv_scale", R"({"type": "diffuse", "reflectance": {"checker": [0.1, 0.2], "uv_scale": [1, 0]}})",
       {"/shapes/0/material/reflectance/uv_scale/1"}},
      {"material error besides the texture", R"({"type": "roughconductor", "alpha": {"checker": [0.1, 0.2]}})",
       {"/shapes/0/material", "missing parameter"}},
      {"openpbr colour texel out of range", R"({"type": "openpbr", "base_color": {"texture": "bright.exr"}})",
       {"/shapes/0/material/base_color", "bright.exr", "texel (1, 0)", "openpbr: base_color must be in [0, 1]"}},
      {"openpbr glass index", R"({"type": "openpbr", "transmission_weight": 1, "specular_ior": {"checker": [1.3, 1.5]}})",
       {"/shapes/0/material/specular_ior", "cannot be a texture here", "transmission_weight"}},
      {"blend", R"({"type": "blend", "weight": 0.5, "bsdfs": [{"type": "diffuse"}, {"type": "diffuse", "reflectance": {"checker": [0.1, 0.2]}}]})",
       {"/shapes/0/material/bsdfs/1/reflectance", "blend", "not supported"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    ScratchDir dir;
    gonio::render::Image rough(6, 5), bright(2, 2);
    for (auto y = 0; y < 5; ++y)
      for (auto x = 0; x < 6; ++x) rough.at(x, y) = gonio::Color(0.2f);
    rough.at(3, 4) = gonio::Color(0);
    for (auto y = 0; y < 2; ++y)
      for (auto x = 0; x < 2; ++x) bright.at(x, y) = gonio::Color(0.5f);
    bright.at(1, 0) = gonio::Color(0.5f, 1.5f, 0.5f);
    gonio::render::write_exr(rough, dir.path("rough.exr"));
    gonio::render::write_exr(bright, dir.path("bright.exr"));
    dir.file("corrupt.png", "this is not a PNG file");
    const std::string scene = dir.file("s.json", quad_scene(c.material));
    const RunResult r = run_gonio({"render", scene, "-o", dir.path("x.png")});
    expect_bad_input(r, {});
    for (const auto& m : c.mentions) EXPECT_TRUE(contains_ci(r.err, m)) << "should mention " << m << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir.path("x.png")));
  }
}

}  // namespace
}  // namespace gonio_cli_test
