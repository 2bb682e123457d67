#pragma once
// The JSON API of `gonio explore` (issue 36, SPEC §3), without HTTP: each endpoint is a
// function from the request body (JSON text) to the response body (JSON text), computed by
// the core library and the renderer's slice — no model is evaluated anywhere else. A bad
// request throws gonio::InputError with the one-line message the CLI would print (the
// server answers it with HTTP 400 {"error": message}). docs/explore.md documents each one.

#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>

namespace gonio::explore {

// Thrown by an endpoint whose request a newer one of the same page and view replaced
// (the server answers 409): a slider moved on, and the old answer would be stale.
struct Superseded : std::runtime_error {
  Superseded() : std::runtime_error("superseded by a newer request of the same view") {}
};

// What every request may refer to: the --data directory (canonical, absolute; empty when
// none was given). A material's file names ("file" of `measured`, a {"spectrum": "x.csv"})
// must name files inside it; anything else is refused, so that a page cannot make the
// server read the rest of the disk.
struct ApiContext {
  std::string data_dir;
  // Set (by the server) when a newer request of the same page and view arrived; the long
  // endpoints (albedo, sphere, check) poll it between steps and throw Superseded.
  std::shared_ptr<const std::atomic<bool>> stale;
  void check_stale() const {
    if (stale && stale->load(std::memory_order_relaxed)) throw Superseded();
  }
};

// GET /api/materials: the registry behind `gonio materials` — every type with its
// parameters (kind, default, range, choices, meaning), a valid example per type, the
// named metals and glasses, and the wavelength range of spectral mode.
std::string api_materials();
// GET /api/data: the regular files directly inside --data (names only).
std::string api_data(const ApiContext& ctx);

// POST endpoints. Every body is a JSON object; "bsdf" holds the material (an object, or
// its JSON text as a string: the parser then reports syntax errors as `gonio eval` does),
// and "wavelength" (nm, where the CLI has --wavelength) selects spectral mode.
std::string api_validate(const std::string& body, const ApiContext& ctx);     // /api/validate
std::string api_eval(const std::string& body, const ApiContext& ctx);         // /api/eval (SPEC §3)
std::string api_lobe(const std::string& body, const ApiContext& ctx);         // /api/lobe
std::string api_lobe3d(const std::string& body, const ApiContext& ctx);       // /api/lobe3d
std::string api_slice(const std::string& body, const ApiContext& ctx);        // /api/slice
std::string api_slice_point(const std::string& body, const ApiContext& ctx);  // /api/slice_point
std::string api_albedo(const std::string& body, const ApiContext& ctx);       // /api/albedo
std::string api_fresnel(const std::string& body, const ApiContext& ctx);      // /api/fresnel
std::string api_check(const std::string& body, const ApiContext& ctx);        // /api/check
// A sphere of the material rendered by gonio render's path tracer under a movable point
// light and a uniform environment: one pass of `spp` samples per pixel with `seed`, linear
// RGB (the page averages passes and tone-maps).
std::string api_sphere(const std::string& body, const ApiContext& ctx);       // /api/sphere
// `gonio fit` of a MERL table in --data: {"file", "model", "distribution", "metric",
// "stride"} -> {"material", "measured", "error", "metric", "evaluations", "seconds"}.
std::string api_fit(const std::string& body, const ApiContext& ctx);          // /api/fit
// The models api_fit takes, a JSON array (empty without Ceres).
std::string api_fit_models();

// Request bounds (a larger request is a 400): the server stays responsive for everyone.
inline constexpr int kMaxLobeCount = 2001;
inline constexpr int kMaxLobe3dTheta = 90, kMaxLobe3dPhi = 360;
inline constexpr int kMaxSliceSize = 512;
inline constexpr int kMaxAlbedoCount = 91;
inline constexpr long long kMaxAlbedoSamples = 1 << 20;
inline constexpr int kMaxFresnelCount = 1801;
inline constexpr long long kMaxEvalPairs = 100000;
inline constexpr int kMaxSphereSize = 256;
inline constexpr int kMaxSphereSpp = 64;

}  // namespace gonio::explore
