// A measured (MERL) material in a scene (issue 12): its file is found relative to the
// scene, and a table of a Lambertian renders as that Lambertian; a table of a glossy
// conductor as the conductor, within the table's interpolation error.

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "../merl_files.h"
#include "gonio/material.h"
#include "gonio/merl.h"
#include "gonio/tabulate.h"
#include "render_test_util.h"

namespace gonio::render::test {
namespace {

std::string plane_scene(const std::string& material) {
  return R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 32, "height": 32},
    "render": {"spp": 4, "seed": 3},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": )" +
         material + R"(}],
    "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5}]})";
}
Image render_in(const std::string& json, const std::string& base_dir) {
  const Scene scene = parse_scene(json, "test scene", base_dir);
  RenderOptions options;
  return render(scene, options);
}
double mean(const Image& img) {
  double s = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) s += img.at(x, y)[0];
  return s / (img.width() * img.height());
}

TEST(MeasuredRender, LambertTableRendersAsTheLambertianWithItsPathRelativeToTheScene) {
  const std::filesystem::path table = gonio_test_merl::lambert_table();
  const Image measured = render_in(plane_scene(R"({"type": "measured", "file": ")" + table.filename().string() + R"("})"),
                                   table.parent_path().string());
  const Image diffuse = render_in(plane_scene(R"({"type": "diffuse", "reflectance": 0.5})"), "");
  double worst = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const double a = measured.at(x, y)[1], b = diffuse.at(x, y)[1];
      worst = std::max(worst, std::abs(a - b) / std::max(b, 1e-6));
    }
  EXPECT_LT(worst, 1e-4);  // point light only: both images are f · cos · I / r², no noise
  EXPECT_GT(mean(diffuse), 0.01);
}

TEST(MeasuredRender, GlossyTableRendersAsItsModel) {
  const std::string model = R"({"type": "roughconductor", "alpha": 0.3, "fresnel": "schlick", "f0": 0.9})";
  const gonio_test_merl::TempTable table(gonio_test_merl::temp_path("render_glossy"));
  write_merl(table.path, tabulate(parse_material(model)));
  const Image measured = render_in(plane_scene(R"({"type": "measured", "file": ")" + table.path + R"("})"), "");
  const Image analytic = render_in(plane_scene(model), "");
  EXPECT_NEAR(mean(measured), mean(analytic), 0.01 * mean(analytic));
}

}  // namespace
}  // namespace gonio::render::test
