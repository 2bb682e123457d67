#pragma once
// SIGINT and SIGTERM for the commands that write files. A signal never leaves a temporary
// output behind, and never goes unanswered:
// - while work is interruptible (a render between its tiles), the first signal sets the
//   stop flag the work polls, and the command finishes what it can (the passes done);
// - a second signal, or the first while nothing polls the flag (reading the scene, where
//   open() of a FIFO without a writer waits for ever; tabulating), removes the registered
//   temporaries and ends the process at once: one line on stderr, status 128 + signal.
// Only async-signal-safe calls happen in the handler (unlink, write, _exit).

#include <atomic>
#include <functional>
#include <string>

namespace gonio::cli {

// Installs the handler (idempotent).
void install_stop_signals();

// Runs `create`, which makes an output file and returns its temporary's path, with SIGINT
// and SIGTERM blocked, then registers the path for the handler to remove: a signal at any
// moment leaves no temporary. At most kMaxRemovable paths of fewer than 4096 bytes.
inline constexpr int kMaxRemovable = 4;
void create_removable(const std::function<std::string()>& create);

// While true, the first signal only sets stop_requested() (the work stops between steps).
void set_interruptible(bool interruptible);
// The flag the work polls, and the signal that set it (0 if none).
const std::atomic<bool>& stop_requested();
int stop_signal();

}  // namespace gonio::cli
