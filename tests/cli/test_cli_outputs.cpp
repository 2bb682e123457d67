// Every file gonio writes (tabulate and measure's tables, measure's --json, render,
// slice and measure's images) goes through one OutputFile (issue 39): a target that is
// not a regular file is refused before any work, and a failed write is one error line
// naming the file, with neither a partial file nor a temporary left behind. A failing
// write is made with RLIMIT_FSIZE in the child, never with a device: a regression would
// replace the device.

#include <sys/stat.h>
#include <sys/types.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;

const std::string kOutDiffuse = R"({"type":"diffuse"})";
const std::string kOutSurface = R"({"type":"flat","material":{"type":"diffuse"}})";
const std::string kOutGantry = R"({"theta_i":0,"theta_o":[0,30]})";

bool is_fifo(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

TEST(CliOutputErrors, SpecialFileTargetsAreRefusedByEveryWriter) {
  ScratchDir dir;
  const std::string fifo = dir.path("fifo.png"), link = dir.path("link.binary"), sub = dir.path("sub.binary");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink(fifo, link);
  fs::create_directory(sub);
  const std::vector<std::string> before = dir.names();
  struct Case {
    std::vector<std::string> args;
    std::string target, reason;
  };
  const std::vector<Case> cases = {
      {{"tabulate", "--bsdf", kOutDiffuse, "-o", fifo}, fifo, "not a regular file"},
      {{"tabulate", "--bsdf", kOutDiffuse, "-o", link}, link, "not a regular file"},
      {{"tabulate", "--bsdf", kOutDiffuse, "-o", sub}, sub, "directory"},
      {{"measure", "--surface", kOutSurface, "-o", link, "--samples", "1000"}, link, "not a regular file"},
      {{"measure", "--surface", kOutSurface, "--gantry", kOutGantry, "--samples", "1000", "--json", fifo}, fifo,
       "not a regular file"},
      {{"measure", "--surface", kOutSurface, "--preview", fifo}, fifo, "not a regular file"},
      {{"slice", "--bsdf", kOutDiffuse, "-o", fifo, "--size", "16"}, fifo, "not a regular file"},
      {{"render", "-o", fifo, "--spp", "1"}, fifo, "not a regular file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args[0] + " -> " + c.target);
    // A writer that opened the FIFO would wait for a reader: the watchdog ends it.
    expect_bad_input(run_gonio(c.args, "", 10), {c.target, c.reason});
    EXPECT_TRUE(is_fifo(fifo)) << "the FIFO was replaced";
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_TRUE(fs::is_directory(sub));
    EXPECT_EQ(dir.names(), before) << "a temporary was left behind";
  }
}

TEST(CliOutputErrors, FailedWriteIsOneLineAndLeavesNothingBehind) {
  ScratchDir dir;
  struct Case {
    std::vector<std::string> args;
    std::string target;
    rlim_t limit;
  };
  // measure -o writes its table as tabulate does (write_merl); not repeated here.
  const std::string table = dir.path("t.binary"), json = dir.path("g.json"), image = dir.path("r.png");
  const std::vector<Case> cases = {
      // A 35 MB table past a 1 MiB limit.
      {{"tabulate", "--bsdf", kOutDiffuse, "-o", table}, table, 1 << 20},
      // The gantry's JSON object is longer than 16 bytes.
      {{"measure", "--surface", kOutSurface, "--gantry", kOutGantry, "--samples", "1000", "--json", json}, json, 16},
      // The image's space is reserved before rendering: refused before the first pass.
      {{"render", "-o", image, "--spp", "1"}, image, 1024},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args[0] + " -> " + c.target);
    const RunResult r = run_gonio_limited(c.args, {c.limit, 0});
    // measure's progress lines come first on stderr; the error is the one line after them.
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.out, "") << describe(r);
    const std::vector<std::string> lines = split_lines(r.err);
    ASSERT_FALSE(lines.empty()) << describe(r);
    for (size_t i = 0; i + 1 < lines.size(); ++i) EXPECT_EQ(lines[i].rfind("measuring: ", 0), 0u) << describe(r);
    EXPECT_EQ(lines.back().rfind("gonio: " + c.target + ": ", 0) == 0 ||
                  lines.back().rfind("gonio: --json " + c.target + ": ", 0) == 0,
              true)
        << describe(r);
    EXPECT_TRUE(contains_ci(lines.back(), "too large")) << describe(r);
    EXPECT_EQ(dir.names(), std::vector<std::string>{}) << "a partial file or a temporary was left behind";
  }
}

}  // namespace
}  // namespace gonio_cli_test
