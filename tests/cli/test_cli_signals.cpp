// SIGINT and SIGTERM always end gonio and leave no file behind (issue 39): a render whose
// scene is a FIFO without a writer waits in open(), where a handler that only set a flag
// left it deaf to Ctrl-C and SIGTERM, with a 0-byte temporary beside the output. Now the
// first signal ends it while nothing polls the flag (a second one ends a running render
// at once: apps/gonio/cli_signals.h).

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;

// gonio started in the background, stderr to a file, so that a test can signal it.
class BackgroundGonio {
 public:
  BackgroundGonio(const std::vector<std::string>& args, const std::string& err_path) {
    std::vector<std::string> argv_s{GONIO_BINARY};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC);
    if (err < 0 || null < 0) throw std::runtime_error("cannot open the child's files");
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::dup2(null, 0);
      ::dup2(null, 1);
      ::dup2(err, 2);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(err);
    ::close(null);
  }
  ~BackgroundGonio() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  BackgroundGonio(const BackgroundGonio&) = delete;
  BackgroundGonio& operator=(const BackgroundGonio&) = delete;

  void signal(int sig) const { ::kill(pid_, sig); }
  // The exit status (128 + signal if killed), or -1 if still running after `seconds`.
  int wait(double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliSignals, RenderWaitingOnAFifoSceneEndsAtTheFirstSignal) {
  for (const int sig : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(sig == SIGTERM ? "SIGTERM" : "SIGINT");
    const ScratchDir dir;
    const std::string fifo = dir.path("scene.json"), err = dir.path("stderr.txt");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    BackgroundGonio gonio({"render", fifo, "-o", dir.path("out.png")}, err);
    // The output's temporary exists once the handler is installed: gonio then waits in
    // open() (a fixed sleep could signal a slow start, under a sanitizer, too early).
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    const auto has_temporary = [&] {
      for (const std::string& n : dir.names())
        if (n.size() > 5 && n.compare(n.size() - 5, 5, ".part") == 0) return true;
      return false;
    };
    while (!has_temporary() && std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_TRUE(has_temporary()) << slurp(err);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // into open()
    gonio.signal(sig);
    EXPECT_EQ(gonio.wait(2.0), 128 + sig) << slurp(err);
    const auto lines = split_lines(slurp(err));
    ASSERT_EQ(lines.size(), 1u) << slurp(err);
    EXPECT_NE(lines[0].find("stopped by"), std::string::npos) << lines[0];
    EXPECT_EQ(dir.names(), (std::vector<std::string>{"scene.json", "stderr.txt"})) << "a file was left behind";
  }
}

}  // namespace
}  // namespace gonio_cli_test
