// libFuzzer target: a glTF 2.0 file (.gltf text or .glb; the reader tells them apart by
// the magic) → render::append_gltf, through a scratch file (the reader takes a path).
// Only InputError may escape; every loaded position, normal, uv and tangent must be
// finite and every index in range.

#include <cmath>
#include <cstdint>

#include "fuzz_util.h"
#include "gonio/error.h"
#include "gonio/render/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = gonio_fuzz::write_scratch(data, size, ".gltf");
  gonio::render::Scene scene;
  try {
    gonio::render::append_gltf(scene, path, {}, "fuzz");
  } catch (const gonio::InputError&) {
    return 0;
  }
  auto finite = [](const gonio::Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  for (const auto& mesh : scene.meshes) {
    for (const auto& v : mesh.positions)
      if (!finite(v)) gonio_fuzz::fail("non-finite position", v.x);
    for (const auto& v : mesh.normals)
      if (!finite(v)) gonio_fuzz::fail("non-finite normal", v.x);
    for (const auto& v : mesh.tangents)
      if (!finite(v)) gonio_fuzz::fail("non-finite tangent", v.x);
    for (const auto& t : mesh.uvs)
      if (!std::isfinite(t.x) || !std::isfinite(t.y)) gonio_fuzz::fail("non-finite uv", t.x);
    if (mesh.indices.size() % 3 != 0) gonio_fuzz::fail("index count not a multiple of 3", double(mesh.indices.size()));
    for (uint32_t i : mesh.indices)
      if (i >= mesh.positions.size()) gonio_fuzz::fail("index out of range", i);
    if (mesh.material < 0 || size_t(mesh.material) >= scene.materials.size()) gonio_fuzz::fail("material out of range", mesh.material);
  }
  return 0;
}
