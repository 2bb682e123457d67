// The mip pyramid of a texture image (texture_image.h) and its reading through
// OpenImageIO (texture_load.h).

#include "gonio/render/texture/texture_image.h"
#include "gonio/render/texture/texture_load.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <utility>

#include "gonio/error.h"
#include "gonio/render/image.h"

namespace gonio::render {

TextureImage::TextureImage(int width, int height, std::vector<Rgba> texels, int channels)
    : channels_(channels) {
  if (width < 1 || height < 1 || texels.size() != size_t(width) * size_t(height))
    throw std::invalid_argument("TextureImage: size does not match the texels");
  levels_.push_back({width, height, std::move(texels)});
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const TextureLevel& src = levels_.back();
    TextureLevel dst{std::max(1, src.width / 2), std::max(1, src.height / 2), {}};
    dst.texels.resize(size_t(dst.width) * size_t(dst.height));
    // Box filter: destination texel (x, y) averages source columns [x0, x1) and rows
    // [y0, y1), where the last destination column/row also takes an odd source's last one.
    for (int y = 0; y < dst.height; ++y) {
      const int y0 = src.height == 1 ? 0 : 2 * y;
      const int y1 = src.height == 1 ? 1 : (y == dst.height - 1 ? src.height : 2 * y + 2);
      for (int x = 0; x < dst.width; ++x) {
        const int x0 = src.width == 1 ? 0 : 2 * x;
        const int x1 = src.width == 1 ? 1 : (x == dst.width - 1 ? src.width : 2 * x + 2);
        double s[4] = {0, 0, 0, 0};
        for (int j = y0; j < y1; ++j)
          for (int i = x0; i < x1; ++i) {
            const Rgba& t = src.at(i, j);
            s[0] += t.r, s[1] += t.g, s[2] += t.b, s[3] += t.a;
          }
        const double n = double((x1 - x0) * (y1 - y0));
        dst.texels[size_t(y) * size_t(dst.width) + size_t(x)] =
            {Float(s[0] / n), Float(s[1] / n), Float(s[2] / n), Float(s[3] / n)};
      }
    }
    levels_.push_back(std::move(dst));
  }
}

std::size_t TextureImage::memory_bytes() const {
  std::size_t n = 0;
  for (const TextureLevel& l : levels_) n += l.texels.size() * sizeof(Rgba);
  return n;
}

namespace {

[[noreturn]] void texture_fail(const std::string& name, const std::string& problem) {
  std::string p = problem;
  std::replace_if(p.begin(), p.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  while (!p.empty() && p.back() == ' ') p.pop_back();
  throw InputError(name + ": " + p);
}

// Interleaved values already in [0, 1] (integer formats) or linear (float formats) to
// texels; `decode` applies the sRGB decoding to the colour channels.
TextureImage to_texture(int w, int h, int channels, const float* v, bool decode,
                        const std::string& name) {
  std::vector<Rgba> texels(size_t(w) * size_t(h));
  for (size_t i = 0; i < texels.size(); ++i) {
    const float* p = v + i * size_t(channels);
    float c[4] = {p[0], p[0], p[0], 1};
    if (channels == 2) c[3] = p[1];
    if (channels >= 3) c[1] = p[1], c[2] = p[2];
    if (channels >= 4) c[3] = p[3];
    for (float x : c)
      if (!std::isfinite(x))
        texture_fail(name, "texel " + std::to_string(i % size_t(w)) + ", " +
                               std::to_string(i / size_t(w)) + " is not finite");
    if (decode)
      for (int k = 0; k < 3; ++k) c[k] = srgb_decode(c[k]);
    texels[i] = {c[0], c[1], c[2], c[3]};
  }
  return TextureImage(w, h, std::move(texels), channels);
}

void check_size(std::int64_t w, std::int64_t h, int channels, const std::string& name) {
  if (w < 1 || h < 1 || w * h > kMaxTexturePixels)
    texture_fail(name, "unsupported image size " + std::to_string(w) + " x " + std::to_string(h));
  if (channels < 1 || channels > 4)
    texture_fail(name, "unsupported channel count " + std::to_string(channels));
}

// Reads the first subimage of an opened ImageInput as floats (OpenImageIO converts
// integer codes to [0, 1]).
TextureImage read_input(OIIO::ImageInput& in, const std::string& name, ColorEncoding encoding) {
  const OIIO::ImageSpec& spec = in.spec();
  const int nch = std::min(spec.nchannels, 4);
  check_size(spec.width, spec.height, nch, name);
  if (spec.depth > 1) texture_fail(name, "volume images are not supported");
  std::vector<float> v(size_t(spec.width) * size_t(spec.height) * size_t(nch));
  if (!in.read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, v.data()))
    texture_fail(name, "cannot read: " + in.geterror());
  // Float formats hold linear values whatever the colour space attribute says.
  const bool integer = spec.format.basetype != OIIO::TypeDesc::FLOAT &&
                       spec.format.basetype != OIIO::TypeDesc::HALF &&
                       spec.format.basetype != OIIO::TypeDesc::DOUBLE;
  return to_texture(spec.width, spec.height, nch, v.data(),
                    integer && encoding == ColorEncoding::Srgb, name);
}

OIIO::ImageSpec read_config() {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // PNG alpha as stored, not premultiplied
  return config;
}

// A file-name extension for OpenImageIO from the bytes' signature, else from `name`.
std::string format_hint(const unsigned char* d, std::size_t n, const std::string& name) {
  auto starts = [&](const char* sig, std::size_t len) { return n >= len && std::memcmp(d, sig, len) == 0; };
  if (starts("\x89PNG", 4)) return "x.png";
  if (starts("\xff\xd8\xff", 3)) return "x.jpg";
  if (starts("\x76\x2f\x31\x01", 4)) return "x.exr";
  if (starts("#?", 2)) return "x.hdr";
  if (starts("II*\0", 4) || starts("MM\0*", 4)) return "x.tif";
  if (starts("BM", 2)) return "x.bmp";
  if (starts("GIF8", 4)) return "x.gif";
  return "x" + std::filesystem::path(name).extension().string();
}

}  // namespace

TextureImage load_texture_file(const std::string& path, ColorEncoding encoding) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) texture_fail(path, "cannot open: no such file");
  const OIIO::ImageSpec config = read_config();
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) texture_fail(path, "cannot read image: " + OIIO::geterror());
  TextureImage img = read_input(*in, path, encoding);
  in->close();
  return img;
}

TextureImage load_texture_memory(const void* data, std::size_t size, const std::string& name,
                                 ColorEncoding encoding) {
  if (size == 0) texture_fail(name, "empty image data");
  OIIO::Filesystem::IOMemReader reader(data, size);
  OIIO::ImageSpec config = read_config();
  // With a configuration, OpenImageIO 2.4 takes the proxy from it, not from the argument.
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open(
      format_hint(static_cast<const unsigned char*>(data), size, name), &config, &reader);
  if (!in) texture_fail(name, "cannot read image: " + OIIO::geterror());
  TextureImage img = read_input(*in, name, encoding);
  in->close();
  return img;
}

TextureImage texture_from_pixels(int width, int height, int channels, int bits, const void* data,
                                 std::size_t size, const std::string& name, ColorEncoding encoding) {
  check_size(width, height, channels, name);
  if (bits != 8 && bits != 16 && bits != 32) texture_fail(name, "unsupported bit depth " + std::to_string(bits));
  const size_t n = size_t(width) * size_t(height) * size_t(channels);
  if (size < n * size_t(bits / 8)) texture_fail(name, "pixel data is truncated");
  std::vector<float> v(n);
  if (bits == 8) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    for (size_t i = 0; i < n; ++i) v[i] = float(p[i]) / 255.0f;
  } else if (bits == 16) {
    const auto* p = static_cast<const std::uint16_t*>(data);
    for (size_t i = 0; i < n; ++i) v[i] = float(p[i]) / 65535.0f;
  } else {
    std::memcpy(v.data(), data, n * sizeof(float));
  }
  return to_texture(width, height, channels, v.data(), bits != 32 && encoding == ColorEncoding::Srgb, name);
}

}  // namespace gonio::render
