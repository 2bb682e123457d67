// gonio explore: the BRDF explorer in the browser (issue 36, SPEC §3). Serves the page and
// its JSON API (src/explore) until SIGINT or SIGTERM, then exits 0.

#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "cli_number.h"
#include "commands.h"
#include "explore/server.h"
#include "gonio/error.h"

extern char** environ;

namespace gonio::cli {

namespace {
// How long the first SIGINT or SIGTERM waits for the requests at work to stop.
constexpr int kStopGraceMs = 1500;

struct ExploreArgs {
  std::int64_t port = 8080;
  std::string host = "127.0.0.1";
  std::string data;
  bool open = false;
};

// --open: the desktop's browser, through xdg-open; a machine without one only warns.
void open_browser(const std::string& url) {
  const char* argv[] = {"xdg-open", url.c_str(), nullptr};
  // The browser must not inherit the blocked SIGINT and SIGTERM of this process.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  if (posix_spawnp(&pid, "xdg-open", nullptr, &attr, const_cast<char* const*>(argv), environ) != 0)
    std::cerr << "gonio: --open: could not start xdg-open; open " << url << " in a browser\n";
  posix_spawnattr_destroy(&attr);
}

void run_explore(const ExploreArgs& a) {
  explore::ServerOptions o;
  o.host = a.host;
  o.port = int(a.port);
  o.data_dir = a.data;
  // SIGINT and SIGTERM are blocked in every thread (the server's inherit the mask) and
  // taken by sigwait below: the server is stopped from an ordinary thread, not a handler.
  sigset_t stop_set;
  sigemptyset(&stop_set);
  sigaddset(&stop_set, SIGINT);
  sigaddset(&stop_set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_set, nullptr);

  explore::Server server(o);
  server.bind();  // InputError (exit 2) for --data, --host, --port
  std::cout << server.url() << std::endl;  // SPEC §3: the URL first, flushed at once
  if (a.open) open_browser(server.url());
  std::atomic<bool> served{true}, finished{false};
  std::thread serving([&] {
    served = server.run();
    finished = true;
    if (!served) ::kill(::getpid(), SIGTERM);  // wakes the sigwait below
  });
  int sig = 0;
  sigwait(&stop_set, &sig);
  // The first signal ends the process: the server stops listening and raises the stop
  // signal of every request at work, which ends at its next step; whatever is still busy
  // after kStopGraceMs (a step of a long computation) is abandoned with the process.
  std::thread stopping([&] { server.stop(); });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(kStopGraceMs);
  while (!finished && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (!finished) {
    std::cout.flush();
    std::fflush(stdout);
    std::_Exit(served ? 0 : 2);
  }
  stopping.join();
  serving.join();
  if (!served) throw InputError("explore: the server stopped listening on " + server.url());
}
}  // namespace

void register_explore(CLI::App& app) {
  auto args = std::make_shared<ExploreArgs>();
  auto* cmd = app.add_subcommand(
      "explore",
      "Serve the BRDF explorer (a page and its JSON API) on http://HOST:PORT/, print that URL, and serve until "
      "Ctrl-C (docs/explore.md)");
  cmd->add_option("--port", args->port, "TCP port, 0 to 65535 (default 8080; 0: any free port)")
      ->transform(decimal_in_range(0, 65535));
  cmd->add_option("--host", args->host,
                  "address to listen on (default 127.0.0.1; requests must name it, 127.0.0.1, [::1] or localhost)");
  cmd->add_option("--data", args->data, "directory whose files (MERL tables, spectra) materials may name");
  cmd->add_flag("--open", args->open, "open the page in the desktop's browser (xdg-open)");
  cmd->callback([args] { run_explore(*args); });
}

}  // namespace gonio::cli
