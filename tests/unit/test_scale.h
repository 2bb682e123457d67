#pragma once
// Monte Carlo sample counts in tests scale with GONIO_TEST_SCALE (the sanitizer pass
// runs with 0.1), never below a floor that keeps the statistics meaningful.

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace gonio::test {

inline std::uint64_t scaled(std::uint64_t n, std::uint64_t floor = 1000) {
  double s = 1;
  if (const char* e = std::getenv("GONIO_TEST_SCALE")) s = std::atof(e);
  if (!(s > 0)) s = 1;
  return std::max<std::uint64_t>(floor, static_cast<std::uint64_t>(double(n) * s));
}

}  // namespace gonio::test
