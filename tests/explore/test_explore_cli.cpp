// `gonio explore` as a user starts it (SPEC §3): the URL as the first line of stdout, at
// once; SIGINT and SIGTERM stop it with status 0; bad options are one line on stderr and
// status 2.

#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>

#include "../cli/run_gonio.h"

extern char** environ;

namespace {

using gonio_cli_test::run_gonio;

// gonio explore ARGS running in the background, its stdout and stderr on pipes.
class RunningExplore {
 public:
  explicit RunningExplore(const std::vector<std::string>& args) {
    int out[2], err[2];
    if (::pipe(out) != 0 || ::pipe(err) != 0) throw std::runtime_error("pipe");
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    posix_spawn_file_actions_addclose(&fa, out[0]);
    posix_spawn_file_actions_addclose(&fa, err[0]);
    std::vector<std::string> all = {GONIO_BINARY, "explore"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, GONIO_BINARY, &fa, nullptr, argv.data(), environ) != 0) throw std::runtime_error("spawn");
    posix_spawn_file_actions_destroy(&fa);
    ::close(out[1]);
    ::close(err[1]);
    out_ = out[0];
    err_ = err[0];
  }
  ~RunningExplore() {
    if (pid_ > 0 && status_ < 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    ::close(out_);
    ::close(err_);
  }

  // The first line on stdout, waiting at most `timeout_ms` (empty if none came).
  std::string first_line(int timeout_ms = 10000) {
    std::string line;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (line.find('\n') == std::string::npos) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      if (left.count() <= 0) return "";
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, int(left.count())) <= 0) return "";
      char c[256];
      const ssize_t n = ::read(out_, c, sizeof c);
      if (n <= 0) return "";
      line.append(c, size_t(n));
    }
    return line.substr(0, line.find('\n'));
  }

  // Sends `sig` and waits (at most 10 s) for the exit status; -1 if it did not end.
  int stop_with(int sig) {
    ::kill(pid_, sig);
    for (int i = 0; i < 1000; ++i) {
      int st = 0;
      if (::waitpid(pid_, &st, WNOHANG) == pid_) {
        status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        return status_;
      }
      ::usleep(10000);
    }
    return -1;
  }

  std::string stderr_text() {
    std::string s;
    char c[256];
    ::fcntl(err_, F_SETFL, O_NONBLOCK);
    for (ssize_t n; (n = ::read(err_, c, sizeof c)) > 0;) s.append(c, size_t(n));
    return s;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1, err_ = -1;
  int status_ = -1;
};

TEST(ExploreCli, PrintsTheUrlServesAndStopsOnSigintAndSigterm) {
  for (const int sig : {SIGINT, SIGTERM}) {
    RunningExplore g({"--port", "0"});
    const std::string url = g.first_line();
    std::smatch m;
    ASSERT_TRUE(std::regex_match(url, m, std::regex(R"(http://127\.0\.0\.1:(\d+)/)"))) << "'" << url << "'";
    httplib::Client c("127.0.0.1", std::stoi(m[1].str()));
    const auto page = c.Get("/");
    ASSERT_TRUE(page);
    EXPECT_EQ(page->status, 200);
    EXPECT_NE(page->body.find("gonio explore"), std::string::npos);
    EXPECT_EQ(g.stop_with(sig), 0) << "signal " << sig;
    EXPECT_EQ(g.stderr_text(), "");
  }
}

TEST(ExploreCli, BadOptionsAreOneLineAndStatus2) {
  const auto expect_error = [](const std::vector<std::string>& args, const std::string& needle) {
    std::vector<std::string> all = {"explore"};
    all.insert(all.end(), args.begin(), args.end());
    const auto r = run_gonio(all);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  };
  expect_error({"--data", "/nonexistent/gonio"}, "--data /nonexistent/gonio: no such directory");
  expect_error({"--data", GONIO_SOURCE_DIR "/CMakeLists.txt"}, "not a directory");
  expect_error({"--port", "70000"}, "--port");
  expect_error({"--port", "-1"}, "--port");
  // 192.0.2.1 (TEST-NET-1) is no address of this machine: binding to it fails at once.
  expect_error({"--host", "192.0.2.1", "--port", "0"}, "--host 192.0.2.1");

  // A port another socket listens on.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(::listen(fd, 1), 0);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  const std::string port = std::to_string(ntohs(a.sin_port));
  expect_error({"--port", port}, "already in use");
  ::close(fd);
}

// Issue 56: the first SIGINT ends the server within seconds however much work it holds
// (five validations of a layered material, half a minute each, one running and four
// queued): the work at hand is told to stop, and what cannot is left behind.
TEST(ExploreCli, FirstSigintEndsItDuringHeavyWork) {
  RunningExplore g({"--port", "0"});
  std::smatch m;
  const std::string url = g.first_line();
  ASSERT_TRUE(std::regex_match(url, m, std::regex(R"(http://127\.0\.0\.1:(\d+)/)"))) << url;
  const int port = std::stoi(m[1].str());
  const std::string body =
      R"({"bsdf":{"type":"layered","top":{"type":"roughdielectric","alpha":0.1},"bottom":{"type":"diffuse"}}})";
  const std::string request = "POST /api/check HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                              "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  std::vector<int> sockets;
  for (int i = 0; i < 5; ++i) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    (void)::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    sockets.push_back(fd);
  }
  ::usleep(300000);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(g.stop_with(SIGINT), 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3.0);
  for (const int fd : sockets) ::close(fd);
}

// Whether `s` is valid UTF-8 (RFC 3629 §4), written out here.
bool is_utf8(const std::string& s) {
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const size_t n = c < 0x80 ? 1 : (c >= 0xC2 && c <= 0xDF) ? 2 : (c >= 0xE0 && c <= 0xEF) ? 3 : (c >= 0xF0 && c <= 0xF4) ? 4 : 0;
    if (n == 0 || i + n > s.size()) return false;
    if (n > 1) {
      const auto b = static_cast<unsigned char>(s[i + 1]);
      const unsigned char lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80, hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
      if (b < lo || b > hi) return false;
    }
    for (size_t k = 2; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    i += n;
  }
  return true;
}

// The CLI shares the explorer's messages: a parse error that quotes part of a two-byte
// character prints it escaped, one valid UTF-8 line, status 2.
TEST(ExploreCli, CliMessagesQuotingInvalidUtf8AreEscaped) {
  const auto r = run_gonio({"eval", "--bsdf", "\xc3\xbf"}, "0 0 1 0 0 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(is_utf8(r.err)) << r.err;
  EXPECT_NE(r.err.find("\\xc3"), std::string::npos) << r.err;
}

// gonio albedo and gonio check refuse a layered material whose walks (max_depth 10000 ×
// samples 64, in range) would take hours at the asked sample count: one line, status 2,
// at once. The default walk is computed.
TEST(ExploreCli, CliRefusesLayeredWorkBeyondTheBound) {
  const std::string heavy =
      R"({"type":"layered","top":{"type":"roughdielectric","alpha":0.1},"bottom":{"type":"diffuse"},)"
      R"("albedo":1,"thickness":10000,"max_depth":10000,"samples":64})";
  for (const std::vector<std::string>& args : {std::vector<std::string>{"albedo", "--bsdf", heavy, "--theta", "30"},
                                               std::vector<std::string>{"check", "--bsdf", heavy}}) {
    const auto start = std::chrono::steady_clock::now();
    const auto r = run_gonio(args);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0) << args[0];
    EXPECT_EQ(r.status, 2) << args[0];
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("walk steps"), std::string::npos) << r.err;
  }
  // Fewer samples of the same material are within the bound.
  const auto ok = run_gonio({"albedo", "--bsdf", heavy, "--theta", "30", "--samples", "16"});
  EXPECT_EQ(ok.status, 0) << ok.err;
}

}  // namespace
