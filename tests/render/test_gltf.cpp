// glTF 2.0 scenes (gltf_loader.h): the project's own small files, written here, rendered
// and compared with closed forms (a spot light's irradiance, an orthographic projection),
// and malformed files refused in one line.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/render/gltf_loader.h"
#include "gonio/render/image.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"
#include "scratch_dir.h"

namespace gonio::render {
namespace {

using nlohmann::json;

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

// A glTF document under construction: one buffer (a data URI) that accessors append to.
struct Doc {
  json j = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", json::array()}}}},
            {"nodes", json::array()}, {"meshes", json::array()}, {"accessors", json::array()},
            {"bufferViews", json::array()}, {"materials", json::array()}};
  std::string bin;

  int accessor(const std::vector<float>& v, const char* type, int comps, bool with_minmax = false) {
    const size_t off = bin.size();
    bin.append(reinterpret_cast<const char*>(v.data()), v.size() * 4);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", v.size() * 4}});
    json a = {{"bufferView", j["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", v.size() / size_t(comps)}, {"type", type}};
    if (with_minmax) {
      std::vector<float> lo(size_t(comps), 1e30f), hi(size_t(comps), -1e30f);
      for (size_t i = 0; i < v.size(); ++i) lo[i % size_t(comps)] = std::min(lo[i % size_t(comps)], v[i]), hi[i % size_t(comps)] = std::max(hi[i % size_t(comps)], v[i]);
      a["min"] = lo, a["max"] = hi;
    }
    j["accessors"].push_back(a);
    return int(j["accessors"].size()) - 1;
  }
  int indices(const std::vector<std::uint32_t>& v) {
    const size_t off = bin.size();
    bin.append(reinterpret_cast<const char*>(v.data()), v.size() * 4);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", v.size() * 4}});
    j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1}, {"componentType", 5125}, {"count", v.size()}, {"type", "SCALAR"}});
    return int(j["accessors"].size()) - 1;
  }
  // A quad corner + s·e1 + t·e2, uv (0,0) at the corner, (1,0) at corner + e1.
  // swap_uv: u along e2, v along e1.
  int quad(const float c[3], const float e1[3], const float e2[3], int material, bool swap_uv = false) {
    std::vector<float> p, n, uv;
    const float st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const float nn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const float l = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    for (const auto& q : st) {
      for (int k = 0; k < 3; ++k) p.push_back(c[k] + q[0] * e1[k] + q[1] * e2[k]), n.push_back(nn[k] / l);
      uv.push_back(q[swap_uv ? 1 : 0]), uv.push_back(q[swap_uv ? 0 : 1]);
    }
    const int P = accessor(p, "VEC3", 3, true), N = accessor(n, "VEC3", 3), T = accessor(uv, "VEC2", 2);
    const int I = indices({0, 1, 2, 0, 2, 3});
    j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", P}, {"NORMAL", N}, {"TEXCOORD_0", T}}}, {"indices", I}, {"material", material}}}}});
    return int(j["meshes"].size()) - 1;
  }
  int node(json n) {
    j["nodes"].push_back(std::move(n));
    return int(j["nodes"].size()) - 1;
  }
  void root(int n) { j["scenes"][0]["nodes"].push_back(n); }
  std::string text() {
    json d = j;
    if (!bin.empty()) d["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return d.dump();
  }
};

// Rotation by −90° about x: local −z points down (−y), local +y points to −z.
const json kLookDown = {-0.70710678, 0.0, 0.0, 0.70710678};

Image render_gltf(const std::string& path, int spp, int size) {
  Scene scene = load_gltf_scene(path);
  scene.settings.spp = spp;
  scene.camera.width = scene.camera.height = size;
  RenderOptions o;
  o.threads = 2;
  return render(scene, o);
}

// KHR_lights_punctual's spot falloff, written out from the extension's specification.
double spot_closed_form(double cos_theta, double inner, double outer) {
  const double scale = 1 / std::max(0.001, std::cos(inner) - std::cos(outer));
  const double t = std::clamp(cos_theta * scale - std::cos(outer) * scale, 0.0, 1.0);
  return t * t;
}

TEST(Gltf, SpotLightOnLambertianFloorMatchesItsIrradiance) {
  gonio::test::ScratchDir dir("gonio_gltf");
  Doc d;
  // A white Lambertian floor: no specular layer (KHR_materials_specular factor 0).
  d.j["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}});
  const float c[3] = {-4, 0, -4}, e1[3] = {0, 0, 8}, e2[3] = {8, 0, 0};  // normal +y
  d.root(d.node({{"mesh", d.quad(c, e1, e2, 0)}}));
  const double I = 10, inner = 0.3, outer = 0.6, h = 2;
  d.j["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
  d.j["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "spot"}, {"intensity", I}, {"spot", {{"innerConeAngle", inner}, {"outerConeAngle", outer}}}}}}}}};
  d.root(d.node({{"translation", {0, h, 0}}, {"rotation", kLookDown}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}));
  // Orthographic camera 5 m up, looking down, 6 m × 6 m on 60 × 60 pixels; image up is −z.
  d.j["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 3}, {"ymag", 3}, {"znear", 0.1}, {"zfar", 100}}}}};
  d.root(d.node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", kLookDown}}));
  const std::string path = dir.file("spot.gltf", d.text());
  const Image img = render_gltf(path, 16, 60);
  ASSERT_EQ(img.width(), 60);
  // Radiance of a white Lambertian floor: E/π with E = I · falloff(θ) · cos θ / r², the
  // pixel's mean by a 16 × 16 quadrature over its footprint.
  for (int col : {30, 33, 36, 38, 40, 45}) {
    const int row = 30;
    double expect = 0;
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b) {
        const double x = ((col + (a + 0.5) / 16) / 60 * 2 - 1) * 3;
        const double z = -(1 - (row + (b + 0.5) / 16) / 60 * 2) * 3;
        const double r2 = x * x + z * z + h * h, ct = h / std::sqrt(r2);
        expect += I * spot_closed_form(ct, inner, outer) * ct / r2 / kPiD;
      }
    expect /= 256;
    EXPECT_NEAR(img.at(col, row)[0], expect, 0.01 * expect + 2e-4) << "column " << col;
  }
}

TEST(Gltf, DirectionalLightGivesItsIrradiance) {
  gonio::test::ScratchDir dir("gonio_gltf");
  Doc d;
  d.j["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}});
  const float c[3] = {-4, 0, -4}, e1[3] = {0, 0, 8}, e2[3] = {8, 0, 0};
  d.root(d.node({{"mesh", d.quad(c, e1, e2, 0)}}));
  d.j["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "directional"}, {"intensity", 3.0}, {"color", {1, 1, 1}}}}}}}};
  d.root(d.node({{"rotation", kLookDown}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}));
  d.j["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 100}}}}};
  d.root(d.node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", kLookDown}}));
  const Image img = render_gltf(dir.file("sun.gltf", d.text()), 4, 20);
  // L = ρ E / π with E = 3 lx straight down, ρ = 0.5.
  EXPECT_NEAR(img.at(10, 10)[1], 0.5 * 3 / kPiD, 1e-3);
}

TEST(Gltf, OrthographicCameraProjectsAndTextureTransformShifts) {
  gonio::test::ScratchDir dir("gonio_gltf");
  // A 2 × 2 texture, nearest, clamped: red, green (top row), blue, white (bottom row).
  Image tex(2, 2);
  tex.at(0, 0) = Color(1, 0, 0), tex.at(1, 0) = Color(0, 1, 0), tex.at(0, 1) = Color(0, 0, 1), tex.at(1, 1) = Color(1, 1, 1);
  write_png(tex, dir.path("rgbw.png"), {0, ToneMap::Clamp});
  for (int shifted = 0; shifted < 2; ++shifted) {
    Doc d;
    d.j["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
    d.j["images"] = {{{"uri", "rgbw.png"}}};
    d.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
    json info = {{"index", 0}};
    if (shifted) info["extensions"] = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
    d.j["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", info}}}, {"extensions", {{"KHR_materials_unlit", json::object()}}}});
    // Square x, y in [0.25, 0.75] at z = 0 facing +z (e1 × e2); uv (0, 0) at its top-left
    // corner, u to the right, v down.
    const float c[3] = {0.25f, 0.75f, 0}, e1[3] = {0, -0.5f, 0}, e2[3] = {0.5f, 0, 0};
    d.root(d.node({{"mesh", d.quad(c, e1, e2, 0, true)}}));
    d.j["cameras"] = {{{"type", "orthographic"}, {"name", "top"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 100}}}}};
    d.root(d.node({{"camera", 0}, {"translation", {0, 0, 5}}}));
    d.j["extensionsUsed"] = {"KHR_materials_unlit", "KHR_texture_transform"};
    const std::string path = dir.file("ortho.gltf", d.text());
    Scene scene = load_gltf_scene(path, {"top"});
    scene.camera.width = scene.camera.height = 40;  // 0.05 m pixels: columns 25–34, rows 5–14 hold the square
    scene.settings.spp = 4;
    RenderOptions o;
    o.threads = 2;
    const Image img = render(scene, o);
    EXPECT_EQ(img.at(24, 10)[0] + img.at(24, 10)[1] + img.at(24, 10)[2], 0);  // left of the square
    EXPECT_EQ(img.at(30, 4)[0] + img.at(30, 4)[1] + img.at(30, 4)[2], 0);     // above it
    EXPECT_EQ(img.at(30, 15)[0] + img.at(30, 15)[1] + img.at(30, 15)[2], 0);  // below it
    const Color tl = img.at(26, 6), tr = img.at(33, 6), bl = img.at(26, 13);
    if (!shifted) {
      EXPECT_NEAR(tl[0], 1, 1e-4);  // red
      EXPECT_NEAR(tl[1], 0, 1e-4);
      EXPECT_NEAR(tr[1], 1, 1e-4);  // green
      EXPECT_NEAR(tr[0], 0, 1e-4);
      EXPECT_NEAR(bl[2], 1, 1e-4);  // blue
    } else {
      // u + 0.5: the left half reads the right column; the right half clamps to it.
      EXPECT_NEAR(tl[1], 1, 1e-4);
      EXPECT_NEAR(tl[0], 0, 1e-4);
      EXPECT_NEAR(tr[1], 1, 1e-4);
      EXPECT_NEAR(bl[0], 1, 1e-4);  // white
    }
  }
}

TEST(Gltf, TextureTransformIsTheExtensionsMatrix) {
  // KHR_texture_transform: uv' = T R S uv with R's columns (cos r, sin r), (−sin r, cos r).
  const TextureTransform t = TextureTransform::make({0.1f, 0.2f}, 0.5f, {2, 3});
  const Vec2 p = t.apply({0.3f, 0.4f});
  EXPECT_NEAR(p.x, std::cos(0.5) * 0.6 - std::sin(0.5) * 1.2 + 0.1, 1e-6);
  EXPECT_NEAR(p.y, std::sin(0.5) * 0.6 + std::cos(0.5) * 1.2 + 0.2, 1e-6);
}

// One line, naming `needle`.
void expect_refused(const std::string& path, const std::string& needle) {
  try {
    load_gltf_scene(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find(needle), std::string::npos) << m;
  }
}

TEST(Gltf, MalformedFilesAreRefusedInOneLine) {
  gonio::test::ScratchDir dir("gonio_gltf");
  expect_refused(dir.file("trunc.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": ["), "trunc.gltf");
  expect_refused(dir.file("trunc.glb", std::string("glTF\x02\0\0\0\xff\0\0\0", 12)), "trunc.glb");
  expect_refused(dir.path("missing.gltf"), "missing.gltf");
  const float c[3] = {0, 0, 0}, e1[3] = {1, 0, 0}, e2[3] = {0, 1, 0};
  {  // an index beyond the vertices
    Doc d;
    d.root(d.node({{"mesh", d.quad(c, e1, e2, -1)}}));
    d.j["meshes"][0]["primitives"][0].erase("material");
    const int bad = d.indices({0, 1, 4});  // 4 vertices: 4 is the first index beyond them
    d.j["meshes"][0]["primitives"][0]["indices"] = bad;
    expect_refused(dir.file("index.gltf", d.text()), "index 4");
  }
  {  // a NaN position
    Doc d;
    const int P = d.accessor({0, 0, 0, 1, 0, 0, std::nanf(""), 1, 0}, "VEC3", 3);
    d.j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", P}}}}}}});
    d.root(d.node({{"mesh", 0}}));
    expect_refused(dir.file("nan.gltf", d.text()), "not finite");
  }
  {  // a cycle in the node graph
    Doc d;
    d.node({{"children", {1}}});
    d.node({{"children", {0}}});
    d.root(0);
    expect_refused(dir.file("cycle.gltf", d.text()), "cycle");
  }
  {  // an accessor that runs past its buffer view
    Doc d;
    const int P = d.accessor({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    d.j["accessors"][size_t(P)]["count"] = 1000000;
    d.j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", P}}}}}}});
    d.root(d.node({{"mesh", 0}}));
    expect_refused(dir.file("count.gltf", d.text()), "exceed");
  }
  {  // required extensions gonio lacks are named
    Doc d;
    d.j["extensionsUsed"] = {"KHR_draco_mesh_compression", "EXT_texture_webp"};
    d.j["extensionsRequired"] = {"KHR_draco_mesh_compression", "EXT_texture_webp"};
    expect_refused(dir.file("draco.gltf", d.text()), "KHR_draco_mesh_compression, EXT_texture_webp");
  }
  {  // an unknown camera name lists the file's
    Doc d;
    d.j["cameras"] = {{{"type", "perspective"}, {"name", "front"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    d.root(d.node({{"camera", 0}}));
    const std::string p = dir.file("cams.gltf", d.text());
    try {
      load_gltf_scene(p, {"side"});
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cameras: front"), std::string::npos) << e.what();
    }
  }
}

TEST(Gltf, NodeHierarchyComposesMatrixAndTrs) {
  gonio::test::ScratchDir dir("gonio_gltf");
  Doc d;
  const float c[3] = {0, 0, 0}, e1[3] = {1, 0, 0}, e2[3] = {0, 1, 0};
  const int mesh = d.quad(c, e1, e2, -1);
  d.j["meshes"][0]["primitives"][0].erase("material");
  // Parent: a matrix translating by (10, 0, 0) (column-major); child: scale (2, 3, 1) then
  // a 90° turn about z (quaternion (0, 0, sin 45°, cos 45°)) then translation (0, 1, 0).
  const int child = d.node({{"mesh", mesh}, {"scale", {2, 3, 1}}, {"rotation", {0, 0, 0.70710678, 0.70710678}}, {"translation", {0, 1, 0}}});
  d.root(d.node({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}, {"children", {child}}}));
  Scene s;
  append_gltf(s, dir.file("tree.gltf", d.text()), {}, "");
  ASSERT_EQ(s.meshes.size(), 1u);
  // Vertex (1, 0, 0) → scale (2, 0, 0) → turn (0, 2, 0) → + (0, 1, 0) → + (10, 0, 0)
  // (turning before scaling would give y = 3 + 1).
  const Vec3 p = s.meshes[0].positions[1];
  EXPECT_NEAR(p.x, 10, 1e-5);
  EXPECT_NEAR(p.y, 3, 1e-5);
  EXPECT_NEAR(p.z, 0, 1e-5);
  // Its normal (0, 0, 1) is unchanged by a turn about z.
  EXPECT_NEAR(s.meshes[0].normals[1].z, 1, 1e-5);
  // The glTF's default material (§3.9.6) is given to primitives without one.
  ASSERT_EQ(s.materials.size(), 1u);
}

}  // namespace
}  // namespace gonio::render
