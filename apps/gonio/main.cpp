// gonio: the command-line face of the library (SPEC §3). Results go to stdout as JSON
// lines; errors go to stderr as one line, with exit status 2 for bad input.

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "gonio/error.h"
#include "gonio/version.h"

namespace {
// The one way an error leaves gonio: one line on stderr, control characters the user
// typed escaped (gonio::escape_control), and the exit status.
int fail(int status, const std::string& message) {
  std::cerr << "gonio: " << gonio::escape_control(message) << "\n";
  return status;
}
}  // namespace

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG, which the writers
  // report as one line and clean up after, instead of the signal killing gonio with the
  // temporary left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"gonio: physically based reflection models, evaluated, sampled and measured"};
  app.require_subcommand(1);
  // SPEC §3: `gonio --version` prints `gonio X.Y.Z` (the CMake project version) and exits 0.
  app.set_version_flag("--version", std::string("gonio ") + GONIO_VERSION_STRING,
                       "Print the version (gonio X.Y.Z) and exit");
  gonio::cli::register_eval(app);
  gonio::cli::register_sample(app);
  gonio::cli::register_albedo(app);
  gonio::cli::register_fresnel(app);
  gonio::cli::register_table(app);
  gonio::cli::register_check(app);
#ifdef GONIO_HAVE_RENDERER
  gonio::cli::register_render(app);
  gonio::cli::register_slice(app);
  gonio::cli::register_measure(app);
#endif
  gonio::cli::register_spectrum(app);
  gonio::cli::register_materials(app);
  gonio::cli::register_tabulate(app);
  gonio::cli::register_subsurface(app);
#ifdef GONIO_HAVE_FIT
  gonio::cli::register_fit(app);
#endif
#ifdef GONIO_HAVE_EXPLORE
  gonio::cli::register_explore(app);
#endif
  // CLI11 reports an unknown first word only as "a subcommand is required"; name it.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    bool known = false;
    std::string names;
    for (const auto* sub : app.get_subcommands({})) {
      known |= sub->get_name() == word;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
#ifndef GONIO_HAVE_FIT
    if (word == "fit") return fail(2, "fit: this gonio was built without Ceres (GONIO_BUILD_FIT=OFF)");
#endif
#ifndef GONIO_HAVE_RENDERER
    if (word == "render" || word == "slice" || word == "measure")
      return fail(2, word + ": this gonio was built without the renderer (GONIO_BUILD_RENDERER=OFF)");
#endif
#ifndef GONIO_HAVE_EXPLORE
    if (word == "explore")
      return fail(2, "explore: this gonio was built without cpp-httplib (libcpp-httplib-dev) or the renderer");
#endif
    if (!known) return fail(2, "unknown subcommand '" + word + "' (known: " + names + ")");
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
    return fail(2, std::string(e.what()) + " (see gonio --help)");
  } catch (const gonio::InputError& e) {
    return fail(2, e.what());
  } catch (const std::bad_alloc&) {
    // The documented bounds keep a request within a few GB; one that still does not fit
    // this machine (or a ulimit) is the request's size, not a bug.
    return fail(2, "out of memory: the request needs more memory than this machine (or its limit) allows; "
                   "ask for fewer samples, pixels, angles or detectors");
  } catch (const std::exception& e) {
    return fail(3, std::string("internal error: ") + e.what());
  }
  // Results go out through C stdio (std::cout is synchronised with it, and some commands
  // printf): a full disk or a bad descriptor shows at the latest when stdout is flushed.
  // When an earlier write failed and the flush has nothing left to write, errno still
  // holds that write's reason (nothing else fails in between).
  std::cout.flush();
  const int earlier = errno;
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  const int reason = flushed ? earlier : errno;
  if (!flushed || std::ferror(stdout) || !std::cout.good())
    return fail(2, std::string("cannot write to stdout: ") + std::strerror(reason != 0 ? reason : EIO));
  return gonio::cli::exit_status();
}

int& gonio::cli::exit_status() {
  static int status = 0;
  return status;
}
