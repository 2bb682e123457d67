#pragma once
// A texture image in memory: linear RGBA float texels with their mip pyramid, the data
// behind every image lookup of the renderer (glTF textures, MaterialX images). Loading is
// in texture_load.h (OpenImageIO), lookups in texture_sampler.h; docs/gltf.md, "Textures".

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gonio/math/constants.h"

namespace gonio::render {

// One texel, linear (colour textures are decoded from sRGB at load, texture_load.h).
struct Rgba {
  Float r = 0, g = 0, b = 0, a = 1;
};

// How stored codes become values: colour data (base colour, emissive) is sRGB-encoded
// and decoded to linear at load; data maps (normals, roughness, metallic) are linear.
enum class ColorEncoding { Srgb, Linear };

// One level of the pyramid: row-major texels, row 0 at the top (the first row of the
// file; texture coordinate t = 0, glTF's and OpenImageIO's convention).
struct TextureLevel {
  int width = 0, height = 0;
  std::vector<Rgba> texels;
  const Rgba& at(int x, int y) const { return texels[size_t(y) * size_t(width) + size_t(x)]; }
};

class TextureImage {
 public:
  TextureImage() = default;
  // Takes level 0 (width × height texels, width, height ≥ 1) and builds the pyramid: each
  // level halves each side (rounded down, at least 1), a texel the mean of the 2 × 2 (or
  // 2 × 1, 1 × 2 at an odd edge: the last row or column is folded into its neighbour's
  // box) texels it covers, down to 1 × 1. `channels` (1–4) is what the file held: a gray
  // image has r = g = b, a missing alpha is 1.
  TextureImage(int width, int height, std::vector<Rgba> texels, int channels);

  bool empty() const { return levels_.empty(); }
  int width() const { return empty() ? 0 : levels_[0].width; }
  int height() const { return empty() ? 0 : levels_[0].height; }
  int channels() const { return channels_; }
  int level_count() const { return int(levels_.size()); }
  const TextureLevel& level(int i) const { return levels_[size_t(i)]; }
  // Bytes held by the texels of every level.
  std::size_t memory_bytes() const;

 private:
  std::vector<TextureLevel> levels_;
  int channels_ = 0;
};

}  // namespace gonio::render
