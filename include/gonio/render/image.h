#pragma once
// Images for the renderer: a linear RGB pixel buffer, its texture lookup, and reading and
// writing OpenEXR (linear float, lossless) and PNG (8-bit sRGB for display, or data maps).
// Every failure of a file operation throws gonio::InputError with one line
// "<path>: <problem>".

#include <cassert>
#include <cstddef>
#include <string>
#include <vector>

#include "gonio/color.h"
#include "gonio/error.h"

namespace gonio::render {

// Linear RGB image, row-major, row 0 at the top.
class Image {
 public:
  Image() = default;
  Image(int width, int height);  // black; throws std::invalid_argument if negative

  int width() const { return width_; }
  int height() const { return height_; }

  Color& at(int x, int y) { return pixels_[index(x, y)]; }
  const Color& at(int x, int y) const { return pixels_[index(x, y)]; }

  // Bilinear lookup with wrap-around at texture coordinates (u, v), u to the right and v
  // up (v = 0 is the bottom edge, as in the usual texture convention). Texel (x, row j
  // from the bottom) has its centre at ((x + 0.5) / width, (j + 0.5) / height).
  // Coordinates outside [0, 1) wrap; an empty image gives black.
  Color bilinear(Float u, Float v) const;

  // Mean over all pixels, accumulated in double; black for an empty image.
  Color average() const;

  const std::vector<Color>& pixels() const { return pixels_; }

 private:
  size_t index(int x, int y) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_);
    return size_t(y) * size_t(width_) + size_t(x);
  }

  int width_ = 0, height_ = 0;
  std::vector<Color> pixels_;
};

enum class ToneMap { Clamp, Filmic };

struct PngOptions {
  Float exposure_stops = 0;
  ToneMap tonemap = ToneMap::Filmic;
};

// Both writers go through ImageOutput (image_output.h): a temporary file of a unique name
// next to `path`, renamed over it once complete.

// Linear float OpenEXR: 32-bit FLOAT channels R, G, B, ZIP compression.
void write_exr(const Image& img, const std::string& path);

// One image of a multi-layer OpenEXR file: channels "<name>.R", "<name>.G", "<name>.B"
// (OpenEXR's naming of layers), or R, G, B when `name` is empty.
struct ExrLayer {
  std::string name;
  const Image* image = nullptr;
};

// 8-bit sRGB PNG: value * 2^exposure_stops, then the tone map per channel, then the sRGB
// transfer function, rounded to the nearest 8-bit code. NaN and negative values give 0.
void write_png(const Image& img, const std::string& path, const PngOptions& opt = {});

// Reads .exr (channels R, G, B or Y, any pixel type; a missing G or B copies R) or .png
// (8 or 16 bit; gray, RGB, palette; alpha ignored). PNG codes are decoded from sRGB to
// linear when `srgb` is true, else taken as linear code / (2^bits - 1) (data such as
// roughness maps). The extension (case-insensitive) chooses the format. An EXR pixel that
// is NaN or infinite is an error.
Image read_image(const std::string& path, bool srgb = true);
// The layer `layer` of an OpenEXR file (channels "<layer>.R" ..., or "<layer>.Y"), with the
// checks of read_image; "" is the default layer (R, G, B).
Image read_exr_layer(const std::string& path, const std::string& layer);

// sRGB transfer function of IEC 61966-2-1 (exposed for tests).
Float srgb_encode(Float linear);
Float srgb_decode(Float encoded);

// The tone map of write_png for one channel value >= 0; the result is in [0, 1].
// Filmic is Narkowicz's fit of the ACES filmic curve (see image.cpp).
Float tone_map(Float x, ToneMap op);

}  // namespace gonio::render
