// The note sink of include/gonio/io/notes.h.
#include "gonio/io/notes.h"

#include <cstdio>
#include <mutex>

namespace gonio {
namespace {
std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}
NoteSink& current_sink() {
  static NoteSink s;
  return s;
}
}  // namespace

NoteSink set_note_sink(NoteSink sink) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  NoteSink old = std::move(current_sink());
  current_sink() = std::move(sink);
  return old;
}

void note(const std::string& line) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  if (current_sink()) {
    current_sink()(line);
    return;
  }
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace gonio
