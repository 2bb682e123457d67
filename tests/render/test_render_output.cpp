// Renders that survive: the output file of `gonio render` (a unique temporary, checked
// before rendering, renamed when complete) and its interruption by SIGINT / SIGTERM (the
// passes completed so far are written; exit 130 / 143).

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "../cli/run_gonio.h"
#include "gonio/render/image_output.h"
#include "gonio/rng.h"
#include "render_test_util.h"
#include "scratch_dir.h"

namespace gonio::render::test {
namespace {

namespace fs = std::filesystem;
using gonio::test::ScratchDir;

// A small scene that renders fast per sample; --spp makes it as long as needed.
const char* kScene = R"({
  "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "width": 32, "height": 24},
  "render": {"spp": 4},
  "shapes": [
    {"type": "quad", "corner": [-3, 0, -3], "edge1": [0, 0, 6], "edge2": [6, 0, 0], "material": {"type": "diffuse"}},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": {"type": "roughconductor", "material": "Au", "alpha": 0.2}}
  ],
  "lights": [{"type": "point", "position": [1, 3, 2], "intensity": 10},
             {"type": "quad", "corner": [-1, 2.5, -1], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 3}],
  "environment": {"radiance": 0.2}
})";

// A running `gonio` with stdout and stderr going to files, optionally under a file-size
// limit (with SIGXFSZ ignored, so that writes past it fail with EFBIG as on a full disk).
class Gonio {
 public:
  Gonio(const std::vector<std::string>& args, const std::string& dir, std::optional<rlim_t> fsize_limit = {})
      : out_(dir + "/.stdout"), err_(dir + "/.stderr") {
    std::vector<std::string> argv_s{GONIO_BINARY};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    // Opened before fork(): the child only calls async-signal-safe functions.
    const int out_fd = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    const int err_fd = ::open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out_fd < 0 || err_fd < 0) throw std::runtime_error("cannot open output capture files");
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::dup2(out_fd, 1);
      ::dup2(err_fd, 2);
      if (fsize_limit) {
        ::signal(SIGXFSZ, SIG_IGN);  // ignored dispositions survive exec
        const rlimit lim{*fsize_limit, *fsize_limit};
        ::setrlimit(RLIMIT_FSIZE, &lim);
      }
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(out_fd);
    ::close(err_fd);
  }
  ~Gonio() {
    if (pid_ > 0 && status_ < 0) {
      ::kill(pid_, SIGKILL);
      wait(1);
    }
    std::remove(out_.c_str());
    std::remove(err_.c_str());
  }

  void signal(int sig) const { ::kill(pid_, sig); }

  // Waits up to `timeout_s`, then kills it; returns the exit status (128 + the signal
  // when killed).
  int wait(int timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    int ws = 0;
    for (;;) {
      const pid_t r = ::waitpid(pid_, &ws, WNOHANG);
      if (r == pid_) break;
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &ws, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    status_ = WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + WTERMSIG(ws);
    return status_;
  }
  std::string out() const { return slurp(out_); }
  std::string err() const { return slurp(err_); }

 private:
  static std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  std::string out_, err_;
  pid_t pid_ = -1;
  int status_ = -1;
};

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Files in `dir` other than the test's own (scene, captures, those named in `keep`).
std::vector<std::string> leftovers(const std::string& dir, const std::vector<std::string>& keep) {
  std::vector<std::string> extra;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name == "s.json" || name == ".stdout" || name == ".stderr") continue;
    if (std::find(keep.begin(), keep.end(), name) != keep.end()) continue;
    extra.push_back(name);
  }
  return extra;
}

void expect_same_pixels(const Image& a, const Image& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(a.at(x, y)[c], b.at(x, y)[c]) << x << "," << y << " channel " << c;
}

// ---------------------------------------------------------------------------------------
// The output location is checked before rendering.

// A render that would take hours (2^20 spp): an output error must come at once.
TEST(RenderOutput, UnwritableOutputFailsBeforeRendering) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kScene);
  fs::create_directory(dir.path("adir.png"));
  std::vector<std::pair<std::string, std::string>> cases = {
      {dir.path("missing/x.png"), "missing"},    // a directory that does not exist
      {dir.path("adir.png"), "directory"},        // the output is a directory
      {dir.path("s.json/x.exr"), "not a directory"},  // a file where the directory should be
      {"/proc/gonio_render_test.png", "/proc"},  // no file can be created there, even by root
  };
  if (::geteuid() != 0) {  // permission bits do not stop root
    fs::create_directory(dir.path("ro"));
    fs::permissions(dir.path("ro"), fs::perms::owner_read | fs::perms::owner_exec);
    cases.push_back({dir.path("ro/x.png"), "Permission denied"});
  }
  for (const auto& [out, mention] : cases) {
    SCOPED_TRACE(out);
    Gonio g({"render", scene, "-o", out, "--spp", "1048576"}, dir.path(""));
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(g.wait(30), 2) << g.err();
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20);
    EXPECT_EQ(g.out(), "");
    const std::string err = g.err();
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(out), std::string::npos) << err;
    EXPECT_NE(err.find(mention), std::string::npos) << err;
  }
  EXPECT_EQ(leftovers(dir.path(""), {"adir.png", "ro"}), std::vector<std::string>{});
  EXPECT_TRUE(fs::is_directory(dir.path("adir.png")));
  if (fs::exists(dir.path("ro"))) fs::permissions(dir.path("ro"), fs::perms::owner_all);
}

// No room for the image (a file-size limit stands in for a full disk): found when the
// file is created, before rendering, by reserving the most the image can take.
TEST(RenderOutput, NoRoomFailsBeforeRendering) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kScene);
  for (const char* name : {"full.exr", "full.png"}) {
    SCOPED_TRACE(name);
    Gonio g({"render", scene, "-o", dir.path(name), "--spp", "1048576"}, dir.path(""), rlim_t(2048));
    EXPECT_EQ(g.wait(30), 2) << g.err();
    EXPECT_EQ(g.out(), "");
    const std::string err = g.err();
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(dir.path(name)), std::string::npos) << err;
    EXPECT_NE(err.find("no room"), std::string::npos) << err;
  }
  EXPECT_EQ(leftovers(dir.path(""), {}), std::vector<std::string>{});
}

// A write that fails part-way (here past a file-size limit, as on a full disk, without
// a reservation) is reported, and leaves neither the image nor its temporary behind.
TEST(RenderOutput, FailedWriteLeavesNoFile) {
  ScratchDir dir;
  Image noise(64, 64);  // incompressible: well over the limit in either format
  Pcg32 rng(3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) noise.at(x, y) = Color(rng.next_float(), rng.next_float(), rng.next_float());
  rlimit saved{};
  ::getrlimit(RLIMIT_FSIZE, &saved);
  auto* saved_handler = ::signal(SIGXFSZ, SIG_IGN);
  const rlimit lim{4096, saved.rlim_max};
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &lim), 0);
  std::string errors[3];
  for (int i = 0; i < 3; ++i) {
    try {
      if (i == 0) write_png(noise, dir.path("w.png"), {0, ToneMap::Clamp});
      if (i == 1) write_exr(noise, dir.path("w.exr"));
      if (i == 2) ImageOutput(dir.path("r.exr")).reserve(64, 64);
    } catch (const InputError& e) {
      errors[i] = e.what();
    }
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  ::signal(SIGXFSZ, saved_handler);
  EXPECT_NE(errors[0].find("File too large"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("File too large"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find("no room for the image"), std::string::npos) << errors[2];
  for (const auto& e : errors) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_EQ(leftovers(dir.path(""), {}), std::vector<std::string>{});
}

// ---------------------------------------------------------------------------------------
// Unique temporaries: two writers of one path never share a file.

TEST(RenderOutput, TwoWritersOfOnePathEachHaveTheirOwnFile) {
  ScratchDir dir;
  const std::string path = dir.path("same.exr");
  Image a(3, 2), b(3, 2);
  a.at(0, 0) = Color(1);
  b.at(0, 0) = Color(2);
  {
    ImageOutput first(path), second(path);
    EXPECT_NE(first.temporary_path(), second.temporary_path());
    EXPECT_TRUE(fs::exists(first.temporary_path()));
    EXPECT_TRUE(fs::exists(second.temporary_path()));
    first.reserve(3, 2);
    second.reserve(3, 2);
    second.write(b);
    EXPECT_EQ(read_image(path).at(0, 0), Color(2));
    first.write(a);  // the last to finish wins, whole
    EXPECT_EQ(read_image(path).at(0, 0), Color(1));
  }
  // A writer that never writes leaves nothing.
  { ImageOutput unused(dir.path("never.png")); }
  EXPECT_EQ(leftovers(dir.path(""), {"same.exr"}), std::vector<std::string>{});
}

// Through a symbolic link the image replaces the file the link names, and the link stays;
// an existing read-only file is not replaced.
TEST(RenderOutput, SymbolicLinkAndReadOnlyTargets) {
  ScratchDir dir;
  std::ofstream(dir.path("real.exr")) << "old";
  fs::create_symlink(dir.path("real.exr"), dir.path("link.exr"));
  Image img(2, 2);
  img.at(1, 1) = Color(5);
  write_exr(img, dir.path("link.exr"));
  EXPECT_TRUE(fs::is_symlink(dir.path("link.exr")));
  EXPECT_EQ(read_image(dir.path("real.exr")).at(1, 1), Color(5));
  if (::geteuid() != 0) {  // permission bits do not stop root
    std::ofstream(dir.path("ro.exr")) << "keep";
    fs::permissions(dir.path("ro.exr"), fs::perms::owner_read);
    try {
      ImageOutput out(dir.path("ro.exr"));
      ADD_FAILURE() << "a read-only file was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("read-only"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_bytes(dir.path("ro.exr")), "keep");
  }
  EXPECT_EQ(leftovers(dir.path(""), {"real.exr", "link.exr", "ro.exr"}), std::vector<std::string>{});
}

// Two renders to one output at the same time: both succeed, and the file is one of the
// two images, whole (byte for byte the file each writes alone).
TEST(RenderOutput, ConcurrentRendersToOneOutput) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kScene);
  const std::string out = dir.path("out.exr");
  ScratchDir capture_a, capture_b;
  {
    Gonio a({"render", scene, "-o", out, "--spp", "256", "--seed", "1", "--threads", "1"}, capture_a.path(""));
    Gonio b({"render", scene, "-o", out, "--spp", "256", "--seed", "2", "--threads", "1"}, capture_b.path(""));
    ASSERT_EQ(a.wait(120), 0) << a.err();
    ASSERT_EQ(b.wait(120), 0) << b.err();
  }
  const std::string got = read_bytes(out);
  for (const char* seed : {"1", "2"}) {
    const auto r = gonio_cli_test::run_gonio(
        {"render", scene, "-o", dir.path(std::string("seed") + seed + ".exr"), "--spp", "256", "--seed", seed}, "", 120);
    ASSERT_EQ(r.status, 0) << gonio_cli_test::describe(r);
  }
  const std::string one = read_bytes(dir.path("seed1.exr")), two = read_bytes(dir.path("seed2.exr"));
  ASSERT_NE(one, two);
  EXPECT_TRUE(got == one || got == two) << "the output is neither render's image";
  EXPECT_EQ(leftovers(dir.path(""), {"out.exr", "seed1.exr", "seed2.exr"}), std::vector<std::string>{});
}

// ---------------------------------------------------------------------------------------
// Stopping a render.

Scene small_scene(int width, int height, int spp) {
  Scene s = parse_scene(kScene, "test scene", "");
  s.camera.width = width;
  s.camera.height = height;
  s.settings.spp = spp;
  s.settings.seed = 9;
  return s;
}

// Stopped in the middle of a pass, the renderer returns the passes completed before it:
// every pixel with the same number of samples k, the image of the render's first k sample
// indices (its `--sample-range 0 k`). (Not a render of k spp: the zsobol sampler lays out
// its indices for the whole count, so a k-spp render takes other samples.)
TEST(RenderStop, StoppedRenderIsTheShorterRender) {
  const Scene scene = small_scene(64, 48, 110);  // 12 tiles, passes of 22 samples per pixel
  std::atomic<bool> stop{false};
  RenderOptions options;
  options.threads = 2;
  options.stop = &stop;
  options.progress = [&](double done) {
    if (done >= 0.5) stop = true;
  };
  RenderStats stats;
  const Image stopped = render(scene, options, &stats);
  EXPECT_TRUE(stats.stopped);
  ASSERT_GT(stats.spp, 0);
  ASSERT_LT(stats.spp, 110);
  EXPECT_EQ(stats.samples, std::uint64_t(64 * 48) * std::uint64_t(stats.spp));

  RenderStats full_stats;
  RenderOptions one_thread;
  one_thread.threads = 1;
  one_thread.sample_end = stats.spp;
  const Image reference = render(scene, one_thread, &full_stats);
  EXPECT_FALSE(full_stats.stopped);
  EXPECT_EQ(full_stats.spp, stats.spp);
  expect_same_pixels(stopped, reference);
}

TEST(RenderStop, StoppedBeforeAnyPassGivesNoSamples) {
  std::atomic<bool> stop{true};
  RenderOptions options;
  options.stop = &stop;
  RenderStats stats;
  const Image img = render(small_scene(8, 8, 4), options, &stats);
  EXPECT_TRUE(stats.stopped);
  EXPECT_EQ(stats.spp, 0);
  EXPECT_EQ(stats.samples, 0u);
  for (const Color& c : img.pixels()) EXPECT_EQ(c.max_component(), 0);
}

// The digits between `before` and `after` in `text`, or "" when they are not there.
std::string spp_in_closing_line(const std::string& text, const std::string& before, const std::string& after) {
  const size_t at = text.find(before);
  if (at == std::string::npos) return "";
  const size_t start = at + before.size();
  size_t end = start;
  while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
  if (end == start || text.compare(end, after.size(), after) != 0) return "";
  return text.substr(start, end - start);
}

// SIGINT and SIGTERM during `gonio render`: the image of the passes completed is written,
// the closing line gives its spp, the exit status is 128 + the signal, and the image is
// bit for bit the one `--spp` with that count renders.
TEST(RenderStop, SignalWritesTheImageRenderedSoFar) {
  for (const int sig : {SIGINT, SIGTERM}) {
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    SCOPED_TRACE(name);
    ScratchDir dir;
    const std::string scene = dir.file("s.json", kScene);
    const std::string out = dir.path("partial.exr");
    std::string spp;  // from the closing line
    std::string err;
    int status = -1;
    // The signal must come after the first pass (~65k samples): wait longer on a slow
    // machine (sanitizers) until one has completed.
    for (int delay_ms = 700; delay_ms <= 12000; delay_ms *= 2) {
      Gonio g({"render", scene, "-o", out, "--spp", "1048576", "--seed", "5", "--threads", "2"}, dir.path(""));
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
      g.signal(sig);
      status = g.wait(60);
      err = g.err();
      spp = spp_in_closing_line(err, "interrupted by " + name + ": rendered 32x24 at ", " spp (of 1048576)");
      if (!spp.empty()) {
        EXPECT_EQ(g.out(), out + "\n");
        break;
      }
      // Too early: no pass was complete, so nothing may have been written.
      EXPECT_NE(err.find("before any pass was complete: no image written"), std::string::npos) << err;
      EXPECT_FALSE(fs::exists(out));
    }
    ASSERT_FALSE(spp.empty()) << err;
    EXPECT_EQ(status, 128 + sig) << err;
    ASSERT_GT(std::stoi(spp), 0);
    EXPECT_EQ(leftovers(dir.path(""), {"partial.exr"}), std::vector<std::string>{});

    // The same first samples, as sums (--sample-range), divided as the renderer divides.
    const auto ref = gonio_cli_test::run_gonio({"render", scene, "-o", dir.path("ref.exr"), "--spp", "1048576",
                                                "--sample-range", "0", spp, "--seed", "5", "--threads", "0"},
                                               "", 300);
    ASSERT_EQ(ref.status, 0) << gonio_cli_test::describe(ref);
    Image mean = read_image(dir.path("ref.exr"));
    for (int y = 0; y < mean.height(); ++y)
      for (int x = 0; x < mean.width(); ++x) mean.at(x, y) = mean.at(x, y) / Float(std::stoi(spp));
    expect_same_pixels(read_image(out), mean);
  }
}

}  // namespace
}  // namespace gonio::render::test
