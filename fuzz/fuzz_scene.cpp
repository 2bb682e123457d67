// libFuzzer target: scene JSON text → render::parse_scene. Only InputError (documented in
// scene_loader.h) may escape. Relative paths resolve in fuzz/data, which holds a tiny
// tex.png, tex.exr and mesh.obj for textures and meshes to reach; inputs naming device,
// proc or sys files are skipped (reading a device is a separate, bounded-read finding,
// not something to hang the fuzzer on).

#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.h"
#include "gonio/error.h"
#include "gonio/render/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string base_dir = GONIO_FUZZ_DATA_DIR;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (gonio_fuzz::names_system_path(text)) return 0;
  try {
    gonio::render::Scene scene = gonio::render::parse_scene(text, "fuzz.json", base_dir);
    (void)scene;
  } catch (const gonio::InputError&) {
  }
  return 0;
}
