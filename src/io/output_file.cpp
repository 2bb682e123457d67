#include "gonio/io/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <random>
#include <system_error>

#include "gonio/error.h"

namespace gonio {

namespace {

[[noreturn]] void fail_output(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

std::string errno_text(int e) { return std::generic_category().message(e); }

// Letters and digits for temporary names, from a generator seeded once per process
// from the system's entropy and the process id.
std::string random_suffix() {
  static std::mutex mutex;
  static std::mt19937_64 engine(std::random_device{}() ^ (std::uint64_t(::getpid()) << 32));
  const char digits[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::lock_guard lock(mutex);
  std::string s(6, 'x');
  for (char& c : s) c = digits[engine() % 62];
  return s;
}

// The file a write to `path` replaces: through a symbolic link, the file it points to.
std::string resolved_target(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_symlink(path, ec)) {
    const fs::path real = fs::canonical(path, ec);
    if (!ec) return real.string();
  }
  return path;
}

void check_resolved_target(const std::string& path, const std::string& target, const std::string& what) {
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) fail_output(path, "cannot write " + what + ": it is a directory");
    if (!S_ISREG(st.st_mode)) fail_output(path, "cannot write " + what + ": it exists and is not a regular file");
    if (::access(target.c_str(), W_OK) != 0) fail_output(path, "cannot write " + what + ": the file is read-only");
  }
  if (std::filesystem::path(target).filename().empty())
    fail_output(path, "cannot write " + what + ": it is a directory");
}

}  // namespace

void check_output_target(const std::string& path, const std::string& what) {
  if (path.empty()) fail_output(path, "empty output path");
  check_resolved_target(path, resolved_target(path), what);
}

OutputFile::OutputFile(const std::string& path, std::string what) : path_(path), what_(std::move(what)) {
  namespace fs = std::filesystem;
  if (path.empty()) fail_output(path, "empty output path");
  const std::string target = resolved_target(path);
  check_resolved_target(path, target, what_);
  const std::string dir = fs::path(target).parent_path().string();
  const std::string shown_dir = dir.empty() ? "." : dir;
  struct stat ds {};
  if (::stat(shown_dir.c_str(), &ds) != 0)
    fail_output(path, "cannot open for writing: " + errno_text(errno) + " (directory " + shown_dir + ")");
  if (!S_ISDIR(ds.st_mode)) fail_output(path, "cannot open for writing: " + shown_dir + " is not a directory");
  // O_EXCL: a name another process holds is never opened twice; try another.
  for (int attempt = 0;; ++attempt) {
    temp_ = target + "." + random_suffix() + ".part";
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0) break;
    const int e = errno;
    temp_.clear();
    if (e == EEXIST && attempt < 100) continue;
    fail_output(path, "cannot open for writing: " + errno_text(e) + " (directory " + shown_dir + ")");
  }
  target_ = target;
}

OutputFile::~OutputFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void OutputFile::reserve(std::uint64_t bytes) {
  if (fd_ < 0) return;
  const int e = ::posix_fallocate(fd_, 0, off_t(bytes));
  // A file system that cannot reserve space (EOPNOTSUPP, EINVAL) leaves the check to the
  // write itself, which reports a full disk as well, only later.
  if (e == 0 || e == EOPNOTSUPP || e == EINVAL) return;
  char size[32];
  std::snprintf(size, sizeof size, "%.1f MB", double(bytes) / 1e6);
  fail_output(path_, "no room for " + what_ + " (up to " + size + "): " + errno_text(e));
}

// stdio buffers, so a full disk may show only at fflush: it, the length (a reservation
// may have made the file longer), fsync and fclose are all checked before the file takes
// its real name.
void OutputFile::commit(const std::function<std::uint64_t(std::FILE*)>& encode) {
  if (fd_ < 0) fail_output(path_, what_ + " was already written");
  std::FILE* f = ::fdopen(fd_, "wb");
  if (!f) fail_output(path_, "cannot write: " + errno_text(errno));
  fd_ = -1;  // f owns it now
  std::uint64_t length = 0;
  try {
    length = encode(f);
  } catch (...) {
    std::fclose(f);
    throw;
  }
  int error = 0;
  if (std::fflush(f) != 0 || std::ferror(f)) error = errno ? errno : EIO;
  if (error == 0 && ::ftruncate(::fileno(f), off_t(length)) != 0) error = errno;
  if (error == 0 && ::fsync(::fileno(f)) != 0 && errno != EINVAL) error = errno;
  errno = 0;
  const int closed = std::fclose(f);
  if (closed != 0 && error == 0) error = errno ? errno : EIO;
  if (error != 0) fail_output(path_, "write failed: " + errno_text(error));
  // Again just before the rename: a render takes hours, and the target may have changed.
  check_resolved_target(path_, target_, what_);
  if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail_output(path_, "cannot write: " + errno_text(errno));
  committed_ = true;
}

void OutputFile::commit(std::string_view bytes) {
  commit([&](std::FILE* f) -> std::uint64_t {
    errno = 0;
    if (std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size())
      fail_output(path_, "write failed: " + errno_text(errno ? errno : EIO));
    return bytes.size();
  });
}

void write_file_whole(const std::string& path, std::string_view bytes, const std::string& what) {
  OutputFile(path, what).commit(bytes);
}

}  // namespace gonio
