#pragma once
// Material descriptions (SPEC §2): a JSON object with a "type" and that type's
// parameters, turned into a BxDF. Unknown types, unknown or missing parameters and
// out-of-range values throw InputError with a message naming the field, e.g.
// "conductor: eta must be > 0, got -1".

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gonio/bxdf.h"
#include "gonio/error.h"

namespace gonio {

// Parses JSON text. `source` names where it came from (e.g. "--bsdf" or a file path) and
// prefixes syntax errors.
BxDF parse_material(std::string_view json_text, std::string_view source = "material");

// Builds a model from an already parsed JSON value. `where` prefixes error messages
// (e.g. a JSON path inside a scene file); empty means none.
BxDF material_from_json(const nlohmann::json& description, const std::string& where = "");

// The material types this build knows, in SPEC §2's order.
const std::vector<std::string_view>& material_type_names();

}  // namespace gonio
