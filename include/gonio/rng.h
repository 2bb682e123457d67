#pragma once
// PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast
// Space-Efficient Statistically Good Algorithms for Random Number Generation",
// the XSH-RR output function on a 64-bit LCG). Deterministic for a given seed and stream,
// so every Monte Carlo figure gonio reports can be reproduced.

#include <cstdint>

#include "gonio/math/constants.h"

namespace gonio {

class Pcg32 {
 public:
  explicit Pcg32(std::uint64_t seed = 0x853c49e6748fea9bULL, std::uint64_t stream = 0xda3e39cb94b95bdbULL) {
    seed_stream(seed, stream);
  }

  void seed_stream(std::uint64_t seed, std::uint64_t stream) {
    state_ = 0;
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }

  std::uint32_t next_u32() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Uniform in [0, 1): the top 24 bits, exactly representable as a float.
  Float next_float() { return static_cast<Float>(next_u32() >> 8) * 0x1p-24f; }
  // Uniform in [0, 1) with 53 bits.
  double next_double() {
    const std::uint64_t hi = next_u32(), lo = next_u32();
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
  }

 private:
  std::uint64_t state_ = 0, inc_ = 1;
};

}  // namespace gonio
