// `gonio render` as a user runs it: outputs, and bad input of every kind (SPEC §3: exit 2,
// one line on stderr naming the file, the JSON path and the problem, nothing on stdout).

#include <filesystem>
#include <fstream>
#include <string>

#include "../cli/run_gonio.h"
#include "scratch_dir.h"

namespace gonio_cli_test {
namespace {

namespace fs = std::filesystem;

using gonio::test::ScratchDir;

const char* kSmallScene = R"({
  "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "width": 24, "height": 16},
  "render": {"spp": 2},
  "shapes": [
    {"type": "quad", "corner": [-3, 0, -3], "edge1": [0, 0, 6], "edge2": [6, 0, 0], "material": {"type": "diffuse"}},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": {"type": "roughconductor", "material": "Au", "alpha": 0.2}}
  ],
  "lights": [{"type": "point", "position": [1, 3, 2], "intensity": 10}],
  "environment": {"radiance": 0.2}
})";

TEST(RenderCli, WritesPngAndExrAndPrintsThePath) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kSmallScene);
  for (const char* name : {"out.png", "out.exr"}) {
    const std::string out = dir.path(name);
    const RunResult r = run_gonio({"render", scene, "-o", out, "--threads", "1", "--seed", "3"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.out, out + "\n");
    EXPECT_TRUE(fs::exists(out) && fs::file_size(out) > 0);
    // The closing line reports time, samples/s and rays/s.
    EXPECT_NE(r.err.find("samples/s"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rays/s"), std::string::npos) << r.err;
  }
}

TEST(RenderCli, MeshFromObj) {
  ScratchDir dir;
  dir.file("tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0.5 1\nvn 0 1 0\nf 1/1/1 3/3/1 2/2/1\n");
  const std::string scene = dir.file("s.json", R"({"camera": {"position": [0, 3, 0.1], "look_at": [0, 0, 0], "width": 8, "height": 8},
    "shapes": [{"type": "mesh", "file": "tri.obj", "scale": 2, "rotate": {"axis": [0, 1, 0], "degrees": 30}, "translate": [0, 0.1, 0],
                "material": {"type": "roughconductor", "material": "Al", "alpha": [0.3, 0.05]}}],
    "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 5}]})");
  const RunResult r = run_gonio({"render", scene, "-o", dir.path("m.png"), "--spp", "1"});
  EXPECT_EQ(r.status, 0) << describe(r);
}

struct BadScene {
  const char* name;
  std::string json;                       // the scene text ("" → the file is not written)
  std::vector<std::string> mentions;      // what the message must name
};

TEST(RenderCli, BadSceneInputIsOneLineAndExit2) {
  const std::vector<BadScene> cases = {
      {"syntax", "{\n  \"camera\": {,\n}", {"s.json", "malformed JSON at line 2, column 14"}},
      {"number overflow", R"({"camera": {"fov": 1e999}})", {"s.json", "malformed JSON", "1e999"}},
      {"top-level field", R"({"cameras": {}})", {"s.json", "cameras", "unknown field"}},
      {"shape type", R"({"shapes": [{"type": "cube", "material": {"type": "diffuse"}}]})", {"/shapes/0/type", "cube"}},
      {"radius", R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": -1, "material": {"type": "diffuse"}}]})", {"/shapes/0/radius", "-1"}},
      {"missing material", R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1}]})", {"/shapes/0", "material"}},
      {"material name", R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "gold"}]})", {"/shapes/0/material", "gold"}},
      {"material parameter", R"({"materials": {"m": {"type": "roughconductor", "material": "Au", "alpha": -0.1}}})", {"/materials/m", "alpha", "-0.1"}},
      {"vector", R"({"shapes": [{"type": "sphere", "center": [0,0], "radius": 1, "material": {"type": "diffuse"}}]})", {"/shapes/0/center"}},
      {"nan-like", R"({"lights": [{"type": "point", "position": [0,1,0], "intensity": "bright"}]})", {"/lights/0/intensity"}},
      {"negative radiance", R"({"lights": [{"type": "quad", "corner": [0,1,0], "edge1": [1,0,0], "edge2": [0,0,1], "radiance": [1,-1,1]}]})", {"/lights/0/radiance/1"}},
      {"degenerate quad", R"({"lights": [{"type": "quad", "corner": [0,1,0], "edge1": [1,0,0], "edge2": [2,0,0], "radiance": 1}]})", {"/lights/0", "edge"}},
      {"light type", R"({"lights": [{"type": "spot"}]})", {"/lights/0/type", "spot"}},
      {"camera", R"({"camera": {"position": [0,0,0], "look_at": [0,0,0]}})", {"/camera", "look_at"}},
      {"width", R"({"camera": {"width": 0}})", {"/camera/width"}},
      {"spp", R"({"render": {"spp": 1.5}})", {"/render/spp"}},
      {"missing obj", R"({"shapes": [{"type": "mesh", "file": "nowhere.obj", "material": {"type": "diffuse"}}]})", {"/shapes/0/file", "nowhere.obj"}},
      {"bad obj index", R"({"shapes": [{"type": "mesh", "file": "bad.obj", "material": {"type": "diffuse"}}]})", {"/shapes/0/file", "bad.obj", "out of range"}},
      {"missing environment map", R"({"environment": {"file": "sky.exr"}})", {"/environment/file", "sky.exr"}},
      {"environment both", R"({"environment": {"file": "sky.exr", "radiance": 1}})", {"/environment"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    ScratchDir dir;
    dir.file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 7\n");
    const std::string scene = dir.file("s.json", c.json);
    const RunResult r = run_gonio({"render", scene, "-o", dir.path("x.png")});
    std::initializer_list<std::string> none{};
    expect_bad_input(r, none);
    for (const auto& m : c.mentions) EXPECT_TRUE(contains_ci(r.err, m)) << "should mention " << m << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir.path("x.png")));
  }
}

TEST(RenderCli, BadCommandLineIsOneLineAndExit2) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kSmallScene);
  expect_bad_input(run_gonio({"render", dir.path("missing.json")}), {"missing.json"});
  expect_bad_input(run_gonio({"render", scene, "-o", dir.path("x.jpg")}), {"x.jpg", ".exr"});
  expect_bad_input(run_gonio({"render", scene, "-o", dir.path("no/such/dir/x.png")}), {"no/such/dir"});
  expect_bad_input(run_gonio({"render", dir.path("")}), {});
  expect_bad_input(run_gonio({"render", scene, "-o", dir.path("y.png"), "--light-sampler", "tree"}),
                   {"--light-sampler", "tree"});
  EXPECT_FALSE(fs::exists(dir.path("y.png")));
}

// SPEC §3: --spp 1–1,048,576, --threads 0–1024 (0: all cores), --seed 0–2,147,483,647,
// decimal only; anything else is exit 2 with one line naming the option.
TEST(RenderCli, IntegerOptionsAreRangeChecked) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", kSmallScene);
  const std::string out = dir.path("x.png");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"--spp", "0"},          {"--spp", "-1"},         {"--spp", "1048577"},   {"--spp", "2147483647"},
      {"--spp", "99999999999999999999"}, {"--spp", "0x10"}, {"--spp", "1e3"},   {"--spp", "2.5"},
      {"--spp", ""},           {"--spp", " 4"},         {"--threads", "-1"},    {"--threads", "1025"},
      {"--threads", "0x2"},    {"--seed", "-1"},        {"--seed", "-5"},       {"--seed", "2147483648"},
      {"--seed", "0b11"},      {"--seed", "seven"},
  };
  for (const auto& [option, value] : bad) {
    SCOPED_TRACE(option + " " + value);
    expect_bad_input(run_gonio({"render", scene, "-o", out, option, value}), {option});
    EXPECT_FALSE(fs::exists(out));
  }
  // The ends of each range are accepted: with a bad output extension after them, the
  // error is about the output, so the option passed (and nothing is rendered).
  const std::vector<std::pair<std::string, std::string>> good = {
      {"--spp", "1"},    {"--spp", "1048576"},    {"--threads", "0"}, {"--threads", "1024"},
      {"--seed", "0"},   {"--seed", "2147483647"}, {"--spp", "010"},
  };
  for (const auto& [option, value] : good) {
    SCOPED_TRACE(option + " " + value);
    expect_bad_input(run_gonio({"render", scene, "-o", dir.path("x.jpg"), option, value}), {"x.jpg"});
  }
  // Leading zeros are decimal, not octal: --spp 010 is 10 samples.
  const RunResult r = run_gonio({"render", scene, "-o", dir.path("ten.exr"), "--spp", "010", "--threads", "0"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.err.find("at 10 spp"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gonio_cli_test
