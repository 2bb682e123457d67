#pragma once
// Threads for the Python module's batch calls, on plain std::thread (the core has no
// threading library, and oneTBB belongs to the renderer). [0, n) is cut into pieces that
// the threads take in turn from a shared counter, the calling thread among them: on a
// machine whose cores are shared (a VM's, or one busy with other work) a thread that gets
// less of its core takes fewer pieces instead of holding up the whole call with a fixed
// half of it. Each element is independent of the others, so the result does not depend
// on the thread count or on which thread took a piece. The first exception a piece throws
// is rethrown here, after every thread has finished, and no further pieces are started.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gonio::python {

// Below this many elements per thread a thread costs more than it saves (starting one
// takes ~20 µs; a Lambert evaluation ~2 ns).
inline constexpr std::size_t kMinPerThread = 1 << 14;

// `threads` 0: every hardware thread.
inline int thread_count(int threads) {
  return threads > 0 ? threads : std::max(1, int(std::thread::hardware_concurrency()));
}

// Pieces per thread: enough that a thread slowed to half speed costs the call about a
// sixteenth of its time, few enough that taking one (an atomic increment) costs nothing.
inline constexpr std::size_t kPiecesPerThread = 16;

// fn(begin, end) over ranges covering [0, n); `grain` elements at least per thread and
// per piece.
template <typename F>
void parallel_ranges(std::size_t n, int threads, F&& fn, std::size_t grain = kMinPerThread) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t t = std::clamp<std::size_t>(n / grain, 1, std::size_t(thread_count(threads)));
  if (t == 1) {
    fn(std::size_t(0), n);
    return;
  }
  const std::size_t piece = std::max(grain, (n + t * kPiecesPerThread - 1) / (t * kPiecesPerThread));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex m;
  auto work = [&] {
    try {
      while (!failed.load(std::memory_order_relaxed)) {
        const std::size_t begin = next.fetch_add(piece, std::memory_order_relaxed);
        if (begin >= n) break;
        fn(begin, std::min(n, begin + piece));
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(m);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  std::vector<std::thread> pool;
  try {
    pool.reserve(t - 1);
    for (std::size_t k = 1; k < t; ++k) pool.emplace_back(work);
  } catch (const std::exception&) {
    // The system gave fewer threads than asked (std::system_error, or no memory for the
    // vector): the ones started and this one take every piece between them.
  }
  work();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace gonio::python
