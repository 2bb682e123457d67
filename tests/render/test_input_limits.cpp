// Scene and OBJ input that gonio once accepted or choked on (issue 9): numbers that do
// not fit a float, strict OBJ statements with file:line errors, bounded reads of scene
// files, and one-line messages. Through the library (load_scene_file), plus `gonio render`
// on an endless device.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../cli/run_gonio.h"
#include "gonio/error.h"
#include "gonio/render/scene_loader.h"
#include "scratch_dir.h"

namespace gonio::render {
namespace {

using gonio::test::ScratchDir;

// The message of the InputError that loading `scene_path` throws ("" when none is thrown).
std::string load_error(const std::string& scene_path) {
  try {
    load_scene_file(scene_path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& msg, const std::vector<std::string>& mentions) {
  ASSERT_FALSE(msg.empty()) << "accepted";
  for (const char c : msg) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20) << "control byte in: " << msg;
  for (const auto& m : mentions) EXPECT_NE(msg.find(m), std::string::npos) << "should mention '" << m << "': " << msg;
}

const std::string kMeshScene = R"({"camera": {"width": 4, "height": 4},
  "shapes": [{"type": "mesh", "file": "m.obj", "material": {"type": "diffuse"}}]})";

// ---------------------------------------------------------------------------------------
// OBJ: every statement parsed completely, numbers finite and float-sized, indices in
// range (negative ones relative to the vertices so far), no NUL or control bytes.

// A NUL byte inside line 2.
constexpr char kNulObj[] = "v 0 0 0\nv 1 0 0\x00\nv 0 0 1\nf 1 2 3\n";

TEST(InputLimits, BadObjStatementsNameFileAndLine) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";
  struct Case {
    std::string obj;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {"v nan nan nan\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", {"m.obj:1:", "nan"}},
      {tri + "v inf 0 0\nf 1 2 3\n", {"m.obj:4:", "inf"}},
      {"v a b c\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", {"m.obj:1:", "'a'"}},
      {"v 0 0 0\nv 1 0 0 \nv 0 0 1x\nf 1 2 3\n", {"m.obj:3:", "'1x'"}},
      {"v 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", {"m.obj:1:", "3"}},
      {tri + "v 1e39 0 0\nf 1 2 3\n", {"m.obj:4:", "1e39", "float"}},
      {tri + "vn 0 1\nf 1 2 3\n", {"m.obj:4:"}},
      {tri + "vt 0.5 nan\nf 1 2 3\n", {"m.obj:4:", "nan"}},
      {tri + "f 1 2 4\n", {"m.obj:4:", "4", "out of range", "3 vertices"}},
      {tri + "f 1 2 0\n", {"m.obj:4:", "0"}},
      {tri + "f -1 -2 -4\n", {"m.obj:4:", "-4", "out of range"}},
      {tri + "f 1 2 99999999999999999999\n", {"m.obj:4:", "99999999999999999999"}},
      {tri + "f 1 2 3.5\n", {"m.obj:4:", "3.5"}},
      {tri + "f 1 2\n", {"m.obj:4:", "3"}},
      {tri + "vt 0 0\nf 1/2 2/1 3/1\n", {"m.obj:5:", "texture coordinate", "out of range"}},
      {tri + "vn 0 1 0\nf 1//1 2//2 3//1\n", {"m.obj:5:", "normal", "out of range"}},
      {tri + "f 1/ 2 3\n", {"m.obj:4:"}},
      {std::string(kNulObj, sizeof kNulObj - 1), {"m.obj:2:", "\\x00"}},
      {tri + "f 1 2 3\x01\n", {"m.obj:4:", "\\x01"}},
      {tri + "curv 0 1 1 2\nf 1 2 3\n", {"m.obj:4:", "curv"}},
      // Materials come from the scene; the file's own are refused, not ignored.
      {"mtllib box.mtl\n" + tri + "f 1 2 3\n", {"m.obj:1:", "'mtllib' is not supported", "material"}},
      {tri + "usemtl red\nf 1 2 3\n", {"m.obj:4:", "'usemtl' is not supported", "material"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.obj);
    ScratchDir dir;
    dir.file("m.obj", c.obj);
    expect_error(load_error(dir.file("s.json", kMeshScene)), c.mentions);
  }
}

TEST(InputLimits, GoodObjStatementsAreAccepted) {
  // Relative (negative) indices, v/t/n forms, w and comments, groups, smoothing, CRLF
  // line ends, a quad: all legal OBJ.
  ScratchDir dir;
  dir.file("m.obj",
           "# a comment\r\no thing\r\ng part\r\ns 1\r\n"
           "v 0 0 0 1\r\nv 1 0 0\r\nv 1 0 1\r\nv 0 0 1\r\nvt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvn 0 1 0\r\n"
           "f -4/-3/-1 -3/-2/-1 -2/-1/-1\r\nf 1//1 3//1 4//1\r\nf 1 2 3 4\r\n");
  const std::string scene = dir.file("s.json", kMeshScene);
  EXPECT_EQ(load_error(scene), "");
  const Scene s = load_scene_file(scene);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].indices.size(), 3u * 4u);
}

// ---------------------------------------------------------------------------------------
// Scene numbers: a value must fit a float; a positive-only one must stay a normal float.

TEST(InputLimits, SceneNumbersMustFitAFloat) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1e39, "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/radius", "float"}},
      {R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1e-320, "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/radius", "float"}},
      {R"({"lights": [{"type": "sphere", "center": [0,0,0], "radius": 1e-40, "radiance": 1}]})",
       {"s.json: /lights/0/radius", "float"}},
      {R"({"shapes": [{"type": "sphere", "center": [1e39,0,0], "radius": 1, "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/center/0", "float"}},
      {R"({"camera": {"position": [0,-3.5e38,0]}})", {"s.json: /camera/position/1", "float"}},
      {R"({"shapes": [{"type": "mesh", "file": "m.obj", "scale": 1e-320, "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/scale", "float"}},
      {R"({"shapes": [{"type": "mesh", "file": "m.obj", "scale": [1, 1e-39, 1], "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/scale/1", "float"}},
      {R"({"shapes": [{"type": "mesh", "file": "m.obj", "rotate": {"axis": [0,1,0], "degrees": 1e39}, "material": {"type": "diffuse"}}]})",
       {"s.json: /shapes/0/rotate/degrees", "float"}},
      {R"({"materials": {"m": {"type": "roughconductor", "material": "Au", "alpha": 1e-320}}})",
       {"s.json: /materials/m", "alpha", "float"}},
  };
  for (const auto& [scene, mentions] : cases) {
    SCOPED_TRACE(scene);
    ScratchDir dir;
    dir.file("m.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n");
    expect_error(load_error(dir.file("s.json", scene)), mentions);
  }
}

// ---------------------------------------------------------------------------------------
// Size and nesting: scene files at most 16 MiB, JSON depth at most 64, one-line errors.

TEST(InputLimits, SceneFileSizeAndNesting) {
  ScratchDir dir;
  std::string big = R"({"camera": {"width": 4, "height": 4}})";
  big.resize((size_t(16) << 20) + 1, '\n');
  expect_error(load_error(dir.file("big.json", big)), {"big.json", "too large", "16 MiB"});

  const std::string deep = R"({"comment": )" + std::string(70000, '[') + std::string(70000, ']') + "}";
  expect_error(load_error(dir.file("deep.json", deep)), {"deep.json", "nested deeper than 64", "line 1, column 76"});

  // A key twice in one object is refused with its line and column (nlohmann kept the last).
  expect_error(load_error(dir.file("dup.json", "{\"camera\": {\"width\": 4,\n \"width\": 8}}")),
               {"dup.json", "duplicate key \"width\"", "line 2, column 2"});

  expect_error(load_error(dir.path("")), {});
  expect_error(load_error(dir.path("nothing.json")), {"nothing.json"});
}

TEST(InputLimits, ObjFileSizeIsBounded) {
  // OBJ meshes may be larger than scenes (64 MiB); /dev/zero is refused once past it.
  ScratchDir dir;
  const std::string scene = dir.file("s.json", R"({"shapes": [{"type": "mesh", "file": "/dev/zero", "material": {"type": "diffuse"}}]})");
  expect_error(load_error(scene), {"/shapes/0/file", "/dev/zero", "too large", "64 MiB"});
}

TEST(InputLimits, UserTextInSceneErrorsIsEscaped) {
  ScratchDir dir;
  const std::string scene = dir.file("s.json", R"({"shapes": [{"type": "cu\nbe\t", "material": {"type": "diffuse"}}]})");
  expect_error(load_error(scene), {"cu\\nbe\\t"});
  const std::string mesh = dir.file("m.json", R"({"shapes": [{"type": "mesh", "file": "no\u0007such.obj", "material": "x"}]})");
  expect_error(load_error(mesh), {"no\\x07such.obj"});
}

TEST(InputLimits, RenderOfAnEndlessDeviceStops) {
  // `gonio render /dev/zero` read until memory ran out.
  const auto r = gonio_cli_test::run_gonio({"render", "/dev/zero"}, "", 10);
  gonio_cli_test::expect_bad_input(r, {"/dev/zero", "too large"});
}

// ---------------------------------------------------------------------------------------
// Light colours as emission spectra (SPEC §2), reduced to linear sRGB. Expected values
// from colorimetry, not from gonio: D65 of luminance 1 is sRGB's white (1, 1, 1); an
// equal-energy spectrum of value v has XYZ = v (1, 1, 1) (the CIE 1931 functions have equal
// integrals), so its sRGB is v times the row sums of IEC 61966-2-1's XYZ → sRGB matrix.

TEST(SceneSpectra, LightColoursTakeEmissionSpectra) {
  ScratchDir dir;
  dir.file("flat.csv", "nm,value\n360,2\n830,2\n");
  const Scene s = load_scene_file(dir.file("s.json", R"({"lights": [
      {"type": "point", "position": [0, 2, 0], "intensity": {"illuminant": "D65"}},
      {"type": "point", "position": [0, 3, 0], "intensity": {"spectrum": "flat.csv"}},
      {"type": "point", "position": [0, 4, 0], "intensity": {"blackbody": 2700}}]})"));
  ASSERT_EQ(s.point_lights.size(), 3u);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.point_lights[0].intensity[c], 1.0, 2e-3) << c;
  const double rows[3] = {3.2406 - 1.5372 - 0.4986, -0.9689 + 1.8758 + 0.0415, 0.0557 - 0.2040 + 1.0570};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.point_lights[1].intensity[c], 2 * rows[c], 2 * rows[c] * 2e-3) << c;
  // A 2700 K blackbody is orange: red above green above blue, luminance about 1.
  const Color warm = s.point_lights[2].intensity;
  EXPECT_GT(warm[0], warm[1]);
  EXPECT_GT(warm[1], warm[2]);
  EXPECT_NEAR(0.2126 * warm[0] + 0.7152 * warm[1] + 0.0722 * warm[2], 1.0, 5e-3);
  expect_error(load_error(dir.file("t.json", R"({"lights": [{"type": "point", "position": [0, 2, 0], "intensity": {"blackbody": 10}}]})")),
               {"t.json: /lights/0/intensity", "blackbody"});
  expect_error(load_error(dir.file("u.json", R"({"lights": [{"type": "point", "position": [0, 2, 0], "intensity": {"sellmeier": 1}}]})")),
               {"u.json: /lights/0/intensity", "sellmeier"});
}

// A material's {"spectrum": "file.csv"} is read relative to the scene file, as a light's
// is, whatever the working directory: a flat reflectance of 0.25 is the grey 0.25 under
// D65 in RGB mode (sRGB's white is D65), and the spectrum itself in spectral mode.
TEST(SceneSpectra, MaterialSpectrumFilesAreRelativeToTheScene) {
  ScratchDir dir;
  dir.file("quarter.csv", "nm,value\n360,0.25\n830,0.25\n");
  const Scene s = load_scene_file(dir.file("s.json", R"({"shapes": [{"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": {"type": "diffuse", "reflectance": {"spectrum": "quarter.csv"}}}]})"));
  ASSERT_EQ(s.materials.size(), 1u);
  const Vec3 n{0, 0, 1};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.materials[0].bxdf.f(n, n)[c] * kPiD, 0.25, 1e-3) << c;
  const auto& spectrum = s.materials[0].spectra.colour[size_t(MaterialParam::Reflectance)];
  ASSERT_TRUE(spectrum.has_value());
  for (const Float l : {380.f, 550.f, 800.f}) EXPECT_FLOAT_EQ(spectrum->eval(l), 0.25f) << l;
  // Not found next to the working directory's files either: the error names the file.
  expect_error(load_error(dir.file("t.json", R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
      "material": {"type": "diffuse", "reflectance": {"spectrum": "missing.csv"}}}]})")),
               {"t.json", "reflectance", "missing.csv"});
}

}  // namespace
}  // namespace gonio::render
