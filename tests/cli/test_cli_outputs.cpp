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
#include <fstream>
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
    // The error is the only line on stderr: no progress when stderr is not a terminal
    // (SPEC §3), measure's included.
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.out, "") << describe(r);
    const std::vector<std::string> lines = split_lines(r.err);
    ASSERT_EQ(lines.size(), 1u) << describe(r);
    EXPECT_EQ(lines.back().rfind("gonio: " + c.target + ": ", 0) == 0 ||
                  lines.back().rfind("gonio: --json " + c.target + ": ", 0) == 0,
              true)
        << describe(r);
    EXPECT_TRUE(contains_ci(lines.back(), "too large")) << describe(r);
    EXPECT_EQ(dir.names(), std::vector<std::string>{}) << "a partial file or a temporary was left behind";
  }
}

// SPEC §3: a scene without lights renders, with one warning line; progress only on a
// terminal (here stderr is a pipe: the closing line alone); an option given an empty
// value is refused, not taken as absent.
TEST(CliRenderMessages, NoLightsWarnsAndAPipeGetsNoProgress) {
  ScratchDir dir;
  const auto scene = [&](const std::string& name, const std::string& lights) {
    const std::string path = dir.path(name);
    std::ofstream(path) << R"({"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 8, "height": 6},
      "render": {"spp": 1}, "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
      "material": {"type": "diffuse"}}])" << lights << "}";
    return path;
  };
  const std::string dark = scene("dark.json", ""), lit = scene("lit.json", R"(, "environment": {"radiance": 1})");
  const std::string emissive = scene("glow.json", R"(, "lights": [{"type": "sphere", "center": [0, 3, 0], "radius": 0.5, "radiance": 0}])");
  const std::string image = dir.path("out.png");
  const RunResult r = run_gonio({"render", dark, "-o", image});
  ASSERT_EQ(r.status, 0) << describe(r);
  const std::vector<std::string> lines = split_lines(r.err);
  ASSERT_EQ(lines.size(), 2u) << describe(r);
  EXPECT_EQ(lines[0], "warning: the scene has no lights; the image is black");
  EXPECT_EQ(lines[1].rfind("rendered 8x6 at 1 spp", 0), 0u) << describe(r);
  // Lit by the environment, or holding a light (even a dark one): no warning, and the
  // closing line alone (a pipe gets no progress).
  for (const std::string& s : {lit, emissive}) {
    const RunResult ok = run_gonio({"render", s, "-o", image});
    ASSERT_EQ(ok.status, 0) << describe(ok);
    const std::vector<std::string> one = split_lines(ok.err);
    ASSERT_EQ(one.size(), 1u) << describe(ok);
    EXPECT_EQ(one[0].rfind("rendered 8x6 at 1 spp", 0), 0u) << describe(ok);
  }
  // A refusal's error line is alone: the warning is not printed before it.
  for (const char* option : {"--sampler", "--light-sampler"}) {
    SCOPED_TRACE(option);
    expect_bad_input(run_gonio({"render", dark, "-o", image, option, ""}), {option, "got \"\""});
  }
}

}  // namespace
}  // namespace gonio_cli_test
