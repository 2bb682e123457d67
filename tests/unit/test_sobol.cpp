// Sobol' points and their Owen scrambling (math/sobol.h), checked by the defining property
// of a (0, 2)-sequence in base 2 rather than against the code's own numbers: every
// aligned block of 2^m points is a (0, m, 2)-net, one point in each of the 2^m elementary
// intervals [a/2^j, (a+1)/2^j) × [b/2^(m−j), (b+1)/2^(m−j)) for every j (Niederreiter 1992,
// Def. 4.1). A random scramble keeps the property (Owen 1995) and makes each coordinate
// uniform.

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <vector>

#include "gonio/math/sobol.h"

namespace {

using gonio::Float;

// Whether the points (x_i, y_i) (fractions of 2^32) form a (0, m, 2)-net.
bool is_net(const std::vector<std::uint32_t>& x, const std::vector<std::uint32_t>& y, int m) {
  for (int j = 0; j <= m; ++j) {
    std::set<std::uint64_t> cells;
    for (size_t i = 0; i < x.size(); ++i) {
      const std::uint64_t col = j == 0 ? 0 : x[i] >> (32 - j), row = j == m ? 0 : y[i] >> (32 - (m - j));
      cells.insert(col << 32 | row);
    }
    if (cells.size() != x.size()) return false;
  }
  return true;
}

TEST(Sobol, FirstPointsOfBothDimensions) {
  // Dimension 0 is van der Corput's radical inverse; dimension 1 has the generator columns
  // 1, 11, 101, 1111 (binary, from the top bit) of the primitive polynomial x + 1: the
  // points 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8 in index order (no Gray code).
  const double d0[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double d1[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(double(gonio::sobol_dim0(std::uint64_t(i))) * 0x1p-32, d0[i]) << i;
    EXPECT_EQ(double(gonio::sobol_dim1(std::uint64_t(i))) * 0x1p-32, d1[i]) << i;
  }
  // Column 4 of dimension 1 is 11110000... xor-shifted once more: 10001 from the top.
  EXPECT_EQ(gonio::sobol_dim1(16), 0x88000000u);
}

TEST(Sobol, AlignedBlocksAreNets) {
  for (int m = 1; m <= 12; ++m)
    for (std::uint64_t block : {0ull, 1ull, 7ull}) {
      std::vector<std::uint32_t> x, y;
      for (std::uint64_t i = block << m; i < (block + 1) << m; ++i)
        x.push_back(gonio::sobol_dim0(i)), y.push_back(gonio::sobol_dim1(i));
      EXPECT_TRUE(is_net(x, y, m)) << "m " << m << " block " << block;
    }
  // A block that is not aligned is not a net (the test can fail).
  std::vector<std::uint32_t> x, y;
  for (std::uint64_t i = 3; i < 19; ++i) x.push_back(gonio::sobol_dim0(i)), y.push_back(gonio::sobol_dim1(i));
  EXPECT_FALSE(is_net(x, y, 4));
}

TEST(Sobol, OwenScramblingKeepsTheNetAndIsAPermutationOfItsTree) {
  for (std::uint32_t seed : {1u, 0x9e3779b9u, 0xdeadbeefu}) {
    for (int m : {4, 9}) {
      std::vector<std::uint32_t> x, y;
      for (std::uint64_t i = 0; i < (1ull << m); ++i)
        x.push_back(gonio::owen_scramble(gonio::sobol_dim0(i), seed)),
            y.push_back(gonio::owen_scramble(gonio::sobol_dim1(i), seed * 3 + 1));
      EXPECT_TRUE(is_net(x, y, m)) << seed << " " << m;
    }
    // Nested: two values sharing their top j bits keep sharing exactly j top bits.
    const std::uint32_t a = 0xabc00000u, b = 0xabd00000u;  // the same top 11 bits, then differ
    const std::uint32_t sa = gonio::owen_scramble(a, seed), sb = gonio::owen_scramble(b, seed);
    EXPECT_EQ(sa >> 21, sb >> 21);
    EXPECT_NE(sa >> 20, sb >> 20);
  }
}

TEST(Sobol, ScrambledCoordinatesAreUniform) {
  // Over random seeds, the first point (index 0, which is 0 unscrambled) is uniform: a
  // histogram of 16 bins, chi-square with 15 degrees of freedom below 37.7 (p = 0.001).
  constexpr int kBins = 16, kSeeds = 16000;
  for (int dim = 0; dim < 2; ++dim) {
    std::vector<int> h(kBins, 0);
    for (std::uint32_t s = 0; s < kSeeds; ++s) {
      const std::uint32_t seed = s * 0x9e3779b9u + 0x7f4a7c15u;
      const Float v = dim == 0 ? gonio::sobol_owen_dim0(0, seed) : gonio::sobol_owen_dim1(0, seed);
      ASSERT_GE(v, 0);
      ASSERT_LT(v, 1);
      ++h[size_t(v * kBins)];
    }
    double chi2 = 0;
    for (int c : h) chi2 += (c - kSeeds / kBins) * double(c - kSeeds / kBins) / (kSeeds / kBins);
    EXPECT_LT(chi2, 37.7) << "dimension " << dim;
  }
  EXPECT_LT(gonio::fraction_to_float(0xffffffffu), 1.0f);
}

TEST(Sobol, FusedPairIsTheTwoScrambledCoordinates) {
  // The sampler's 2-D draw (both hashes' inputs from one set of lookups by the reversed
  // index's bytes, both outputs to floats by lookups) against the two one-dimensional
  // formulas above, which reverse bit by bit.
  std::uint32_t r = 0x12345678u;
  for (int k = 0; k < 2000; ++k) {
    r = r * 1664525u + 1013904223u;
    const std::uint32_t s0 = r ^ 0xa5a5a5a5u, s1 = r * 0x9e3779b9u + 7u;
    const std::uint64_t index = gonio::reverse_bits32(r);
    const auto p = gonio::sobol_owen_2d_of_reversed(r, s0, s1);
    ASSERT_EQ(p[0], gonio::sobol_owen_dim0(index, s0)) << r;
    ASSERT_EQ(p[1], gonio::sobol_owen_dim1(index, s1)) << r;
  }
}

TEST(Sobol, ReversedFractionByTablesIsTheReversalsFloat) {
  // Every byte value in each of the four positions (the tables' every entry, and the top
  // byte that must not count), then random words; against the float of the reversal made
  // bit by bit, compared exactly.
  for (int b = 0; b < 32; ++b) ASSERT_EQ(gonio::reverse_bits32(1u << b), 1u << (31 - b)) << b;
  for (int byte = 0; byte < 4; ++byte)
    for (std::uint32_t b = 0; b < 256; ++b) {
      const std::uint32_t w = b << (8 * byte) | (byte == 0 ? 0x00ff0000u : 0x1u);
      ASSERT_EQ(gonio::reversed_fraction_to_float(w), gonio::fraction_to_float(gonio::reverse_bits32(w))) << std::hex << w;
    }
  std::uint32_t w = 1;
  for (int k = 0; k < 100000; ++k) {
    w = w * 1664525u + 1013904223u;
    ASSERT_EQ(gonio::reversed_fraction_to_float(w), gonio::fraction_to_float(gonio::reverse_bits32(w))) << std::hex << w;
  }
  EXPECT_LT(gonio::reversed_fraction_to_float(0xffffffffu), 1.0f);
}

TEST(Sobol, MortonInterleavesXInTheEvenBits) {
  EXPECT_EQ(gonio::morton2(0, 0), 0u);
  EXPECT_EQ(gonio::morton2(1, 0), 1u);
  EXPECT_EQ(gonio::morton2(0, 1), 2u);
  EXPECT_EQ(gonio::morton2(3, 5), 0b100111u);  // x 011, y 101 -> y2 x2 y1 x1 y0 x0 = 1 0 0 1 1 1
  EXPECT_EQ(gonio::morton2(0xffffffffu, 0), 0x5555555555555555ULL);
}

}  // namespace
