// The material reference (issue 10): `gonio materials [TYPE] [--markdown]`, the committed
// docs/materials.md, and the parser agreeing with the registry both are printed from.

#include <fstream>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <cstdint>
#include <vector>

#include "../merl_files.h"
#include "gonio/material.h"
#include "gonio/rgl/write.h"
#include "gonio/material_types.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The committed reference must be exactly what the tool prints, byte for byte.
TEST(CliMaterials, DocsMaterialsMdIsTheGeneratedReference) {
  const std::string path = std::string(GONIO_SOURCE_DIR) + "/docs/materials.md";
  const std::string committed = read_file(path);
  const RunResult r = run_gonio({"materials", "--markdown"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  if (r.out == committed) return;
  // Name the first line that differs.
  const auto want = split_lines(r.out), have = split_lines(committed);
  size_t i = 0;
  while (i < want.size() && i < have.size() && want[i] == have[i]) ++i;
  ADD_FAILURE() << "docs/materials.md differs from `gonio materials --markdown` (first at line " << i + 1
                << ":\n  committed: " << (i < have.size() ? have[i] : "<end of file>")
                << "\n  generated: " << (i < want.size() ? want[i] : "<end of output>")
                << ")\nRegenerate it: build/bin/gonio materials --markdown > docs/materials.md";
}

// The types of SPEC §2 this build implements, in SPEC §2's order (written out here, not
// taken from the registry).
// A small RGL .bsdf file (a Lambertian, written by gonio's own writer at a low resolution).
const std::string& small_rgl_file() {
  static const gonio_test_merl::TempTable file(gonio_test_merl::temp_path("materials_rgl"));
  static const bool written = [] {
    gonio::RglWriteOptions opt;
    opt.n_theta_i = 4;
    opt.n_ndf = 16;
    opt.n_sample = 8;
    const std::vector<std::uint8_t> bytes =
        gonio::tabulate_rgl(gonio::parse_material(R"({"type":"diffuse","reflectance":0.5})"), opt);
    gonio_test_merl::write_bytes(file.path, std::vector<unsigned char>(bytes.begin(), bytes.end()));
    return true;
  }();
  (void)written;
  return file.path;
}

const std::vector<std::string> kImplemented = {"diffuse", "mirror",     "conductor", "dielectric", "roughconductor",
                                               "roughdielectric", "orennayar", "phong", "blinnphong", "ward",
                                               "ashikhminshirley", "plastic", "blend", "measured", "rgl", "subsurface",
                                               "eon", "sheen", "thindielectric", "layered", "openpbr",
                                               "gltf_pbr",
                                               "oren_nayar_diffuse_bsdf", "conductor_bsdf", "dielectric_bsdf",
                                               "sheen_bsdf", "mix", "add", "multiply", "layer",
                                               "hair", "chiang_hair_bsdf"};

TEST(CliMaterials, ListsEveryTypeOnOneLine) {
  const RunResult r = run_gonio({"materials"});
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), kImplemented.size()) << r.out;
  for (size_t i = 0; i < lines.size(); ++i) {
    EXPECT_EQ(lines[i].substr(0, kImplemented[i].size() + 1), kImplemented[i] + " ") << lines[i];
    EXPECT_GT(lines[i].size(), kImplemented[i].size() + 10) << "no description: " << lines[i];
  }
}

TEST(CliMaterials, OneTypeShowsItsParameters) {
  const RunResult r = run_gonio({"materials", "roughconductor"});
  ASSERT_EQ(r.status, 0) << describe(r);
  for (const char* m : {"alpha: number or [alpha_x, alpha_y]; default required; range (0, 10]",
                        "distribution: \"ggx\" or \"beckmann\"; default \"ggx\"", "multiscatter: true or false; default false",
                        "material: measured metal: Au", "source: Cook & Torrance 1982"})
    EXPECT_NE(r.out.find(m), std::string::npos) << m << "\n" << r.out;
  const RunResult o = run_gonio({"materials", "orennayar"});
  EXPECT_NE(o.out.find("sigma: number; default required; range [0, 90) degrees"), std::string::npos) << o.out;
}

TEST(CliMaterials, UnknownTypeIsOneLineExitTwo) {
  const RunResult r = run_gonio({"materials", "roughconductr"});
  expect_bad_input(r, {"unknown type", "roughconductr", "roughconductor"});
  expect_bad_input(run_gonio({"materials", "diffuse", "--markdown"}), {"--markdown"});
}

// Unknown parameters name the ones the type takes (one line, exit 2).
TEST(CliMaterials, UnknownParameterListsTheValidOnes) {
  const RunResult r = run_gonio({"eval", "--bsdf", R"({"type":"roughconductor","alpha":0.2,"material":"Au","distrib":"ggx"})"},
                                "0 0 1 0 0 1\n");
  expect_bad_input(r);
  EXPECT_EQ(r.err,
            "gonio: --bsdf: roughconductor: unknown parameter 'distrib'; roughconductor takes alpha, distribution, "
            "fresnel, eta, k, material, f0, f82, multiscatter, thin_film\n");
  // A misspelt required parameter is named as unknown, not reported missing.
  const RunResult typo = run_gonio({"eval", "--bsdf", R"({"type":"roughconductor","alpah":0.2,"material":"Au"})"},
                                   "0 0 1 0 0 1\n");
  expect_bad_input(typo);
  EXPECT_EQ(typo.err,
            "gonio: --bsdf: roughconductor: unknown parameter 'alpah'; roughconductor takes alpha, distribution, "
            "fresnel, eta, k, material, f0, f82, multiscatter, thin_film\n");
}

TEST(CliMaterials, UnknownParameterInABlendComponent) {
  const RunResult r = run_gonio(
      {"albedo", "--theta", "0", "--bsdf",
       R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"mirror"},{"type":"diffuse","colour":0.5}]})"});
  expect_bad_input(r);
  EXPECT_EQ(r.err, "gonio: --bsdf: blend.bsdfs[1]: diffuse: unknown parameter 'colour'; diffuse takes reflectance\n");
  const RunResult top = run_gonio(
      {"albedo", "--theta", "0", "--bsdf",
       R"({"type":"blend","weight":0.5,"wieght":0.5,"bsdfs":[{"type":"mirror"},{"type":"diffuse"}]})"});
  expect_bad_input(top);
  EXPECT_EQ(top.err, "gonio: --bsdf: blend: unknown parameter 'wieght'; blend takes weight, bsdfs\n");
}

// A description of each type that the parser accepts with nothing but its required
// parameters (written here from SPEC §2, not from the registry). Made on first use, not
// when the program starts: `measured` writes a 35 MB table, and every test of this
// program runs in its own process (0.2 s each in Release, 0.35 s under ASan).
const std::map<std::string, nlohmann::json>& minimal_descriptions() {
  static const std::map<std::string, nlohmann::json> descriptions = {
      {"diffuse", {{"type", "diffuse"}}},
      {"mirror", {{"type", "mirror"}}},
      {"conductor", {{"type", "conductor"}, {"eta", 1.5}}},
      {"dielectric", {{"type", "dielectric"}}},
      {"roughconductor", {{"type", "roughconductor"}, {"alpha", 0.3}, {"eta", 1.5}}},
      {"roughdielectric", {{"type", "roughdielectric"}, {"alpha", 0.3}}},
      {"orennayar", {{"type", "orennayar"}, {"sigma", 20}}},
      {"eon", {{"type", "eon"}}},
      {"phong", {{"type", "phong"}, {"kd", 0}, {"ks", 0}, {"exponent", 10}}},
      {"blinnphong", {{"type", "blinnphong"}, {"kd", 0}, {"ks", 0}, {"exponent", 10}}},
      {"ward", {{"type", "ward"}, {"kd", 0}, {"ks", 0}, {"alpha", 0.3}}},
      {"ashikhminshirley", {{"type", "ashikhminshirley"}, {"rd", 0}, {"rs", 0}, {"nu", 10}, {"nv", 10}}},
      {"plastic", {{"type", "plastic"}}},
      {"blend", {{"type", "blend"}, {"weight", 0.5}, {"bsdfs", {{{"type", "diffuse"}}, {{"type", "mirror"}}}}}},
      {"layered", {{"type", "layered"}, {"top", {{"type", "dielectric"}}}, {"bottom", {{"type", "diffuse"}}}}},
      {"measured", {{"type", "measured"}, {"file", gonio_test_merl::lambert_table()}}},
      {"rgl", {{"type", "rgl"}, {"file", small_rgl_file()}}},
      {"subsurface", {{"type", "subsurface"}, {"sigma_s", 1}, {"sigma_a", 0.1}}},
      {"sheen", {{"type", "sheen"}}},
      {"thindielectric", {{"type", "thindielectric"}}},
      {"openpbr", {{"type", "openpbr"}}},
      {"gltf_pbr", {{"type", "gltf_pbr"}}},
      {"oren_nayar_diffuse_bsdf", {{"type", "oren_nayar_diffuse_bsdf"}}},
      {"conductor_bsdf", {{"type", "conductor_bsdf"}}},
      {"dielectric_bsdf", {{"type", "dielectric_bsdf"}}},
      {"sheen_bsdf", {{"type", "sheen_bsdf"}}},
      {"mix", {{"type", "mix"}, {"fg", {{"type", "sheen_bsdf"}}}, {"bg", {{"type", "oren_nayar_diffuse_bsdf"}}}}},
      {"add", {{"type", "add"}, {"in1", {{"type", "sheen_bsdf"}}}, {"in2", {{"type", "oren_nayar_diffuse_bsdf"}}}}},
      {"multiply", {{"type", "multiply"}, {"in1", {{"type", "oren_nayar_diffuse_bsdf"}}}}},
      {"layer", {{"type", "layer"}, {"top", {{"type", "dielectric_bsdf"}}}, {"base", {{"type", "oren_nayar_diffuse_bsdf"}}}}},
      {"hair", {{"type", "hair"}}},
      {"chiang_hair_bsdf", {{"type", "chiang_hair_bsdf"}}},
  };
  return descriptions;
}

bool parses(const nlohmann::json& j, std::string* error = nullptr) {
  try {
    gonio::material_from_json(j);
    return true;
  } catch (const gonio::InputError& e) {
    if (error) *error = e.what();
    return false;
  }
}

// What the reference says is what the parser does: every registered type is one of
// SPEC §2's; leaving out a required parameter is an error; a default given explicitly
// gives the same model as leaving it out; the ends of each range are accepted or refused
// as their brackets say, and values beyond are refused with a message naming the range.
TEST(CliMaterials, ParserFollowsTheReference) {
  ASSERT_EQ(gonio::material_types().size(), kImplemented.size());
  const gonio::Vec3 wo = gonio::normalize(gonio::Vec3{0.3f, 0.1f, 1}), wi = gonio::normalize(gonio::Vec3{-0.2f, 0.4f, 1});
  for (const auto& t : gonio::material_types()) {
    const std::string type(t.name);
    ASSERT_TRUE(minimal_descriptions().count(type)) << type;
    ASSERT_TRUE(parses(minimal_descriptions().at(type))) << minimal_descriptions().at(type).dump();
    for (const auto& p : t.params) {
      const std::string key(p.name);
      nlohmann::json base = minimal_descriptions().at(type);
      if (type == "plastic" && key == "distribution") base["alpha"] = 0.3;  // a rough coat
      if (key == "f82") {  // F82-tint: f0 and f82, no index
        base.erase("eta");
        base["fresnel"] = "f82";
        base["f0"] = 0.5;
      }
      if (type == "subsurface") {  // each key within its form of the medium
        if (key == "distribution") base["alpha"] = 0.3;  // a rough boundary
        if (key == "albedo" || key == "mfp") base = {{"type", "subsurface"}, {"albedo", 0.5}, {"mfp", 1}};
        if (key == "medium" || key == "scale") base = {{"type", "subsurface"}, {"medium", "marble"}};
      }
      // The base with `key` set to v (f0 needs Schlick and no index).
      auto with = [&](const nlohmann::json& v) {
        nlohmann::json j = base;
        if (key == "f0") {
          j.erase("eta");
          j["fresnel"] = "schlick";
        }
        if (key == "material") j.erase("eta");
        j[key] = v;
        return j;
      };
      if (p.required) {
        nlohmann::json j = base;
        j.erase(key);
        std::string err;
        EXPECT_FALSE(parses(j, &err)) << type << " without " << key;
        EXPECT_NE(err.find("missing parameter '" + key + "'"), std::string::npos) << err;
      }
      if (!p.default_json.empty()) {
        const auto explicit_default = gonio::material_from_json(with(nlohmann::json::parse(p.default_json)));
        const auto implicit = gonio::material_from_json(base);
        EXPECT_EQ(explicit_default.f(wo, wi), implicit.f(wo, wi)) << type << "." << key;
        EXPECT_EQ(explicit_default.pdf(wo, wi), implicit.pdf(wo, wi)) << type << "." << key;
      }
      if (!p.range.present) continue;
      // gltf_pbr's iridescence is declared (MaterialX's input) but refused above 0 until it is
      // implemented (docs/gltf_pbr.md): tests/unit/test_gltf_pbr.cpp checks the refusal.
      if (type == "gltf_pbr" && key == "iridescence") continue;
      const double lo = p.range.lo, hi = p.range.hi;
      // A pair (MaterialX's vector2) takes each value as [v, v].
      const bool pair = p.kind == gonio::ParamKind::Pair;
      const auto value = [&](double v) { return pair ? nlohmann::json::array({v, v}) : nlohmann::json(v); };
      // A value strictly inside, the two ends, and two values beyond them.
      // (A whole number for the counts: layered's max_depth and samples; gltf_pbr's alpha_mode.)
      const double inside = lo + 0.25 * (hi - lo);
      const bool whole = key == "max_depth" || key == "samples" || key == "alpha_mode";
      EXPECT_TRUE(parses(with(value(whole ? std::round(inside) : inside)))) << type << "." << key;
      std::string err;
      EXPECT_EQ(parses(with(value(lo)), &err), !p.range.lo_open) << type << "." << key << " = " << lo << ": " << err;
      EXPECT_EQ(parses(with(value(hi)), &err), !p.range.hi_open) << type << "." << key << " = " << hi << ": " << err;
      for (double beyond : {lo - 1e-3 * (hi - lo) - 1e-3, hi + 1e-3 * (hi - lo) + 1e-3}) {
        EXPECT_FALSE(parses(with(value(beyond)), &err)) << type << "." << key << " = " << beyond;
        EXPECT_NE(err.find(key + " must be"), std::string::npos) << err;
      }
    }
  }
}

}  // namespace
}  // namespace gonio_cli_test
