#pragma once
// Textures for spatially varying materials (lecture §3.2: the 6-D spatially varying BRDF
// as a 4-D model whose parameters are looked up at the surface point): an image or a
// procedural checker, evaluated at the hit's texture coordinates. Scene JSON:
// docs/scene-format.md, "Textures".

#include <algorithm>
#include <cmath>
#include <memory>

#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/render/image.h"
#include "gonio/render/texture/texture_image.h"
#include "gonio/render/texture/texture_sampler.h"
#include "gonio/render/texture/texture_transform.h"

namespace gonio::render {

struct Texture {
  // An image (bilinear, wrapping, v up), else a checker of `a` and `b`.
  std::shared_ptr<const Image> image;
  Color a, b;
  Float su = 1, sv = 1;  // uv_scale: the texture repeats su times along u, sv along v
  // The image's smallest and largest value per channel, which the loader validated:
  // bilinear weights can sum to 1 + 1 ulp, and a value must not leave the checked range.
  Color lo, hi;
  // A glTF texture (gltf_loader.h) instead: an image of the shared texture layer with its
  // sampler and KHR_texture_transform, read at glTF's uv (v down from the top row); the
  // texel's RGB (channel < 0) or one channel (0–3: r, g, b, a) times `factor`, clamped to
  // [lo, hi].
  std::shared_ptr<const TextureImage> layer_image;
  TextureSampler sampler;
  TextureTransform transform;
  int channel = -1;
  Color factor{1};

  // No allocation, no exception.
  Color eval(const Vec2& uv) const {
    if (layer_image) {
      const Rgba t = lookup(*layer_image, sampler, transform.apply(uv));
      const Float ch[4] = {t.r, t.g, t.b, t.a};
      Color c = channel < 0 ? Color(t.r, t.g, t.b) : Color(ch[channel & 3]);
      c *= factor;
      for (int i = 0; i < Color::size(); ++i) c[i] = std::clamp(c[i], lo[i], hi[i]);
      return c;
    }
    const Float u = uv.x * su, v = uv.y * sv;
    if (image) {
      Color c = image->bilinear(u, v);
      for (int i = 0; i < Color::size(); ++i) c[i] = std::clamp(c[i], lo[i], hi[i]);
      return c;
    }
    // `a` where floor(u) + floor(v) is even (fmod keeps the sign: −1 is odd).
    return std::fmod(std::floor(u) + std::floor(v), Float(2)) == 0 ? a : b;
  }
};

// One varying parameter of a material and the texture that gives its values.
struct ParamTexture {
  MaterialParam param = MaterialParam::Reflectance;
  Texture texture;
};

}  // namespace gonio::render
