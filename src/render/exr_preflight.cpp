// The header of an OpenEXR file, checked against the file's size before OpenEXR reads it.
// Layout from "OpenEXR File Layout" (openexr.com, file format version 2): magic, a version
// field whose bits 9–12 flag tiles, long names, deep data and multiple parts; then
// attributes (name, type name, int32 size, value) up to an empty name; then an offset table
// of one uint64 per chunk; then the chunks.

#include "exr_preflight.h"

#include <sys/types.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <system_error>

#include "gonio/error.h"

namespace gonio::render {
namespace {

class HeaderReader {
 public:
  HeaderReader(std::FILE* f, std::uint64_t size, const std::string& path) : f_(f), size_(size), path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(path_ + ": " + problem); }
  [[noreturn]] void corrupt(const std::string& problem) const { fail("corrupt OpenEXR header: " + problem); }

  std::uint64_t position() const { return pos_; }
  std::uint64_t remaining() const { return size_ - pos_; }

  void read(void* out, std::uint64_t n, const char* what) {
    if (n > remaining()) corrupt(std::string(what) + " runs past the end of the file");
    if (std::fread(out, 1, n, f_) != n) fail("cannot read: " + std::generic_category().message(errno));
    pos_ += n;
  }
  std::uint32_t u32(const char* what) {
    unsigned char b[4];
    read(b, 4, what);
    return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
  }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  unsigned char u8(const char* what) {
    unsigned char b;
    read(&b, 1, what);
    return b;
  }
  // A NUL-terminated name of at most `max` characters.
  std::string name(size_t max, const char* what) {
    std::string s;
    for (;;) {
      const unsigned char c = u8(what);
      if (c == 0) return s;
      if (s.size() == max) corrupt(std::string(what) + " longer than " + std::to_string(max) + " characters");
      s += char(c);
    }
  }
  void skip(std::uint64_t n, const char* what) {
    if (n > remaining()) corrupt(std::string(what) + " runs past the end of the file");
    if (fseeko(f_, off_t(pos_ + n), SEEK_SET) != 0) fail("cannot read: " + std::generic_category().message(errno));
    pos_ += n;
  }

 private:
  std::FILE* f_;
  std::uint64_t size_;
  std::uint64_t pos_ = 0;
  const std::string& path_;
};

// Scan lines per chunk of each compression (the layout document's table), by enum value.
constexpr int kLinesPerChunk[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
constexpr int kCompressionNone = 0;

struct Window {
  std::int64_t width, height;
};

// Uncompressed bytes of one full image: per channel its sampled pixel count (rounded down,
// so that a subsampled channel is never over-counted) times its pixel size.
std::int64_t channel_bytes(HeaderReader& in, std::uint32_t size, size_t max_name, const Window& w) {
  const std::uint64_t end = in.position() + size;
  std::int64_t bytes = 0;
  for (;;) {
    if (in.position() >= end) in.corrupt("channel list without its terminating NUL");
    const std::string channel = in.name(max_name, "channel name");
    if (channel.empty()) break;
    const std::int32_t type = in.i32("channel type");
    in.skip(4, "channel flags");
    const std::int32_t xs = in.i32("channel sampling"), ys = in.i32("channel sampling");
    if (type < 0 || type > 2) in.corrupt("channel '" + channel + "' has unknown pixel type " + std::to_string(type));
    if (xs < 1 || ys < 1) in.corrupt("channel '" + channel + "' has sampling " + std::to_string(xs) + " x " + std::to_string(ys));
    const std::int64_t pixel = type == 1 ? 2 : 4;  // HALF; UINT and FLOAT are 4 bytes
    bytes += (w.width / xs) * (w.height / ys) * pixel;  // ≤ 2^27 · 4 per channel
  }
  if (in.position() != end) in.corrupt("channel list of the wrong size");
  return bytes;
}

}  // namespace

void preflight_exr(std::FILE* f, std::uint64_t file_size, const std::string& path) {
  if (fseeko(f, 0, SEEK_SET) != 0) throw InputError(path + ": cannot read: " + std::generic_category().message(errno));
  HeaderReader in(f, file_size, path);
  in.skip(4, "magic number");  // checked by the caller
  const std::uint32_t version = in.u32("version field");
  if ((version & 0xff) != 2) in.fail("unsupported OpenEXR version " + std::to_string(version & 0xff));
  if (version & 0x800) in.fail("deep OpenEXR files are not supported");
  if (version & 0x1000) in.fail("multi-part OpenEXR files are not supported");
  if (version & ~std::uint32_t(0x6ff)) in.corrupt("unknown flags in the version field");
  const bool tiled = version & 0x200;
  const size_t max_name = (version & 0x400) ? 255 : 31;

  std::optional<Window> window;
  int compression = kCompressionNone;
  std::int64_t tile_x = 0, tile_y = 0;
  std::uint64_t channels_at = 0;
  std::uint32_t channels_size = 0;
  for (;;) {
    const std::string name = in.name(max_name, "attribute name");
    if (name.empty()) break;
    const std::string type = in.name(max_name, "attribute type");
    const std::int32_t size = in.i32("attribute size");
    if (size < 0 || std::uint64_t(size) > in.remaining())
      in.corrupt("attribute '" + name + "' claims " + std::to_string(size) + " bytes, more than the file holds");
    if (name == "dataWindow" && type == "box2i" && size == 16) {
      const std::int64_t x0 = in.i32("dataWindow"), y0 = in.i32("dataWindow");
      const std::int64_t x1 = in.i32("dataWindow"), y1 = in.i32("dataWindow");
      window = Window{x1 - x0 + 1, y1 - y0 + 1};
    } else if (name == "compression" && type == "compression" && size == 1) {
      compression = in.u8("compression");
      if (compression >= int(std::size(kLinesPerChunk))) in.corrupt("unknown compression " + std::to_string(compression));
    } else if (name == "tiles" && type == "tiledesc" && size == 9) {
      tile_x = in.u32("tiles");
      tile_y = in.u32("tiles");
      in.skip(1, "tiles");
    } else if (name == "channels" && type == "chlist") {
      // Read once the data window is known (attributes come in any order).
      channels_at = in.position();
      channels_size = std::uint32_t(size);
      in.skip(std::uint64_t(size), "channel list");
    } else {
      in.skip(std::uint64_t(size), "attribute value");
    }
  }
  const std::uint64_t header_end = in.position();
  // Missing attributes are OpenEXR's to report; without a window nothing is allocated.
  if (!window) return;
  const auto [w, h] = *window;
  if (w <= 0 || h <= 0 || w > kMaxImagePixels / h)
    in.fail("unsupported image size " + std::to_string(w) + " x " + std::to_string(h));

  std::uint64_t chunks;
  if (tiled) {
    if (tile_x < 1 || tile_y < 1 || tile_x > kMaxExrTilePixels / tile_y)
      in.fail("unsupported tile size " + std::to_string(tile_x) + " x " + std::to_string(tile_y));
    // The first level alone: mipmaps and ripmaps only add chunks.
    chunks = std::uint64_t((w + tile_x - 1) / tile_x) * std::uint64_t((h + tile_y - 1) / tile_y);
  } else {
    chunks = std::uint64_t((h + kLinesPerChunk[compression] - 1) / kLinesPerChunk[compression]);
  }
  if (chunks > in.remaining() / 8)
    in.corrupt("its " + std::to_string(chunks) + " chunk offsets do not fit in a file of " + std::to_string(file_size) +
               " bytes");

  if (channels_at == 0) return;
  HeaderReader list(f, header_end, path);
  list.skip(channels_at, "channel list");
  const std::int64_t raw = channel_bytes(list, channels_size, max_name, *window);
  const std::int64_t size = std::int64_t(std::min<std::uint64_t>(file_size, std::uint64_t(1) << 40));
  const std::int64_t limit = compression == kCompressionNone ? size : size * kMaxExrCompressionRatio;
  if (raw > limit)
    in.corrupt("it claims " + std::to_string(w) + " x " + std::to_string(h) + " pixels (" + std::to_string(raw) +
               " bytes) in a file of " + std::to_string(file_size) + " bytes");
}

}  // namespace gonio::render
