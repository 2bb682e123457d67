#pragma once
// The first two dimensions of the Sobol' sequence (Sobol' 1967), Owen-scrambled by hashing
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), §3–4), and the Morton
// order of pixels. The two dimensions form a (0, 2)-sequence in base 2: every aligned
// block of 2^m consecutive points is a (0, m, 2)-net — each of the 2^m elementary
// intervals of area 2^−m holds exactly one point — and Owen scrambling keeps that property
// while making every point uniformly distributed (Owen 1995). Higher dimensions are made
// by scrambling these two with independent seeds ("padding", Kollig & Keller 2002), so
// no table of direction numbers is needed.

#include <array>
#include <bit>
#include <cstdint>

#include "gonio/math/constants.h"

namespace gonio {

constexpr std::uint32_t reverse_bits32(std::uint32_t v) {
  // The bytes' order by one byte swap, then the bits within each byte.
  v = __builtin_bswap32(v);
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  return ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
}

namespace sobol_detail {

// Sobol's second dimension (primitive polynomial x + 1, m_k = 1): generator column k is
// c_k = c_{k−1} xor (c_{k−1} >> 1) from c_0 = 2^31, i.e. Pascal's triangle mod 2.
// The point of index i is the xor of the columns of i's set bits; it is tabulated per byte
// of i, so a point costs four lookups.
constexpr std::array<std::array<std::uint32_t, 256>, 4> make_dim1_tables() {
  std::array<std::uint32_t, 32> column{};
  column[0] = 0x80000000u;
  for (int k = 1; k < 32; ++k) column[k] = column[k - 1] ^ (column[k - 1] >> 1);
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (int byte = 0; byte < 4; ++byte)
    for (int b = 0; b < 256; ++b) {
      std::uint32_t v = 0;
      for (int bit = 0; bit < 8; ++bit)
        if (b >> bit & 1) v ^= column[8 * byte + bit];
      t[byte][b] = reverse_bits32(v);
    }
  return t;
}
// Stored bit-reversed: the scramble works on reversed values (owen_scramble).
inline constexpr auto kDim1Reversed = make_dim1_tables();

constexpr std::uint32_t sobol_dim1_reversed(std::uint64_t index) {
  const auto i = std::uint32_t(index);
  const auto& t = kDim1Reversed;
  return t[0][i & 0xff] ^ t[1][(i >> 8) & 0xff] ^ t[2][(i >> 16) & 0xff] ^ t[3][i >> 24];
}

// Both coordinates' inputs to the output scramble, indexed by the bytes of r, the index's
// bit reversal (the sampler's shuffled index comes reversed): the low 32 bits of the xor
// of the four entries are reverse(r), dimension 0's value of the index bit-reversed; the
// high 32 bits are dimension 1's value bit-reversed (byte k of r is byte 3 − k of the index
// with its bits reversed). One set of four lookups replaces a 32-bit reversal and the
// second dimension's own lookups.
constexpr std::array<std::array<std::uint64_t, 256>, 4> make_pair_tables_of_reversed() {
  std::array<std::array<std::uint64_t, 256>, 4> t{};
  for (int byte = 0; byte < 4; ++byte)
    for (std::uint32_t b = 0; b < 256; ++b) {
      const std::uint32_t dim0 = reverse_bits32(b << (8 * byte));
      const std::uint32_t dim1 = kDim1Reversed[std::size_t(3 - byte)][reverse_bits32(b) >> 24];
      t[std::size_t(byte)][b] = std::uint64_t(dim1) << 32 | dim0;
    }
  return t;
}
inline constexpr auto kPairOfReversed = make_pair_tables_of_reversed();

constexpr std::uint64_t sobol_pair_reversed_of_reversed(std::uint32_t r) {
  const auto& t = kPairOfReversed;
  return t[0][r & 0xff] ^ t[1][(r >> 8) & 0xff] ^ t[2][(r >> 16) & 0xff] ^ t[3][r >> 24];
}

// fraction_to_float(reverse_bits32(w)) as a sum of three terms, one per byte of w that
// reaches the float's 24 bits: byte k of w, reversed, is bits 8k … 8k + 7 below the
// point. Every partial sum is a multiple of 2^−24 below 1, so the sum is exact and equal to
// the conversion bit for bit; three lookups cost less than a reversal and a conversion.
inline constexpr auto kReversedByteFraction = [] {
  std::array<std::array<Float, 256>, 3> t{};
  for (int byte = 0; byte < 3; ++byte)
    for (std::uint32_t b = 0; b < 256; ++b)
      t[std::size_t(byte)][b] = Float(reverse_bits32(b) >> 24) / Float(1u << (8 * (byte + 1)));
  return t;
}();

// A permutation of 32-bit words in which each bit is flipped by a function of the bits
// below it only: Laine & Karras 2011's hash, with the constants of Vegdahl's 2021
// improvement ("Building a better LK hash", which passes the avalanche tests Burley's
// §4 version fails). Applied to bit-reversed values it flips each bit of the original by a
// hash of the bits above it: a nested uniform (Owen) scramble (Burley 2020, §3).
constexpr std::uint32_t lk_hash(std::uint32_t v, std::uint32_t seed) {
  v ^= v * 0x3d20adeau;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526c56u;
  v ^= v * 0x53a22864u;
  return v;
}

}  // namespace sobol_detail

// Unscrambled points of the first two dimensions, as 32-bit fractions of 2^32. Only the
// low 32 bits of the index count (the columns of higher bits are zero in 32 bits).
constexpr std::uint32_t sobol_dim0(std::uint64_t index) { return reverse_bits32(std::uint32_t(index)); }
constexpr std::uint32_t sobol_dim1(std::uint64_t index) {
  return reverse_bits32(sobol_detail::sobol_dim1_reversed(index));
}

// Owen scrambling of a 32-bit fraction (Burley 2020, nested_uniform_scramble).
constexpr std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed) {
  return reverse_bits32(sobol_detail::lk_hash(reverse_bits32(v), seed));
}

// A 32-bit fraction as a float in [0, 1): its top 24 bits, so it never rounds up to 1.
constexpr Float fraction_to_float(std::uint32_t v) { return Float(v >> 8) * 0x1p-24f; }

// fraction_to_float(reverse_bits32(w)), from the tables above.
constexpr Float reversed_fraction_to_float(std::uint32_t w) {
  const auto& t = sobol_detail::kReversedByteFraction;
  return (t[0][w & 0xff] + t[1][(w >> 8) & 0xff]) + t[2][(w >> 16) & 0xff];
}

// Scrambled points in [0, 1). Dimension 0 is bit-reversal, so its scramble needs no
// reversal of its own: reverse(lk(reverse(reverse(i)))) = reverse(lk(i)).
constexpr Float sobol_owen_dim0(std::uint64_t index, std::uint32_t seed) {
  return fraction_to_float(reverse_bits32(sobol_detail::lk_hash(std::uint32_t(index), seed)));
}
constexpr Float sobol_owen_dim1(std::uint64_t index, std::uint32_t seed) {
  return fraction_to_float(reverse_bits32(sobol_detail::lk_hash(sobol_detail::sobol_dim1_reversed(index), seed)));
}

// Both coordinates at once, for the index whose low 32 bits are reverse(r): equal to
// {sobol_owen_dim0(i, seed0), sobol_owen_dim1(i, seed1)}. Both hashes' inputs come from one
// set of lookups by the bytes of r, and both outputs go to floats by lookups instead of
// reversals (the renderer draws a 2-D point per decision: this is its cost per number,
// docs/benchmarks.md).
constexpr std::array<Float, 2> sobol_owen_2d_of_reversed(std::uint32_t r, std::uint32_t seed0, std::uint32_t seed1) {
  const std::uint64_t inputs = sobol_detail::sobol_pair_reversed_of_reversed(r);
  return {reversed_fraction_to_float(sobol_detail::lk_hash(std::uint32_t(inputs), seed0)),
          reversed_fraction_to_float(sobol_detail::lk_hash(std::uint32_t(inputs >> 32), seed1))};
}

// Morton (Z-order) index of a pixel: the bits of x and y interleaved, x in the even bits.
constexpr std::uint64_t morton2(std::uint32_t x, std::uint32_t y) {
  const auto spread = [](std::uint64_t v) {
    v &= 0xffffffffULL;
    v = (v | (v << 16)) & 0x0000ffff0000ffffULL;
    v = (v | (v << 8)) & 0x00ff00ff00ff00ffULL;
    v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0fULL;
    v = (v | (v << 2)) & 0x3333333333333333ULL;
    return (v | (v << 1)) & 0x5555555555555555ULL;
  };
  return spread(x) | (spread(y) << 1);
}

}  // namespace gonio
