// libFuzzer target: surface JSON text (SPEC §3 `gonio measure --surface`) →
// measure::parse_surface. Only InputError (documented in surface.h) may escape; an
// accepted surface's height field must be a whole n × n grid of finite heights over a
// finite, positive size. Relative paths resolve in fuzz/data (a tiny tex.png for the
// "image" type); inputs naming device, proc or sys files are skipped, as in fuzz_scene.

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.h"
#include "gonio/error.h"
#include "gonio/measure/surface.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string base_dir = GONIO_FUZZ_DATA_DIR;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (gonio_fuzz::names_system_path(text)) return 0;
  gonio::measure::Surface s;
  try {
    s = gonio::measure::parse_surface(text, "fuzz", base_dir);
  } catch (const gonio::InputError&) {
    return 0;
  }
  const auto& f = s.field;
  if (!(f.n > 0)) gonio_fuzz::fail("height field without samples", f.n);
  if (f.z.size() != static_cast<size_t>(f.n) * static_cast<size_t>(f.n))
    gonio_fuzz::fail("height field not n x n", static_cast<double>(f.z.size()));
  if (!(std::isfinite(f.size) && f.size > 0)) gonio_fuzz::fail("height field size", f.size);
  for (const float z : f.z)
    if (!std::isfinite(z)) gonio_fuzz::fail("non-finite height", z);
  return 0;
}
