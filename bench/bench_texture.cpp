// The texture layer's cost per hit (issue 58, docs/gltf.md "Speed and memory"): the three
// lookups a glTF metallic-roughness material makes (base colour, metallic-roughness,
// normal) on 1024 × 1024 images, bilinear, repeat, at random uv; and a textured openpbr
// material's whole Material::at (those lookups plus with_params making the model).

#include <benchmark/benchmark.h>

#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "gonio/material.h"
#include "gonio/render/scene.h"
#include "gonio/render/texture/texture_image.h"
#include "gonio/render/texture/texture_sampler.h"
#include "gonio/spectral_material.h"

namespace {

using namespace gonio;
using namespace gonio::render;

std::shared_ptr<const TextureImage> noise_image(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Rgba> t(1024 * 1024);
  for (Rgba& c : t) c = {u(rng), u(rng), u(rng), 1};
  return std::make_shared<const TextureImage>(1024, 1024, std::move(t), 3);
}

std::vector<Vec2> random_uvs() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2, 2);
  std::vector<Vec2> v(4096);
  for (Vec2& p : v) p = {u(rng), u(rng)};
  return v;
}

void BM_ThreeLookups(benchmark::State& state) {
  const auto a = noise_image(1), b = noise_image(2), c = noise_image(3);
  const TextureSampler s;
  const std::vector<Vec2> uv = random_uvs();
  size_t i = 0;
  for (auto _ : state) {
    const Vec2 p = uv[i++ & 4095];
    const Rgba x = lookup(*a, s, p), y = lookup(*b, s, p), z = lookup(*c, s, p);
    benchmark::DoNotOptimize(x.r + y.g + z.b);
  }
}
BENCHMARK(BM_ThreeLookups);

void BM_TexturedOpenPbrAt(benchmark::State& state) {
  Material m;
  m.bxdf = material_with_spectra_from_json({{"type", "openpbr"}, {"base_diffuse_roughness", 0.0}}, "bench", "").bxdf;
  const char* keys[3] = {"base_color", "specular_roughness", "base_metalness"};
  for (int k = 0; k < 3; ++k) {
    ParamTexture pt;
    pt.param = *varying_param("openpbr", keys[k]);
    pt.texture.layer_image = noise_image(unsigned(k + 1));
    pt.texture.channel = k == 0 ? -1 : k;
    pt.texture.lo = Color(0);
    pt.texture.hi = Color(1);
    m.textures.push_back(pt);
  }
  const std::vector<Vec2> uv = random_uvs();
  std::optional<BxDF> scratch;
  size_t i = 0;
  for (auto _ : state) {
    const BxDF& b = m.at(uv[i++ & 4095], scratch);
    benchmark::DoNotOptimize(&b);
  }
}
BENCHMARK(BM_TexturedOpenPbrAt);

}  // namespace

BENCHMARK_MAIN();
