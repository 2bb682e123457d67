// gonio: the command-line face of the library (SPEC §3). Results go to stdout as JSON
// lines; errors go to stderr as one line, with exit status 2 for bad input.

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "gonio/error.h"

int main(int argc, char** argv) {
  CLI::App app{"gonio: physically based reflection models, evaluated, sampled and measured"};
  app.require_subcommand(1);
  gonio::cli::register_eval(app);
  gonio::cli::register_sample(app);
  gonio::cli::register_albedo(app);
  gonio::cli::register_fresnel(app);
  gonio::cli::register_table(app);
  gonio::cli::register_check(app);
  gonio::cli::register_render(app);
  // CLI11 reports an unknown first word only as "a subcommand is required"; name it.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    bool known = false;
    std::string names;
    for (const auto* sub : app.get_subcommands({})) {
      known |= sub->get_name() == word;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "gonio: unknown subcommand '" << word << "' (known: " << names << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "gonio: " << e.what() << " (see gonio --help)\n";
    return 2;
  } catch (const gonio::InputError& e) {
    std::cerr << "gonio: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "gonio: internal error: " << e.what() << "\n";
    return 3;
  }
  std::cout.flush();
  return std::cout.good() ? gonio::cli::exit_status() : 3;
}

int& gonio::cli::exit_status() {
  static int status = 0;
  return status;
}
