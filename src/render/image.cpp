// Image buffer, texture lookup, and OpenEXR / PNG input and output.
//
// Writes go to a temporary file of a unique name next to <path> (image_output.h) and are
// renamed over <path> only after every byte has been written and the file closed without
// error, so a failed write never leaves a half-written file under the requested name.

#include "gonio/render/image.h"
#include "gonio/render/image_output.h"

#include "exr_preflight.h"
#include "gonio/io/output_file.h"

#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <new>
#include <stdexcept>
#include <system_error>
#include <type_traits>

namespace gonio::render {

// The I/O code addresses channels as floats at fixed offsets inside a Color.
static_assert(kColorChannels == 3, "image I/O is RGB only");
static_assert(std::is_standard_layout_v<Color> && sizeof(Color) == 3 * sizeof(Float));
static_assert(std::is_same_v<Float, float>, "EXR slices are 32-bit FLOAT");

namespace {

// Largest image read_image accepts (exr_preflight.h): far above any texture, and it keeps
// a corrupt header from requesting an allocation that exhausts memory.
constexpr std::int64_t kMaxPixels = kMaxImagePixels;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

std::string errno_text(int e) { return std::generic_category().message(e); }

// Library messages may span lines; InputError messages must not.
std::string one_line(const char* text) {
  std::string s(text);
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// ---------------------------------------------------------------------------------------
// Files

class InFile {
 public:
  explicit InFile(const std::string& path) : f_(std::fopen(path.c_str(), "rb")) {
    if (!f_) fail(path, "cannot open: " + errno_text(errno));
  }
  ~InFile() { std::fclose(f_); }
  InFile(const InFile&) = delete;
  InFile& operator=(const InFile&) = delete;
  FILE* get() const { return f_; }

 private:
  FILE* f_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// ---------------------------------------------------------------------------------------
// OpenEXR, through streams over our own FILE* so that every write error is seen: the
// OutputFile destructor writes the line-offset table and swallows any error it meets.

class ExrOutStream : public Imf::OStream {
 public:
  ExrOutStream(FILE* f, const std::string& name) : Imf::OStream(name.c_str()), f_(f) {}
  void write(const char c[], int n) override {
    if (n < 0 || std::fwrite(c, 1, size_t(n), f_) != size_t(n)) raise();
    end_ = std::max(end_, tellp());
  }
  uint64_t tellp() override {
    const off_t p = ftello(f_);
    if (p < 0) raise();
    return uint64_t(p);
  }
  void seekp(uint64_t pos) override {
    if (fseeko(f_, off_t(pos), SEEK_SET) != 0) raise();
  }
  int error() const { return error_; }
  // The file's length: the library seeks back to fill in the offset table at the end.
  uint64_t end() const { return end_; }

 private:
  [[noreturn]] void raise() {
    if (error_ == 0) error_ = errno ? errno : EIO;
    throw Iex::IoExc(errno_text(error_));
  }
  FILE* f_;
  int error_ = 0;
  uint64_t end_ = 0;
};

class ExrInStream : public Imf::IStream {
 public:
  ExrInStream(FILE* f, const std::string& name) : Imf::IStream(name.c_str()), f_(f) {}
  bool read(char c[], int n) override {
    if (n < 0 || std::fread(c, 1, size_t(n), f_) != size_t(n))
      throw Iex::InputExc(std::ferror(f_) ? errno_text(errno) : "unexpected end of file");
    return true;
  }
  uint64_t tellg() override {
    const off_t p = ftello(f_);
    if (p < 0) throw Iex::InputExc(errno_text(errno));
    return uint64_t(p);
  }
  void seekg(uint64_t pos) override {
    if (pos > uint64_t(INT64_MAX) || fseeko(f_, off_t(pos), SEEK_SET) != 0)
      throw Iex::InputExc("seek beyond the file");
  }
  void clear() override { std::clearerr(f_); }

 private:
  FILE* f_;
};

Image read_exr(const std::string& path, const std::string& layer = "") {
  InFile f(path);
  // The magic number first: a clear "not an OpenEXR file" beats a decoder's complaint.
  const unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  unsigned char magic[4];
  if (std::fread(magic, 1, 4, f.get()) != 4) {
    if (std::ferror(f.get())) fail(path, "cannot read: " + errno_text(errno));
    fail(path, "not an OpenEXR file");
  }
  if (std::memcmp(magic, kMagic, 4) != 0) fail(path, "not an OpenEXR file");
  struct stat st;
  if (fstat(fileno(f.get()), &st) != 0) fail(path, "cannot read: " + errno_text(errno));
  if (!S_ISREG(st.st_mode)) fail(path, "not a regular file");
  preflight_exr(f.get(), std::uint64_t(st.st_size), path);
  if (std::fseek(f.get(), 0, SEEK_SET) != 0) fail(path, "cannot read: " + errno_text(errno));

  try {
    ExrInStream stream(f.get(), path);
    Imf::InputFile file(stream);
    const Imath::Box2i dw = file.header().dataWindow();
    const std::int64_t w = std::int64_t(dw.max.x) - dw.min.x + 1;
    const std::int64_t h = std::int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > kMaxPixels)
      fail(path, "unsupported image size " + std::to_string(w) + " x " + std::to_string(h));

    // Which file channel fills R, G, B; null copies R afterwards. A layer's channels are
    // "<layer>.R" and so on (OpenEXR's naming of layers).
    const Imf::ChannelList& channels = file.header().channels();
    const std::string prefix = layer.empty() ? "" : layer + ".";
    const std::string names[4] = {prefix + "R", prefix + "G", prefix + "B", prefix + "Y"};
    const char* source[3] = {nullptr, nullptr, nullptr};
    if (channels.findChannel(names[0])) {
      source[0] = names[0].c_str();
      if (channels.findChannel(names[1])) source[1] = names[1].c_str();
      if (channels.findChannel(names[2])) source[2] = names[2].c_str();
    } else if (channels.findChannel(names[3])) {
      source[0] = names[3].c_str();
    } else {
      fail(path, "no " + names[0] + " or " + names[3] + " channel");
    }
    for (const char* name : source) {
      if (!name) continue;
      const Imf::Channel* c = channels.findChannel(name);
      if (c->xSampling != 1 || c->ySampling != 1)
        fail(path, std::string("subsampled channel ") + name + " is not supported");
    }

    Image img(static_cast<int>(w), static_cast<int>(h));
    char* base = reinterpret_cast<char*>(&img.at(0, 0));
    Imf::FrameBuffer fb;
    for (int i = 0; i < 3; ++i) {
      if (!source[i]) continue;
      // The library converts HALF and UINT channels to FLOAT.
      fb.insert(source[i], Imf::Slice::Make(Imf::FLOAT, base + i * sizeof(Float), dw,
                                            sizeof(Color), sizeof(Color) * size_t(w)));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);

    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        Color& c = img.at(x, y);
        if (!source[1]) c[1] = c[0];
        if (!source[2]) c[2] = c[0];
        // A NaN or infinite texel would reach every shading point that filters it.
        for (int i = 0; i < 3; ++i)
          if (!std::isfinite(c[i]))
            fail(path, std::string("channel ") + (source[i] ? source[i] : source[0]) + " of pixel (" +
                           std::to_string(x) + ", " + std::to_string(y) + ") is " +
                           (std::isnan(c[i]) ? "NaN" : "infinite"));
      }
    return img;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "image too large for memory");
  } catch (const std::exception& e) {
    fail(path, "corrupt OpenEXR file: " + one_line(e.what()));
  }
}

// ---------------------------------------------------------------------------------------
// PNG. libpng reports errors by longjmp. Each function that calls libpng under setjmp
// holds only trivially destructible objects, so the jump skips no destructor; buffers
// and the png structs are owned by the caller's frame.

struct PngStatus {
  char message[256];
};

void on_png_error(png_structp png, png_const_charp msg) {
  auto* status = static_cast<PngStatus*>(png_get_error_ptr(png));
  std::snprintf(status->message, sizeof status->message, "%s", msg ? msg : "unknown error");
  png_longjmp(png, 1);
}

// Warnings (e.g. an odd gamma chunk) do not stop decoding; the library prints nothing.
void on_png_warning(png_structp, png_const_charp) {}

// libpng's read or write struct with its info struct, destroyed on every path.
template <bool kWrite>
class PngHandle {
 public:
  explicit PngHandle(PngStatus* status) {
    png_ = kWrite ? png_create_write_struct(PNG_LIBPNG_VER_STRING, status, on_png_error, on_png_warning)
                  : png_create_read_struct(PNG_LIBPNG_VER_STRING, status, on_png_error, on_png_warning);
    if (png_) info_ = png_create_info_struct(png_);
  }
  ~PngHandle() {
    if (!png_) return;
    if constexpr (kWrite) png_destroy_write_struct(&png_, info_ ? &info_ : nullptr);
    else png_destroy_read_struct(&png_, info_ ? &info_ : nullptr, nullptr);
  }
  PngHandle(const PngHandle&) = delete;
  PngHandle& operator=(const PngHandle&) = delete;
  bool ok() const { return png_ && info_; }
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};
using PngReader = PngHandle<false>;
using PngWriter = PngHandle<true>;

struct PngLayout {
  png_uint_32 width, height;
  int channels, bit_depth;
  size_t row_bytes;
};

// After the 8 signature bytes: header, then transforms to 1 (gray) or 3 (RGB) channels
// of 8 or 16 bits.
bool png_decode_header(png_structp png, png_infop info, FILE* f, PngLayout* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  png_set_expand(png);  // palette -> RGB, gray below 8 bits -> 8 bits, tRNS -> alpha
  png_set_strip_alpha(png);
  png_read_update_info(png, info);
  out->width = png_get_image_width(png, info);
  out->height = png_get_image_height(png, info);
  out->channels = png_get_channels(png, info);
  out->bit_depth = png_get_bit_depth(png, info);
  out->row_bytes = png_get_rowbytes(png, info);
  return true;
}

bool png_decode_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);  // checks the rest of the file too: a cut-off file is an error
  return true;
}

bool png_encode(png_structp png, png_infop info, FILE* f, png_uint_32 width,
                png_uint_32 height, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);  // the default writer raises an error on a short fwrite
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

Image read_png(const std::string& path, bool srgb) {
  InFile f(path);
  png_byte signature[8];
  if (std::fread(signature, 1, 8, f.get()) != 8) {
    if (std::ferror(f.get())) fail(path, "cannot read: " + errno_text(errno));
    fail(path, "not a PNG file");
  }
  if (png_sig_cmp(signature, 0, 8) != 0) fail(path, "not a PNG file");

  PngStatus status{};
  PngReader reader(&status);
  if (!reader.ok()) fail(path, "out of memory");
  PngLayout layout{};
  if (!png_decode_header(reader.png(), reader.info(), f.get(), &layout))
    fail(path, std::string("corrupt PNG: ") + status.message);
  if ((layout.channels != 1 && layout.channels != 3) ||
      (layout.bit_depth != 8 && layout.bit_depth != 16))
    fail(path, "unsupported PNG layout");
  const std::int64_t w = layout.width, h = layout.height;
  if (w * h > kMaxPixels)
    fail(path, "unsupported image size " + std::to_string(w) + " x " + std::to_string(h));
  const int bytes = layout.bit_depth / 8;
  if (layout.row_bytes != size_t(w) * size_t(layout.channels * bytes))
    fail(path, "unsupported PNG layout");

  try {
    std::vector<png_byte> data(layout.row_bytes * size_t(h));
    std::vector<png_bytep> rows(static_cast<size_t>(h));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = data.data() + y * layout.row_bytes;
    if (!png_decode_rows(reader.png(), reader.info(), rows.data()))
      fail(path, std::string("corrupt or truncated PNG: ") + status.message);

    // Every possible code decoded once.
    const int max_code = (1 << layout.bit_depth) - 1;
    std::vector<Float> decode(size_t(max_code) + 1);
    for (int i = 0; i <= max_code; ++i) {
      const Float v = Float(i) / Float(max_code);
      decode[size_t(i)] = srgb ? srgb_decode(v) : v;
    }

    Image img(static_cast<int>(w), static_cast<int>(h));
    for (int y = 0; y < img.height(); ++y) {
      const png_byte* p = rows[size_t(y)];
      for (int x = 0; x < img.width(); ++x) {
        Color& c = img.at(x, y);
        for (int i = 0; i < layout.channels; ++i, p += bytes) {
          const int code = bytes == 1 ? p[0] : (p[0] << 8) | p[1];  // 16-bit is big-endian
          c[i] = decode[size_t(code)];
        }
        if (layout.channels == 1) c[1] = c[2] = c[0];
      }
    }
    return img;
  } catch (const std::bad_alloc&) {
    fail(path, "image too large for memory");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Image

Image::Image(int width, int height) {
  if (width < 0 || height < 0) throw std::invalid_argument("Image: negative size");
  width_ = width;
  height_ = height;
  pixels_.assign(size_t(width) * size_t(height), Color(0));
}

Color Image::bilinear(Float u, Float v) const {
  if (pixels_.empty()) return Color(0);
  // Continuous texel coordinates, texel centres at integers; double keeps the centres
  // exact enough at large resolutions.
  double s = double(u) * width_ - 0.5, t = double(v) * height_ - 0.5;
  if (!std::isfinite(s)) s = 0;
  if (!std::isfinite(t)) t = 0;
  const double s0 = std::floor(s), t0 = std::floor(t);
  const Float fx = Float(s - s0), fy = Float(t - t0);
  auto wrap = [](double i, int n) {
    double m = std::fmod(i, double(n));
    if (m < 0) m += n;
    return std::min(static_cast<int>(m), n - 1);
  };
  const int x0 = wrap(s0, width_), x1 = x0 + 1 == width_ ? 0 : x0 + 1;
  const int j0 = wrap(t0, height_), j1 = j0 + 1 == height_ ? 0 : j0 + 1;
  // j counts rows from the bottom; storage counts them from the top.
  const int y0 = height_ - 1 - j0, y1 = height_ - 1 - j1;
  return (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x1, y0) +
         (1 - fx) * fy * at(x0, y1) + fx * fy * at(x1, y1);
}

Color Image::average() const {
  if (pixels_.empty()) return Color(0);
  double sum[kColorChannels] = {};
  for (const Color& c : pixels_)
    for (int i = 0; i < kColorChannels; ++i) sum[i] += c[i];
  Color mean;
  for (int i = 0; i < kColorChannels; ++i) mean[i] = Float(sum[i] / double(pixels_.size()));
  return mean;
}

// ---------------------------------------------------------------------------------------
// Transfer functions

Float srgb_encode(Float linear) {
  const double x = linear;
  return Float(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
}

Float srgb_decode(Float encoded) {
  const double x = encoded;
  return Float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

Float tone_map(Float x, ToneMap op) {
  if (!(x > 0)) return 0;  // also NaN
  switch (op) {
    case ToneMap::Clamp:
      return std::min(x, Float(1));
    case ToneMap::Filmic:
      // K. Narkowicz, "ACES Filmic Tone Mapping Curve", blog post dated 2016-01-06
      // (usually cited as 2015): a rational fit of the ACES RRT+ODT curve, pre-exposed so
      // that 1 maps to about 0.8. It reaches 1 near x = 7.24; returning 1 early keeps
      // x * x from overflowing.
      if (x >= 8) return 1;
      return std::min(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), Float(1));
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// Writing: encoders into an open file, returning the file's length.

namespace {

uint64_t encode_exr(const std::vector<ExrLayer>& layers, FILE* f, const std::string& path) {
  if (layers.empty() || !layers[0].image) fail(path, "cannot write an empty image");
  const int w = layers[0].image->width(), h = layers[0].image->height();
  if (w == 0 || h == 0) fail(path, "cannot write an empty image");
  for (const ExrLayer& l : layers)
    if (!l.image || l.image->width() != w || l.image->height() != h)
      fail(path, "layer \"" + l.name + "\" differs in size from the first layer");
  ExrOutStream stream(f, path);
  try {
    Imf::Header header(w, h);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    for (const ExrLayer& l : layers) {
      // The library only reads through the slices; its interface wants char*.
      char* base = const_cast<char*>(reinterpret_cast<const char*>(l.image->pixels().data()));
      const char* channel[3] = {"R", "G", "B"};
      for (int i = 0; i < 3; ++i) {
        const std::string name = l.name.empty() ? std::string(channel[i]) : l.name + "." + channel[i];
        header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        fb.insert(name, Imf::Slice(Imf::FLOAT, base + i * sizeof(Float), sizeof(Color), sizeof(Color) * size_t(w)));
      }
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    if (stream.error() != 0) fail(path, "write failed: " + errno_text(stream.error()));
    fail(path, "cannot write OpenEXR: " + one_line(e.what()));
  }
  if (stream.error() != 0) fail(path, "write failed: " + errno_text(stream.error()));
  return stream.end();
}

uint64_t encode_png(const Image& img, FILE* f, const std::string& path, const PngOptions& opt) {
  if (img.width() == 0 || img.height() == 0) fail(path, "cannot write an empty image");
  const double scale = std::exp2(double(opt.exposure_stops));
  const size_t row_bytes = 3 * size_t(img.width());
  std::vector<png_byte> data(row_bytes * size_t(img.height()));
  std::vector<png_bytep> rows(size_t(img.height()));
  for (int y = 0; y < img.height(); ++y) {
    png_byte* p = data.data() + size_t(y) * row_bytes;
    rows[size_t(y)] = p;
    for (int x = 0; x < img.width(); ++x)
      for (int i = 0; i < 3; ++i) {
        const Float mapped = tone_map(Float(img.at(x, y)[i] * scale), opt.tonemap);
        const long code = std::lround(srgb_encode(mapped) * 255);
        *p++ = static_cast<png_byte>(std::clamp(code, 0L, 255L));
      }
  }
  PngStatus status{};
  PngWriter writer(&status);
  if (!writer.ok()) fail(path, "out of memory");
  errno = 0;
  if (!png_encode(writer.png(), writer.info(), f, png_uint_32(img.width()),
                  png_uint_32(img.height()), rows.data())) {
    const int error = errno;
    std::string problem = std::string("cannot write PNG: ") + status.message;
    if (error != 0) problem += " (" + errno_text(error) + ")";
    fail(path, problem);
  }
  const off_t end = ftello(f);  // libpng writes straight through, never seeking
  if (end < 0) fail(path, "write failed: " + errno_text(errno));
  return uint64_t(end);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The output file

ImageOutput::ImageOutput(const std::string& path) : path_(path), file_(path, "the image") {
  const std::string ext = lower_extension(path);
  format_ = ext == ".exr" ? Format::Exr : ext == ".png" ? Format::Png : Format::Unknown;
}

std::uint64_t ImageOutput::max_exr_bytes(int width, int height, int layers) {
  // ZIP blocks of 16 rows are stored raw when compression does not shrink them (OpenEXR
  // file layout: 8 bytes of row number and size per block, 8 per offset-table entry),
  // plus the header, a few hundred bytes.
  const std::uint64_t raw =
      std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0)) * 12 * std::uint64_t(std::max(layers, 1));
  return raw + 16 * (std::uint64_t(std::max(height, 0)) / 16 + 1) + 65536;
}

std::uint64_t ImageOutput::max_png_bytes(int width, int height) {
  // Filtered rows (a filter byte + 3 bytes per pixel) through zlib, whose worst case adds
  // about 0.03% (deflateBound), in IDAT chunks of 8 KiB with 12 bytes each of framing.
  const std::uint64_t raw = std::uint64_t(std::max(height, 0)) * (1 + 3 * std::uint64_t(std::max(width, 0)));
  return raw + raw / 128 + 65536;
}

void ImageOutput::reserve(int width, int height, int exr_layers) {
  const std::uint64_t exr = max_exr_bytes(width, height, exr_layers);
  file_.reserve(format_ == Format::Exr   ? exr
                : format_ == Format::Png ? max_png_bytes(width, height)
                                         : std::max(exr, max_png_bytes(width, height)));
}

void ImageOutput::write(const Image& img, const PngOptions& png) {
  if (format_ == Format::Unknown) fail(path_, "unknown image format (expected .exr or .png)");
  finish([&](FILE* f) {
    return format_ == Format::Exr ? encode_exr({{"", &img}}, f, path_) : encode_png(img, f, path_, png);
  });
}

void ImageOutput::write_exr(const Image& img) {
  finish([&](FILE* f) { return encode_exr({{"", &img}}, f, path_); });
}

void ImageOutput::write_exr_layers(const std::vector<ExrLayer>& layers) {
  finish([&](FILE* f) { return encode_exr(layers, f, path_); });
}

void ImageOutput::write_png(const Image& img, const PngOptions& png) {
  finish([&](FILE* f) { return encode_png(img, f, path_, png); });
}

// OutputFile checks every step of the write before the file takes its real name.
void ImageOutput::finish(const std::function<std::uint64_t(FILE*)>& encode) { file_.commit(encode); }

void write_exr(const Image& img, const std::string& path) {
  if (img.width() == 0 || img.height() == 0) fail(path, "cannot write an empty image");
  ImageOutput(path).write_exr(img);
}

void write_png(const Image& img, const std::string& path, const PngOptions& opt) {
  if (img.width() == 0 || img.height() == 0) fail(path, "cannot write an empty image");
  ImageOutput(path).write_png(img, opt);
}

// ---------------------------------------------------------------------------------------
// Reading

Image read_exr_layer(const std::string& path, const std::string& layer) {
  if (lower_extension(path) != ".exr") fail(path, "layers are read from OpenEXR files only (expected .exr)");
  return read_exr(path, layer);
}

Image read_image(const std::string& path, bool srgb) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return read_exr(path);
  if (ext == ".png") return read_png(path, srgb);
  fail(path, "unknown image format (expected .exr or .png)");
}

}  // namespace gonio::render
