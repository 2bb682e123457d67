// libFuzzer target: MaterialX documents → materialx_to_json (include/gonio/io/materialx.h).
// Input: the document text; when it holds a NUL byte, the text before it is the material's
// name and the document follows. Only InputError may escape the reader; an accepted
// document must give an object with a string "type" whose every number is finite, and the
// material parser may only answer it with InputError too. The node graph compiler runs on
// whatever graphs the document connects: each document is read at the default point and
// at a far one (u, v = 1e6, −3.5; position −1e3, 7, 0), where periodic and clamping nodes
// meet large arguments.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/io/materialx.h"
#include "gonio/material.h"
#include "gonio/material_types.h"

namespace {

// Aborts (a crash libFuzzer records) on a non-finite number anywhere in `v`.
void check_finite(const nlohmann::json& v) {
  if (v.is_number() && !std::isfinite(v.get<double>())) std::abort();
  if (v.is_structured())
    for (const auto& e : v) check_finite(e);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const char* text = reinterpret_cast<const char*>(data);
  const auto* nul = static_cast<const char*>(std::memchr(text, 0, size));
  std::optional<std::string> name;
  std::string_view doc(text, size);
  if (nul) {
    name = std::string(text, size_t(nul - text));
    doc = std::string_view(nul + 1, size - size_t(nul - text) - 1);
  }
  gonio::MaterialxPoint far;
  far.u = 1e6;
  far.v = -3.5;
  far.px = -1e3;
  far.py = 7;
  for (const gonio::MaterialxPoint& at : {gonio::MaterialxPoint{}, far}) {
    nlohmann::json j;
    try {
      j = gonio::materialx_to_json(doc, "fuzz.mtlx", name, nullptr, at);
    } catch (const gonio::InputError&) {
      return 0;  // the documented error for bad input
    }
    if (!j.is_object() || !j.contains("type") || !j["type"].is_string()) std::abort();
    check_finite(j);
    try {
      gonio::material_from_json(j, "fuzz.mtlx");
    } catch (const gonio::InputError&) {
    }
  }
  return 0;
}
