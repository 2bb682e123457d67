#include "cli_signals.h"

#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>

namespace gonio::cli {

namespace {

// The handler's whole state: lock-free atomics and fixed buffers written before their
// count is published.
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
std::atomic<bool> g_interruptible{false};
std::atomic<int> g_removable_count{0};
char g_removable[kMaxRemovable][4096];
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

void write_stderr(const char* text) {
  for (size_t done = 0, n = std::strlen(text); done < n;) {
    const ssize_t w = ::write(STDERR_FILENO, text + done, n - done);
    if (w <= 0) return;
    done += size_t(w);
  }
}

extern "C" void on_stop_signal(int sig) {
  const bool again = g_stop.exchange(true);
  if (!again) g_signal.store(sig);
  if (g_interruptible.load() && !again) return;
  for (int i = 0, n = g_removable_count.load(); i < n; ++i) ::unlink(g_removable[i]);
  write_stderr(sig == SIGTERM ? "gonio: stopped by SIGTERM" : "gonio: stopped by SIGINT");
  write_stderr(again ? " (a second signal): nothing written\n" : ": nothing written\n");
  ::_exit(128 + sig);
}

sigset_t stop_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

void install_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sa.sa_mask = stop_set();  // one handler at a time
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void create_removable(const std::function<std::string()>& create) {
  const sigset_t set = stop_set();
  sigset_t old;
  pthread_sigmask(SIG_BLOCK, &set, &old);
  std::string path;
  try {
    path = create();
  } catch (...) {
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw;
  }
  const int n = g_removable_count.load();
  if (n < kMaxRemovable && path.size() < sizeof g_removable[0]) {
    std::memcpy(g_removable[n], path.c_str(), path.size() + 1);
    g_removable_count.store(n + 1);
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);  // a signal that came meanwhile is handled now
}

void set_interruptible(bool interruptible) { g_interruptible.store(interruptible); }

const std::atomic<bool>& stop_requested() { return g_stop; }

int stop_signal() { return g_signal.load(); }

}  // namespace gonio::cli
