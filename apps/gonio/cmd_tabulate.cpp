// gonio tabulate: a material written as a MERL table (SPEC §3 and §2 `measured`).

#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "cli_signals.h"
#include "commands.h"
#include "gonio/merl.h"
#include "gonio/io/output_file.h"
#include "gonio/rgl/write.h"
#include "gonio/tabulate.h"

namespace gonio::cli {

namespace {
struct TabulateArgs {
  std::string bsdf, output, format = "merl";
};

// --format rgl: the RGL .bsdf tensor file (SPEC §3; include/gonio/rgl/write.h), anisotropic
// when the material is.
void run_tabulate_rgl(const TabulateArgs& a, const BxDF& model) {
  install_stop_signals();
  std::optional<OutputFile> out;
  create_removable([&] { return out.emplace(a.output, "the file").temporary_path(); });
  RglWriteOptions opt;
  opt.anisotropic = !model.is_isotropic();
  opt.description = "gonio tabulate: " + model.name();
  const std::vector<std::uint8_t> bytes = tabulate_rgl(model, opt);
  out->commit(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  std::cout << "{\"file\":"
            << nlohmann::json(a.output).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
            << ",\"format\":\"rgl\",\"bytes\":" << bytes.size() << ",\"anisotropic\":"
            << (opt.anisotropic ? "true" : "false") << "}\n";
}

void run_tabulate(const TabulateArgs& a) {
  const BxDF model = load_bsdf(a.bsdf);
  if (a.format == "rgl") return run_tabulate_rgl(a, model);
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
  cmd->add_option("-o,--output", args->output, "the table to write (MERL .binary, or RGL .bsdf with --format rgl)")
      ->required();
  cmd->add_option("--format", args->format, "merl (default) or rgl (an RGL .bsdf tensor file, SPEC §3)")
      ->check(CLI::IsMember({"merl", "rgl"}));
  cmd->callback([args] { run_tabulate(*args); });
}

}  // namespace gonio::cli
