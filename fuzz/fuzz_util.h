#pragma once
// Helpers shared by the libFuzzer targets: a per-process scratch file for readers that
// take a path, and checks that abort (a crash libFuzzer records) on a contract breach.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>

#include "gonio/color.h"

namespace gonio_fuzz {

// True for an input that names a system path (/dev, /proc, /sys): a scene or surface
// that refers to files would make the fuzzer read devices (/dev/zero without end).
inline bool names_system_path(std::string_view text) {
  return text.find("/dev") != std::string_view::npos || text.find("/proc") != std::string_view::npos ||
         text.find("/sys") != std::string_view::npos;
}

// A file unique to this process (libFuzzer's -jobs run several processes), rewritten for
// every input: the readers under test take paths. In /dev/shm when there is one: on a
// disk, ext4 flushes a file truncated and rewritten at its close (auto_da_alloc), which
// held the OBJ, PNG and EXR targets at ~4 ms per input, waiting on the disk.
inline std::string write_scratch(const uint8_t* data, size_t size, const char* extension) {
  static const std::string base = [] {
    std::error_code ec;
    const std::filesystem::path dir =
        std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
    return (dir / ("gonio_fuzz_" + std::to_string(::getpid()))).string();
  }();
  const std::string path = base + extension;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write scratch file %s\n", path.c_str());
    std::abort();
  }
  return path;
}

[[noreturn]] inline void fail(const char* what, double value) {
  std::fprintf(stderr, "fuzz: contract broken: %s (value %.9g)\n", what, value);
  std::abort();
}

// Finite and >= 0, as every value a BxDF returns must be.
inline void check_value(const char* what, double v) {
  if (!std::isfinite(v) || v < 0) fail(what, v);
}
template <int N>
void check_color(const char* what, const gonio::BasicColor<N>& c) {
  for (int i = 0; i < N; ++i) check_value(what, c[i]);
}

}  // namespace gonio_fuzz
