#pragma once
// Test helper for the command-line tool: runs the built `gonio` binary (GONIO_BINARY) with
// an argv vector — no shell, so JSON arguments with quotes and spaces pass verbatim —
// feeds it stdin from a temporary file, and captures stdout, stderr and the exit status
// separately. Plus small helpers to parse the JSON-lines output and to check the SPEC §3
// error contract (exit 2, one line on stderr, nothing on stdout).

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace gonio_cli_test {

using nlohmann::json;

struct RunResult {
  int status = -1;      // exit status; 128 + signal number if killed by a signal
  std::string out;      // everything written to stdout
  std::string err;      // everything written to stderr
};

// A temporary file removed when the object goes out of scope.
class TempFile {
 public:
  explicit TempFile(const std::string& contents, const char* stem = "gonio_cli_test") {
    std::string tmpl = (std::filesystem::temp_directory_path() / (std::string(stem) + "_XXXXXX")).string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    const int fd = ::mkstemp(buf.data());
    if (fd < 0) throw std::runtime_error("mkstemp failed");
    path_ = buf.data();
    size_t done = 0;
    while (done < contents.size()) {
      const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
      if (n < 0) {
        if (errno == EINTR) continue;
        ::close(fd);
        throw std::runtime_error("write to temp file failed");
      }
      done += size_t(n);
    }
    ::close(fd);
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Resource limits set in the child before it runs gonio (0: unlimited). A file-size
// limit makes a write past it fail with EFBIG (gonio ignores SIGXFSZ itself; the child
// keeps the default action, so that a gonio that did not would be killed and the test
// fail), which tests a failed write without touching a device; an address-space limit
// makes an allocation past it fail (std::bad_alloc).
// AddressSanitizer reserves terabytes of address space for its shadow: under it (the
// sanitizer build's tests) an address-space limit is not applied.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kCanLimitAddressSpace = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kCanLimitAddressSpace = false;
#else
inline constexpr bool kCanLimitAddressSpace = true;
#endif
#else
inline constexpr bool kCanLimitAddressSpace = true;
#endif

struct ChildLimits {
  rlim_t file_bytes = 0;
  rlim_t address_space_bytes = 0;
};

// Runs GONIO_BINARY with `args` (argv[1..]) and `stdin_text` on its standard input.
// A watchdog kills the child after `timeout_s` seconds (status then 128 + SIGKILL).
// With `stdout_path`, the child's stdout is that file (e.g. /dev/full) and r.out stays empty.
inline RunResult run_gonio(const std::vector<std::string>& args, const std::string& stdin_text = "",
                           int timeout_s = 30, const char* stdout_path = nullptr, ChildLimits limits = {}) {
  RunResult r;
  TempFile in(stdin_text, "gonio_cli_stdin");
  const int in_fd = ::open(in.path().c_str(), O_RDONLY | O_CLOEXEC);
  if (in_fd < 0) throw std::runtime_error("cannot reopen stdin temp file");
  const int file_out_fd = stdout_path ? ::open(stdout_path, O_WRONLY | O_CLOEXEC) : -1;
  if (stdout_path && file_out_fd < 0) throw std::runtime_error(std::string("cannot open ") + stdout_path);

  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe failed");

  std::vector<std::string> argv_s;
  argv_s.push_back(GONIO_BINARY);
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);

  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    // Child: only async-signal-safe calls from here on.
    ::dup2(in_fd, 0);
    ::dup2(file_out_fd >= 0 ? file_out_fd : out_pipe[1], 1);
    ::dup2(err_pipe[1], 2);
    if (limits.file_bytes != 0) {
      ::signal(SIGXFSZ, SIG_DFL);
      const rlimit fsize{limits.file_bytes, limits.file_bytes};
      ::setrlimit(RLIMIT_FSIZE, &fsize);
    }
    if (limits.address_space_bytes != 0 && kCanLimitAddressSpace) {
      const rlimit as{limits.address_space_bytes, limits.address_space_bytes};
      ::setrlimit(RLIMIT_AS, &as);
    }
    ::execv(argv[0], argv.data());
    const char msg[] = "run_gonio: execv failed\n";
    (void)!::write(2, msg, sizeof msg - 1);
    ::_exit(127);
  }
  ::close(in_fd);
  if (file_out_fd >= 0) ::close(file_out_fd);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);

  // Read both pipes until EOF, without letting either fill up and block the child.
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&r.out, &r.err};
  int open_count = 2;
  bool killed = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  char buf[65536];
  while (open_count > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0 && !killed) {
      ::kill(pid, SIGKILL);
      killed = true;
    }
    const int n = ::poll(fds, 2, left > 0 ? int(std::min<long long>(left, 1000)) : 100);
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t got = ::read(fds[i].fd, buf, sizeof buf);
      if (got > 0) {
        sinks[i]->append(buf, size_t(got));
      } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
  for (auto& f : fds)
    if (f.fd >= 0) ::close(f.fd);

  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(wstatus)) r.status = WEXITSTATUS(wstatus);
  else if (WIFSIGNALED(wstatus)) r.status = 128 + WTERMSIG(wstatus);
  return r;
}

// As run_gonio, with the child's stdout written to `stdout_path` (e.g. /dev/full).
inline RunResult run_gonio_stdout_to(const std::string& stdout_path, const std::vector<std::string>& args,
                                     const std::string& stdin_text = "", int timeout_s = 30) {
  return run_gonio(args, stdin_text, timeout_s, stdout_path.c_str());
}

// As run_gonio, with resource limits in the child.
inline RunResult run_gonio_limited(const std::vector<std::string>& args, ChildLimits limits, int timeout_s = 30) {
  return run_gonio(args, "", timeout_s, nullptr, limits);
}

inline std::string describe(const RunResult& r) {
  return "exit status " + std::to_string(r.status) + "\n--- stdout ---\n" + r.out +
         "--- stderr ---\n" + r.err;
}

// The subcommands the tool knows, from its own error for an unknown one.
inline std::vector<std::string> gonio_subcommands() {
  const RunResult r = run_gonio({"no-such-subcommand"});
  const auto open = r.err.find("(known: "), close = r.err.rfind(')');
  EXPECT_NE(open, std::string::npos) << r.err;
  std::vector<std::string> names;
  if (open == std::string::npos) return names;
  std::stringstream list(r.err.substr(open + 8, close - open - 8));
  std::string name;
  while (std::getline(list, name, ',')) names.push_back(name.substr(name.find_first_not_of(' ')));
  return names;
}

inline std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> lines;
  std::string cur;
  for (char c : s) {
    if (c == '\n') {
      lines.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) lines.push_back(cur);
  return lines;
}

inline bool contains_ci(std::string hay, std::string needle) {
  for (auto& c : hay) c = char(std::tolower(static_cast<unsigned char>(c)));
  for (auto& c : needle) c = char(std::tolower(static_cast<unsigned char>(c)));
  return hay.find(needle) != std::string::npos;
}

// True when no JSON number in `v` (recursively) is NaN or infinite.
inline bool all_finite(const json& v) {
  if (v.is_number()) return std::isfinite(v.get<double>());
  if (v.is_array() || v.is_object()) {
    for (const auto& e : v) if (!all_finite(e)) return false;
  }
  return true;
}

// Parses stdout as JSON lines; every line must be one JSON object, and the raw text must
// not hold "nan"/"inf" anywhere. Adds a test failure (and skips the line) otherwise.
inline std::vector<json> parse_json_lines(const RunResult& r) {
  std::vector<json> objs;
  if (!r.out.empty()) {
    EXPECT_EQ(r.out.back(), '\n') << "stdout does not end with a newline\n" << describe(r);
  }
  EXPECT_FALSE(contains_ci(r.out, "nan")) << describe(r);
  EXPECT_FALSE(contains_ci(r.out, "inf")) << describe(r);
  for (const auto& line : split_lines(r.out)) {
    json j;
    try {
      j = json::parse(line);
    } catch (const json::exception& e) {
      ADD_FAILURE() << "stdout line is not JSON: '" << line << "': " << e.what();
      continue;
    }
    EXPECT_TRUE(j.is_object()) << "stdout line is not a JSON object: " << line;
    EXPECT_TRUE(all_finite(j)) << "non-finite number in: " << line;
    objs.push_back(std::move(j));
  }
  return objs;
}

// Runs and expects success with exactly one JSON object on stdout.
inline json run_one(const std::vector<std::string>& args, const std::string& stdin_text = "") {
  const RunResult r = run_gonio(args, stdin_text);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "") << describe(r);
  const auto objs = parse_json_lines(r);
  EXPECT_EQ(objs.size(), 1u) << describe(r);
  return objs.empty() ? json::object() : objs.front();
}

// Runs and expects success with one JSON object per input line.
inline std::vector<json> run_lines(const std::vector<std::string>& args, const std::string& stdin_text,
                                   size_t expected_lines) {
  const RunResult r = run_gonio(args, stdin_text);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "") << describe(r);
  auto objs = parse_json_lines(r);
  EXPECT_EQ(objs.size(), expected_lines) << describe(r);
  return objs;
}

// SPEC §3 error contract for bad input: exit status 2, nothing on stdout, exactly one
// (non-empty, newline-terminated) line on stderr, which mentions every string in
// `mentions` (case-insensitive).
inline void expect_bad_input(const RunResult& r, std::initializer_list<std::string> mentions = {}) {
  EXPECT_EQ(r.status, 2) << describe(r);
  EXPECT_EQ(r.out, "") << "partial output on stdout\n" << describe(r);
  const auto lines = split_lines(r.err);
  EXPECT_EQ(lines.size(), 1u) << "stderr must be exactly one line\n" << describe(r);
  if (!r.err.empty()) {
    EXPECT_EQ(r.err.back(), '\n') << describe(r);
  }
  EXPECT_FALSE(lines.empty() || lines.front().empty()) << "empty error message\n" << describe(r);
  for (const auto& m : mentions)
    EXPECT_TRUE(contains_ci(r.err, m)) << "stderr should mention '" << m << "'\n" << describe(r);
}

// Colour value [r, g, b] as three doubles, with format checks.
inline std::array<double, 3> color3(const json& v) {
  std::array<double, 3> c{NAN, NAN, NAN};
  EXPECT_TRUE(v.is_array() && v.size() == 3) << v.dump();
  if (!(v.is_array() && v.size() == 3)) return c;
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(v[i].is_number()) << v.dump();
    if (v[i].is_number()) c[i] = v[i].get<double>();
  }
  return c;
}

inline double num(const json& obj, const char* key) {
  EXPECT_TRUE(obj.contains(key)) << "missing key '" << key << "' in " << obj.dump();
  if (!obj.contains(key)) return NAN;
  EXPECT_TRUE(obj.at(key).is_number()) << "'" << key << "' is not a number in " << obj.dump();
  return obj.at(key).is_number() ? obj.at(key).get<double>() : NAN;
}

// %.17g, so angles and indices reach the tool with full double precision.
inline std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

constexpr double kPi = 3.14159265358979323846;
inline double deg(double d) { return d * kPi / 180; }

// A fresh directory under the temporary directory, removed with what it holds.
class ScratchDir {
 public:
  ScratchDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "gonio_cli_XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    dir_ = tmpl;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // The names in the directory, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> v;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }

 private:
  std::filesystem::path dir_;
};

}  // namespace gonio_cli_test
