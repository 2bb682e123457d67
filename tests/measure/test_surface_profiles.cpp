// The deterministic microsurfaces (include/gonio/measure/profiles.h) through parse_surface:
// V-grooves with exact facet slopes, heights read back from EXR and PNG images, and the
// preview image (preview.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "gonio/error.h"
#include "gonio/measure/preview.h"
#include "gonio/measure/profiles.h"
#include "gonio/measure/surface.h"
#include "gonio/render/image.h"

namespace gm = gonio::measure;
namespace fs = std::filesystem;

namespace {


// A fresh directory under the system's temporary directory, removed at the end.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) {
    path = fs::temp_directory_path() /
           ("gonio_surface_" + name + "_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

// Every facet of a V-groove surface is inclined by exactly the angle: the forward
// differences along x alternate +tan, −tan (valley at even i, ridge at odd i), those along
// y are 0, and n = 2 · grooves.
TEST(VGroove, FacetSlopesAreExactlyPlusMinusTanAngle) {
  for (const double angle : {10.0, 45.0, 60.0, 80.0}) {
    const gm::Surface s = gm::parse_surface(R"({"type": "vgroove", "angle": )" + std::to_string(angle) +
                                            R"(, "grooves": 5, "size": 2, "material": {"type": "mirror"}})");
    const gm::HeightField& f = s.field;
    ASSERT_EQ(f.n, 10);
    EXPECT_EQ(f.size, 2.0);
    const double t = std::tan(angle * gonio::kPiD / 180), h = f.spacing();
    for (int j = 0; j < f.n; ++j)
      for (int i = 0; i < f.n; ++i) {
        const double sx = (f.at(i + 1, j) - f.at(i, j)) / h, sy = (f.at(i, j + 1) - f.at(i, j)) / h;
        EXPECT_NEAR(sx, i % 2 ? -t : t, 1e-6 * t) << angle << " " << i << " " << j;
        EXPECT_EQ(sy, 0.0);
        if (i % 2 == 0) {
          EXPECT_EQ(f.at(i, j), 0.0f) << "valleys at height 0 on even grid lines";
        }
      }
  }
  EXPECT_EQ(gm::parse_surface(R"({"type": "vgroove", "angle": 30, "material": {"type": "mirror"}})").field.n, 32)
      << "16 grooves by default";
}

// Heights read back from a float EXR: z = height · size · R, with image row 0 at y = top.
TEST(ImageSurface, ExrHeightsReadBack) {
  TempDir dir("exr");
  const int w = 6;
  gonio::render::Image img(w, w);
  for (int r = 0; r < w; ++r)
    for (int x = 0; x < w; ++x) img.at(x, r) = gonio::Color(0.125f * x - 0.25f * r, 9.0f, 9.0f);  // G, B ignored
  gonio::render::write_exr(img, (dir.path / "h.exr").string());
  const gm::Surface s = gm::parse_surface(R"({"type": "image", "file": "h.exr", "height": 0.5, "size": 4,
                                              "material": {"type": "diffuse"}})",
                                          "--surface", dir.path.string());
  ASSERT_EQ(s.field.n, w);
  EXPECT_EQ(s.field.size, 4.0);
  for (int r = 0; r < w; ++r)
    for (int x = 0; x < w; ++x)
      EXPECT_FLOAT_EQ(s.field.at(x, w - 1 - r), float(0.5 * 4 * (0.125 * x - 0.25 * r))) << x << " " << r;
}

// A PNG's codes are data, not sRGB: code c is height · size · c/255.
TEST(ImageSurface, PngCodesAreLinear) {
  TempDir dir("png");
  gonio::render::Image img(4, 4);
  img.at(1, 0) = gonio::Color(1.0f);  // top row, x = 1
  img.at(3, 2) = gonio::Color(1.0f);
  img.at(2, 1) = gonio::Color(0.2f);  // written sRGB-encoded: code round(255 · encode(0.2)) = 124
  const float mid = float(0.25 * std::round(255 * gonio::render::srgb_encode(0.2f)) / 255);
  gonio::render::write_png(img, (dir.path / "h.png").string(), {0, gonio::render::ToneMap::Clamp});
  const gm::Surface s = gm::parse_surface(R"({"type": "image", "file": "h.png", "height": 0.25,
                                              "material": {"type": "diffuse"}})",
                                          "--surface", dir.path.string());
  ASSERT_EQ(s.field.n, 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const bool white = (i == 1 && j == 3) || (i == 3 && j == 1), grey = i == 2 && j == 2;
      EXPECT_FLOAT_EQ(s.field.at(i, j), white ? 0.25f : (grey ? mid : 0.0f)) << i << " " << j;
    }
}

TEST(ImageSurface, BadImagesNameTheFile) {
  TempDir dir("bad");
  gonio::render::write_exr(gonio::render::Image(4, 3), (dir.path / "wide.exr").string());
  const auto message = [&](const std::string& file) -> std::string {
    try {
      gm::parse_surface(R"({"type": "image", "file": ")" + file + R"(", "height": 1, "material": {"type": "diffuse"}})",
                        "--surface", dir.path.string());
    } catch (const gonio::InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string missing = message("missing.png");
  EXPECT_NE(missing.find("image: "), std::string::npos) << missing;
  EXPECT_NE(missing.find("missing.png"), std::string::npos) << missing;
  const std::string wide = message("wide.exr");
  EXPECT_NE(wide.find("wide.exr"), std::string::npos) << wide;
  EXPECT_NE(wide.find("square"), std::string::npos) << wide;
}

// The preview: at most 1024² pixels, whole pixels per cell or whole cells per pixel;
// a flat surface is uniform; on V-grooves the facets facing the light (from −x) are the
// brighter ones.
TEST(SurfacePreview, SizeAndShading) {
  EXPECT_EQ(gm::preview_side(1), 1024);
  EXPECT_EQ(gm::preview_side(64), 1024);
  EXPECT_EQ(gm::preview_side(300), 900);
  EXPECT_EQ(gm::preview_side(1024), 1024);
  EXPECT_EQ(gm::preview_side(1500), 750);
  EXPECT_EQ(gm::preview_side(2048), 1024);

  TempDir dir("preview");
  const std::string flat = (dir.path / "flat.png").string();
  gm::write_surface_preview(gm::flat_height_field(), flat, {false, 16});
  const gonio::render::Image a = gonio::render::read_image(flat);
  ASSERT_EQ(a.width(), 16);
  ASSERT_EQ(a.height(), 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) EXPECT_EQ(a.at(x, y)[1], a.at(0, 0)[1]);

  const std::string groove = (dir.path / "groove.png").string();
  gm::write_surface_preview(gm::vgroove_height_field(45, 2), groove, {false, 64});
  const gonio::render::Image b = gonio::render::read_image(groove);
  ASSERT_EQ(b.width(), 64);  // n = 4, 16 pixels per cell
  // cell 0 rises along +x (normal towards −x, the light's side), cell 1 falls
  EXPECT_GT(b.at(8, 32)[1], b.at(24, 32)[1] + 0.1f);

  // an unwritable path is bad input, and the message names it
  try {
    gm::write_surface_preview(gm::flat_height_field(), "/nonexistent-dir/preview.png", {false, 16});
    ADD_FAILURE() << "no error";
  } catch (const gonio::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/preview.png"), std::string::npos) << e.what();
  }
}
