// glTF 2.0 scenes (gltf_loader.h), parsed by tinygltf. tinygltf reads the JSON, the
// buffers (files, data URIs, the .glb binary chunk) and hands us each image's encoded
// bytes; this file checks every index and byte range itself before it reads, walks the
// node graph, and maps materials, lights and cameras onto gonio's (docs/gltf.md).
//
// References: the glTF 2.0 specification (Khronos, 2021) §3.5 (node transforms), §3.6–3.7
// (accessors, meshes), §3.9 (materials), §3.10 (cameras); the KHR_lights_punctual,
// KHR_texture_transform, KHR_mesh_quantization, KHR_materials_* extension specifications.

#include "gonio/render/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/io/notes.h"
#include "gonio/material.h"
#include "gonio/spectral_material.h"
#include "gonio/render/texture/texture_load.h"

namespace gonio::render {

namespace {

using nlohmann::json;

// Column-major 4 × 4 matrix, as glTF stores it.
using Mat4 = std::array<double, 16>;

Mat4 identity4() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[size_t(k * 4 + row)] * b[size_t(c * 4 + k)];
      r[size_t(c * 4 + row)] = s;
    }
  return r;
}

Vec3 xform_point(const Mat4& m, const Vec3& p) {
  return {Float(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12]), Float(m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13]),
          Float(m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14])};
}
Vec3 xform_vector(const Mat4& m, const Vec3& v) {
  return {Float(m[0] * v.x + m[4] * v.y + m[8] * v.z), Float(m[1] * v.x + m[5] * v.y + m[9] * v.z),
          Float(m[2] * v.x + m[6] * v.y + m[10] * v.z)};
}
// Normals go through the inverse transpose of the upper 3 × 3 (its cofactor matrix, up
// to the determinant's positive or negative scale, which normalisation and the sign fix
// below absorb).
Vec3 xform_normal(const Mat4& m, const Vec3& n, bool flip) {
  const double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6], i = m[10];
  const double cof[9] = {e * i - f * h, -(d * i - f * g), d * h - e * g, -(b * i - c * h), a * i - c * g,
                         -(a * h - b * g), b * f - c * e, -(a * f - c * d), a * e - b * d};
  Vec3 r{Float(cof[0] * n.x + cof[1] * n.y + cof[2] * n.z), Float(cof[3] * n.x + cof[4] * n.y + cof[5] * n.z),
         Float(cof[6] * n.x + cof[7] * n.y + cof[8] * n.z)};
  if (flip) r = -r;
  const Float l = length(r);
  return l > 0 && std::isfinite(l) ? r / l : Vec3{0, 0, 1};
}
double det3(const Mat4& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
}

// The MeshTransform of a scene JSON's "gltf" shape as a matrix: scale, then rotation
// about an axis (Rodrigues), then translation (mesh_loader.h's order).
Mat4 transform_matrix(const MeshTransform& t) {
  const Vec3 k = normalize(t.rotate_axis);
  const double th = double(t.rotate_degrees) * kPi / 180, c = std::cos(th), s = std::sin(th), v = 1 - c;
  const double R[9] = {c + k.x * k.x * v,       k.x * k.y * v - k.z * s, k.x * k.z * v + k.y * s,
                       k.y * k.x * v + k.z * s, c + k.y * k.y * v,       k.y * k.z * v - k.x * s,
                       k.z * k.x * v - k.y * s, k.z * k.y * v + k.x * s, c + k.z * k.z * v};
  Mat4 m = identity4();
  const double sc[3] = {t.scale.x, t.scale.y, t.scale.z};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) m[size_t(col * 4 + row)] = R[row * 3 + col] * sc[col];
  m[12] = t.translate.x, m[13] = t.translate.y, m[14] = t.translate.z;
  return m;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Extensions gonio reads (docs/gltf.md); any other in extensionsRequired is refused.
const std::set<std::string>& supported_extensions() {
  static const std::set<std::string> s = {
      "KHR_lights_punctual",         "KHR_texture_transform",       "KHR_mesh_quantization",
      "KHR_materials_unlit",         "KHR_materials_emissive_strength", "KHR_materials_ior",
      "KHR_materials_specular",      "KHR_materials_transmission",  "KHR_materials_volume",
      "KHR_materials_clearcoat",     "KHR_materials_sheen",         "KHR_materials_iridescence"};
  return s;
}

struct ImageBytes {
  std::vector<std::vector<unsigned char>> bytes;  // per glTF image, the encoded file
};

// tinygltf's image hook: keeps the encoded bytes; OpenImageIO decodes them once we know
// whether the image holds colour (sRGB) or data (linear).
bool keep_image_bytes(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                      const unsigned char* bytes, int size, void* user) {
  auto* store = static_cast<ImageBytes*>(user);
  if (index < 0 || size < 0) {
    if (err) *err = "image " + std::to_string(index) + ": invalid image data";
    return false;
  }
  if (store->bytes.size() <= size_t(index)) store->bytes.resize(size_t(index) + 1);
  store->bytes[size_t(index)].assign(bytes, bytes + size);
  image->width = image->height = 1;  // decoded later
  return true;
}

// What one textureInfo says: image, sampler, texCoord set and KHR_texture_transform.
struct TexRef {
  int texture = -1;
  int texcoord = 0;
  TextureTransform transform;
};

class GltfReader {
 public:
  GltfReader(std::string path, std::string where) : path_(std::move(path)), where_(std::move(where)) {}

  std::vector<GltfCamera> read(Scene& scene, const MeshTransform& t) {
    parse();
    check_extensions();
    scene_ = &scene;
    const Mat4 root = transform_matrix(t);
    if (model_.scenes.empty()) {
      // No scene: the file is a library of assets, and nothing is drawn (§3.3).
      note(name() + ": no scene; nothing to render");
      return {};
    }
    int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (size_t(s) >= model_.scenes.size()) fail("scene " + std::to_string(s) + " does not exist");
    const auto& nodes = model_.scenes[size_t(s)].nodes;
    for (size_t i = 0; i < nodes.size(); ++i) visit(nodes[i], root, "/scenes/" + std::to_string(s) + "/nodes/" + std::to_string(i), 0);
    for (const std::string& n : noted_) note(name() + ": " + n);
    return std::move(cameras_);
  }

 private:
  std::string path_, where_;
  tinygltf::Model model_;
  ImageBytes images_;
  Scene* scene_ = nullptr;
  std::vector<GltfCamera> cameras_;
  std::vector<int> on_path_;               // node indices from the root to the current one
  std::map<int, int> material_index_;      // glTF material → scene material (-1: default)
  std::map<std::pair<int, bool>, std::shared_ptr<const TextureImage>> decoded_;
  std::set<std::string> noted_;            // notes, each once

  std::string name() const { return where_.empty() ? path_ : where_ + ": " + path_; }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(name() + ": " + what); }
  void once(const std::string& what) { noted_.insert(what); }

  void parse() {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_image_bytes, &images_);
    std::string err, warn;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) fail("cannot open: no such file");
    // .glb by its magic, else JSON text.
    bool binary = false;
    if (FILE* f = std::fopen(path_.c_str(), "rb")) {
      char magic[4] = {};
      binary = std::fread(magic, 1, 4, f) == 4 && std::memcmp(magic, "glTF", 4) == 0;
      std::fclose(f);
    }
    bool ok = false;
    try {
      ok = binary ? loader.LoadBinaryFromFile(&model_, &err, &warn, path_)
                  : loader.LoadASCIIFromFile(&model_, &err, &warn, path_);
    } catch (const std::exception& e) {
      err = e.what();
    }
    if (!ok) {
      std::string line = err.empty() ? "not a valid glTF file" : err;
      std::replace_if(line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
      while (!line.empty() && line.back() == ' ') line.pop_back();
      fail(line);
    }
  }

  void check_extensions() {
    std::string refused;
    for (const std::string& e : model_.extensionsRequired)
      if (!supported_extensions().count(e)) refused += (refused.empty() ? "" : ", ") + e;
    if (!refused.empty()) fail("required extension" + std::string(refused.find(',') != std::string::npos ? "s " : " ") + refused + " not supported");
    for (const std::string& e : model_.extensionsUsed)
      if (!supported_extensions().count(e)) once("extension " + e + " is not supported and is ignored");
  }

  // ---------------------------------------------------------------- nodes
  Mat4 local_matrix(const tinygltf::Node& n, const std::string& at) const {
    auto finite = [&](const std::vector<double>& v, const char* field) {
      for (double x : v)
        if (!std::isfinite(x)) fail(at + "/" + field + ": not a finite number");
    };
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) fail(at + "/matrix: must have 16 numbers");
      finite(n.matrix, "matrix");
      Mat4 m;
      std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
      return m;
    }
    finite(n.translation, "translation");
    finite(n.rotation, "rotation");
    finite(n.scale, "scale");
    // M = T · R · S (§3.5.2), R from the unit quaternion (x, y, z, w).
    double x = 0, y = 0, z = 0, w = 1;
    if (n.rotation.size() == 4) {
      x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
      const double l = std::sqrt(x * x + y * y + z * z + w * w);
      if (!(l > 0)) fail(at + "/rotation: zero quaternion");
      x /= l, y /= l, z /= l, w /= l;
    }
    const double s[3] = {n.scale.size() == 3 ? n.scale[0] : 1, n.scale.size() == 3 ? n.scale[1] : 1,
                         n.scale.size() == 3 ? n.scale[2] : 1};
    const double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                         2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                         2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    Mat4 m = identity4();
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) m[size_t(col * 4 + row)] = R[row * 3 + col] * s[col];
    if (n.translation.size() == 3) m[12] = n.translation[0], m[13] = n.translation[1], m[14] = n.translation[2];
    return m;
  }

  void visit(int index, const Mat4& parent, const std::string& at, int depth) {
    if (index < 0 || size_t(index) >= model_.nodes.size()) fail(at + ": node " + std::to_string(index) + " does not exist");
    if (std::find(on_path_.begin(), on_path_.end(), index) != on_path_.end() || depth > 1024)
      fail("/nodes/" + std::to_string(index) + ": the node graph has a cycle");
    on_path_.push_back(index);
    const tinygltf::Node& n = model_.nodes[size_t(index)];
    const std::string here = "/nodes/" + std::to_string(index);
    const Mat4 world = mul(parent, local_matrix(n, here));
    if (n.mesh >= 0) mesh(n.mesh, world, here);
    if (n.camera >= 0) camera(n.camera, world, here);
    if (n.skin >= 0) once("skins are not supported (meshes are drawn in their bind pose)");
    auto it = n.extensions.find("KHR_lights_punctual");
    if (it != n.extensions.end() && it->second.Has("light")) light(it->second.Get("light").GetNumberAsInt(), world, here);
    for (int c : n.children) visit(c, world, here + "/children", depth + 1);
    on_path_.pop_back();
  }

  // ---------------------------------------------------------------- accessors
  // Reads accessor `a` as `comps` floats per element (integers normalised when the
  // accessor says so, KHR_mesh_quantization), checking every byte range.
  std::vector<float> read_floats(int a, int comps, const std::string& at) const {
    if (a < 0 || size_t(a) >= model_.accessors.size()) fail(at + ": accessor " + std::to_string(a) + " does not exist");
    const tinygltf::Accessor& acc = model_.accessors[size_t(a)];
    const std::string here = "/accessors/" + std::to_string(a);
    if (acc.sparse.isSparse) fail(here + ": sparse accessors are not supported");
    const int ncomp = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (ncomp != comps) fail(here + ": has " + std::to_string(ncomp) + " components, " + at + " needs " + std::to_string(comps));
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    if (csize <= 0) fail(here + "/componentType: invalid, got " + std::to_string(acc.componentType));
    if (acc.count > (size_t(1) << 28)) fail(here + "/count: too large, got " + std::to_string(acc.count));
    std::vector<float> out(acc.count * size_t(comps), 0.0f);
    if (acc.bufferView < 0) return out;  // all zeros (§3.6.2.1)
    const unsigned char* base = view_bytes(acc, size_t(comps) * size_t(csize), here);
    const size_t stride = stride_of(acc, size_t(comps) * size_t(csize));
    for (size_t i = 0; i < acc.count; ++i)
      for (int c = 0; c < comps; ++c) {
        const unsigned char* p = base + i * stride + size_t(c * csize);
        float v = 0;
        switch (acc.componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
          case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t x; std::memcpy(&x, p, 1); v = acc.normalized ? std::max(float(x) / 127.0f, -1.0f) : float(x); break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = acc.normalized ? float(*p) / 255.0f : float(*p); break;
          case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t x; std::memcpy(&x, p, 2); v = acc.normalized ? std::max(float(x) / 32767.0f, -1.0f) : float(x); break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t x; std::memcpy(&x, p, 2); v = acc.normalized ? float(x) / 65535.0f : float(x); break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t x; std::memcpy(&x, p, 4); v = float(x); break; }
          default: fail(here + "/componentType: not allowed here, got " + std::to_string(acc.componentType));
        }
        if (!std::isfinite(v)) fail(here + ": element " + std::to_string(i) + " is not finite");
        out[i * size_t(comps) + size_t(c)] = v;
      }
    return out;
  }

  size_t stride_of(const tinygltf::Accessor& acc, size_t elem) const {
    const tinygltf::BufferView& bv = model_.bufferViews[size_t(acc.bufferView)];
    return bv.byteStride ? bv.byteStride : elem;
  }

  // The first byte of accessor `acc`'s data, after checking that count elements of `elem`
  // bytes at its stride lie inside its buffer view and buffer.
  const unsigned char* view_bytes(const tinygltf::Accessor& acc, size_t elem, const std::string& here) const {
    if (size_t(acc.bufferView) >= model_.bufferViews.size()) fail(here + "/bufferView: " + std::to_string(acc.bufferView) + " does not exist");
    const tinygltf::BufferView& bv = model_.bufferViews[size_t(acc.bufferView)];
    const std::string bvat = "/bufferViews/" + std::to_string(acc.bufferView);
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size()) fail(bvat + "/buffer: " + std::to_string(bv.buffer) + " does not exist");
    const auto& data = model_.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
      fail(bvat + ": bytes " + std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) + " exceed the buffer's " + std::to_string(data.size()));
    const size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (bv.byteStride && bv.byteStride < elem) fail(bvat + "/byteStride: " + std::to_string(bv.byteStride) + " is smaller than an element");
    if (acc.count > 0) {
      const size_t need = acc.byteOffset + (acc.count - 1) * stride + elem;
      if (acc.byteOffset > bv.byteLength || (acc.count - 1) > (bv.byteLength / stride) || need > bv.byteLength)
        fail(here + ": " + std::to_string(acc.count) + " elements exceed buffer view " + std::to_string(acc.bufferView) + " (" + std::to_string(bv.byteLength) + " bytes)");
    }
    return data.data() + bv.byteOffset + acc.byteOffset;
  }

  std::vector<std::uint32_t> read_indices(int a, size_t vertex_count, const std::string& at) const {
    if (a < 0 || size_t(a) >= model_.accessors.size()) fail(at + ": accessor " + std::to_string(a) + " does not exist");
    const tinygltf::Accessor& acc = model_.accessors[size_t(a)];
    const std::string here = "/accessors/" + std::to_string(a);
    if (acc.type != TINYGLTF_TYPE_SCALAR) fail(here + ": indices must be SCALAR");
    if (acc.count > (size_t(1) << 30)) fail(here + "/count: too large, got " + std::to_string(acc.count));
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(here + "/componentType: indices must be unsigned byte, short or int, got " + std::to_string(acc.componentType));
    if (acc.bufferView < 0 || acc.sparse.isSparse) fail(here + ": indices need a buffer view (and no sparse storage)");
    const unsigned char* base = view_bytes(acc, size_t(csize), here);
    const size_t stride = stride_of(acc, size_t(csize));
    std::vector<std::uint32_t> out(acc.count);
    for (size_t i = 0; i < acc.count; ++i) {
      const unsigned char* p = base + i * stride;
      std::uint32_t v = 0;
      if (csize == 1) v = *p;
      else if (csize == 2) { uint16_t x; std::memcpy(&x, p, 2); v = x; }
      else std::memcpy(&v, p, 4);
      if (v >= vertex_count)
        fail(here + ": index " + std::to_string(v) + " at " + std::to_string(i) + " is out of range (" + std::to_string(vertex_count) + " vertices)");
      out[i] = v;
    }
    return out;
  }

  // ---------------------------------------------------------------- meshes
  void mesh(int index, const Mat4& world, const std::string& at) {
    if (size_t(index) >= model_.meshes.size()) fail(at + "/mesh: " + std::to_string(index) + " does not exist");
    const tinygltf::Mesh& gm = model_.meshes[size_t(index)];
    const bool flip = det3(world) < 0;  // a mirroring transform turns the winding around
    for (size_t p = 0; p < gm.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = gm.primitives[p];
      const std::string pat = "/meshes/" + std::to_string(index) + "/primitives/" + std::to_string(p);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != TINYGLTF_MODE_TRIANGLE_FAN &&
          prim.mode != -1) {
        once("points and lines are not drawn (" + pat + ")");
        continue;
      }
      if (prim.extensions.count("KHR_draco_mesh_compression")) fail(pat + ": KHR_draco_mesh_compression is not supported");
      auto attr = [&](const char* key) { auto it = prim.attributes.find(key); return it == prim.attributes.end() ? -1 : it->second; };
      const int pos = attr("POSITION");
      if (pos < 0) fail(pat + "/attributes: no POSITION");
      const std::vector<float> P = read_floats(pos, 3, pat + "/attributes/POSITION");
      const size_t nv = P.size() / 3;
      Mesh m;
      m.positions.resize(nv);
      for (size_t i = 0; i < nv; ++i) {
        m.positions[i] = xform_point(world, {P[3 * i], P[3 * i + 1], P[3 * i + 2]});
        if (!std::isfinite(m.positions[i].x) || !std::isfinite(m.positions[i].y) || !std::isfinite(m.positions[i].z))
          fail(pat + "/attributes/POSITION: vertex " + std::to_string(i) + " is not finite once placed");
      }
      if (const int a = attr("NORMAL"); a >= 0) {
        const std::vector<float> N = read_floats(a, 3, pat + "/attributes/NORMAL");
        if (N.size() != P.size()) fail(pat + "/attributes/NORMAL: count differs from POSITION's");
        m.normals.resize(nv);
        for (size_t i = 0; i < nv; ++i) m.normals[i] = xform_normal(world, {N[3 * i], N[3 * i + 1], N[3 * i + 2]}, false);
      }
      if (const int a = attr("TEXCOORD_0"); a >= 0) {
        const std::vector<float> T = read_floats(a, 2, pat + "/attributes/TEXCOORD_0");
        if (T.size() != 2 * nv) fail(pat + "/attributes/TEXCOORD_0: count differs from POSITION's");
        m.uvs.resize(nv);
        for (size_t i = 0; i < nv; ++i) m.uvs[i] = {T[2 * i], T[2 * i + 1]};
      }
      if (const int a = attr("TANGENT"); a >= 0) {
        const std::vector<float> T = read_floats(a, 4, pat + "/attributes/TANGENT");
        if (T.size() != 4 * nv) fail(pat + "/attributes/TANGENT: count differs from POSITION's");
        m.tangents.resize(nv);
        for (size_t i = 0; i < nv; ++i) {
          const Vec3 t = xform_vector(world, {T[4 * i], T[4 * i + 1], T[4 * i + 2]});
          const Float l = length(t);
          m.tangents[i] = l > 0 ? t / l : Vec3{1, 0, 0};
        }
      }
      if (attr("COLOR_0") >= 0) once("vertex colours (COLOR_0) are ignored");
      if (attr("JOINTS_0") >= 0 || !prim.targets.empty()) once("skinning and morph targets are ignored");
      // Triangles: indexed or not; strips and fans unrolled (§3.7.2.1).
      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0) idx = read_indices(prim.indices, nv, pat + "/indices");
      else {
        idx.resize(nv);
        for (size_t i = 0; i < nv; ++i) idx[i] = std::uint32_t(i);
      }
      if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        std::vector<std::uint32_t> tri;
        for (size_t i = 2; i < idx.size(); ++i) {
          if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) tri.insert(tri.end(), {idx[0], idx[i - 1], idx[i]});
          else if (i % 2 == 0) tri.insert(tri.end(), {idx[i - 2], idx[i - 1], idx[i]});
          else tri.insert(tri.end(), {idx[i - 1], idx[i - 2], idx[i]});
        }
        idx = std::move(tri);
      }
      idx.resize(idx.size() - idx.size() % 3);
      if (flip)
        for (size_t t = 0; t + 2 < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
      if (idx.empty()) continue;
      m.indices = std::move(idx);
      if (m.tangents.empty() && !m.uvs.empty()) m.tangents = uv_tangents(m);
      m.material = material(prim.material, pat + "/material");
      scene_->meshes.push_back(std::move(m));
    }
  }

  // Tangents where the file has none: per vertex, the area-weighted sum of its triangles'
  // dP/du (the direction of increasing u, MikkTSpace's convention for the tangent, which
  // glTF §3.7.2.1 names), made orthogonal to the vertex normal.
  static std::vector<Vec3> uv_tangents(const Mesh& m) {
    std::vector<Vec3> t(m.positions.size(), Vec3{0, 0, 0});
    for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const std::uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
      const Vec3 e1 = m.positions[b] - m.positions[a], e2 = m.positions[c] - m.positions[a];
      const Float du1 = m.uvs[b].x - m.uvs[a].x, dv1 = m.uvs[b].y - m.uvs[a].y;
      const Float du2 = m.uvs[c].x - m.uvs[a].x, dv2 = m.uvs[c].y - m.uvs[a].y;
      const Float det = du1 * dv2 - du2 * dv1;
      if (!(std::abs(det) > 0)) continue;
      // dP/du = (e1 dv2 − e2 dv1) / det; scaled by |det| the sum weighs by uv area.
      const Vec3 dpdu = (e1 * dv2 - e2 * dv1) * (det > 0 ? Float(1) : Float(-1));
      t[a] += dpdu, t[b] += dpdu, t[c] += dpdu;
    }
    for (size_t v = 0; v < t.size(); ++v) {
      Vec3 x = t[v];
      if (!m.normals.empty()) x = x - m.normals[v] * dot(m.normals[v], x);
      const Float l = length(x);
      t[v] = l > 0 && std::isfinite(l) ? x / l : Vec3{0, 0, 0};
    }
    return t;
  }

  // ---------------------------------------------------------------- materials
  static double num(const tinygltf::Value& v, const char* key, double def) {
    if (!v.IsObject() || !v.Has(key)) return def;
    const tinygltf::Value& x = v.Get(key);
    return x.IsNumber() ? x.GetNumberAsDouble() : def;
  }
  static std::array<double, 3> vec3v(const tinygltf::Value& v, const char* key, std::array<double, 3> def) {
    if (!v.IsObject() || !v.Has(key)) return def;
    const tinygltf::Value& x = v.Get(key);
    if (!x.IsArray() || x.ArrayLen() != 3) return def;
    for (int i = 0; i < 3; ++i) def[size_t(i)] = x.Get(i).IsNumber() ? x.Get(i).GetNumberAsDouble() : def[size_t(i)];
    return def;
  }

  TexRef texref(int index, int texcoord, const tinygltf::ExtensionMap& ext, const std::string& at) {
    TexRef r{index, texcoord, {}};
    if (index < 0) return r;
    if (size_t(index) >= model_.textures.size()) fail(at + "/index: texture " + std::to_string(index) + " does not exist");
    auto it = ext.find("KHR_texture_transform");
    if (it != ext.end()) {
      const tinygltf::Value& v = it->second;
      Vec2 off{0, 0}, sc{1, 1};
      if (v.Has("offset") && v.Get("offset").ArrayLen() == 2) off = {Float(v.Get("offset").Get(0).GetNumberAsDouble()), Float(v.Get("offset").Get(1).GetNumberAsDouble())};
      if (v.Has("scale") && v.Get("scale").ArrayLen() == 2) sc = {Float(v.Get("scale").Get(0).GetNumberAsDouble()), Float(v.Get("scale").Get(1).GetNumberAsDouble())};
      const Float rot = Float(num(v, "rotation", 0));
      if (!std::isfinite(off.x) || !std::isfinite(off.y) || !std::isfinite(sc.x) || !std::isfinite(sc.y) || !std::isfinite(rot))
        fail(at + "/extensions/KHR_texture_transform: not finite");
      r.transform = TextureTransform::make(off, rot, sc);
      if (v.Has("texCoord")) r.texcoord = v.Get("texCoord").GetNumberAsInt();
    }
    if (r.texcoord != 0) once("texture coordinate sets other than TEXCOORD_0 are read as TEXCOORD_0");
    return r;
  }
  TexRef texref(const tinygltf::TextureInfo& t, const std::string& at) { return texref(t.index, t.texCoord, t.extensions, at); }
  TexRef texref_value(const tinygltf::Value& ext, const char* key, const std::string& at) {
    if (!ext.IsObject() || !ext.Has(key)) return {};
    const tinygltf::Value& v = ext.Get(key);
    tinygltf::ExtensionMap em;
    if (v.Has("extensions") && v.Get("extensions").Has("KHR_texture_transform"))
      em["KHR_texture_transform"] = v.Get("extensions").Get("KHR_texture_transform");
    return texref(int(num(v, "index", -1)), int(num(v, "texCoord", 0)), em, at + "/" + key);
  }

  std::shared_ptr<const TextureImage> image_of(int texture, bool srgb, const std::string& at) {
    const tinygltf::Texture& t = model_.textures[size_t(texture)];
    int source = t.source;
    for (const char* e : {"KHR_texture_basisu", "EXT_texture_webp", "MSFT_texture_dds"})
      if (t.extensions.count(e) && source < 0) fail(at + ": texture " + std::to_string(texture) + " needs " + e + ", which is not supported");
    if (source < 0 || size_t(source) >= model_.images.size()) fail(at + ": texture " + std::to_string(texture) + " has no image");
    const auto key = std::make_pair(source, srgb);
    if (auto it = decoded_.find(key); it != decoded_.end()) return it->second;
    if (size_t(source) >= images_.bytes.size() || images_.bytes[size_t(source)].empty())
      fail("/images/" + std::to_string(source) + ": no image data");
    const auto& b = images_.bytes[size_t(source)];
    const tinygltf::Image& im = model_.images[size_t(source)];
    const std::string label = name() + ": /images/" + std::to_string(source) + (im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "" : " (" + im.uri + ")");
    auto img = std::make_shared<const TextureImage>(load_texture_memory(b.data(), b.size(), label, srgb ? ColorEncoding::Srgb : ColorEncoding::Linear));
    decoded_[key] = img;
    return img;
  }

  TextureSampler sampler_of(int texture) const {
    TextureSampler s;
    const tinygltf::Texture& t = model_.textures[size_t(texture)];
    if (t.sampler < 0 || size_t(t.sampler) >= model_.samplers.size()) return s;  // repeat, auto filtering
    const tinygltf::Sampler& g = model_.samplers[size_t(t.sampler)];
    auto wrap = [](int w) { return w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE ? TextureWrap::Clamp : w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::Mirror : TextureWrap::Repeat; };
    s.wrap_s = wrap(g.wrapS);
    s.wrap_t = wrap(g.wrapT);
    if (g.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) s.mag = TextureFilter::Nearest;
    switch (g.minFilter) {
      case TINYGLTF_TEXTURE_FILTER_NEAREST: s.min = TextureFilter::Nearest; s.mipmaps = false; break;
      case TINYGLTF_TEXTURE_FILTER_LINEAR: s.mipmaps = false; break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: s.min = TextureFilter::Nearest; break;
      default: break;
    }
    return s;
  }

  // A texture driving gltf_pbr parameter `key`: the texel's RGB (channel < 0) or one channel, times factor.
  void bind(Material& m, const TexRef& r, const char* key, int channel, const Color& factor, bool srgb, const std::string& at) {
    if (r.texture < 0) return;
    const auto param = varying_param("gltf_pbr", key);
    if (!param) return;
    ParamTexture pt;
    pt.param = *param;
    Texture& t = pt.texture;
    t.layer_image = image_of(r.texture, srgb, at);
    t.sampler = sampler_of(r.texture);
    t.transform = r.transform;
    t.channel = channel;
    t.factor = factor;
    t.lo = Color(0);
    t.hi = Color(1);
    m.textures.push_back(std::move(pt));
  }

  // A glTF material as gonio's `gltf_pbr` (SPEC §3: the Khronos model, one piece of code
  // with MaterialX's gltf_pbr nodes; docs/gltf_pbr.md), its factors as the parameters and its
  // textures driving them per hit.
  int material(int index, const std::string& at) {
    if (auto it = material_index_.find(index); it != material_index_.end()) return it->second;
    json d = {{"type", "gltf_pbr"}};
    const tinygltf::Material* gm = nullptr;
    std::string mat = "/materials/" + std::to_string(index);
    if (index >= 0) {
      if (size_t(index) >= model_.materials.size()) fail(at + ": material " + std::to_string(index) + " does not exist");
      gm = &model_.materials[size_t(index)];
    }
    // glTF's default material (§3.9.6): white, metallic 1, roughness 1 (gltf_pbr's defaults).
    std::array<double, 4> bc{1, 1, 1, 1};
    double metallic = 1, roughness = 1;
    std::array<double, 3> emissive{0, 0, 0};
    double strength = 1;
    const tinygltf::Value none;
    auto ext = [&](const char* name) -> const tinygltf::Value& {
      if (!gm) return none;
      auto it = gm->extensions.find(name);
      return it == gm->extensions.end() ? none : it->second;
    };
    if (gm) {
      const auto& pbr = gm->pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4) std::copy(pbr.baseColorFactor.begin(), pbr.baseColorFactor.end(), bc.begin());
      metallic = pbr.metallicFactor;
      roughness = pbr.roughnessFactor;
      if (gm->emissiveFactor.size() == 3) std::copy(gm->emissiveFactor.begin(), gm->emissiveFactor.end(), emissive.begin());
      strength = num(ext("KHR_materials_emissive_strength"), "emissiveStrength", 1);
    }
    auto in01 = [&](double v, const std::string& field) {
      if (!(v >= 0 && v <= 1)) fail(mat + "/" + field + ": must be in [0, 1], got " + std::to_string(v));
      return v;
    };
    auto clamp01 = [](double v) { return std::clamp(v, 0.0, 1.0); };
    auto colour01 = [&](const std::array<double, 3>& c) { return json{clamp01(c[0]), clamp01(c[1]), clamp01(c[2])}; };
    for (int i = 0; i < 4; ++i) in01(bc[size_t(i)], "pbrMetallicRoughness/baseColorFactor");
    in01(metallic, "pbrMetallicRoughness/metallicFactor");
    in01(roughness, "pbrMetallicRoughness/roughnessFactor");
    for (double e : emissive) in01(e, "emissiveFactor");
    if (!(strength >= 0 && std::isfinite(strength))) fail(mat + "/extensions/KHR_materials_emissive_strength/emissiveStrength: must be >= 0");
    const bool unlit = ext("KHR_materials_unlit").IsObject();
    d["base_color"] = {bc[0], bc[1], bc[2]};
    d["metallic"] = metallic;
    d["roughness"] = roughness;
    d["ior"] = std::clamp(num(ext("KHR_materials_ior"), "ior", 1.5), 1.0, 5.0);
    if (const auto& s = ext("KHR_materials_specular"); s.IsObject()) {
      d["specular"] = clamp01(num(s, "specularFactor", 1));
      d["specular_color"] = colour01(vec3v(s, "specularColorFactor", {1, 1, 1}));
    }
    const double transmission = clamp01(num(ext("KHR_materials_transmission"), "transmissionFactor", 0));
    d["transmission"] = transmission;
    if (const auto& vol = ext("KHR_materials_volume"); vol.IsObject()) {
      d["thickness"] = std::clamp(num(vol, "thicknessFactor", 0), 0.0, 1e9);
      const double dist = num(vol, "attenuationDistance", 0);
      if (dist > 0 && std::isfinite(dist)) {
        d["attenuation_distance"] = std::min(dist, 1e9);
        d["attenuation_color"] = colour01(vec3v(vol, "attenuationColor", {1, 1, 1}));
      }
    }
    if (const auto& c = ext("KHR_materials_clearcoat"); c.IsObject()) {
      d["clearcoat"] = clamp01(num(c, "clearcoatFactor", 0));
      d["clearcoat_roughness"] = clamp01(num(c, "clearcoatRoughnessFactor", 0));
    }
    if (const auto& s = ext("KHR_materials_sheen"); s.IsObject()) {
      d["sheen_color"] = colour01(vec3v(s, "sheenColorFactor", {0, 0, 0}));
      d["sheen_roughness"] = clamp01(num(s, "sheenRoughnessFactor", 0));
    }
    if (const auto& a = ext("KHR_materials_anisotropy"); a.IsObject()) {
      d["anisotropy_strength"] = clamp01(num(a, "anisotropyStrength", 0));
      d["anisotropy_rotation"] = std::clamp(num(a, "anisotropyRotation", 0), -1000.0, 1000.0);
    }
    if (const auto& x = ext("KHR_materials_dispersion"); x.IsObject())
      d["dispersion"] = std::clamp(num(x, "dispersion", 0), 0.0, 1e4);
    if (const auto& x = ext("KHR_materials_diffuse_transmission"); x.IsObject()) {
      d["diffuse_transmission"] = clamp01(num(x, "diffuseTransmissionFactor", 0));
      d["diffuse_transmission_color"] = colour01(vec3v(x, "diffuseTransmissionColorFactor", {1, 1, 1}));
    }
    if (ext("KHR_materials_iridescence").IsObject())
      once("KHR_materials_iridescence is not implemented yet (gltf_pbr, docs/gltf_pbr.md): rendered without the film");
    const double emit = std::max({emissive[0], emissive[1], emissive[2]});
    if (emit > 0 && strength > 0) {
      d["emissive"] = {emissive[0], emissive[1], emissive[2]};
      d["emissive_strength"] = std::min(strength, 1e9);
    }
    if (unlit) {
      // KHR_materials_unlit: the surface shows its base colour whatever the light: an
      // emitter of radiance base colour that reflects nothing (a black dielectric without
      // specular reflection).
      d = {{"type", "gltf_pbr"}, {"base_color", 0.0}, {"metallic", 0.0}, {"specular", 0.0},
           {"emissive", {bc[0], bc[1], bc[2]}}, {"emissive_strength", 1.0}};
    }
    // Alpha (§3.9.4): OPAQUE ignores alpha; MASK cuts out where alpha < alphaCutoff; BLEND
    // is coverage. From the factor only (a texture's alpha is not read yet).
    if (gm && gm->alphaMode == "MASK") {
      d["alpha_mode"] = 1;
      d["alpha"] = bc[3];
      d["alpha_cutoff"] = clamp01(gm->alphaCutoff);
    } else if (gm && gm->alphaMode == "BLEND") {
      d["alpha_mode"] = 2;
      d["alpha"] = bc[3];
    }
    if (gm && (gm->normalTexture.index >= 0)) once("normal textures are not applied yet (shading normals come from NORMAL)");
    if (gm && (gm->occlusionTexture.index >= 0)) once("occlusion textures are ignored (a path tracer computes occlusion)");

    Material m;
    m.name = gm ? gm->name : "gltf default";
    MaterialWithSpectra parsed = material_with_spectra_from_json(d, name() + ": " + mat, "");
    m.bxdf = std::move(parsed.bxdf);
    m.spectra = std::move(parsed.spectra);
    if (gm && !unlit) {
      const auto& pbr = gm->pbrMetallicRoughness;
      bind(m, texref(pbr.baseColorTexture, mat + "/pbrMetallicRoughness/baseColorTexture"), "base_color", -1,
           Color(Float(bc[0]), Float(bc[1]), Float(bc[2])), true, mat);
      const TexRef mr = texref(pbr.metallicRoughnessTexture, mat + "/pbrMetallicRoughness/metallicRoughnessTexture");
      bind(m, mr, "roughness", 1, Color(Float(roughness)), false, mat);  // roughness in G
      bind(m, mr, "metallic", 2, Color(Float(metallic)), false, mat);    // metalness in B
      if (emit > 0 && strength > 0)
        bind(m, texref(gm->emissiveTexture, mat + "/emissiveTexture"), "emissive", -1,
             Color(Float(emissive[0]), Float(emissive[1]), Float(emissive[2])), true, mat);
    } else if (gm && unlit) {
      bind(m, texref(gm->pbrMetallicRoughness.baseColorTexture, mat + "/pbrMetallicRoughness/baseColorTexture"), "emissive", -1,
           Color(Float(bc[0]), Float(bc[1]), Float(bc[2])), true, mat);
    }
    if (const auto* model = std::get_if<GltfPbrBxDF>(&m.bxdf.models())) {
      const auto& p = model->params;
      m.emits = p.emissive_strength > 0 && !p.emissive.is_black() && model->coverage() > 0;
      m.emits_both_sides = false;  // glTF 2.0 §3.9.3: emission leaves the front face
    }
    scene_->materials.push_back(std::move(m));
    const int id = int(scene_->materials.size()) - 1;
    material_index_[index] = id;
    return id;
  }

  // ---------------------------------------------------------------- lights, cameras
  void light(int index, const Mat4& world, const std::string& at) {
    if (index < 0 || size_t(index) >= model_.lights.size()) fail(at + "/extensions/KHR_lights_punctual/light: " + std::to_string(index) + " does not exist");
    const tinygltf::Light& l = model_.lights[size_t(index)];
    const std::string lat = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
    Color c(1);
    if (l.color.size() == 3) c = Color(Float(l.color[0]), Float(l.color[1]), Float(l.color[2]));
    if (!(l.intensity >= 0 && std::isfinite(l.intensity)) || !c.is_finite() || c[0] < 0 || c[1] < 0 || c[2] < 0)
      fail(lat + ": colour and intensity must be finite and >= 0");
    PointLight p;
    // Photometric units one to one (SPEC §3): I cd → radiant intensity I; E lx → irradiance E.
    p.intensity = c * Float(l.intensity);
    p.position = xform_point(world, {0, 0, 0});
    const Vec3 dir = xform_vector(world, {0, 0, -1});  // lights point along their local −z
    p.direction = length(dir) > 0 ? normalize(dir) : Vec3{0, 0, -1};
    if (l.type == "directional") p.directional = true;
    else if (l.type == "spot") {
      const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
      if (!(inner >= 0 && inner < outer && outer <= kPi / 2 + 1e-9)) fail(lat + "/spot: needs 0 <= innerConeAngle < outerConeAngle <= pi/2");
      p.cos_outer = Float(std::cos(outer));
      p.cos_inner = Float(std::cos(inner));
    } else if (l.type != "point") {
      fail(lat + "/type: must be point, spot or directional, got \"" + l.type + "\"");
    }
    if (l.range > 0) once("the range of KHR_lights_punctual lights is ignored (inverse-square falloff)");
    scene_->point_lights.push_back(p);
  }

  void camera(int index, const Mat4& world, const std::string& at) {
    if (size_t(index) >= model_.cameras.size()) fail(at + "/camera: " + std::to_string(index) + " does not exist");
    const tinygltf::Camera& gc = model_.cameras[size_t(index)];
    const std::string cat = "/cameras/" + std::to_string(index);
    GltfCamera out;
    out.name = gc.name;
    Camera& c = out.camera;
    // A camera looks along its local −z with +y up (§3.10.1).
    c.position = xform_point(world, {0, 0, 0});
    const Vec3 fwd = xform_vector(world, {0, 0, -1}), up = xform_vector(world, {0, 1, 0});
    if (!(length(fwd) > 0) || !(length(up) > 0)) fail(cat + ": its node's transform is degenerate");
    c.look_at = c.position + normalize(fwd);
    c.up = normalize(up);
    double aspect = 0;
    if (gc.type == "orthographic") {
      const double ymag = gc.orthographic.ymag, xmag = gc.orthographic.xmag;
      if (!(ymag > 0 && std::isfinite(ymag)) || !(xmag > 0 && std::isfinite(xmag))) fail(cat + "/orthographic: xmag and ymag must be > 0");
      c.ortho_half_height = Float(ymag * length(up));
      aspect = xmag / ymag;
    } else {
      const double yfov = gc.perspective.yfov;
      if (!(yfov > 0 && yfov < kPi)) fail(cat + "/perspective/yfov: must be in (0, pi), got " + std::to_string(yfov));
      c.fov_deg = Float(yfov * 180 / kPi);
      aspect = gc.perspective.aspectRatio;
    }
    if (aspect > 0 && std::isfinite(aspect) && aspect < 100) {
      out.has_aspect = true;
      c.height = 360;
      c.width = std::max(1, int(std::lround(360 * aspect)));
    }
    cameras_.push_back(out);
  }
};

}  // namespace

bool is_gltf_path(const std::string& path) {
  const std::string e = lower(std::filesystem::path(path).extension().string());
  return e == ".gltf" || e == ".glb";
}

std::vector<GltfCamera> append_gltf(Scene& scene, const std::string& path, const MeshTransform& transform,
                                    const std::string& where) {
  GltfReader r(path, where);
  return r.read(scene, transform);
}

Scene load_gltf_scene(const std::string& path, const GltfSceneOptions& options) {
  Scene scene;
  scene.environment = Environment();
  const std::vector<GltfCamera> cams = append_gltf(scene, path, {}, "");
  if (!options.camera.empty()) {
    auto it = std::find_if(cams.begin(), cams.end(), [&](const GltfCamera& c) { return c.name == options.camera; });
    if (it == cams.end()) {
      std::string names;
      for (const auto& c : cams)
        if (!c.name.empty()) names += (names.empty() ? "" : ", ") + c.name;
      throw InputError(path + ": --camera " + options.camera + ": no such camera" + (names.empty() ? " (the file names none)" : " (cameras: " + names + ")"));
    }
    scene.camera = it->camera;
  } else if (!cams.empty()) {
    scene.camera = cams.front().camera;
  } else {
    // No camera: look at the geometry's bounding box from +z, far enough for a 40° view.
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const Mesh& m : scene.meshes)
      for (const Vec3& p : m.positions)
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    if (hi.x >= lo.x) {
      const Vec3 c = (lo + hi) * Float(0.5);
      const Float r = std::max(length(hi - lo) * Float(0.5), Float(1e-3));
      scene.camera.look_at = c;
      scene.camera.position = c + Vec3{0, 0, r / std::tan(Float(20) * kPi / 180) + (hi.z - c.z)};
      scene.camera.up = {0, 1, 0};
    }
  }
  return scene;
}

}  // namespace gonio::render
