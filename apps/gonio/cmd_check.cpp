// gonio check: run the validator on one material (SPEC §3). Exit 0 when every property
// holds, 1 when one fails.

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_io.h"
#include "cli_work.h"
#include "commands.h"
#include "gonio/bxdf.h"
#include "gonio/merl/coverage.h"
#include "gonio/validate.h"

#include <nlohmann/json.hpp>

namespace gonio::cli {

namespace {
struct CheckArgs {
  std::string bsdf;
  bool json = false;
  std::int64_t seed = 1;
};

// A measured table's missing entries above the horizon (measured_data.h): reported as a
// row of its own, a warning that does not fail the check (the model is still plausible;
// it reads the holes as interpolated or black, issue 55).
struct Coverage {
  double missing = 0;
  std::string detail;
};
std::optional<Coverage> table_coverage(const BxDF& bxdf) {
  const auto* m = std::get_if<MeasuredBxDF>(&bxdf.models());
  if (!m || !m->data) return std::nullopt;
  Coverage c;
  c.missing = merl_missing_fraction(m->data->table());
  c.detail = c.missing > 0 ? "missing entries above the horizon: interpolated, or 0 where all eight neighbours are"
                           : "every entry above the horizon is measured";
  return c;
}

void run_check(const CheckArgs& a) {
  const BxDF bxdf = load_bsdf(a.bsdf);
  check_cli_work(bxdf, kValidationEvaluations, "check");
  const ValidationReport report = validate(bxdf, {std::uint64_t(a.seed), 1.0});
  const std::optional<Coverage> coverage = table_coverage(bxdf);
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
    if (coverage)
      out += ",{\"name\":\"coverage\",\"figure\":" + json_number(coverage->missing) +
             ",\"threshold\":0,\"pass\":true,\"warning\":" + (coverage->missing > 0 ? "true" : "false") +
             ",\"detail\":" + nlohmann::json(coverage->detail).dump() + "}";
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
    if (coverage)
      std::printf("  %-13s %-13.6g %-13s %-5s  %s\n", "coverage", coverage->missing, "0",
                  coverage->missing > 0 ? "WARN" : "pass", coverage->detail.c_str());
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
  add_point_options(*cmd);
  cmd->add_flag("--json", args->json, "print one JSON object instead of the table");
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (default 1)")
      ->transform(decimal_in_range(0, kMaxSeed));
  cmd->callback([args] { run_check(*args); });
}

}  // namespace gonio::cli
