// gonio check: run the validator on one material (SPEC §3). Exit 0 when every property
// holds, 1 when one fails.

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "cli_io.h"
#include "cli_work.h"
#include "commands.h"
#include "gonio/validate.h"

#include <nlohmann/json.hpp>

namespace gonio::cli {

namespace {
struct CheckArgs {
  std::string bsdf;
  bool json = false;
  std::int64_t seed = 1;
};

void run_check(const CheckArgs& a) {
  const BxDF bxdf = load_bsdf(a.bsdf);
  check_cli_work(bxdf, kValidationEvaluations, "check");
  const ValidationReport report = validate(bxdf, {std::uint64_t(a.seed), 1.0});
  if (a.json) {
    std::string out = std::string("{\"pass\":") + (report.pass() ? "true" : "false") + ",\"properties\":[";
    for (size_t i = 0; i < report.properties.size(); ++i) {
      const auto& p = report.properties[i];
      if (i) out += ",";
      out += "{\"name\":\"" + p.name + "\",\"figure\":" + (p.figure ? json_number(*p.figure) : "null") +
             ",\"threshold\":" + json_number(p.threshold) + ",\"pass\":" + (p.pass ? "true" : "false");
      // A property that does not apply says so, and why (e.g. reciprocity of the LTC sheen).
      if (!p.applicable) out += ",\"applicable\":false,\"reason\":" + nlohmann::json(p.detail).dump();
      out += "}";
    }
    std::cout << out << "]}\n";
  } else {
    std::printf("gonio check: %s\n", bxdf.name().c_str());
    std::printf("  %-13s %-13s %-13s %-5s  %s\n", "property", "figure", "threshold", "", "where / how");
    for (const auto& p : report.properties) {
      char fig[32] = "n/a", thr[32];
      if (p.figure) std::snprintf(fig, sizeof fig, "%.6g", *p.figure);
      std::snprintf(thr, sizeof thr, "%.6g", p.threshold);
      std::printf("  %-13s %-13s %-13s %-5s  %s\n", p.name.c_str(), fig, thr, !p.pass ? "FAIL" : p.applicable ? "pass" : "n/a",
                  p.detail.c_str());
    }
    std::printf("%s\n", report.pass() ? "all properties hold" : "some properties FAIL");
  }
  std::fflush(stdout);
  if (!report.pass()) exit_status() = 1;
}
}  // namespace

void register_check(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  auto* cmd = app.add_subcommand(
      "check",
      "Validate a material: finite, reciprocity, energy, chi2, pdf_integral, consistency, isotropy, "
      "linearity, weights. Exit 0 when all hold, 1 otherwise");
  cmd->add_option("--bsdf", args->bsdf, "material JSON text, or @path to a file holding it")->required();
  cmd->add_flag("--json", args->json, "print one JSON object instead of the table");
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (default 1)")
      ->transform(decimal_in_range(0, kMaxSeed));
  cmd->callback([args] { run_check(*args); });
}

}  // namespace gonio::cli
