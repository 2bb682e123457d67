// `gonio materials --from-mtlx FILE [--material NAME]` (SPEC §3): one JSON object on
// stdout, or exit 2 with one line naming the file (and node or input). The documents are
// tests/data/mtlx; tests/unit/test_materialx.cpp checks every value they map to.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gonio/material_types.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

std::string mtlx_data(const std::string& name) {
  return (std::filesystem::path(GONIO_SOURCE_DIR) / "tests/data/mtlx" / name).string();
}

TEST(CliMaterialx, PrintsOneOpenPbrObject) {
  const RunResult r = run_gonio({"materials", "--from-mtlx", mtlx_data("openpbr_138_draft.mtlx")});
  // Until the openpbr type is in this build the JSON is not checked by the parser.
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 1u) << r.out;
  const json j = json::parse(lines[0]);
  EXPECT_EQ(j.at("type"), "openpbr");
  EXPECT_EQ(j.size(), 37u + 1 + 2) << j.dump();  // 37 parameters, type, two rotations
  EXPECT_DOUBLE_EQ(j.at("thin_film_thickness").get<double>(), 0.5);  // 500 nm
  EXPECT_DOUBLE_EQ(j.at("thin_film_weight").get<double>(), 1);
  EXPECT_DOUBLE_EQ(j.at("specular_roughness_anisotropy").get<double>(), 0.9);
  EXPECT_TRUE(j.at("geometry_thin_walled").is_boolean());
}

TEST(CliMaterialx, MaterialChoosesAmongSeveral) {
  const RunResult red = run_gonio({"materials", "--from-mtlx", mtlx_data("several.mtlx"), "--material", "M_red"});
  ASSERT_EQ(red.status, 0) << describe(red);
  EXPECT_EQ(json::parse(red.out).at("base_color"), json::array({0.8, 0.1, 0.1}));
  const RunResult blue = run_gonio({"materials", "--from-mtlx", mtlx_data("several.mtlx"), "--material", "M_blue"});
  ASSERT_EQ(blue.status, 0) << describe(blue);
  EXPECT_EQ(json::parse(blue.out).at("base_color"), json::array({0.1, 0.1, 0.8}));
}

TEST(CliMaterialx, AmbiguousMissingAndAbsent) {
  const std::string several = mtlx_data("several.mtlx");
  // SPEC §3: several surfaces and no NAME: one line each (as --material would print it).
  const RunResult each = run_gonio({"materials", "--from-mtlx", several});
  ASSERT_EQ(each.status, 0) << describe(each);
  const auto lines = split_lines(each.out);
  ASSERT_EQ(lines.size(), 2u) << each.out;
  EXPECT_EQ(json::parse(lines[0]).at("base_color"), json::array({0.8, 0.1, 0.1}));
  EXPECT_EQ(json::parse(lines[1]).at("base_color"), json::array({0.1, 0.1, 0.8}));
  // A material description must name one of them.
  expect_bad_input(run_gonio({"eval", "--bsdf", json({{"mtlx", several}}).dump()}, "0 0 1 0 0 1\n"),
                   {several, "several surfaces", "M_red", "M_blue"});
  expect_bad_input(run_gonio({"materials", "--from-mtlx", several, "--material", "M_none"}), {several, "\"M_none\""});
  const std::string absent = mtlx_data("no_such_file.mtlx");
  expect_bad_input(run_gonio({"materials", "--from-mtlx", absent}), {absent});
  // --material needs --from-mtlx; TYPE does not go with it.
  EXPECT_EQ(run_gonio({"materials", "--material", "M"}).status, 2);
  expect_bad_input(run_gonio({"materials", "diffuse", "--from-mtlx", several}), {"--from-mtlx"});
}

// SPEC §3: --list prints the surface names, one per line, by SPEC §2's naming rule.
TEST(CliMaterialx, ListPrintsTheSurfaceNames) {
  const RunResult r = run_gonio({"materials", "--from-mtlx", mtlx_data("several.mtlx"), "--list"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.out, "M_red\nM_blue\n");
  const RunResult g = run_gonio({"materials", "--from-mtlx", mtlx_data("graph_nodes.mtlx"), "--list"});
  ASSERT_EQ(g.status, 0) << describe(g);
  EXPECT_EQ(g.out, "M_mix\nM_arith\nM_ramp\nM_custom\nM_misc\n");
  EXPECT_EQ(run_gonio({"materials", "--list"}).status, 2);  // needs --from-mtlx
}

// SPEC §2: eval (and sample, albedo, check) evaluate a graph at --uv and --position.
// M_mix's base colour is mix(red, blue, u) (tests/data/mtlx/graph_nodes.mtlx).
TEST(CliMaterialx, UvAndPositionChooseWhereTheGraphIsEvaluated) {
  const std::string bsdf = json({{"mtlx", mtlx_data("graph_nodes.mtlx")}, {"material", "M_mix"}}).dump();
  const auto red_over_blue = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"eval", "--bsdf", bsdf};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_gonio(args, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 0) << describe(r);
    const json j = json::parse(r.out);
    return j.at("f")[0].get<double>() / j.at("f")[2].get<double>();
  };
  // u = 0 gives base colour (1, 0, 0), u = 1 (0, 0, 1): the red and blue channels trade
  // places, so the two ratios are reciprocal; the default point 0.5 is (0.5, 0, 0.5).
  const double r0 = red_over_blue({"--uv", "0", "0.5"}), r1 = red_over_blue({"--uv", "1", "0.5"});
  EXPECT_GT(r0, 1.5);
  EXPECT_NEAR(r0 * r1, 1.0, 1e-6);
  EXPECT_NEAR(red_over_blue({}), 1.0, 1e-6);
  EXPECT_NEAR(red_over_blue({"--uv", "0.5", "0.5", "--position", "1", "2", "3"}), 1.0, 1e-6);
  EXPECT_EQ(run_gonio({"eval", "--bsdf", bsdf, "--uv", "0"}, "0 0 1 0 0 1\n").status, 2);
  EXPECT_EQ(run_gonio({"check", "--bsdf", bsdf, "--position", "1", "2", "3", "--uv", "0.1", "0.2", "--help"}).status, 0);
}

// Every document of tests/data/mtlx/errors: exit 2, one line naming the file and the
// fragment listed for it in EXPECTED.txt (the node, the input or the problem).
TEST(CliMaterialx, EveryErrorDocumentIsOneLineAndExit2) {
  std::ifstream list(mtlx_data("errors/EXPECTED.txt"));
  ASSERT_TRUE(list) << "no errors/EXPECTED.txt";
  std::string line;
  int cases = 0;
  while (std::getline(list, line)) {
    if (line.empty() || line[0] == '#') continue;
    const size_t tab = line.find('\t');
    ASSERT_NE(tab, std::string::npos) << line;
    const std::string file = mtlx_data("errors/" + line.substr(0, tab)), fragment = line.substr(tab + 1);
    SCOPED_TRACE(file);
    // SPEC §2's missing image names the file as FILE:LINE inside its parentheses.
    const bool image = fragment.rfind("image not found", 0) == 0;
    expect_bad_input(run_gonio({"materials", "--from-mtlx", file}), {file + (image ? ":" : ": "), fragment});
    ++cases;
  }
  EXPECT_GE(cases, 19);
}

// The material JSON path: a relative "mtlx" is relative to the working directory on the
// command line. Without the openpbr type in this build, the parser's unknown-type error
// for the produced JSON (exit 2) shows the document was read.
TEST(CliMaterialx, BsdfTakesADocument) {
  const std::string rel = std::filesystem::relative(mtlx_data("several.mtlx")).string();
  ASSERT_FALSE(std::filesystem::path(rel).is_absolute());
  const json bsdf = {{"mtlx", rel}, {"material", "M_red"}};
  const RunResult r = run_gonio({"eval", "--bsdf", bsdf.dump()}, "0 0 1 0 0 1\n");
  if (!gonio::find_material_type("openpbr")) {
    expect_bad_input(r, {rel, "unknown type \"openpbr\""});
    GTEST_SKIP() << "this build has no openpbr type: checked the dispatch only";
  }
  ASSERT_EQ(r.status, 0) << describe(r);
}


// A one-material document (material "M", shader "SR") with `inputs` (XML text).
std::string cli_mtlx_doc(const std::string& category, const std::string& inputs) {
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n  <" + category + " name=\"SR\" type=\"surfaceshader\">\n" +
         inputs + "  </" + category +
         ">\n  <surfacematerial name=\"M\" type=\"material\">\n"
         "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\" />\n"
         "  </surfacematerial>\n</materialx>\n";
}
std::string cli_mtlx_input(const std::string& name, const std::string& type, const std::string& value) {
  return "    <input name=\"" + name + "\" type=\"" + type + "\" value=\"" + value + "\" />\n";
}

// Issue 55 §4: a value a hair outside its range (OpenPBR's own examples) is clamped; the
// JSON is printed and one stderr line names each clamped input.
TEST(CliMaterialx, ClampedValuesPrintTheMaterialAndOneNote) {
  const TempFile doc(cli_mtlx_doc("open_pbr_surface", cli_mtlx_input("specular_color", "color3", "1.00000007, 1, 1") +
                                                          cli_mtlx_input("base_color", "color3", "1.0619, 0.5, 0.2")));
  const RunResult r = run_gonio({"materials", "--from-mtlx", doc.path()});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(json::parse(r.out).at("specular_color"), json::array({1.0, 1.0, 1.0}));
  EXPECT_EQ(json::parse(r.out).at("base_color"), json::array({1.0, 0.5, 0.2}));
  const auto lines = split_lines(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_NE(lines[0].find(doc.path() + ": "), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("specular_color 1.00000007, 1, 1 -> 1, 1, 1 (line 4)"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("base_color 1.0619, 0.5, 0.2 -> 1, 0.5, 0.2 (line 5)"), std::string::npos) << lines[0];
}

// Issue 55 §5: on a refusal the error is the only stderr line (SPEC §3): the note on the
// clamped colour before the bad input is dropped.
TEST(CliMaterialx, ARefusalDropsTheClampNote) {
  const TempFile doc(cli_mtlx_doc("open_pbr_surface", cli_mtlx_input("specular_color", "color3", "1.5, 1, 1") +
                                                          cli_mtlx_input("coat_roughness", "float", "-0.5")));
  const RunResult r = run_gonio({"materials", "--from-mtlx", doc.path()});
  expect_bad_input(r, {doc.path() + ": line 5: ", "input coat_roughness: -0.5 is negative"});
  EXPECT_EQ(r.err.find("clamped"), std::string::npos) << r.err;
}

// A .mtlx path is read as a scene file is (docs/materialx.md): a FIFO too, so that a
// generated document can be piped in. The writer waits, without blocking, for the reader.
TEST(CliMaterialx, AFifoIsReadLikeAScene) {
  const ScratchDir dir;
  const std::string fifo = dir.path("doc.mtlx");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string text = cli_mtlx_doc("open_pbr_surface", cli_mtlx_input("base_weight", "float", "0.25"));
  std::thread writer([&] {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    int fd = -1;
    while (fd < 0 && std::chrono::steady_clock::now() < end) {
      fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);  // ENXIO until a reader opens it
      if (fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (fd < 0) return;
    ::fcntl(fd, F_SETFL, 0);  // blocking writes from here
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += size_t(n);
    }
    ::close(fd);
  });
  const RunResult r = run_gonio({"materials", "--from-mtlx", fifo});
  writer.join();
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(json::parse(r.out).at("base_weight"), 0.25);
}

// Unpolarized Fresnel reflectance of a smooth dielectric of index n seen from air at
// incidence cos_i (Born & Wolf §1.5.2, the Fresnel equations), written here.
double fresnel_from_air(double n, double cos_i) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Issue 56 §1: Standard Surface's coat, a second guard independent of the unit test's.
// Autodesk Standard Surface 1.0 (Georgiev et al. 2019, §"Coat"): a coat of weight `coat`
// and index coat_IOR is a dielectric over the rest, and coat_color tints what lies under it
// (base_color · lerp(1, coat_color, coat)). A smooth coat of weight 1 over a base that
// reflects nothing (base 0, specular 0) reflects exactly the Fresnel reflectance of
// coat_IOR, which the material read from the document must give.
TEST(CliMaterialx, StandardSurfaceCoatMatchesTheSpecification) {
  const double coat_ior = 2.0;
  const TempFile doc(cli_mtlx_doc("standard_surface", cli_mtlx_input("base", "float", "0") +
                                                          cli_mtlx_input("specular", "float", "0") +
                                                          cli_mtlx_input("coat", "float", "1") +
                                                          cli_mtlx_input("coat_roughness", "float", "0") +
                                                          cli_mtlx_input("coat_IOR", "float", fmt(coat_ior))));
  const std::string bsdf = json{{"mtlx", doc.path()}}.dump();
  if (!gonio::find_material_type("openpbr")) GTEST_SKIP() << "this build has no openpbr type";
  for (const double theta : {0.0, 60.0}) {
    SCOPED_TRACE(theta);
    const json a = run_one({"albedo", "--bsdf", bsdf, "--theta", fmt(theta)});
    const double want = fresnel_from_air(coat_ior, std::cos(deg(theta)));  // 1/9 at normal incidence
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.at("reflectance")[c].get<double>(), want, 2e-3) << a.dump();
  }
  // The tint: base 0.5 grey under a coat of weight 0.5 and colour (0.2, 0.4, 0.6):
  // 0.5 · (1 + 0.5 · (c − 1)) = (0.3, 0.35, 0.4).
  const TempFile tinted(cli_mtlx_doc("standard_surface", cli_mtlx_input("base_color", "color3", "0.5, 0.5, 0.5") +
                                                             cli_mtlx_input("coat", "float", "0.5") +
                                                             cli_mtlx_input("coat_color", "color3", "0.2, 0.4, 0.6")));
  const RunResult r = run_gonio({"materials", "--from-mtlx", tinted.path()});
  ASSERT_EQ(r.status, 0) << describe(r);
  const json j = json::parse(r.out);
  const double want[3] = {0.3, 0.35, 0.4};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(j.at("base_color")[c].get<double>(), want[c], 1e-12) << j.dump();
  EXPECT_DOUBLE_EQ(j.at("coat_weight").get<double>(), 0.5);
}

}  // namespace
}  // namespace gonio_cli_test
