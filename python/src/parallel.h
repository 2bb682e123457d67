#pragma once
// Threads for the Python module's batch calls: [0, n) cut into one contiguous range per
// thread, on plain std::thread (the core has no threading library, and oneTBB belongs to
// the renderer). Each element is independent of the others, so the result does not
// depend on the thread count. The first exception a range throws is rethrown here, after
// every thread has finished.

#include <algorithm>
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

// fn(begin, end) over ranges covering [0, n); `grain` elements at least per thread.
template <typename F>
void parallel_ranges(std::size_t n, int threads, F&& fn, std::size_t grain = kMinPerThread) {
  const std::size_t t = std::clamp<std::size_t>(n / std::max<std::size_t>(grain, 1), 1, std::size_t(thread_count(threads)));
  if (t == 1) {
    fn(std::size_t(0), n);
    return;
  }
  std::exception_ptr error;
  std::mutex m;
  std::vector<std::thread> pool;
  pool.reserve(t);
  for (std::size_t k = 0; k < t; ++k) {
    pool.emplace_back([&, k] {
      try {
        fn(n * k / t, n * (k + 1) / t);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(m);
        if (!error) error = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace gonio::python
