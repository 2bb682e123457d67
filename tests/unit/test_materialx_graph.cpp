// MaterialX node graphs (src/io/materialx.cpp's compiler, include/gonio/io/materialx_graph.h):
// each value of tests/data/mtlx/graph_nodes.mtlx at uv (0.25, 0.75), position (2, −1, 0.5),
// worked out by hand in the comments from the node definitions (MaterialX Specification
// v1.39, Standard Nodes; the GLSL reference functions named there), never printed by the
// code. Also the refusals: cycles, depth, size, unsupported nodes, missing images.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/io/materialx.h"
#include "gonio/io/materialx_graph.h"
#include "gonio/material.h"

namespace gonio {
namespace {

using nlohmann::json;

std::string graph_doc() { return (std::filesystem::path(GONIO_SOURCE_DIR) / "tests/data/mtlx/graph_nodes.mtlx").string(); }

MaterialxPoint test_point() {
  MaterialxPoint p;
  p.u = 0.25;
  p.v = 0.75;
  p.px = 2;
  p.py = -1;
  p.pz = 0.5;
  return p;
}

json graph_material(const std::string& name, const MaterialxPoint& at = test_point()) {
  return materialx_file_to_json(graph_doc(), name, nullptr, at);
}

void expect_rgb(const json& v, double r, double g, double b) {
  ASSERT_TRUE(v.is_array() && v.size() == 3) << v.dump();
  EXPECT_NEAR(v[0].get<double>(), r, 1e-12) << v.dump();
  EXPECT_NEAR(v[1].get<double>(), g, 1e-12) << v.dump();
  EXPECT_NEAR(v[2].get<double>(), b, 1e-12) << v.dump();
}

TEST(MaterialxGraph, MixOfTexcoord) {
  // mix(bg (1,0,0), fg (0,0,1), s): bg (1 − s) + fg s, s = u.
  expect_rgb(graph_material("M_mix").at("base_color"), 0.75, 0, 0.25);
  expect_rgb(graph_material("M_mix", MaterialxPoint{}).at("base_color"), 0.5, 0, 0.5);  // SPEC §2's default uv 0.5 0.5
}

TEST(MaterialxGraph, Arithmetic) {
  const json j = graph_material("M_arith");
  EXPECT_NEAR(j.at("specular_roughness").get<double>(), 0.25, 1e-12);  // clamp(2 · 0.1 + 0.05)
  EXPECT_NEAR(j.at("coat_weight").get<double>(), 0.75, 1e-12);         // 1 − 0.5²
  EXPECT_NEAR(j.at("base_weight").get<double>(), 0.25, 1e-12);         // 1 / 4
  EXPECT_NEAR(j.at("fuzz_weight").get<double>(), 0.5, 1e-12);          // 2.5 mod 1 (in2's default 1)
  // smoothstep(0.25; 0, 1) = t² (3 − 2t) = 0.0625 · 2.5.
  EXPECT_NEAR(j.at("coat_roughness").get<double>(), 0.15625, 1e-12);
}

TEST(MaterialxGraph, RampAndPlace2d) {
  const json j = graph_material("M_ramp");
  // ramp4 at (s, t) = (0.25, 0.75): top = tl·0.75 + tr·0.25 = (0.75, 0.25, 0), bottom =
  // bl·0.75 + br·0.25 = (0.25, 0.25, 1); bottom·0.25 + top·0.75.
  expect_rgb(j.at("base_color"), 0.625, 0.25, 0.25);
  // place2d (operationorder 0): ((0.25, 0.75) − pivot (0.5, 0.5)) / 2 = (−0.125, 0.125);
  // rotate2d 90°: (cos·x + sin·y, −sin·x + cos·y) = (0.125, 0.125); − offset (0.1, 0)
  // + pivot = (0.525, 0.625).
  expect_rgb(j.at("coat_color"), 0.525, 0.625, 0);
}

TEST(MaterialxGraph, NodedefImplementedByANodegraphAndInterfaceInputs) {
  const json j = graph_material("M_custom");
  expect_rgb(j.at("base_color"), 0.1, 0.2, 0.3);     // (0.2, 0.4, 0.6) × the definition's amount 0.5
  expect_rgb(j.at("coat_color"), 0.25, 0.25, 0.25);  // the definition's in (1, 1, 1) × 0.25
  EXPECT_NEAR(j.at("specular_roughness").get<double>(), 0.6, 1e-12);  // the graph's input k 0.3 × 2
}

TEST(MaterialxGraph, ConditionalsSwitchRampsAndSwizzles) {
  const json j = graph_material("M_misc");
  EXPECT_NEAR(j.at("coat_weight").get<double>(), 0.9, 1e-12);         // v 0.75 > 0.5: in1
  expect_rgb(j.at("base_color"), 0.25, 0.25, 0.25);                   // ramplr: mix(black, white, u)
  EXPECT_NEAR(j.at("specular_roughness").get<double>(), 0.7, 1e-12);  // switch which 2: in3
  EXPECT_NEAR(j.at("fuzz_weight").get<double>(), 0.6, 1e-12);         // (1, 2, 3) · (0.1, 0.1, 0.1)
  EXPECT_NEAR(j.at("base_weight").get<double>(), 0.2, 1e-12);         // splitlr: u 0.25 < center 0.5
  EXPECT_NEAR(j.at("base_metalness").get<double>(), 0.2, 1e-12);      // separate3's outg of (0.1, 0.2, 0.3)
  MaterialxPoint other = test_point();
  other.v = 0.25;
  EXPECT_NEAR(graph_material("M_misc", other).at("coat_weight").get<double>(), 0.1, 1e-12);  // in2
}

TEST(MaterialxGraph, TheMaterialParserTakesTheShadingPoint) {
  const json d = {{"mtlx", graph_doc()}, {"material", "M_mix"}, {"uv", {1.0, 0.0}}};
  EXPECT_NO_THROW(material_from_json(d));
  const json bad = {{"mtlx", graph_doc()}, {"material", "M_mix"}, {"uv", {1.0}}};
  try {
    material_from_json(bad);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("uv must be an array of 2 numbers"), std::string::npos) << e.what();
  }
}

// The program on its own: registers, constants, an instruction per node.
TEST(MaterialxGraph, ProgramRunsInOrderWithoutTheDocument) {
  mtlxgraph::Program p;
  const auto half = p.constant({0.5, 0.5, 0.5, 0.5});
  mtlxgraph::Instr tc;
  tc.op = mtlxgraph::Op::Texcoord;
  const auto uv = p.emit(tc);
  mtlxgraph::Instr mul;
  mul.op = mtlxgraph::Op::Multiply;
  mul.in = {uv, half, 0, 0, 0, 0};
  const auto out = p.emit(mul);
  std::vector<mtlxgraph::Reg> regs(p.register_count());
  mtlxgraph::ShadingPoint at;
  at.u = 0.8;
  at.v = 0.2;
  p.run(at, regs);
  EXPECT_DOUBLE_EQ(regs[out][0], 0.4);
  EXPECT_DOUBLE_EQ(regs[out][1], 0.1);
}

// ---- Refusals: one line each -------------------------------------------------------

std::string doc_error(const std::string& body) {
  const std::string doc = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body + "</materialx>\n";
  try {
    materialx_to_json(doc, "doc.mtlx");
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }
  return "";
}

// An open_pbr_surface whose base_color is the nodegraph NG's output out, and `graph`.
std::string with_graph(const std::string& graph_nodes, const std::string& out_type = "color3") {
  return "  <nodegraph name=\"NG\">\n" + graph_nodes + "    <output name=\"out\" type=\"" + out_type +
         "\" nodename=\"last\" />\n  </nodegraph>\n"
         "  <open_pbr_surface name=\"SR\" type=\"surfaceshader\">\n"
         "    <input name=\"base_color\" type=\"color3\" nodegraph=\"NG\" output=\"out\" />\n"
         "  </open_pbr_surface>\n";
}

TEST(MaterialxGraph, ACycleIsRefused) {
  const std::string m = doc_error(with_graph(
      "    <add name=\"last\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"other\" /></add>\n"
      "    <add name=\"other\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"last\" /></add>\n"));
  EXPECT_NE(m.find("doc.mtlx: line 4: <add> \"last\": a cycle"), std::string::npos) << m;
}

// Joins its parts (GCC 12 warns falsely, -Warray-bounds, on chains of string +).
std::string join(std::initializer_list<std::string_view> parts) {
  std::string s;
  for (const std::string_view p : parts) s.append(p);
  return s;
}

TEST(MaterialxGraph, ATooDeepGraphIsRefused) {
  std::string nodes = "    <constant name=\"n0\" type=\"color3\"><input name=\"value\" type=\"color3\" value=\"0.1, 0.1, 0.1\" /></constant>\n";
  for (int i = 1; i <= 200; ++i) {
    const std::string name = i == 200 ? std::string("last") : join({"n", std::to_string(i)});
    nodes += join({"    <add name=\"", name, "\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"n",
                   std::to_string(i - 1), "\" /></add>\n"});
  }
  const std::string m = doc_error(with_graph(nodes));
  EXPECT_NE(m.find("nested more than 128 deep"), std::string::npos) << m;
  EXPECT_EQ(m.substr(0, 15), "doc.mtlx: line ") << m;
}

TEST(MaterialxGraph, AnEnormousGraphIsRefused) {
  // A binary tree of adds 15 levels deep: 2^15 − 1 nodes, each compiled once, more than
  // the program's bound of kMaxInstructions operations.
  std::string nodes;
  const int levels = 15;
  const auto node_name = [](int level, int k) {
    return level == 0 ? std::string("last") : join({"n", std::to_string(level), "_", std::to_string(k)});
  };
  for (int level = levels - 1; level >= 0; --level)
    for (int k = 0; k < (1 << level); ++k) {
      if (level == levels - 1) {
        nodes += join({"<constant name=\"", node_name(level, k), "\" type=\"color3\"><input name=\"value\" type=\"color3\" value=\"0,0,0\"/></constant>\n"});
        continue;
      }
      nodes += join({"<add name=\"", node_name(level, k), "\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"",
                     node_name(level + 1, 2 * k), "\"/><input name=\"in2\" type=\"color3\" nodename=\"", node_name(level + 1, 2 * k + 1),
                     "\"/></add>\n"});
    }
  const std::string m = doc_error(with_graph(nodes));
  EXPECT_NE(m.find("the graph is too large (more than 10000 operations or 60000 values)"), std::string::npos) << m;
}

TEST(MaterialxGraph, AnUnsupportedNodeIsNamedWithItsCategoryAndLine) {
  const std::string m = doc_error(with_graph("    <blur name=\"last\" type=\"color3\" />\n"));
  EXPECT_EQ(m, "doc.mtlx: line 4: <blur> \"last\": unsupported node (category \"blur\", type \"color3\")");
}

TEST(MaterialxGraph, AMissingImageIsNamedWithNodeFileAndLine) {
  const std::string m = doc_error(with_graph(
      "    <image name=\"last\" type=\"color3\">\n"
      "      <input name=\"file\" type=\"filename\" value=\"gonio_no_such_texture_7f3a.png\" />\n"
      "    </image>\n"));
  EXPECT_EQ(m, "image not found: gonio_no_such_texture_7f3a.png (node last, doc.mtlx:5)");
}

TEST(MaterialxGraph, ImagesResolveThroughFileprefixAncestorsAndTheSearchPath) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / "gonio_mtlx_image_paths";
  fs::remove_all(root);
  fs::create_directories(root / "resources/Images");
  fs::create_directories(root / "resources/Materials/Examples");
  fs::create_directories(root / "elsewhere");
  std::ofstream(root / "resources/Images/brass.png") << "not read here";
  std::ofstream(root / "elsewhere/wood.png") << "not read here";
  const auto doc_at = [&](const std::string& attrs, const std::string& file) {
    const fs::path p = root / "resources/Materials/Examples/doc.mtlx";
    std::ofstream(p) << "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\"" << attrs << ">\n"
                     << with_graph("    <image name=\"last\" type=\"color3\">\n      <input name=\"file\" type=\"filename\" value=\"" +
                                   file + "\" />\n    </image>\n")
                     << "</materialx>\n";
    try {
      materialx_file_to_json(p.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // Found (in an ancestor folder, by fileprefix): the lookup itself is what this build lacks.
  EXPECT_NE(doc_at("", "resources/Images/brass.png").find("image lookups are not in this build yet"), std::string::npos);
  EXPECT_NE(doc_at(" fileprefix=\"resources/Images/\"", "brass.png").find("image lookups are not in this build yet"),
            std::string::npos);
  EXPECT_NE(doc_at("", "wood.png").find("image not found: wood.png (node last, "), std::string::npos);
  ::setenv("GONIO_MTLX_SEARCH_PATH", ("/nonexistent:" + (root / "elsewhere").string()).c_str(), 1);
  EXPECT_NE(doc_at("", "wood.png").find("image lookups are not in this build yet"), std::string::npos);
  ::unsetenv("GONIO_MTLX_SEARCH_PATH");
  fs::remove_all(root);
}

}  // namespace
}  // namespace gonio
