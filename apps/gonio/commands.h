#pragma once
// Each subcommand registers its options and its action on the main CLI11 app.
// Actions throw gonio::InputError for bad input (exit 2).

#include <CLI/CLI.hpp>

namespace gonio::cli {

void register_eval(CLI::App& app);
void register_sample(CLI::App& app);
void register_albedo(CLI::App& app);
void register_fresnel(CLI::App& app);
void register_table(CLI::App& app);
void register_check(CLI::App& app);
void register_render(CLI::App& app);
void register_slice(CLI::App& app);
void register_measure(CLI::App& app);  // with the renderer (Embree, oneTBB)
void register_spectrum(CLI::App& app);
void register_materials(CLI::App& app);
void register_tabulate(CLI::App& app);
void register_subsurface(CLI::App& app);
void register_fit(CLI::App& app);  // when built with GONIO_BUILD_FIT
void register_explore(CLI::App& app);  // when built with cpp-httplib (GONIO_BUILD_EXPLORE)

// Exit status of a run that completed without an error (1 when a check failed).
int& exit_status();

}  // namespace gonio::cli
