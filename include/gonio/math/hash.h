#pragma once
// Integer hashing for deterministic random numbers: seeds of per-pixel streams, scrambles
// of low-discrepancy points, the layered walk's per-evaluation seeds.

#include <cstdint>

namespace gonio {

// splitmix64's finaliser (Steele, Lea & Flood 2014): a bijective mix of 64 bits.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// splitmix64's whole step (the golden-ratio increment, then the finaliser): mix64 would map
// 0 to 0, this does not.
constexpr std::uint64_t splitmix64(std::uint64_t x) { return mix64(x + 0x9e3779b97f4a7c15ULL); }

}  // namespace gonio
