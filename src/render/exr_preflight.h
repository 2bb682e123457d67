#pragma once
// A check of an OpenEXR file's header against the file's own size, made before OpenEXR
// sees it. OpenEXR trusts the header: an attribute that claims 1.4 GB, or a data window of
// 2^27 pixels in a file of a few hundred bytes, makes it allocate that much before it
// finds the file truncated (the fuzz_exr findings of issue 9: 1.6–1.9 GB allocations, 8 s
// for a 317-byte file). Everything a header claims must fit in the file.

#include <cstdint>
#include <cstdio>
#include <string>

namespace gonio::render {

// Largest number of pixels read_image accepts (16384 x 8192), whatever the file claims.
inline constexpr std::int64_t kMaxImagePixels = std::int64_t(1) << 27;
// Largest tile (2048 x 2048 pixels): OpenEXR allocates whole tiles whatever the image size.
inline constexpr std::int64_t kMaxExrTilePixels = std::int64_t(1) << 22;
// Largest ratio of uncompressed pixel bytes to file bytes for a compressed file. Deflate
// (ZIP, ZIPS, PXR24) cannot exceed 1032:1 (RFC 1951: 258-byte matches in ≥ 2 bits), RLE
// 64:1, B44 about 11:1, PIZ about 450:1 (a 9-bit run code per 256 zero values); 2048:1
// is above them all, so that only an implausible claim is refused.
inline constexpr std::int64_t kMaxExrCompressionRatio = 2048;

// Reads the header of the OpenEXR file `f` (positioned anywhere; `file_size` bytes long)
// and throws InputError "<path>: <problem>" when it cannot describe this file: a
// multi-part or deep file (not supported), an attribute or name running past the end of
// the file, a data window beyond kMaxImagePixels, a tile beyond kMaxExrTilePixels, an
// offset table that does not fit in the file, or more pixel bytes than the file could
// hold at its compression. Leaves `f` at an unspecified position.
void preflight_exr(std::FILE* f, std::uint64_t file_size, const std::string& path);

}  // namespace gonio::render
