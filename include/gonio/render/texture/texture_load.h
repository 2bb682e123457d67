#pragma once
// Reading texture images through OpenImageIO: any format it reads (PNG, JPEG, OpenEXR,
// Radiance HDR, TIFF, ...) from a file or from bytes in memory (a glTF data URI or .glb
// buffer view). Integer codes become [0, 1] (code / (2^bits − 1)) then, for
// ColorEncoding::Srgb, linear by the sRGB transfer function of IEC 61966-2-1 (RGB only;
// alpha stays linear). Float formats (EXR, HDR) are linear already and taken as they are.
// Alpha is read unassociated (as stored). Every failure throws InputError with one line
// "<name>: <problem>"; a non-finite texel is an error.

#include <cstddef>
#include <cstdint>
#include <string>

#include "gonio/render/texture/texture_image.h"

namespace gonio::render {

// Largest image accepted (pixels): far above any texture; keeps a corrupt header from
// asking for an allocation that exhausts memory.
inline constexpr std::int64_t kMaxTexturePixels = std::int64_t(1) << 28;

TextureImage load_texture_file(const std::string& path, ColorEncoding encoding);

// `name` names the image in messages and, when the bytes' signature is not recognised
// (PNG, JPEG, EXR, Radiance HDR, TIFF, BMP, GIF are), its extension picks the format.
TextureImage load_texture_memory(const void* data, std::size_t size, const std::string& name,
                                 ColorEncoding encoding);

// Pixels already decoded (e.g. by tinygltf): `channels` 1–4 interleaved, `bits` 8 or 16
// (unsigned integer codes) or 32 (float), row 0 at the top.
TextureImage texture_from_pixels(int width, int height, int channels, int bits, const void* data,
                                 std::size_t size, const std::string& name, ColorEncoding encoding);

}  // namespace gonio::render
