// The shared image and texture layer (include/gonio/render/texture/): lookups against
// values worked out by hand, the mip pyramid's box means, and reading through OpenImageIO
// with sRGB decoding by the IEC 61966-2-1 closed form.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gonio/error.h"
#include "gonio/render/image.h"
#include "gonio/render/texture/texture_image.h"
#include "gonio/render/texture/texture_load.h"
#include "gonio/render/texture/texture_sampler.h"
#include "scratch_dir.h"

namespace gonio::render {
namespace {

// IEC 61966-2-1 decoding, written out here independently of the library's.
double iec_srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// A width × height image whose texel (x, y) has r = x, g = y, b = 10 y + x, a = 1.
TextureImage ramp(int w, int h) {
  std::vector<Rgba> t;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.push_back({Float(x), Float(y), Float(10 * y + x), 1});
  return TextureImage(w, h, std::move(t), 3);
}

TEST(TextureLayer, WrapIndexModes) {
  using texture_detail::wrap_index;
  EXPECT_EQ(wrap_index(-1, 4, TextureWrap::Repeat), 3);
  EXPECT_EQ(wrap_index(5, 4, TextureWrap::Repeat), 1);
  EXPECT_EQ(wrap_index(-1, 4, TextureWrap::Clamp), 0);
  EXPECT_EQ(wrap_index(9, 4, TextureWrap::Clamp), 3);
  // Mirrored repeat of 0 1 2 3: ... 1 0 | 0 1 2 3 | 3 2 1 0 | 0 1 ...
  EXPECT_EQ(wrap_index(-1, 4, TextureWrap::Mirror), 0);
  EXPECT_EQ(wrap_index(-2, 4, TextureWrap::Mirror), 1);
  EXPECT_EQ(wrap_index(4, 4, TextureWrap::Mirror), 3);
  EXPECT_EQ(wrap_index(7, 4, TextureWrap::Mirror), 0);
  EXPECT_EQ(wrap_index(8, 4, TextureWrap::Mirror), 0);
}

TEST(TextureLayer, NearestAndBilinearAtKnownPoints) {
  const TextureImage img = ramp(4, 2);
  TextureSampler nearest;
  nearest.mag = nearest.min = TextureFilter::Nearest;
  // s = 0.6 is in column 2 (covers [0.5, 0.75)); t = 0.7 in row 1 (t down from the top).
  Rgba c = lookup(img, nearest, {0.6f, 0.7f});
  EXPECT_EQ(c.r, 2);
  EXPECT_EQ(c.g, 1);
  // Bilinear at a texel centre gives the texel; halfway between centres, the mean.
  const TextureSampler lin;
  c = lookup(img, lin, {(1 + 0.5f) / 4, (0 + 0.5f) / 2});
  EXPECT_NEAR(c.r, 1, 1e-6);
  EXPECT_NEAR(c.g, 0, 1e-6);
  c = lookup(img, lin, {2.0f / 4, 1.0f / 2});  // between columns 1, 2 and rows 0, 1
  EXPECT_NEAR(c.r, 1.5, 1e-6);
  EXPECT_NEAR(c.g, 0.5, 1e-6);
  // A quarter of the way from column 1's centre to column 2's: 1.25.
  c = lookup(img, lin, {(1.5f + 0.25f) / 4, 0.25f});
  EXPECT_NEAR(c.r, 1.25, 1e-6);
}

TEST(TextureLayer, WrapModesAtTheEdge) {
  const TextureImage img = ramp(4, 1);
  TextureSampler s;
  // s = 0: halfway between column 3 (wrapped) and column 0's centre at −0.5 texel... the
  // lookup point is 0.5 texel left of column 0's centre.
  s.wrap_s = TextureWrap::Repeat;
  EXPECT_NEAR(lookup(img, s, {0, 0.5f}).r, 1.5, 1e-6);   // (3 + 0) / 2
  s.wrap_s = TextureWrap::Clamp;
  EXPECT_NEAR(lookup(img, s, {0, 0.5f}).r, 0, 1e-6);     // (0 + 0) / 2
  EXPECT_NEAR(lookup(img, s, {-3.2f, 0.5f}).r, 0, 1e-6);
  EXPECT_NEAR(lookup(img, s, {7.0f, 0.5f}).r, 3, 1e-6);
  s.wrap_s = TextureWrap::Mirror;
  EXPECT_NEAR(lookup(img, s, {0, 0.5f}).r, 0, 1e-6);     // mirrored neighbour of 0 is 0
  // Repeat is periodic with period 1, mirror with period 2 and symmetric about 1.
  s.wrap_s = TextureWrap::Repeat;
  EXPECT_NEAR(lookup(img, s, {0.3f + 5, 0.5f}).r, lookup(img, s, {0.3f, 0.5f}).r, 1e-4);
  s.wrap_s = TextureWrap::Mirror;
  EXPECT_NEAR(lookup(img, s, {1.3f, 0.5f}).r, lookup(img, s, {0.7f, 0.5f}).r, 1e-4);
  EXPECT_NEAR(lookup(img, s, {-0.3f, 0.5f}).r, lookup(img, s, {0.3f, 0.5f}).r, 1e-4);
  // Non-finite coordinates read a texel, never NaN.
  const Rgba n = lookup(img, s, {std::nanf(""), INFINITY});
  EXPECT_TRUE(std::isfinite(n.r) && std::isfinite(n.g));
}

TEST(TextureLayer, MipPyramidIsTheBoxMean) {
  const TextureImage img = ramp(4, 4);
  ASSERT_EQ(img.level_count(), 3);
  // Level 1 texel (1, 0) averages columns 2, 3 of rows 0, 1: r = 2.5, g = 0.5.
  EXPECT_NEAR(img.level(1).at(1, 0).r, 2.5, 1e-6);
  EXPECT_NEAR(img.level(1).at(1, 0).g, 0.5, 1e-6);
  // The 1 × 1 level is the mean of all: r = 1.5, g = 1.5, b = 16.5.
  EXPECT_NEAR(img.level(2).at(0, 0).b, 16.5, 1e-5);
  // An odd size folds its last column into the last box: 3 → 1 averages all three.
  const TextureImage odd = ramp(3, 1);
  ASSERT_EQ(odd.level_count(), 2);
  EXPECT_NEAR(odd.level(1).at(0, 0).r, 1, 1e-6);
  // A footprint of 4 texels reads level 2 (the mean); 2 texels level 1; trilinear between.
  const TextureSampler s;
  EXPECT_NEAR(lookup(img, s, {0.3f, 0.6f}, 4).b, 16.5, 1e-4);
  const Float l1 = lookup(img, s, {0.25f, 0.25f}, 2).r;   // level 1, texel (0, 0) centre
  EXPECT_NEAR(l1, 0.5, 1e-5);
  EXPECT_NEAR(lookup(img, s, {0.25f, 0.25f}, std::sqrt(8.0f)).r, 0.5 * (0.5 + 1.5), 1e-4);
  TextureSampler none = s;
  none.mipmaps = false;
  EXPECT_NEAR(lookup(img, none, {0.125f, 0.125f}, 4).r, 0, 1e-6);
}

TEST(TextureLayer, PixelsDecodeSrgbForColourOnly) {
  const unsigned char px[4] = {0, 128, 255, 64};  // one RGBA texel
  const TextureImage srgb = texture_from_pixels(1, 1, 4, 8, px, 4, "t", ColorEncoding::Srgb);
  EXPECT_NEAR(srgb.level(0).at(0, 0).g, iec_srgb_to_linear(128 / 255.0), 1e-6);
  EXPECT_NEAR(srgb.level(0).at(0, 0).b, 1, 1e-6);
  EXPECT_NEAR(srgb.level(0).at(0, 0).a, 64 / 255.0, 1e-6);  // alpha stays linear
  const TextureImage lin = texture_from_pixels(1, 1, 4, 8, px, 4, "t", ColorEncoding::Linear);
  EXPECT_NEAR(lin.level(0).at(0, 0).g, 128 / 255.0, 1e-6);
  const std::uint16_t gray[2] = {65535, 32768};  // gray + alpha
  const TextureImage ga = texture_from_pixels(1, 1, 2, 16, gray, 4, "t", ColorEncoding::Linear);
  EXPECT_EQ(ga.level(0).at(0, 0).b, 1);
  EXPECT_NEAR(ga.level(0).at(0, 0).a, 32768 / 65535.0, 1e-6);
  EXPECT_THROW(texture_from_pixels(2, 2, 4, 8, px, 4, "t", ColorEncoding::Linear), InputError);
  EXPECT_THROW(texture_from_pixels(1, 1, 5, 8, px, 5, "t", ColorEncoding::Linear), InputError);
  const float bad[3] = {1, NAN, 0};
  EXPECT_THROW(texture_from_pixels(1, 1, 3, 32, bad, 12, "t", ColorEncoding::Linear), InputError);
}

std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

TEST(TextureLayer, ReadsPngFromFileAndMemory) {
  gonio::test::ScratchDir dir("gonio_texture");
  Image img(2, 1);
  img.at(0, 0) = Color(0.2f, 0.5f, 1.0f);
  img.at(1, 0) = Color(0.0f, 0.05f, 0.8f);
  const std::string png = dir.path("a.png");
  write_png(img, png, {0, ToneMap::Clamp});
  for (int memory = 0; memory < 2; ++memory) {
    const std::string bytes = slurp(png);
    const TextureImage t = memory ? load_texture_memory(bytes.data(), bytes.size(), "embedded", ColorEncoding::Srgb)
                                  : load_texture_file(png, ColorEncoding::Srgb);
    ASSERT_EQ(t.width(), 2);
    // 8-bit sRGB codes: the round trip is within half a code's step.
    EXPECT_NEAR(t.level(0).at(0, 0).r, 0.2, 0.003);
    EXPECT_NEAR(t.level(0).at(0, 0).g, 0.5, 0.003);
    EXPECT_NEAR(t.level(0).at(1, 0).g, 0.05, 0.001);
    // As data, the code itself: sRGB-encoded 0.5 is code 188.
    const TextureImage d = memory ? load_texture_memory(bytes.data(), bytes.size(), "embedded", ColorEncoding::Linear)
                                  : load_texture_file(png, ColorEncoding::Linear);
    EXPECT_NEAR(d.level(0).at(0, 0).g, 188 / 255.0, 1e-6);
    // Truncated bytes: one error, no crash.
    EXPECT_THROW(load_texture_memory(bytes.data(), bytes.size() / 2, "cut.png", ColorEncoding::Srgb), InputError);
  }
  EXPECT_THROW(load_texture_file(dir.path("missing.png"), ColorEncoding::Srgb), InputError);
  const std::string junk = dir.file("junk.png", "not an image at all");
  EXPECT_THROW(load_texture_file(junk, ColorEncoding::Srgb), InputError);
}

TEST(TextureLayer, ReadsExrAndRadianceHdrAsLinear) {
  gonio::test::ScratchDir dir("gonio_texture");
  Image img(1, 2);
  img.at(0, 0) = Color(3.5f, 0.25f, 0.0f);
  img.at(0, 1) = Color(0.125f, 7.0f, 1.0f);
  write_exr(img, dir.path("a.exr"));
  const TextureImage e = load_texture_file(dir.path("a.exr"), ColorEncoding::Srgb);  // float: never decoded
  EXPECT_EQ(e.level(0).at(0, 0).r, 3.5f);
  EXPECT_EQ(e.level(0).at(0, 1).g, 7.0f);
  // Radiance RGBE, uncompressed scanline: mantissas (128, 64, 32), exponent 129 give
  // m · 2^(e − 136) = (1, 0.5, 0.25) (Ward, Graphics Gems II "Real pixels").
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
  const unsigned char px[8] = {128, 64, 32, 129, 128, 128, 128, 130};
  hdr.append(reinterpret_cast<const char*>(px), 8);
  std::ofstream(dir.path("a.hdr"), std::ios::binary) << hdr;
  const TextureImage h = load_texture_file(dir.path("a.hdr"), ColorEncoding::Srgb);
  ASSERT_EQ(h.width(), 2);
  EXPECT_NEAR(h.level(0).at(0, 0).r, 1.0, 0.01);
  EXPECT_NEAR(h.level(0).at(0, 0).g, 0.5, 0.01);
  EXPECT_NEAR(h.level(0).at(0, 0).b, 0.25, 0.01);
  EXPECT_NEAR(h.level(0).at(1, 0).r, 2.0, 0.02);
}

}  // namespace
}  // namespace gonio::render
