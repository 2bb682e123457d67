// The renderer's samplers (render/sampler.h): what each promises, checked by counting
// points in elementary intervals, not against numbers the code printed.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "gonio/render/sampler.h"

namespace {

using gonio::Float;
using gonio::render::PixelSampler;
using gonio::render::SamplerType;

// Whether the points form a (0, m, 2)-net: one point in each elementary interval of area
// 2^−m (Niederreiter 1992, Def. 4.1). Floats in [0, 1) with 24 bits.
bool is_net(const std::vector<std::array<Float, 2>>& p, int m) {
  for (int j = 0; j <= m; ++j) {
    std::set<std::pair<long, long>> cells;
    for (const auto& q : p) cells.insert({long(std::ldexp(q[0], j)), long(std::ldexp(q[1], m - j))});
    if (cells.size() != p.size()) return false;
  }
  return true;
}

std::vector<std::array<Float, 2>> pixel_points(PixelSampler& s, int x, int y, int n, int dim) {
  std::vector<std::array<Float, 2>> p;
  for (int i = 0; i < n; ++i) {
    s.start(x, y, std::uint64_t(i));
    p.push_back(s.get2d(dim));
  }
  return p;
}

TEST(Sampler, EveryPixelsPowerOfTwoSamplesAreANet) {
  // Odd and even log2 of the count (the Z-order index then has a base-2 digit at the
  // bottom), odd image sizes, several dimensions.
  for (SamplerType type : {SamplerType::ZSobol, SamplerType::Sobol})
    for (int log2n : {2, 3, 4, 5, 8}) {
      const int n = 1 << log2n;
      PixelSampler s(type, n, 5);
      for (auto [x, y] : {std::pair{0, 0}, std::pair{36, 20}, std::pair{17, 3}})
        for (int dim : {0, 5, 9, 44}) {
          EXPECT_TRUE(is_net(pixel_points(s, x, y, n, dim), log2n))
              << gonio::render::sampler_type_name(type) << " n " << n << " pixel " << x << "," << y << " dim " << dim;
          // A 1-D dimension: one sample in each of the n strata.
          std::set<long> strata;
          for (int i = 0; i < n; ++i) {
            s.start(x, y, std::uint64_t(i));
            strata.insert(long(s.get1d(dim + 2) * Float(n)));
          }
          EXPECT_EQ(strata.size(), size_t(n)) << "1-D, dim " << dim + 2;
        }
    }
  // The independent sampler is not stratified (the test can fail).
  PixelSampler s(SamplerType::Independent, 16, 5);
  EXPECT_FALSE(is_net(pixel_points(s, 3, 3, 16, 0), 4));
}

TEST(Sampler, ZSobolNeighbouringPixelsShareOneNet) {
  // An aligned 2×2 block of pixels with 4 samples each holds 16 consecutive aligned indices
  // of the sequence: together a (0, 4, 2)-net in every pair of dimensions (Ahmed & Wonka
  // 2020's screen-space property). Per-pixel sequences (sobol) do not have it.
  int zsobol_nets = 0, sobol_nets = 0, blocks = 0;
  for (int dim : {0, 5, 13})
    for (auto [bx, by] : {std::pair{0, 0}, std::pair{2, 6}, std::pair{10, 4}}) {
      ++blocks;
      for (SamplerType type : {SamplerType::ZSobol, SamplerType::Sobol}) {
        PixelSampler s(type, 4, 9);
        std::vector<std::array<Float, 2>> p;
        for (int y = by; y < by + 2; ++y)
          for (int x = bx; x < bx + 2; ++x) {
            const auto q = pixel_points(s, x, y, 4, dim);
            p.insert(p.end(), q.begin(), q.end());
          }
        (type == SamplerType::ZSobol ? zsobol_nets : sobol_nets) += is_net(p, 4);
      }
    }
  EXPECT_EQ(zsobol_nets, blocks);
  EXPECT_LT(sobol_nets, blocks);
}

TEST(Sampler, DimensionsOfOneSampleAreIndependent) {
  // Two 1-D dimensions of a pixel's 16 samples, each stratified: how many samples have
  // both below ½. With the strata paired at random it has mean 4 and a variance of at most
  // 2 (16/15 for a uniformly random pairing; 2 for the nested shuffle of sobol, where the
  // 8 pairs of indices differing in their lowest bit each hold one such sample per
  // dimension, matched with probability ½: Binomial(8, ½)); independent numbers give
  // Binomial(16, ¼), variance 3. Scrambling the same point in both dimensions without
  // shuffling the index makes it 0 or 8 in every pixel (squared deviation 16).
  for (SamplerType type : {SamplerType::ZSobol, SamplerType::Sobol, SamplerType::Independent}) {
    PixelSampler s(type, 16, 3);
    double dev2 = 0, mean = 0;
    int pixels = 0;
    for (int y = 0; y < 64; y += 2)
      for (int x = 0; x < 64; x += 2, ++pixels) {
        int both = 0;
        for (int i = 0; i < 16; ++i) {
          s.start(x, y, std::uint64_t(i));
          both += s.get1d(7) < Float(0.5) && s.get1d(11) < Float(0.5);
        }
        dev2 += (both - 4.0) * (both - 4.0), mean += both;
      }
    mean /= pixels, dev2 /= pixels;
    EXPECT_NEAR(mean, 4, 0.25) << gonio::render::sampler_type_name(type);
    EXPECT_LT(dev2, type == SamplerType::Independent ? 4 : 2.6) << gonio::render::sampler_type_name(type);
    EXPECT_GT(dev2, type == SamplerType::Independent ? 2.2 : 0.6) << gonio::render::sampler_type_name(type);
  }
}

TEST(Sampler, NumbersDependOnlyOnPixelSampleAndDimension) {
  for (SamplerType type : {SamplerType::ZSobol, SamplerType::Sobol, SamplerType::Independent}) {
    PixelSampler a(type, 64, 11), b(type, 64, 11), c(type, 64, 12);
    a.start(7, 9, 33);
    b.start(1, 1, 2);
    (void)b.get2d(3);
    const std::uint32_t other_stream = b.rng().next_u32();  // another sample's stream, begun
    b.start(7, 9, 33);
    EXPECT_EQ(a.get1d(20), b.get1d(20));
    EXPECT_EQ(a.get2d(4), b.get2d(4));
    // The stream is seeded on first use: start() must still restart it.
    const std::uint32_t first = a.rng().next_u32();
    EXPECT_EQ(first, b.rng().next_u32());
    EXPECT_NE(first, other_stream);
    a.start(7, 9, 34);
    EXPECT_NE(a.rng().next_u32(), first) << "each sample its own stream";
    c.start(7, 9, 33);
    EXPECT_NE(a.get1d(21), c.get1d(21)) << "the seed must matter";
    for (int dim = 0; dim < 200; ++dim) {
      const Float v = a.get1d(dim);
      EXPECT_TRUE(v >= 0 && v < 1) << dim << " " << v;
    }
  }
}

TEST(Sampler, ZSobolMeanOverManySamplesIsAHalf) {
  // Unbiased: over 64 pixels × 64 samples, each of a few dimensions averages ½ within
  // what a stratified estimate allows (far tighter than independent numbers' 0.0045).
  PixelSampler s(SamplerType::ZSobol, 64, 2);
  for (int dim : {0, 3, 40}) {
    double sum = 0;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        for (int i = 0; i < 64; ++i) {
          s.start(x, y, std::uint64_t(i));
          sum += s.get1d(dim);
        }
    EXPECT_NEAR(sum / 4096, 0.5, 1e-3) << dim;
  }
}

TEST(Sampler, Names) {
  EXPECT_EQ(gonio::render::sampler_type_from_name("zsobol"), SamplerType::ZSobol);
  EXPECT_EQ(gonio::render::sampler_type_from_name("sobol"), SamplerType::Sobol);
  EXPECT_EQ(gonio::render::sampler_type_from_name("independent"), SamplerType::Independent);
  EXPECT_FALSE(gonio::render::sampler_type_from_name("halton"));
}

}  // namespace

namespace {

// The dimension layout gives each decision dimensions of its own: a number shared by two
// decisions of one bounce (say the roulette and the lobe) would correlate them.
TEST(SamplerDims, EveryDecisionHasDimensionsOfItsOwn) {
  namespace d = gonio::render::dims;
  std::set<int> used;
  const auto take = [&](int first, int count) {
    for (int k = first; k < first + count; ++k) EXPECT_TRUE(used.insert(k).second) << "dimension " << k << " twice";
  };
  take(d::kPixel, 2), take(d::kWavelength, 1), take(d::kLens, 2);
  for (int b = 0; b < 3; ++b) {
    const int base = d::bounce(b);
    take(base + d::kChoiceAndLobe, 2), take(base + d::kLightPosition, 2), take(base + d::kDirection, 2),
        take(base + d::kRoulette, 1);
    EXPECT_LE(d::kRoulette + 1, d::kPerBounce);
  }
  EXPECT_EQ(*used.begin(), 0);
}

}  // namespace
