// gonio tabulate: a material written as a MERL table (SPEC §3 and §2 `measured`).

#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "cli_signals.h"
#include "commands.h"
#include "gonio/merl.h"
#include "gonio/io/output_file.h"
#include "gonio/tabulate.h"

namespace gonio::cli {

namespace {
struct TabulateArgs {
  std::string bsdf, output;
};

void run_tabulate(const TabulateArgs& a) {
  const BxDF model = load_bsdf(a.bsdf);
  // A target that cannot be written fails before the work; a signal removes the temporary.
  install_stop_signals();
  std::optional<OutputFile> out;
  create_removable([&] { return out.emplace(a.output, "the table").temporary_path(); });
  const MerlTable table = tabulate(model);
  write_merl(*out, table);
  std::size_t missing = 0;
  for (std::size_t e = 0; e < MerlTable::kEntries; ++e) missing += table.rgb[3 * e] < 0;
  std::cout << "{\"file\":" << nlohmann::json(a.output).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << ",\"entries\":" << MerlTable::kEntries
            << ",\"below_horizon\":" << missing << "}\n";
}
}  // namespace

void register_tabulate(CLI::App& app) {
  auto args = std::make_shared<TabulateArgs>();
  auto* cmd = app.add_subcommand(
      "tabulate",
      "Writes an isotropic material as a MERL table (90 x 90 x 180 half/difference bins, SPEC §2 `measured`); "
      "prints {\"file\":..,\"entries\":..,\"below_horizon\":..}");
  cmd->add_option("--bsdf", args->bsdf, "material JSON, or @file")->required();
  cmd->add_option("-o,--output", args->output, "the table to write (MERL .binary)")->required();
  cmd->callback([args] { run_tabulate(*args); });
}

}  // namespace gonio::cli
