// The random-walk slab estimator (slab_walk.h).

#include "gonio/subsurface/slab_walk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>
#include <vector>

#include "slab_path.h"

namespace gonio {
namespace {

constexpr int kChannels = Color::size();

struct BlockSums {
  std::array<double, kChannels> sum{}, sum2{};
  std::array<std::array<double, kChannels>, kSlabProfilePoints> bins{};
  std::uint64_t steps = 0;
};

// Blocks run at once, then summed: memory stays bounded whatever --samples is (up to
// 10¹² paths, 2.4·10⁸ blocks).
constexpr std::uint64_t kBlocksPerWave = 256;

// Index of the annulus [r_k / √q, r_k √q] holding r, or −1.
int annulus(Float r, Float log_r0, Float inv_log_q) {
  if (!(r > 0)) return -1;
  const Float k = std::floor((std::log(r) - log_r0) * inv_log_q + Float(0.5));
  return k >= 0 && k < kSlabProfilePoints ? int(k) : -1;
}

}  // namespace

SlabResult slab_random_walk(const Subsurface& s, std::uint64_t samples, std::uint64_t seed, int threads) {
  SlabWalkOptions o;
  o.threads = threads;
  return slab_random_walk(s, samples, seed, o);
}

SlabResult slab_random_walk(const Subsurface& s, std::uint64_t samples, std::uint64_t seed,
                            const SlabWalkOptions& options) {
  samples = std::max<std::uint64_t>(samples, 1);
  SlabResult result;
  const std::vector<Float> radii = slab_profile_radii(s.medium);
  const Float log_r0 = std::log(radii[0]);
  const Float log_q = std::log(radii[1] / radii[0]);
  const Float inv_log_q = 1 / log_q;

  const DipoleEscape tail(s.medium, s.eta);  // for the paths stopped at kMaxWalkSteps
  const std::uint64_t blocks = (samples + kSlabBlock - 1) / kSlabBlock;
  auto run_block = [&](std::uint64_t b, BlockSums& bs) {
    bs = BlockSums{};
    Pcg32 rng(seed, b);
    WalkStats stats;
    const std::uint64_t begin = b * kSlabBlock, end = std::min(samples, begin + kSlabBlock);
    for (std::uint64_t i = begin; i < end; ++i) {
      Float r = -1;
      const Color c = detail::trace_slab_path(s.boundary, s.medium, rng, r, stats, kMaxWalkSteps, &tail);
      for (int k = 0; k < kChannels; ++k) {
        bs.sum[size_t(k)] += c[k];
        bs.sum2[size_t(k)] += double(c[k]) * c[k];
      }
      const int a = annulus(r, log_r0, inv_log_q);
      if (a >= 0)
        for (int k = 0; k < kChannels; ++k) bs.bins[size_t(a)][size_t(k)] += c[k];
    }
    bs.steps = stats.steps;
  };

  unsigned n_threads = options.threads > 0 ? unsigned(options.threads) : std::max(1u, std::thread::hardware_concurrency());
  n_threads = unsigned(std::min<std::uint64_t>(n_threads, std::min(blocks, kBlocksPerWave)));
  // Summed in block order: the same doubles whatever the thread count.
  std::array<double, kChannels> sum{}, sum2{};
  std::array<std::array<double, kChannels>, kSlabProfilePoints> bins{};
  std::uint64_t steps = 0;
  std::vector<BlockSums> wave(size_t(std::min(blocks, kBlocksPerWave)));
  for (std::uint64_t first = 0; first < blocks; first += kBlocksPerWave) {
    const std::uint64_t count = std::min(kBlocksPerWave, blocks - first);
    if (n_threads <= 1) {
      for (std::uint64_t i = 0; i < count; ++i) run_block(first + i, wave[size_t(i)]);
    } else {
      std::vector<std::thread> pool;
      for (unsigned t = 0; t < n_threads; ++t)
        pool.emplace_back([&, t] {
          for (std::uint64_t i = t; i < count; i += n_threads) run_block(first + i, wave[size_t(i)]);
        });
      for (auto& th : pool) th.join();
    }
    for (std::uint64_t i = 0; i < count; ++i) {
      const BlockSums& bs = wave[size_t(i)];
      for (int k = 0; k < kChannels; ++k) {
        sum[size_t(k)] += bs.sum[size_t(k)];
        sum2[size_t(k)] += bs.sum2[size_t(k)];
      }
      for (int a = 0; a < kSlabProfilePoints; ++a)
        for (int k = 0; k < kChannels; ++k) bins[size_t(a)][size_t(k)] += bs.bins[size_t(a)][size_t(k)];
      steps += bs.steps;
    }
  }
  if (options.steps) *options.steps = steps;

  const double n = double(samples);
  for (int k = 0; k < kChannels; ++k) {
    const double mean = sum[size_t(k)] / n;
    const double var = std::max(0.0, sum2[size_t(k)] / n - mean * mean);
    result.Rd[k] = Float(mean);
    result.stderr_[k] = Float(samples > 1 ? std::sqrt(var / (n - 1)) : 0.0);
  }
  // Annulus k spans [r_k / √q, r_k √q]: area π r_k² (q − 1/q).
  const double q = std::exp(double(log_q));
  result.profile.resize(kSlabProfilePoints);
  for (int a = 0; a < kSlabProfilePoints; ++a) {
    const double r = radii[size_t(a)];
    const double area = kPiD * r * r * (q - 1 / q);
    result.profile[size_t(a)].r = Float(r);
    for (int k = 0; k < kChannels; ++k)
      result.profile[size_t(a)].value[k] = Float(bins[size_t(a)][size_t(k)] / (n * area));
  }
  return result;
}

}  // namespace gonio
