// OBJ → Mesh with tinyobjloader, vertex deduplication, transform and UV tangents.

#include "gonio/render/mesh_loader.h"

#include <cmath>
#include <map>
#include <tuple>

#include <tiny_obj_loader.h>

#include "gonio/error.h"

namespace gonio::render {
namespace {

// Rodrigues' rotation of v about the unit axis k by angle a.
Vec3 rotate(const Vec3& v, const Vec3& k, Float cos_a, Float sin_a) {
  return v * cos_a + cross(k, v) * sin_a + k * (dot(k, v) * (1 - cos_a));
}

}  // namespace

Mesh load_obj_mesh(const std::string& path, const MeshTransform& t, const std::string& where) {
  auto fail = [&](const std::string& msg) -> void { throw InputError(where + ": " + path + ": " + msg); };
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    for (char& c : err) if (c == '\n') c = ' ';
    fail(err.empty() ? "cannot read the OBJ file" : err);
  }
  const tinyobj::attrib_t& a = reader.GetAttrib();
  const size_t nv = a.vertices.size() / 3, nn = a.normals.size() / 3, nt = a.texcoords.size() / 2;

  // One mesh vertex per distinct (position, normal, uv) triple.
  std::map<std::tuple<int, int, int>, std::uint32_t> vertex_of;
  std::vector<tinyobj::index_t> corners;
  for (const auto& shape : reader.GetShapes()) {
    size_t offset = 0;
    for (const auto fv : shape.mesh.num_face_vertices) {
      if (fv != 3) fail("a face has " + std::to_string(fv) + " vertices after triangulation");
      for (size_t k = 0; k < 3; ++k) corners.push_back(shape.mesh.indices[offset + k]);
      offset += fv;
    }
  }
  if (corners.empty()) fail("no triangles");
  bool all_normals = true, all_uvs = true;
  for (const auto& c : corners) {
    if (c.vertex_index < 0 || static_cast<size_t>(c.vertex_index) >= nv)
      fail("vertex index " + std::to_string(c.vertex_index + 1) + " out of range (" + std::to_string(nv) + " vertices)");
    if (c.normal_index >= 0 && static_cast<size_t>(c.normal_index) >= nn) fail("normal index out of range");
    if (c.texcoord_index >= 0 && static_cast<size_t>(c.texcoord_index) >= nt) fail("texture coordinate index out of range");
    all_normals &= c.normal_index >= 0;
    all_uvs &= c.texcoord_index >= 0;
  }

  const Float angle = t.rotate_degrees * kPi / 180;
  const Float ca = std::cos(angle), sa = std::sin(angle);
  const Vec3 axis = normalize(t.rotate_axis);
  Mesh m;
  for (const auto& c : corners) {
    const auto key = std::make_tuple(c.vertex_index, all_normals ? c.normal_index : -1, all_uvs ? c.texcoord_index : -1);
    auto [it, inserted] = vertex_of.try_emplace(key, static_cast<std::uint32_t>(m.positions.size()));
    if (inserted) {
      const auto vi = static_cast<size_t>(c.vertex_index);
      Vec3 p{a.vertices[3 * vi], a.vertices[3 * vi + 1], a.vertices[3 * vi + 2]};
      p = rotate({p.x * t.scale.x, p.y * t.scale.y, p.z * t.scale.z}, axis, ca, sa) + t.translate;
      if (!is_finite(p)) fail("vertex " + std::to_string(vi + 1) + " is not finite");
      m.positions.push_back(p);
      if (all_normals) {
        const auto ni = static_cast<size_t>(c.normal_index);
        Vec3 n{a.normals[3 * ni], a.normals[3 * ni + 1], a.normals[3 * ni + 2]};
        // Normals transform by the inverse transpose: divide by the scale, then rotate.
        n = rotate({n.x / t.scale.x, n.y / t.scale.y, n.z / t.scale.z}, axis, ca, sa);
        m.normals.push_back(is_finite(n) ? normalize(n) : Vec3{});
      }
      if (all_uvs) {
        const auto ti = static_cast<size_t>(c.texcoord_index);
        m.uvs.push_back({a.texcoords[2 * ti], a.texcoords[2 * ti + 1]});
      }
    }
    m.indices.push_back(it->second);
  }

  // Tangents along dP/du, accumulated over the triangles around each vertex
  // (E. Lengyel, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh", 2001).
  if (all_uvs) {
    m.tangents.assign(m.positions.size(), Vec3{});
    for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const std::uint32_t i0 = m.indices[i], i1 = m.indices[i + 1], i2 = m.indices[i + 2];
      const Vec3 e1 = m.positions[i1] - m.positions[i0], e2 = m.positions[i2] - m.positions[i0];
      const Float du1 = m.uvs[i1].x - m.uvs[i0].x, dv1 = m.uvs[i1].y - m.uvs[i0].y;
      const Float du2 = m.uvs[i2].x - m.uvs[i0].x, dv2 = m.uvs[i2].y - m.uvs[i0].y;
      const Float det = du1 * dv2 - du2 * dv1;
      if (!(std::abs(det) > 1e-20f)) continue;
      const Vec3 dpdu = (e1 * dv2 - e2 * dv1) / det;
      if (!is_finite(dpdu)) continue;
      for (std::uint32_t v : {i0, i1, i2}) m.tangents[v] += dpdu;
    }
  }
  return m;
}

}  // namespace gonio::render
