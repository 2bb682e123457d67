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
#include <set>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

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

// OpenEXR reads a value of a known fixed-size type by its type, whatever its size field
// says, so a size that disagrees would put this reader and OpenEXR's out of step: it must
// be the type's (OpenEXR's standard attribute types, their layouts in the document).
int fixed_size(const std::string& type) {
  static const std::pair<const char*, int> kSizes[] = {
      {"box2i", 16}, {"box2f", 16},    {"chromaticities", 32}, {"compression", 1}, {"double", 8},
      {"envmap", 1}, {"float", 4},     {"int", 4},             {"keycode", 28},    {"lineOrder", 1},
      {"m33f", 36},  {"m33d", 72},     {"m44f", 64},           {"m44d", 128},      {"rational", 8},
      {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8},            {"v2f", 8},         {"v2d", 16},
      {"v3i", 12},   {"v3f", 12},      {"v3d", 24},            {"deepImageState", 1}};
  for (const auto& [name, size] : kSizes)
    if (type == name) return size;
  return -1;
}

struct Window {
  std::int64_t width, height;
};

struct Channel {
  std::int64_t pixel_bytes, x_sampling, y_sampling;
};

// A channel list, read by its content as OpenEXR reads it (names up to an empty one), which
// must take exactly `size` bytes.
std::vector<Channel> read_channels(HeaderReader& in, std::int32_t size, size_t max_name) {
  const std::uint64_t end = in.position() + std::uint64_t(size);
  std::vector<Channel> channels;
  for (;;) {
    const std::string channel = in.name(max_name, "channel name");
    if (channel.empty()) break;
    const std::int32_t type = in.i32("channel type");
    in.skip(4, "channel flags");
    const std::int32_t xs = in.i32("channel sampling"), ys = in.i32("channel sampling");
    if (type < 0 || type > 2) in.corrupt("channel '" + channel + "' has unknown pixel type " + std::to_string(type));
    if (xs < 1 || ys < 1)
      in.corrupt("channel '" + channel + "' has sampling " + std::to_string(xs) + " x " + std::to_string(ys));
    channels.push_back({type == 1 ? 2 : 4, xs, ys});  // HALF; UINT and FLOAT are 4 bytes
    if (in.position() > end) break;
  }
  if (in.position() != end) in.corrupt("a channel list whose size field is not its size");
  return channels;
}

// A preview image (uint32 width, height, then RGBA bytes) must be as large as it says:
// OpenEXR allocates width x height x 4 bytes from the two numbers.
void check_preview(HeaderReader& in, std::int32_t size) {
  if (size < 8) in.corrupt("a preview attribute of " + std::to_string(size) + " bytes");
  const std::uint64_t w = in.u32("preview size"), h = in.u32("preview size");
  if ((h != 0 && w > std::uint64_t(size) / h) || w * h * 4 != std::uint64_t(size) - 8) in.corrupt("a preview image larger than its attribute");
  in.skip(std::uint64_t(size) - 8, "preview image");
}

// A string vector (int32 length, then the characters, repeated): OpenEXR allocates each
// length it reads, so each must lie within the attribute.
void check_string_vector(HeaderReader& in, std::int32_t size) {
  const std::uint64_t end = in.position() + std::uint64_t(size);
  while (in.position() < end) {
    if (end - in.position() < 4) in.corrupt("a string vector whose size field is not its size");
    const std::int32_t length = in.i32("string length");
    if (length < 0 || std::uint64_t(length) > end - in.position())
      in.corrupt("a string of " + std::to_string(length) + " bytes beyond its attribute");
    in.skip(std::uint64_t(length), "string");
  }
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
  std::vector<Channel> channels;
  // OpenEXR reads a repeated attribute into the same value (a second channel list adds to
  // the first), which no writer produces and this reader would not follow.
  std::set<std::string> seen;
  for (;;) {
    const std::string name = in.name(max_name, "attribute name");
    if (name.empty()) break;
    if (!seen.insert(name).second) in.corrupt("attribute '" + name + "' appears twice");
    const std::string type = in.name(max_name, "attribute type");
    const std::int32_t size = in.i32("attribute size");
    if (size < 0 || std::uint64_t(size) > in.remaining())
      in.corrupt("attribute '" + name + "' claims " + std::to_string(size) + " bytes, more than the file holds");
    const int expected = fixed_size(type);
    if (expected >= 0 && size != expected)
      in.corrupt("attribute '" + name + "' of type " + type + " has size " + std::to_string(size) + ", not " +
                 std::to_string(expected));
    if (name == "dataWindow" && type == "box2i") {
      const std::int64_t x0 = in.i32("dataWindow"), y0 = in.i32("dataWindow");
      const std::int64_t x1 = in.i32("dataWindow"), y1 = in.i32("dataWindow");
      window = Window{x1 - x0 + 1, y1 - y0 + 1};
    } else if (name == "compression" && type == "compression") {
      compression = in.u8("compression");
      if (compression >= int(std::size(kLinesPerChunk))) in.corrupt("unknown compression " + std::to_string(compression));
    } else if (name == "tiles" && type == "tiledesc") {
      tile_x = in.u32("tiles");
      tile_y = in.u32("tiles");
      in.skip(1, "tiles");
    } else if (type == "chlist") {
      std::vector<Channel> list = read_channels(in, size, max_name);
      if (name == "channels") channels = std::move(list);
    } else if (type == "preview") {
      check_preview(in, size);
    } else if (type == "stringvector") {
      check_string_vector(in, size);
    } else if (type == "idmanifest") {
      // Compressed, with sizes inside; no texture needs one.
      in.fail("OpenEXR ID manifests are not supported");
    } else {
      // Strings, float vectors and types OpenEXR does not know are read by their size.
      in.skip(std::uint64_t(size), "attribute value");
    }
  }
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

  // Uncompressed bytes of the image: per channel its sampled pixel count (rounded down,
  // so that a subsampled channel is never over-counted) times its pixel size.
  const std::int64_t size = std::int64_t(std::min<std::uint64_t>(file_size, std::uint64_t(1) << 40));
  const std::int64_t limit = compression == kCompressionNone ? size : size * kMaxExrCompressionRatio;
  std::int64_t raw = 0;
  for (const Channel& c : channels)
    if (raw <= limit) raw += (w / c.x_sampling) * (h / c.y_sampling) * c.pixel_bytes;  // each ≤ 2^29
  if (raw > limit)
    in.corrupt("it claims " + std::to_string(w) + " x " + std::to_string(h) + " pixels (" + std::to_string(raw) +
               " bytes) in a file of " + std::to_string(file_size) + " bytes");
}

}  // namespace gonio::render
