#pragma once
// Data read from a file once per process while it is in use: measured tables (MERL,
// RGL) are megabytes, and a scene or a sweep names the same file many times. Keyed by
// the canonical path and the modification time, so a file rewritten in place is read
// again; the cache holds weak pointers, so a table no model uses is freed.

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>

namespace gonio {

// The T read from `path` by `read` (a callable returning std::shared_ptr<const T>), or the
// one read before while it lives. `read` runs outside the lock; two threads may both read
// a file the first time, and the later one's copy is kept.
template <typename T, typename Read>
std::shared_ptr<const T> cached_file(const std::string& path, Read&& read) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<const T>> cache;
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  std::string key = ec ? path : canonical.string();
  const auto mtime = std::filesystem::last_write_time(path, ec);
  if (!ec) {
    key.push_back('|');
    key.append(std::to_string(mtime.time_since_epoch().count()));
  }
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end())
      if (auto data = it->second.lock()) return data;
  }
  std::shared_ptr<const T> data = read();
  const std::lock_guard<std::mutex> lock(mutex);
  cache[key] = data;
  return data;
}

}  // namespace gonio
