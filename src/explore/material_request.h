#pragma once
// The material of an explorer request: the body parsed (bounded, one-line errors), the
// material's file names confined to --data, the model made by the library's parser with
// the CLI's messages ("--bsdf: roughconductor: alpha must be > 0, got -0.1"), in RGB mode
// or at one wavelength.

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "gonio/bxdf.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio::explore {

// The request body as a JSON object; InputError "request body: ..." otherwise.
nlohmann::json parse_request(std::string_view body);

// "wavelength" in nm, [360, 830]; nothing when absent or null.
std::optional<Float> request_wavelength(const nlohmann::json& body);

// The material of "bsdf" as JSON with every file name replaced by the canonical path of
// the file inside ctx.data_dir. InputError when "bsdf" is missing, is not JSON, or names a
// file outside --data (an absolute path, "..", a symlink leading out, or no --data).
// `key` "compare" reads the second material of a comparison, named "--compare" in its
// errors as `gonio slice --compare` names it.
nlohmann::json sanitized_material(const nlohmann::json& body, const ApiContext& ctx, const char* key = "bsdf");

// The RGB model of "bsdf", through parse_material with the source "--bsdf" (or of
// "compare", with "--compare").
BxDF load_material(const nlohmann::json& body, const ApiContext& ctx, const char* key = "bsdf");

// The model at one wavelength (as `gonio eval --wavelength`), kept with what it points into.
struct MaterialAtWavelength {
  MaterialWithSpectra material;
  SpectralScratch scratch;
  SampledWavelengths wavelengths;
  SpectralBxDF bxdf;
};
std::unique_ptr<MaterialAtWavelength> load_material_at_wavelength(const nlohmann::json& body, const ApiContext& ctx,
                                                                  Float nm);

// The integer `name` of a request in [lo, hi] (`fallback` when absent or null); a number
// with a fraction, or one out of range, is an InputError naming it.
long long integer_field(const nlohmann::json& body, const char* name, long long fallback, long long lo, long long hi);

// Refuses (InputError, "`what`: about N evaluations of C walk steps each ...") a request
// whose `evaluations` of the model, at evaluation_cost.h's steps each, exceed
// kMaxRequestWork: decided before any work starts.
void check_work(const BxDF& bxdf, double evaluations, std::string_view what);
void check_work(const SpectralBxDF& bxdf, double evaluations, std::string_view what);

// A valid material of each type, for the page's editor to start from (the registry's
// defaults alone do not make a conductor, a blend or a layered material). `measured`
// names a file, valid only with such a file in --data.
nlohmann::json example_material(std::string_view type);

}  // namespace gonio::explore
