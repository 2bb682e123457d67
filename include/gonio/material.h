#pragma once
// Material descriptions (SPEC §2): a JSON object with a "type" and that type's
// parameters, turned into a BxDF. Unknown types, unknown or missing parameters and
// out-of-range values throw InputError with a message naming the field, e.g.
// "conductor: eta must be in [0.0001, 10000], got -1". Each type's parameters, defaults
// and ranges come from the registry in material_types.h (also the source of `gonio
// materials` and docs/materials.md).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gonio/bxdf.h"
#include "gonio/bxdf/gltf_pbr_params.h"
#include "gonio/bxdf/openpbr_params.h"
#include "gonio/error.h"

namespace gonio {

// Deepest nesting of blends: a blend evaluates every part, so a tree of blends costs up
// to 2^depth evaluations per call (256 here); and 10,000 levels took a minute and 4 GB to
// parse (each level's error prefix copies the one above).
inline constexpr int kMaxBlendDepth = 8;

// Parses JSON text. `source` names where it came from (e.g. "--bsdf" or a file path) and
// prefixes syntax errors.
BxDF parse_material(std::string_view json_text, std::string_view source = "material");

// Builds a model from an already parsed JSON value. `where` prefixes error messages
// (e.g. a JSON path inside a scene file); empty means none. A spectrum's relative CSV path
// ({"spectrum": "file.csv"}) is resolved in `base_dir` (a scene's directory; empty: the
// working directory).
BxDF material_from_json(const nlohmann::json& description, const std::string& where = "",
                        const std::string& base_dir = "");

// The material types this build knows, in SPEC §2's order.
const std::vector<std::string_view>& material_type_names();

// --- Spatially varying parameters ---------------------------------------------------
// Lecture §3.2: a spatially varying BRDF, six-dimensional, is written as a 4-D model
// whose parameters are functions of the surface position (textures). The core knows
// nothing of textures; it names the parameters that may vary and rebuilds a model with
// new values of them. The ranges stay in material_from_json, the one place that checks
// them: a caller validates the values a texture takes by substituting them into a
// description and parsing it (each parameter's `probe` is a value that passes alone).

enum class MaterialParam : std::uint8_t {
  Reflectance, Kd, Ks, Rd, Rs, F0, Eta, K,
  SheenColor,       // sheen: "color"
  Alpha,            // both alpha_x and alpha_y (an isotropic roughness)
  AlphaX, AlphaY,   // the entries of "alpha": [alpha_x, alpha_y]
  Sigma, Exponent, Nu, Nv,
  // openpbr's colour and number parameters: OpenPbrFirst + i is kOpenPbrFields[i]
  // (bxdf/openpbr_params.h), so that their list is not written here again.
  OpenPbrFirst,
  // gltf_pbr's: kGltfPbrFirst + i is kGltfPbrFields[i] (bxdf/gltf_pbr_params.h); only those
  // whose `varying` is set are named by varying_param.
};
inline constexpr std::size_t kGltfPbrFirst = std::size_t(MaterialParam::OpenPbrFirst) + kOpenPbrFieldCount;
inline constexpr std::size_t kMaterialParamCount = kGltfPbrFirst + kGltfPbrFieldCount;

struct MaterialParamInfo {
  std::string_view key;  // the JSON key of SPEC §2 ("alpha" for Alpha, AlphaX and AlphaY)
  bool scalar;           // a number; else a colour (a number or [r, g, b])
  double probe;          // a value material_from_json accepts whatever the other values
};
const MaterialParamInfo& material_param_info(MaterialParam p);

// The parameter of material `type` that JSON key `key` names, when it may vary over a
// surface: "alpha" gives Alpha (callers map the entries of [alpha_x, alpha_y] to AlphaX
// and AlphaY). nullopt for any other key, an unknown type, and "blend".
std::optional<MaterialParam> varying_param(std::string_view type, std::string_view key);
// The keys of `type` that may vary, for messages ("alpha, eta, k, f0").
std::string varying_param_keys(std::string_view type);
// Why `key`, which varying_param names, may not vary in this `description` (nullopt: it
// may). openpbr's specular_ior and specular_weight set the index of the glass behind a
// translucent base: an index that changed along a surface would not bound one medium
// (dielectric's rule), so they may not vary where transmission_weight is not 0 and the
// material is not thin-walled (a thin sheet bounds no medium).
std::optional<std::string> varying_param_refused(const nlohmann::json& description, std::string_view key);

// A value in the units of SPEC §2 (sigma in degrees); a scalar parameter reads channel 0.
struct ParamValue {
  MaterialParam param = MaterialParam::Reflectance;
  Color value;
};

// `model` with the given parameters replaced and what depends on them recomputed (a
// conductor's F0 from eta and k; the multiple-scattering lobe of a rough conductor, kept
// when `model` has one and the new roughness is not smooth; an openpbr model made again
// from its parameters, its quadratures reused when none of their inputs changed). Parameters the model does
// not have are ignored. No allocation and no exception, for use at every shading point
// of a textured surface; the values must lie in the ranges material_from_json accepts.
BxDF with_params(const BxDF& model, std::span<const ParamValue> values) noexcept;

}  // namespace gonio
