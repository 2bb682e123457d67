#pragma once
// Deterministic parallel loop over blocks (private to gonio_measure): blocks run in
// batches of a fixed size on oneTBB; each writes its own result, and the results are
// merged on the calling thread in block order. The batch size does not depend on the
// thread count, so neither does any sum.

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace gonio::measure::detail {

inline constexpr std::uint64_t kBatchBlocks = 64;

// `work(block, result)` fills result (reset by the caller's `reset`); `merge(block, result)`
// runs in block order.
template <typename Result, typename Reset, typename Work, typename Merge>
void run_blocks(std::uint64_t blocks, int threads, const std::function<void(double)>& progress, Reset reset,
                Work work, Merge merge) {
  const std::size_t parallelism =
      threads > 0 ? std::size_t(threads) : std::max<std::size_t>(1, std::thread::hardware_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, parallelism);
  std::vector<Result> results(std::size_t(std::min<std::uint64_t>(blocks, kBatchBlocks)));
  for (std::uint64_t first = 0; first < blocks; first += kBatchBlocks) {
    const std::uint64_t count = std::min<std::uint64_t>(kBatchBlocks, blocks - first);
    tbb::parallel_for(std::uint64_t(0), count, [&](std::uint64_t b) {
      reset(results[b]);
      work(first + b, results[b]);
    });
    for (std::uint64_t b = 0; b < count; ++b) merge(first + b, results[b]);
    if (progress) progress(double(first + count) / double(blocks));
  }
}

}  // namespace gonio::measure::detail
