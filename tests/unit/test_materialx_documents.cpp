// MaterialX document structure (src/io/materialx.cpp, SPEC §2): xi:include (nesting
// bound, cycles), SPEC §2's naming rule (surfacematerials; else NODEGRAPH/OUTPUT
// surfaceshader outputs and top-level surface shader nodes), pbrlib's `surface` wrapper,
// a node of a gonio material type mapped under its own name, and what is ignored with a
// note (displacement, shading normals). The documents are written by each test.

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/io/materialx.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A fresh folder for one test's documents.
fs::path doc_dir(const std::string& test) {
  const fs::path d = fs::temp_directory_path() / ("gonio_mtlx_docs_" + test);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_doc(const fs::path& p, const std::string& body) {
  std::ofstream(p) << "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
                   << body << "</materialx>\n";
}

std::string shader(const std::string& name, double roughness) {
  return "  <open_pbr_surface name=\"" + name + "\" type=\"surfaceshader\">\n    <input name=\"specular_roughness\" type=\"float\" value=\"" +
         std::to_string(roughness) + "\" />\n  </open_pbr_surface>\n";
}

std::string material(const std::string& name, const std::string& shader_name) {
  return "  <surfacematerial name=\"" + name + "\" type=\"material\">\n    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"" +
         shader_name + "\" />\n  </surfacematerial>\n";
}

std::string error_of(const fs::path& p, const std::optional<std::string>& name = std::nullopt) {
  try {
    materialx_file_to_json(p.string(), name);
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }
  return "";
}

TEST(MaterialxDocuments, XIncludeBringsTheIncludedDocumentsElements) {
  const fs::path d = doc_dir("include");
  fs::create_directories(d / "lib");
  write_doc(d / "lib/shaders.mtlx", shader("SR_inc", 0.125));
  write_doc(d / "main.mtlx", "  <xi:include href=\"lib/shaders.mtlx\" />\n" + material("M", "SR_inc"));
  EXPECT_DOUBLE_EQ(materialx_file_to_json((d / "main.mtlx").string()).at("specular_roughness").get<double>(), 0.125);
  // An error inside the included document names that document and its line.
  write_doc(d / "lib/bad.mtlx", "  <open_pbr_surface name=\"SR_bad\" type=\"surfaceshader\">\n    <input name=\"base_weight\" type=\"float\" value=\"x\" />\n  </open_pbr_surface>\n");
  write_doc(d / "bad_main.mtlx", "  <xi:include href=\"lib/bad.mtlx\" />\n" + material("M", "SR_bad"));
  const std::string m = error_of(d / "bad_main.mtlx");
  EXPECT_NE(m.find((d / "lib/bad.mtlx").string() + ": line 4: <open_pbr_surface> \"SR_bad\": input base_weight"), std::string::npos) << m;
  fs::remove_all(d);
}

TEST(MaterialxDocuments, XIncludeCyclesDepthAndMissingFilesAreRefused) {
  const fs::path d = doc_dir("include_bad");
  write_doc(d / "a.mtlx", "  <xi:include href=\"b.mtlx\" />\n" + shader("SR", 0.5));
  write_doc(d / "b.mtlx", "  <xi:include href=\"a.mtlx\" />\n");
  const std::string cycle = error_of(d / "a.mtlx");
  EXPECT_NE(cycle.find((d / "b.mtlx").string() + ": line 3: <xi:include> \"a.mtlx\": an include cycle"), std::string::npos) << cycle;
  // A chain of 10 documents: more than 8 nested includes.
  for (int i = 0; i < 10; ++i) {
    std::string file = "c", next = "  <xi:include href=\"c";
    file.append(std::to_string(i)).append(".mtlx");
    next.append(std::to_string(i + 1)).append(".mtlx\" />\n");
    write_doc(d / file, i == 9 ? shader("SR", 0.5) : next);
  }
  const std::string deep = error_of(d / "c0.mtlx");
  EXPECT_NE(deep.find("includes nested more than 8 deep"), std::string::npos) << deep;
  write_doc(d / "missing.mtlx", "  <xi:include href=\"nowhere.mtlx\" />\n" + shader("SR", 0.5));
  const std::string missing = error_of(d / "missing.mtlx");
  EXPECT_NE(missing.find("line 3: <xi:include> \"nowhere.mtlx\": no such document"), std::string::npos) << missing;
  fs::remove_all(d);
}

TEST(MaterialxDocuments, NamingRuleMaterialsFirst) {
  const fs::path d = doc_dir("naming");
  write_doc(d / "two.mtlx", shader("SR_a", 0.1) + shader("SR_b", 0.2) + material("M_a", "SR_a") + material("M_b", "SR_b"));
  EXPECT_EQ(materialx_surface_names((d / "two.mtlx").string()), (std::vector<std::string>{"M_a", "M_b"}));
  EXPECT_NEAR(materialx_file_to_json((d / "two.mtlx").string(), "M_b").at("specular_roughness").get<double>(), 0.2, 1e-12);
  const std::string none = error_of(d / "two.mtlx");
  EXPECT_NE(none.find("several surfaces (\"M_a\", \"M_b\")"), std::string::npos) << none;
  // Without materials: a nodegraph's surfaceshader output as NODEGRAPH/OUTPUT and a
  // top-level shader node, in document order.
  write_doc(d / "bare.mtlx",
            "  <nodegraph name=\"NG\">\n" + shader("SR_in", 0.3) +
                "    <output name=\"surf\" type=\"surfaceshader\" nodename=\"SR_in\" />\n  </nodegraph>\n" + shader("SR_top", 0.4));
  EXPECT_EQ(materialx_surface_names((d / "bare.mtlx").string()), (std::vector<std::string>{"NG/surf", "SR_top"}));
  EXPECT_NEAR(materialx_file_to_json((d / "bare.mtlx").string(), "NG/surf").at("specular_roughness").get<double>(), 0.3, 1e-12);
  EXPECT_NEAR(materialx_file_to_json((d / "bare.mtlx").string(), "SR_top").at("specular_roughness").get<double>(), 0.4, 1e-12);
  const std::string wrong = error_of(d / "bare.mtlx", "SR_in");
  EXPECT_NE(wrong.find("no surface named \"SR_in\" (its surfaces: \"NG/surf\", \"SR_top\")"), std::string::npos) << wrong;
  write_doc(d / "one.mtlx", shader("SR_only", 0.6));
  EXPECT_NEAR(materialx_file_to_json((d / "one.mtlx").string()).at("specular_roughness").get<double>(), 0.6, 1e-12);
  write_doc(d / "empty.mtlx", "");
  EXPECT_NE(error_of(d / "empty.mtlx").find("the document has no surface"), std::string::npos);
  fs::remove_all(d);
}

TEST(MaterialxDocuments, SurfaceWrapperAndANodeOfAGonioTypeByItsName) {
  const fs::path d = doc_dir("surface");
  // pbrlib's surface around a BSDF node; `diffuse` is a gonio type, so the node maps to
  // {"type": "diffuse", its inputs}.
  write_doc(d / "s.mtlx",
            "  <diffuse name=\"D\" type=\"BSDF\">\n    <input name=\"reflectance\" type=\"color3\" value=\"0.2, 0.4, 0.6\" />\n  </diffuse>\n"
            "  <surface name=\"S\" type=\"surfaceshader\">\n    <input name=\"bsdf\" type=\"BSDF\" nodename=\"D\" />\n"
            "    <input name=\"opacity\" type=\"float\" value=\"1\" />\n  </surface>\n" +
                material("M", "S"));
  EXPECT_EQ(materialx_file_to_json((d / "s.mtlx").string()), json::parse(R"({"type": "diffuse", "reflectance": [0.2, 0.4, 0.6]})"));
  // An emitter or a partial opacity keeps the wrapper.
  write_doc(d / "o.mtlx",
            "  <diffuse name=\"D\" type=\"BSDF\" />\n"
            "  <surface name=\"S\" type=\"surfaceshader\">\n    <input name=\"bsdf\" type=\"BSDF\" nodename=\"D\" />\n"
            "    <input name=\"opacity\" type=\"float\" value=\"0.5\" />\n  </surface>\n" +
                material("M", "S"));
  EXPECT_EQ(materialx_file_to_json((d / "o.mtlx").string()), json::parse(R"({"type": "surface", "bsdf": {"type": "diffuse"}, "opacity": 0.5})"));
  // A pbrlib node this build has no type for: refused naming node, category and line.
  write_doc(d / "u.mtlx",
            "  <burley_diffuse_bsdf name=\"H\" type=\"BSDF\" />\n"
            "  <surface name=\"S\" type=\"surfaceshader\">\n    <input name=\"bsdf\" type=\"BSDF\" nodename=\"H\" />\n  </surface>\n" +
                material("M", "S"));
  EXPECT_EQ(error_of(d / "u.mtlx"),
            (d / "u.mtlx").string() + ": line 3: <burley_diffuse_bsdf> \"H\": unsupported node (category \"burley_diffuse_bsdf\", type \"BSDF\")");
  fs::remove_all(d);
}

TEST(MaterialxDocuments, DisplacementAndNormalMapsAreIgnoredWithANote) {
  const fs::path d = doc_dir("ignored");
  write_doc(d / "n.mtlx",
            "  <nodegraph name=\"NG\">\n    <normal name=\"n\" type=\"vector3\" />\n    <output name=\"out\" type=\"vector3\" nodename=\"n\" />\n  </nodegraph>\n"
            "  <open_pbr_surface name=\"SR\" type=\"surfaceshader\">\n    <input name=\"geometry_normal\" type=\"vector3\" nodegraph=\"NG\" output=\"out\" />\n  </open_pbr_surface>\n"
            "  <displacement name=\"disp\" type=\"displacementshader\" />\n"
            "  <surfacematerial name=\"M\" type=\"material\">\n    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\" />\n"
            "    <input name=\"displacementshader\" type=\"displacementshader\" nodename=\"disp\" />\n  </surfacematerial>\n");
  std::string note;
  const json j = materialx_file_to_json((d / "n.mtlx").string(), std::nullopt, &note);
  EXPECT_EQ(j.at("type"), "openpbr");
  EXPECT_NE(note.find("input geometry_normal ignored: the shading frame is the caller's (line 8)"), std::string::npos) << note;
  EXPECT_NE(note.find("<surfacematerial> \"M\": input displacementshader ignored (line 13)"), std::string::npos) << note;
  fs::remove_all(d);
}

}  // namespace
}  // namespace gonio
