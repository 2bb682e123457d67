// Shared pieces of include/gonio/measure/instrument.h.
#include "gonio/measure/instrument.h"

#include <cmath>

namespace gonio::measure {

Vec3 spherical_direction(double theta, double phi) {
  const double s = std::sin(theta);
  return Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(std::cos(theta))};
}

void entry_point(std::uint64_t k, bool full_block, Pcg32& rng, double& u, double& v) {
  const double ju = rng.next_double(), jv = rng.next_double();
  if (!full_block) {
    u = ju, v = jv;
    return;
  }
  // De-interleave the 13 bits of k: even bits give the column (7 bits, 128), odd bits
  // the row (6 bits, 64); each half is gathered by halving the gaps between its bits.
  const auto i = static_cast<unsigned>(k % kBlockRays);
  auto even_bits = [](unsigned b) {
    b &= 0x5555u;
    b = (b | (b >> 1)) & 0x3333u;
    b = (b | (b >> 2)) & 0x0F0Fu;
    return (b | (b >> 4)) & 0x00FFu;
  };
  const unsigned x = even_bits(i), y = even_bits(i >> 1);
  u = (x + ju) / 128.0;
  v = (y + jv) / 64.0;
}

std::uint64_t block_stream(std::uint64_t task, std::uint64_t block) {
  // SplitMix64's finaliser (Steele, Lea & Flood 2014) spreads (task, block) over the
  // 2^63 PCG32 streams.
  std::uint64_t z = task * 0x9E3779B97F4A7C15ULL + block + 0xD1B54A32D192ED03ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace gonio::measure
