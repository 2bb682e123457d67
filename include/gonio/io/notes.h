#pragma once
// Notes: what the library says about input it accepts but the user should hear about,
// one line each (e.g. a measured table with missing entries, measured_data.h). They go to
// stderr unless a program installs its own sink (the Python module turns them into
// warnings.warn).

#include <functional>
#include <string>

namespace gonio {

using NoteSink = std::function<void(const std::string& line)>;

// Installs `sink` (empty: back to stderr) and returns the one it replaces. Thread-safe.
NoteSink set_note_sink(NoteSink sink);

// Hands one line (no newline) to the sink.
void note(const std::string& line);

}  // namespace gonio
