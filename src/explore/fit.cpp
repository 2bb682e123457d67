// /api/fit: `gonio fit` from the page (docs/fitting.md): a MERL table of --data fitted by
// an analytic model with Ceres (library gonio_fit), when the build has it.

#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "explore/material_request.h"
#include "gonio/error.h"
#include "gonio/json_text.h"

#ifdef GONIO_EXPLORE_HAVE_FIT
#include "gonio/fit/fit.h"
#include "gonio/merl.h"
#endif

namespace gonio::explore {

std::string api_fit(const std::string& body, const ApiContext& ctx) {
#ifdef GONIO_EXPLORE_HAVE_FIT
  using nlohmann::json;
  const json b = parse_request(body);
  const auto text = [&](const char* key, const std::string& fallback) {
    const auto it = b.find(key);
    if (it == b.end() || it->is_null()) return fallback;
    if (!it->is_string()) throw InputError(std::string(key) + " must be a string, got " + json_excerpt(*it));
    return it->get<std::string>();
  };
  const std::string file = text("file", "");
  if (file.empty()) throw InputError("file: missing (a MERL table in --data)");
  // The table's path, confined to --data as a `measured` material's file is.
  const json measured = {{"type", "measured"}, {"file", file}};
  const std::string path = sanitized_material(json{{"bsdf", measured}}, ctx)["file"];
  FitOptions options;
  options.model = text("model", "roughconductor");
  options.distribution = text("distribution", "");
  options.metric = parse_fit_metric(text("metric", "log"));
  const auto stride = b.find("stride");
  if (stride != b.end() && !stride->is_null()) {
    if (!stride->is_number_integer() || *stride < 1 || *stride > 30)
      throw InputError("stride must be an integer in [1, 30], got " + json_excerpt(*stride));
    options.stride = stride->get<int>();
  }
  check_fit_options(options);
  static std::once_flag quiet;
  std::call_once(quiet, [] { quiet_solver_log(); });
  // One fit at a time (seconds of a core and a 35 MB table each); a newer request of the
  // same page replaces one still waiting.
  static OneAtATime gate(2);
  gate.acquire(ctx, "fit");
  struct Release {
    ~Release() { gate.release(); }
  } release;
  ctx.check_stop();
  const FitResult r = fit_merl(read_merl(path), options);
  return json({{"material", r.material},
               {"measured", measured},
               {"error", r.error},
               {"metric", fit_metric_name(options.metric)},
               {"evaluations", r.evaluations},
               {"seconds", r.seconds}})
      .dump();
#else
  (void)body;
  (void)ctx;
  throw InputError("fit: this gonio was built without Ceres (GONIO_BUILD_FIT=OFF)");
#endif
}

std::string api_fit_models() {
  nlohmann::json models = nlohmann::json::array();
#ifdef GONIO_EXPLORE_HAVE_FIT
  for (const auto& m : fit_model_names()) models.push_back(m);
#endif
  return models.dump();
}

}  // namespace gonio::explore
