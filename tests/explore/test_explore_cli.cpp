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

#include <chrono>
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

}  // namespace
