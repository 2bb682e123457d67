// Image buffer, transfer functions and file I/O. Expected values come from the formulas
// (IEC 61966-2-1 sRGB, Narkowicz's ACES fit) evaluated by hand, and the decoders are
// also fed PNG and OpenEXR files assembled byte by byte here, so they are checked
// against the file formats rather than only against our own writers.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "gonio/render/image.h"

namespace gonio::render {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Helpers

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("gonio_image_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs fn, expects InputError, returns its message.
template <typename Fn>
std::string input_error(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no exception";
  return {};
}

void expect_one_line_naming(const std::string& message, const std::string& path) {
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// --- a minimal PNG encoder: stored (uncompressed) deflate blocks, bitwise CRC ---------

void put_be32(std::string& s, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s += char((v >> shift) & 0xff);
}

uint32_t crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (unsigned char b : bytes) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

std::string zlib_stored(const std::string& raw) {
  std::string z = "\x78\x01";
  size_t pos = 0;
  do {
    const size_t n = std::min<size_t>(raw.size() - pos, 65535);
    const bool last = pos + n == raw.size();
    z += char(last ? 1 : 0);
    z += char(n & 0xff);
    z += char(n >> 8);
    z += char(~n & 0xff);
    z += char((~n >> 8) & 0xff);
    z.append(raw, pos, n);
    pos += n;
  } while (pos < raw.size());
  uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  put_be32(z, (b << 16) | a);
  return z;
}

std::string png_chunk(const std::string& type, const std::string& data) {
  std::string c;
  put_be32(c, uint32_t(data.size()));
  const std::string body = type + data;
  c += body;
  put_be32(c, crc32(body));
  return c;
}

// rows: the raw scanlines without filter bytes.
std::string make_png(uint32_t width, int bit_depth, int color_type,
                     const std::vector<std::string>& rows, const std::string& palette = {}) {
  std::string ihdr;
  put_be32(ihdr, width);
  put_be32(ihdr, uint32_t(rows.size()));
  ihdr += char(bit_depth);
  ihdr += char(color_type);
  ihdr += std::string(3, '\0');  // deflate, adaptive filtering, no interlace
  std::string raw;
  for (const std::string& row : rows) raw += '\0' + row;  // filter type None
  std::string png = "\x89PNG\r\n\x1a\n";
  png += png_chunk("IHDR", ihdr);
  if (!palette.empty()) png += png_chunk("PLTE", palette);
  png += png_chunk("IDAT", zlib_stored(raw));
  png += png_chunk("IEND", "");
  return png;
}

// --- a minimal scanline OpenEXR encoder: FLOAT channels, no compression ---------------

void put_le32(std::string& s, uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) s += char((v >> shift) & 0xff);
}
void put_float(std::string& s, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_le32(s, bits);
}
void put_attr(std::string& s, const std::string& name, const std::string& type,
              const std::string& value) {
  s += name + '\0' + type + '\0';
  put_le32(s, uint32_t(value.size()));
  s += value;
}

// channels: (name, values row-major over the data window), names in ascending order as
// the format requires.
// `extra` is appended to the header as raw attribute bytes (put_attr).
std::string make_exr(int x0, int y0, int width, int height,
                     const std::vector<std::pair<std::string, std::vector<float>>>& channels,
                     const std::string& extra = "") {
  std::string s = "\x76\x2f\x31\x01";
  put_le32(s, 2);  // version 2, single-part scanline
  std::string chlist;
  for (const auto& [name, values] : channels) {
    chlist += name + '\0';
    put_le32(chlist, 2);  // FLOAT
    chlist += std::string(4, '\0');  // pLinear, reserved
    put_le32(chlist, 1);
    put_le32(chlist, 1);
  }
  chlist += '\0';
  std::string box;
  for (int v : {x0, y0, x0 + width - 1, y0 + height - 1}) put_le32(box, uint32_t(v));
  std::string one, zero2;
  put_float(one, 1);
  put_float(zero2, 0);
  put_float(zero2, 0);
  put_attr(s, "channels", "chlist", chlist);
  put_attr(s, "compression", "compression", std::string(1, '\0'));
  put_attr(s, "dataWindow", "box2i", box);
  put_attr(s, "displayWindow", "box2i", box);
  put_attr(s, "lineOrder", "lineOrder", std::string(1, '\0'));
  put_attr(s, "pixelAspectRatio", "float", one);
  put_attr(s, "screenWindowCenter", "v2f", zero2);
  put_attr(s, "screenWindowWidth", "float", one);
  s += extra;
  s += '\0';
  const size_t block = 8 + size_t(width) * 4 * channels.size();
  const size_t first = s.size() + 8 * size_t(height);
  for (int y = 0; y < height; ++y) {
    const uint64_t offset = first + size_t(y) * block;
    put_le32(s, uint32_t(offset));
    put_le32(s, uint32_t(offset >> 32));
  }
  for (int y = 0; y < height; ++y) {
    put_le32(s, uint32_t(y0 + y));
    put_le32(s, uint32_t(block - 8));
    for (const auto& [name, values] : channels)
      for (int x = 0; x < width; ++x) put_float(s, values[size_t(y * width + x)]);
  }
  return s;
}

// ---------------------------------------------------------------------------------------
// Image

TEST(Image, ConstructionAccessAverage) {
  Image img(3, 2);
  EXPECT_EQ(img.width(), 3);
  EXPECT_EQ(img.height(), 2);
  ASSERT_EQ(img.pixels().size(), 6u);
  for (const Color& c : img.pixels()) EXPECT_TRUE(c.is_black());
  img.at(2, 1) = Color(6, 12, 18);
  img.at(0, 0) = Color(0, 6, 0);
  EXPECT_EQ(img.pixels()[5], Color(6, 12, 18));  // row-major
  EXPECT_EQ(img.average(), Color(1, 3, 3));
  EXPECT_TRUE(Image().average().is_black());
  EXPECT_THROW(Image(-1, 2), std::invalid_argument);
}

TEST(Image, AverageAccumulatesInDouble) {
  // 2^24 + 1 ones would stall a float sum at 2^24; a 4096 x 4097 image is the same sum.
  Image img(4096, 4097);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) img.at(x, y) = Color(1);
  EXPECT_EQ(img.average(), Color(1));
}

// A 3 x 2 image; texel (x, j) with j counted from the bottom is image pixel (x, 1 - j).
Image texture() {
  Image img(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      img.at(x, y) = Color(Float(x + 10 * y), Float(100 + x), Float(200 + 10 * y));
  return img;
}

void expect_color_near(const Color& a, const Color& b, double tol = 1e-4) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "channel " << i;
}

TEST(Image, BilinearTexelCentres) {
  const Image img = texture();
  for (int j = 0; j < 2; ++j)
    for (int x = 0; x < 3; ++x) {
      const Float u = (Float(x) + 0.5f) / 3, v = (Float(j) + 0.5f) / 2;
      expect_color_near(img.bilinear(u, v), img.at(x, 1 - j));
    }
  // v = 0.25 is the bottom row's centre, i.e. the last stored row.
  expect_color_near(img.bilinear(0.5f / 3, 0.25f), img.at(0, 1));
}

TEST(Image, BilinearHalfwayIsMean) {
  const Image img = texture();
  // Between texels 0 and 1 of the bottom row.
  expect_color_near(img.bilinear(1.0f / 3, 0.25f), 0.5f * (img.at(0, 1) + img.at(1, 1)));
  // Between the two rows at x = 2.
  expect_color_near(img.bilinear(2.5f / 3, 0.5f), 0.5f * (img.at(2, 0) + img.at(2, 1)));
  // Centre of four texels.
  expect_color_near(img.bilinear(2.0f / 3, 0.5f),
                    0.25f * (img.at(1, 0) + img.at(2, 0) + img.at(1, 1) + img.at(2, 1)));
}

TEST(Image, BilinearWraps) {
  const Image img = texture();
  // u = 0 lies halfway between the last and the first column.
  expect_color_near(img.bilinear(0, 0.25f), 0.5f * (img.at(2, 1) + img.at(0, 1)));
  // v = 0 lies halfway between the bottom and the top row.
  expect_color_near(img.bilinear(0.5f / 3, 0), 0.5f * (img.at(0, 1) + img.at(0, 0)));
  // Whole periods away, and negative coordinates.
  expect_color_near(img.bilinear(1.5f / 3 + 2, 0.75f - 3), img.at(1, 0));
  expect_color_near(img.bilinear(-0.5f / 3, 0.25f), img.at(2, 1));
  // Non-finite coordinates do not crash; an empty image is black.
  EXPECT_TRUE(img.bilinear(std::numeric_limits<Float>::quiet_NaN(), 0.5f).is_finite());
  EXPECT_TRUE(Image().bilinear(0.3f, 0.3f).is_black());
  // A 1 x 1 image is constant.
  Image one(1, 1);
  one.at(0, 0) = Color(0.25f, 0.5f, 0.75f);
  expect_color_near(one.bilinear(0.9f, 0.1f), one.at(0, 0), 1e-6);
}

// ---------------------------------------------------------------------------------------
// Transfer functions

TEST(Srgb, EncodeAtHandPoints) {
  // Linear segment 12.92 x up to 0.0031308, then 1.055 x^(1/2.4) - 0.055.
  EXPECT_EQ(srgb_encode(0), 0);
  EXPECT_NEAR(srgb_encode(0.001f), 0.01292f, 1e-7);
  EXPECT_NEAR(srgb_encode(0.0031308f), 0.04045f, 1e-6);  // 12.92 * 0.0031308 = 0.0404499
  // 2^(-5/12) = 0.7491535, times 1.055 minus 0.055.
  EXPECT_NEAR(srgb_encode(0.5f), 0.735357f, 1e-6);
  EXPECT_NEAR(srgb_encode(1), 1.0f, 1e-6);
}

TEST(Srgb, DecodeAtHandPoints) {
  EXPECT_EQ(srgb_decode(0), 0);
  EXPECT_NEAR(srgb_decode(0.04045f), 0.0031308f, 1e-7);
  EXPECT_NEAR(srgb_decode(0.5f), 0.214041f, 1e-6);  // (0.555 / 1.055)^2.4
  EXPECT_NEAR(srgb_decode(1), 1.0f, 1e-6);
}

TEST(Srgb, DecodeInvertsEncode) {
  for (int i = 0; i <= 1000; ++i) {
    const Float x = Float(i) / 1000;
    EXPECT_NEAR(srgb_decode(srgb_encode(x)), x, 2e-6) << x;
  }
  // The two segments meet (the standard's pieces agree to about 1e-7 at the knee).
  EXPECT_NEAR(srgb_encode(0.0031308f), srgb_encode(std::nextafter(0.0031308f, 1.0f)), 1e-6);
}

TEST(ToneMap, ClampIsMinWithOne) {
  EXPECT_EQ(tone_map(0.25f, ToneMap::Clamp), 0.25f);
  EXPECT_EQ(tone_map(1, ToneMap::Clamp), 1);
  EXPECT_EQ(tone_map(7, ToneMap::Clamp), 1);
  EXPECT_EQ(tone_map(-1, ToneMap::Clamp), 0);
  EXPECT_EQ(tone_map(std::numeric_limits<Float>::quiet_NaN(), ToneMap::Clamp), 0);
}

TEST(ToneMap, FilmicMonotoneAndBounded) {
  EXPECT_EQ(tone_map(0, ToneMap::Filmic), 0);
  // x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14) at x = 1: 2.54 / 3.16 = 127 / 158.
  EXPECT_NEAR(tone_map(1, ToneMap::Filmic), 127.0 / 158.0, 1e-6);
  Float previous = 0;
  for (int i = 1; i <= 200000; ++i) {
    const Float x = Float(i) * 1e-4f;  // up to 20, beyond the shoulder
    const Float y = tone_map(x, ToneMap::Filmic);
    ASSERT_GE(y, previous) << x;
    ASSERT_LE(y, 1) << x;
    previous = y;
  }
  for (Float big : {10.0f, 1e3f, 1e20f, std::numeric_limits<Float>::max(),
                    std::numeric_limits<Float>::infinity()}) {
    EXPECT_LE(tone_map(big, ToneMap::Filmic), 1) << big;
    EXPECT_GE(tone_map(big, ToneMap::Filmic), 0.999f) << big;
  }
  EXPECT_EQ(tone_map(-3, ToneMap::Filmic), 0);
  EXPECT_EQ(tone_map(std::numeric_limits<Float>::quiet_NaN(), ToneMap::Filmic), 0);
}

// ---------------------------------------------------------------------------------------
// OpenEXR

TEST_F(ImageFiles, ExrRoundTripIsExact) {
  const Float values[] = {0.0f, 1.0f, 0.5f, 3.75f, 1e6f, 65504.0f, 1e-30f, 1e-42f,  // denormal
                          -2.5f, 0.1f, 123.456f, 7e-8f, 1e30f, 0.333333f, 2.0f};
  Image img(5, 3);
  int k = 0;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x, ++k)
      img.at(x, y) = Color(values[k % 15], values[(k + 4) % 15], values[(k + 9) % 15]);
  const std::string path = file("round.exr");
  write_exr(img, path);
  const Image back = read_image(path);
  ASSERT_EQ(back.width(), 5);
  ASSERT_EQ(back.height(), 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_EQ(back.at(x, y), img.at(x, y)) << x << "," << y;
  EXPECT_FALSE(fs::exists(path + ".part"));
}

TEST_F(ImageFiles, ExrIsFloatRgbZip) {
  Image img(2, 2);
  img.at(1, 0) = Color(0.5f, 0.25f, 2.0f);
  const std::string path = file("h.exr");
  write_exr(img, path);
  const std::string bytes = read_bytes(path);
  // The header names the three FLOAT (type 2) channels and ZIP compression (value 3).
  for (const char* name : {"B", "G", "R"})
    EXPECT_NE(bytes.find(std::string(name) + '\0' + std::string("\x02\0\0\0", 4)),
              std::string::npos) << name;
  EXPECT_NE(bytes.find(std::string("compression\0compression\0\x01\0\0\0\x03", 29)),
            std::string::npos);
}

TEST_F(ImageFiles, ExrHandMadeLuminanceAndOffsetWindow) {
  // Y only, data window starting at (10, 20): gray pixels, origin dropped.
  const std::string path = file("y.exr");
  write_bytes(path, make_exr(10, 20, 3, 2, {{"Y", {0.5f, 1.5f, 2.5f, 3.5f, 1e-20f, 100.0f}}}));
  const Image img = read_image(path);
  ASSERT_EQ(img.width(), 3);
  ASSERT_EQ(img.height(), 2);
  EXPECT_EQ(img.at(0, 0), Color(0.5f));
  EXPECT_EQ(img.at(2, 0), Color(2.5f));
  EXPECT_EQ(img.at(1, 1), Color(1e-20f));
  EXPECT_EQ(img.at(2, 1), Color(100.0f));
}

TEST_F(ImageFiles, ExrHandMadeMissingChannelsCopyRed) {
  const std::string path = file("rg.exr");
  // Channels sorted by name: A (ignored), G, R; B is missing.
  write_bytes(path, make_exr(0, 0, 2, 1, {{"A", {9, 9}}, {"G", {0.25f, 0.75f}},
                                          {"R", {1, 2}}}));
  const Image img = read_image(path);
  EXPECT_EQ(img.at(0, 0), Color(1, 0.25f, 1));
  EXPECT_EQ(img.at(1, 0), Color(2, 0.75f, 2));

  const std::string none = file("z.exr");
  write_bytes(none, make_exr(0, 0, 1, 1, {{"Z", {1}}}));
  const std::string msg = input_error([&] { read_image(none); });
  expect_one_line_naming(msg, none);
  EXPECT_NE(msg.find("no R or Y channel"), std::string::npos) << msg;
}

TEST_F(ImageFiles, ExtensionIsCaseInsensitive) {
  Image img(1, 1);
  img.at(0, 0) = Color(0.2f, 0.4f, 8.0f);
  write_exr(img, file("upper.EXR"));
  EXPECT_EQ(read_image(file("upper.EXR")).at(0, 0), img.at(0, 0));
  write_png(img, file("upper.Png"), {0, ToneMap::Clamp});
  EXPECT_EQ(read_image(file("upper.Png"), false).at(0, 0)[2], 1.0f);
}

// ---------------------------------------------------------------------------------------
// PNG

TEST_F(ImageFiles, PngRoundTripWithinQuantisation) {
  const int w = 64, h = 16;
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int k = y * w + x;
      img.at(x, y) = Color(Float(k) / (w * h - 1), Float((k * 37) % 1024) / 1023,
                           Float((k * 101) % 997) / 996);
    }
  img.at(0, 0) = Color(0, 0.0031308f, 1);
  const std::string path = file("round.png");
  write_png(img, path, {0, ToneMap::Clamp});
  const Image back = read_image(path);
  const Image codes = read_image(path, false);
  ASSERT_EQ(back.width(), w);
  ASSERT_EQ(back.height(), h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int i = 0; i < 3; ++i) {
        const Float v = img.at(x, y)[i], r = back.at(x, y)[i];
        // Rounding to 8 bits errs by at most half a code in the encoded domain...
        EXPECT_NEAR(srgb_encode(r), srgb_encode(v), 0.5 / 255 + 1e-6);
        // ...which is within 1/255 in linear where the decode's slope is below 2 (about
        // x < 0.75); near 1 the slope is 2.27, so a half code there is 1.14/255.
        EXPECT_NEAR(r, v, (v < 0.75f ? 1.0 : 1.15) / 255);
        // Without sRGB decoding the codes come back as code / 255.
        const long code = std::lround(srgb_encode(v) * 255);
        EXPECT_EQ(codes.at(x, y)[i], Float(code) / 255);
      }
  EXPECT_EQ(back.at(0, 0)[0], 0);
  EXPECT_EQ(back.at(0, 0)[2], 1);
  EXPECT_FALSE(fs::exists(path + ".part"));
}

TEST_F(ImageFiles, PngExposureNanNegativeInfinity) {
  Image img(5, 1);
  img.at(0, 0) = Color(0.25f);
  img.at(1, 0) = Color(std::numeric_limits<Float>::quiet_NaN());
  img.at(2, 0) = Color(-4);
  img.at(3, 0) = Color(std::numeric_limits<Float>::infinity());
  img.at(4, 0) = Color(0.0625f);
  const std::string path = file("e.png");
  write_png(img, path, {2, ToneMap::Clamp});  // x 4
  const Image codes = read_image(path, false);
  EXPECT_EQ(codes.at(0, 0), Color(1));
  EXPECT_EQ(codes.at(1, 0), Color(0));
  EXPECT_EQ(codes.at(2, 0), Color(0));
  EXPECT_EQ(codes.at(3, 0), Color(1));
  EXPECT_EQ(codes.at(4, 0)[0], Float(std::lround(srgb_encode(0.25f) * 255)) / 255);
}

TEST_F(ImageFiles, PngFilmicRampIsMonotone) {
  const int w = 512;
  Image img(w, 1);
  for (int x = 0; x < w; ++x) img.at(x, 0) = Color(Float(x) / 16);  // 0 .. 32
  const std::string path = file("ramp.png");
  write_png(img, path);  // default: Filmic
  const Image codes = read_image(path, false);
  EXPECT_EQ(codes.at(0, 0), Color(0));
  EXPECT_EQ(codes.at(w - 1, 0), Color(1));
  for (int x = 1; x < w; ++x) EXPECT_GE(codes.at(x, 0)[0], codes.at(x - 1, 0)[0]) << x;
  // 1 maps to 127/158 before sRGB encoding.
  EXPECT_EQ(codes.at(16, 0)[1], Float(std::lround(srgb_encode(127.0f / 158) * 255)) / 255);
}

TEST_F(ImageFiles, PngHandMadeLayouts) {
  // 8-bit gray.
  write_bytes(file("g8.png"), make_png(2, 8, 0, {std::string("\x00\xff", 2)}));
  Image img = read_image(file("g8.png"), false);
  EXPECT_EQ(img.at(0, 0), Color(0));
  EXPECT_EQ(img.at(1, 0), Color(1));
  EXPECT_NEAR(read_image(file("g8.png")).at(1, 0)[0], 1, 1e-6);

  // 16-bit gray, big-endian samples.
  write_bytes(file("g16.png"), make_png(2, 16, 0, {std::string("\x80\x00\x00\x01", 4)}));
  img = read_image(file("g16.png"), false);
  EXPECT_EQ(img.at(0, 0), Color(Float(32768) / 65535));
  EXPECT_EQ(img.at(1, 0), Color(Float(1) / 65535));
  // sRGB 32768/65535 = 0.50000763 decodes to about 0.2140.
  EXPECT_NEAR(read_image(file("g16.png")).at(0, 0)[0], 0.214041, 2e-5);

  // 8-bit RGBA: alpha ignored; two rows to check the order.
  write_bytes(file("rgba.png"),
              make_png(1, 8, 6, {std::string("\x33\x66\x99\x00", 4),
                                 std::string("\xff\x00\x80\x10", 4)}));
  img = read_image(file("rgba.png"), false);
  EXPECT_EQ(img.at(0, 0), Color(Float(0x33) / 255, Float(0x66) / 255, Float(0x99) / 255));
  EXPECT_EQ(img.at(0, 1), Color(1, 0, Float(0x80) / 255));

  // Gray + alpha.
  write_bytes(file("ga.png"), make_png(1, 8, 4, {std::string("\x40\x00", 2)}));
  EXPECT_EQ(read_image(file("ga.png"), false).at(0, 0), Color(Float(0x40) / 255));

  // 4-bit palette: two entries, indices 1 then 0 packed in one byte.
  write_bytes(file("pal.png"), make_png(2, 4, 3, {std::string("\x10", 1)},
                                        std::string("\x0a\x14\x1e\xc8\x64\x32", 6)));
  img = read_image(file("pal.png"), false);
  EXPECT_EQ(img.at(0, 0), Color(Float(200) / 255, Float(100) / 255, Float(50) / 255));
  EXPECT_EQ(img.at(1, 0), Color(Float(10) / 255, Float(20) / 255, Float(30) / 255));

  // 16-bit RGB.
  write_bytes(file("rgb16.png"),
              make_png(1, 16, 2, {std::string("\xff\xff\x00\x00\x12\x34", 6)}));
  EXPECT_EQ(read_image(file("rgb16.png"), false).at(0, 0),
            Color(1, 0, Float(0x1234) / 65535));
}

// ---------------------------------------------------------------------------------------
// Errors

TEST_F(ImageFiles, MissingFilesThrow) {
  for (const char* name : {"missing.png", "missing.exr"}) {
    const std::string path = file(name);
    const std::string msg = input_error([&] { read_image(path); });
    expect_one_line_naming(msg, path);
    EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  }
}

TEST_F(ImageFiles, UnknownExtensionThrows) {
  const std::string path = file("photo.jpg");
  write_bytes(path, "not really");
  const std::string msg = input_error([&] { read_image(path); });
  expect_one_line_naming(msg, path);
  expect_one_line_naming(input_error([&] { read_image(file("noext")); }), file("noext"));
}

TEST_F(ImageFiles, TruncatedPngThrows) {
  Image img(64, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      img.at(x, y) = Color(Float((x * 7 + y * 13) % 64) / 63, Float(x) / 63, Float(y) / 63);
  const std::string good = file("good.png");
  write_png(img, good, {0, ToneMap::Clamp});
  const std::string bytes = read_bytes(good);
  ASSERT_GT(bytes.size(), 200u);
  for (size_t keep : {size_t(8), size_t(20), size_t(40), bytes.size() / 2, bytes.size() - 5}) {
    const std::string path = file("cut" + std::to_string(keep) + ".png");
    write_bytes(path, bytes.substr(0, keep));
    expect_one_line_naming(input_error([&] { read_image(path); }), path);
  }
  // Shorter than the signature, and a flipped byte inside the compressed data (CRC error).
  write_bytes(file("tiny.png"), "\x89PN");
  expect_one_line_naming(input_error([&] { read_image(file("tiny.png")); }), file("tiny.png"));
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = char(flipped[bytes.size() / 2] ^ 0x5a);
  write_bytes(file("flip.png"), flipped);
  expect_one_line_naming(input_error([&] { read_image(file("flip.png")); }), file("flip.png"));
}

TEST_F(ImageFiles, TextFilesThrow) {
  const std::string exr = file("notes.exr");
  write_bytes(exr, "This is a text file,\nnot an image.\n");
  std::string msg = input_error([&] { read_image(exr); });
  expect_one_line_naming(msg, exr);
  EXPECT_NE(msg.find("not an OpenEXR file"), std::string::npos) << msg;

  const std::string png = file("notes.png");
  write_bytes(png, "This is a text file,\nnot an image.\n");
  msg = input_error([&] { read_image(png); });
  expect_one_line_naming(msg, png);
  EXPECT_NE(msg.find("not a PNG file"), std::string::npos) << msg;

  write_bytes(file("empty.exr"), "");
  expect_one_line_naming(input_error([&] { read_image(file("empty.exr")); }),
                         file("empty.exr"));
}

// What an OpenEXR header claims must fit in the file: OpenEXR allocates what it is told
// before it finds the file short (fuzz_exr: 1.6–1.9 GB for files of a few hundred bytes,
// 8 s for fuzz/corpus/exr/slow-attribute-317-bytes.exr, whose attribute claims 1.4 GB).
TEST_F(ImageFiles, ExrHeaderClaimsBeyondTheFileAreRefused) {
  const std::vector<std::pair<std::string, std::vector<float>>> red = {{"R", {0.5f, 0.25f}}};
  auto refused = [&](const std::string& name, const std::string& bytes, const std::string& words) {
    const std::string path = file(name);
    write_bytes(path, bytes);
    const std::string msg = input_error([&] { read_image(path); });
    expect_one_line_naming(msg, path);
    EXPECT_NE(msg.find(words), std::string::npos) << msg;
  };
  std::string huge_attr = std::string("screen") + '\0' + "x" + '\0';
  put_le32(huge_attr, 1467444992);
  huge_attr += std::string(60, '\0');
  refused("attr.exr", make_exr(0, 0, 1, 2, red, huge_attr), "attribute 'screen' claims 1467444992 bytes");

  // The data window of a valid 1 x 2 file, widened in place: (x1, y1) follow (x0, y0).
  auto with_window = [](std::string bytes, int x1, int y1, char compression) {
    const std::string key = std::string("dataWindow") + '\0' + "box2i" + '\0';
    const size_t box = bytes.find(key) + key.size() + 4;
    std::string corner;
    put_le32(corner, uint32_t(x1));
    put_le32(corner, uint32_t(y1));
    bytes.replace(box + 8, 8, corner);
    const std::string ckey = std::string("compression") + '\0' + "compression" + '\0';
    bytes[bytes.find(ckey) + ckey.size() + 4] = compression;
    return bytes;
  };
  const std::string small = make_exr(0, 0, 1, 2, red);
  // 8192 scan lines need 8192 offsets (64 KiB) in a file of a few hundred bytes.
  refused("lines.exr", with_window(small, 16383, 8191, 0), "chunk offsets do not fit");
  // One ZIP chunk (16 lines) of 65536 x 16 FLOAT pixels: 4 MiB in a file of ~400 bytes,
  // beyond any compression's ratio; uncompressed, even 2 lines of 4096 are too many.
  refused("ratio.exr", with_window(small, 65535, 15, 3), "claims 65536 x 16 pixels");
  refused("raw.exr", with_window(small, 4095, 1, 0), "claims 4096 x 2 pixels");
  refused("window.exr", with_window(small, 1 << 20, 1 << 20, 3), "unsupported image size");

  // A second channel list adds to the first in OpenEXR; repeated attributes are refused.
  std::string twice = std::string("channels") + '\0' + "chlist" + '\0';
  put_le32(twice, 1);
  twice += '\0';
  refused("twice.exr", make_exr(0, 0, 1, 2, red, twice), "attribute 'channels' appears twice");

  std::string multipart = small;
  multipart[5] = 0x10;  // version field bit 12
  refused("parts.exr", multipart, "multi-part");
  std::string deep = small;
  deep[5] = 0x08;  // bit 11
  refused("deep.exr", deep, "deep");
}

// A NaN or infinite EXR pixel is refused, naming it (fuzz_exr found NaN passed through).
TEST_F(ImageFiles, ExrNonFinitePixelsAreRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  write_bytes(file("nan.exr"), make_exr(0, 0, 2, 2, {{"B", {0, 0, 0, 0}}, {"G", {0, 0, 0, nan}}, {"R", {1, 1, 1, 1}}}));
  std::string msg = input_error([&] { read_image(file("nan.exr")); });
  expect_one_line_naming(msg, file("nan.exr"));
  EXPECT_NE(msg.find("channel G of pixel (1, 1) is NaN"), std::string::npos) << msg;
  write_bytes(file("inf.exr"), make_exr(0, 0, 2, 1, {{"Y", {-inf, 0}}}));
  msg = input_error([&] { read_image(file("inf.exr")); });
  EXPECT_NE(msg.find("channel Y of pixel (0, 0) is infinite"), std::string::npos) << msg;
}

TEST_F(ImageFiles, TruncatedExrThrows) {
  Image img(32, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) img.at(x, y) = Color(Float(x * y) / 7, Float(x), Float(y));
  const std::string good = file("good.exr");
  write_exr(img, good);
  const std::string bytes = read_bytes(good);
  for (size_t keep : {size_t(4), size_t(30), bytes.size() / 2, bytes.size() - 3}) {
    const std::string path = file("cut" + std::to_string(keep) + ".exr");
    write_bytes(path, bytes.substr(0, keep));
    expect_one_line_naming(input_error([&] { read_image(path); }), path);
  }
}

TEST_F(ImageFiles, WritingToMissingDirectoryThrows) {
  Image img(2, 2);
  for (const char* name : {"no/such/dir/out.png", "no/such/dir/out.exr"}) {
    const std::string path = file(name);
    const std::string msg = input_error([&] {
      if (path.ends_with(".png")) write_png(img, path);
      else write_exr(img, path);
    });
    expect_one_line_naming(msg, path);
    EXPECT_NE(msg.find("cannot open for writing: No such file or directory"), std::string::npos)
        << msg;
  }
  EXPECT_FALSE(fs::exists(dir_ / "no"));
}

TEST_F(ImageFiles, FailedWriteLeavesNoFile) {
  // The target is a directory: the data is written, but it cannot take the name.
  const std::string path = file("taken.png");
  fs::create_directory(path);
  expect_one_line_naming(input_error([&] { write_png(Image(2, 2), path); }), path);
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_FALSE(fs::exists(path + ".part"));

  // An empty image cannot be written in either format.
  expect_one_line_naming(input_error([&] { write_exr(Image(), file("e.exr")); }), file("e.exr"));
  expect_one_line_naming(input_error([&] { write_png(Image(), file("e.png")); }), file("e.png"));
  EXPECT_FALSE(fs::exists(file("e.exr")));
  EXPECT_FALSE(fs::exists(file("e.png")));

  // A write that fails part-way (a full disk): test_render_output.cpp, under a file
  // size limit.
}

TEST_F(ImageFiles, OverwritesExistingFile) {
  const std::string path = file("again.exr");
  write_bytes(path, "old contents");
  Image img(1, 1);
  img.at(0, 0) = Color(42);
  write_exr(img, path);
  EXPECT_EQ(read_image(path).at(0, 0), Color(42));
}

}  // namespace
}  // namespace gonio::render
