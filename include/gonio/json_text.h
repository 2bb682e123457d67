#pragma once
// JSON text → nlohmann::json, with bad input reported as one InputError line that names
// the source and the line and column, e.g.
//   "scene.json: malformed JSON at line 3, column 5: unexpected ','; expected string literal".
// Shared by material descriptions and renderer scenes.

#include <string_view>

#include <nlohmann/json.hpp>

namespace gonio {

nlohmann::json parse_json_text(std::string_view text, std::string_view source);

}  // namespace gonio
