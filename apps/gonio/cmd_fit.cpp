// gonio fit: fits an analytic model to a MERL table (SPEC §3, docs/fitting.md).

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "cli_io.h"
#include "commands.h"
#include "gonio/fit/fit.h"
#include "gonio/json_text.h"
#include "gonio/merl.h"
#include "gonio/rgl/data.h"
#include "gonio/tabulate.h"

namespace gonio::cli {

namespace {
bool is_tensor_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[12] = {};
  in.read(head, sizeof head);
  return in.gcount() == 12 && std::memcmp(head, "tensor_file", 12) == 0;
}

struct FitArgs {
  std::string data, model, distribution, metric = "log", init;
  std::int64_t stride = 3;
};

// Wall-clock seconds to the millisecond: a timing, not a value to round-trip.
std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

void run_fit(const FitArgs& a) {
  quiet_solver_log();  // a failed fit is one line (ours), not Ceres's log before it
  FitOptions options;
  options.model = a.model;
  options.distribution = a.distribution;
  options.metric = parse_fit_metric(a.metric);
  options.stride = int(a.stride);
  if (!a.init.empty()) {
    // The JSON text itself or @path, as --bsdf.
    if (a.init[0] == '@') {
      try {
        const std::string path = a.init.substr(1);
        options.init = parse_json_text(read_text_file(path, kMaxJsonFileBytes, "an --init file"), path);
      } catch (const InputError& e) {
        throw InputError(std::string("--init: ") + e.what());
      }
    } else {
      options.init = parse_json_text(a.init, "--init");
    }
  }
  // The model and its init are checked before the 35 MB table is read.
  check_fit_options(options);
  // MERL or RGL, told apart by content (SPEC §3): an RGL .bsdf file starts with
  // "tensor_file\0"; it is tabulated as a MERL table (its rgl model, SPEC §2) and fitted so.
  const MerlTable table = is_tensor_file(a.data) ? tabulate(RglBxDF::make(load_rgl(a.data))) : read_merl(a.data);
  const FitResult r = fit_merl(table, options);
  std::cout << "{\"material\":" << r.material.dump() << ",\"error\":" << json_number(r.error) << ",\"metric\":\""
            << fit_metric_name(options.metric) << "\",\"evaluations\":" << r.evaluations
            << ",\"seconds\":" << seconds(r.seconds) << "}\n";
}
}  // namespace

void register_fit(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit an analytic model to a MERL table; prints "
      "{\"material\":{...},\"error\":e,\"metric\":\"log|ngan\",\"evaluations\":n,\"seconds\":s}");
  cmd->add_option("--data", args->data, "the MERL .binary table or RGL .bsdf file to fit (told apart by content)")->required();
  cmd->add_option("--model", args->model,
                  "roughconductor, plastic, blinnphong, phong, ward, ashikhminshirley, orennayar or blend")
      ->required();
  cmd->add_option("--distribution", args->distribution, "ggx or beckmann (roughconductor, plastic, blend)");
  cmd->add_option("--metric", args->metric, "ngan (cosine-weighted L2) or log (log-compressed, the default)");
  cmd->add_option("--init", args->init,
                  "a starting material of that type (may be partial; JSON text or @path): its values start the fit, "
                  "its fresnel, distribution and (plastic) eta are kept");
  cmd->add_option("--stride", args->stride,
                  "subsample of the fit: every θh bin, every N-th θd bin, every 2N-th φd bin (default 3; the error "
                  "is always over the whole table)")
      ->transform(decimal_in_range(1, 45));
  cmd->callback([args] { run_fit(*args); });
}

}  // namespace gonio::cli
