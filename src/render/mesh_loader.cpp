// OBJ → Mesh: a strict check of every statement, then tinyobjloader, vertex
// deduplication, transform and UV tangents.

#include "gonio/render/mesh_loader.h"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <map>
#include <string_view>
#include <tuple>
#include <vector>

#include <tiny_obj_loader.h>

#include "gonio/error.h"
#include "gonio/json_text.h"

namespace gonio::render {
namespace {

// --- Strict OBJ statements ----------------------------------------------------------
// tinyobjloader is lenient by design: "nan" or "a" read as numbers, "1x" as 1, a NUL
// ends its line, out-of-range indices are left for the caller. So every line is checked
// here first, with "file:line: problem" errors, and tinyobjloader then only ever sees
// text known to be well-formed; it keeps doing the parsing and the triangulation.
// Accepted: v (3, 4 or 6 numbers), vt (1 to 3), vn (3), f (3 or more corners), l (2 or
// more), p (1 or more), the names o, g, s, and # comments. mtllib and usemtl are refused:
// a mesh takes its one material from the scene, and silently dropping the file's own
// materials would render something other than what the file describes.

class ObjChecker {
 public:
  explicit ObjChecker(const std::string& name) : name_(name) {}

  void check(std::string_view text) {
    size_t line_no = 0;
    for (size_t start = 0; start < text.size();) {
      size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      ++line_no;
      line_ = line_no;
      line(text.substr(start, end - start));
      start = end + 1;
    }
    // Positive indices may point forward; they are held to the file's totals at its end.
    for (const auto& f : forward_) {
      line_ = f.line;
      in_range(f.kind, f.index, counts_[f.kind], false);
    }
  }

 private:
  enum Kind { kVertex, kTexcoord, kNormal };
  struct Forward {
    size_t line;
    Kind kind;
    long long index;
  };

  // 'text', for messages. (Built by appending: GCC 12 warns falsely about "'" + string, bug 105651.)
  static std::string quoted(std::string_view text) {
    std::string s(1, '\'');
    s.append(text);
    s += '\'';
    return s;
  }

  [[noreturn]] void fail(const std::string& msg) const {
    throw InputError(name_ + ":" + std::to_string(line_) + ": " + msg);
  }

  void line(std::string_view s) {
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);  // CRLF line ends
    for (const char ch : s) {
      const auto c = static_cast<unsigned char>(ch);
      if ((c < 0x20 && c != '\t') || c == 0x7f) fail("control character " + quoted(std::string_view(&ch, 1)) + " in the line");
    }
    std::vector<std::string_view> tok;
    for (size_t i = 0; i < s.size();) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
      if (i >= s.size() || s[i] == '#') break;  // the rest is a comment
      const size_t b = i;
      while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
      tok.push_back(s.substr(b, i - b));
    }
    if (tok.empty()) return;
    const std::string_view key = tok[0];
    const size_t n = tok.size() - 1;
    if (key == "v") {
      if (n != 3 && n != 4 && n != 6) fail("v needs 3 numbers (x y z; or 4 with w, 6 with r g b), got " + std::to_string(n));
      numbers(tok);
      ++counts_[kVertex];
    } else if (key == "vt") {
      if (n < 1 || n > 3) fail("vt needs 1 to 3 numbers (u [v [w]]), got " + std::to_string(n));
      numbers(tok);
      ++counts_[kTexcoord];
    } else if (key == "vn") {
      if (n != 3) fail("vn needs 3 numbers (x y z), got " + std::to_string(n));
      numbers(tok);
      ++counts_[kNormal];
    } else if (key == "f" || key == "l" || key == "p") {
      const size_t least = key == "f" ? 3 : key == "l" ? 2 : 1;
      if (n < least)
        fail(std::string(key) + " needs at least " + std::to_string(least) + " vertices, got " + std::to_string(n));
      for (size_t i = 1; i < tok.size(); ++i) corner(tok[i]);
    } else if (key == "mtllib" || key == "usemtl") {
      fail(quoted(key) + " is not supported: a mesh takes its one material from the scene (the shape's "
           "\"material\"); remove the mtllib/usemtl lines, or split the mesh into one OBJ file per material");
    } else if (key != "o" && key != "g" && key != "s") {
      fail("unsupported statement " + quoted(key) + " (gonio reads v, vt, vn, f, l, p, o, g, s)");
    }
  }

  // Every number parsed completely, finite, and within float range (what the mesh stores).
  void numbers(const std::vector<std::string_view>& tok) const {
    for (size_t i = 1; i < tok.size(); ++i) {
      const std::string_view t = tok[i];
      const bool plus = t[0] == '+' && t.size() > 1 && t[1] != '-';
      const char* first = t.data() + (plus ? 1 : 0);
      const char* last = t.data() + t.size();
      double v = 0;
      const auto r = std::from_chars(first, last, v);
      const bool whole = r.ptr == last;
      if (whole && (r.ec == std::errc::result_out_of_range || (r.ec == std::errc() && std::isfinite(v) && std::abs(v) > FLT_MAX)))
        fail(quoted(t) + " does not fit in a float");
      if (r.ec != std::errc() || !whole) fail(quoted(t) + " is not a number");
      if (!std::isfinite(v)) fail(quoted(t) + " is not a finite number");
    }
  }

  // One vertex reference: v, v/t, v//n or v/t/n.
  void corner(std::string_view c) {
    std::string_view part[3];
    size_t parts = 0;
    for (size_t b = 0;;) {
      const size_t slash = c.find('/', b);
      if (parts == 3) fail(quoted(c) + " is not a vertex reference (v, v/t, v//n or v/t/n)");
      part[parts++] = c.substr(b, slash == std::string_view::npos ? std::string_view::npos : slash - b);
      if (slash == std::string_view::npos) break;
      b = slash + 1;
    }
    const bool ok = !part[0].empty() && !(parts == 2 && part[1].empty()) && !(parts == 3 && part[2].empty());
    if (!ok) fail(quoted(c) + " is not a vertex reference (v, v/t, v//n or v/t/n)");
    index(kVertex, part[0]);
    if (parts >= 2 && !part[1].empty()) index(kTexcoord, part[1]);
    if (parts == 3) index(kNormal, part[2]);
  }

  static const char* kind_name(Kind k) {
    return k == kVertex ? "vertex" : k == kTexcoord ? "texture coordinate" : "normal";
  }
  static std::string count_text(Kind k, long long count) {
    const char* plural = k == kVertex ? " vertices" : k == kTexcoord ? " texture coordinates" : " normals";
    return std::to_string(count) + plural;
  }

  // An index counts from 1; a negative one counts back from the last element so far.
  void index(Kind k, std::string_view t) {
    long long i = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), i);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail(std::string(kind_name(k)) + " index " + quoted(t) + " is not an integer in range");
    if (i == 0) fail(std::string(kind_name(k)) + " index 0 is not allowed (OBJ counts from 1)");
    if (i < 0) in_range(k, i, counts_[k], true);
    else if (i > counts_[k]) forward_.push_back({line_, k, i});
  }

  void in_range(Kind k, long long i, long long count, bool so_far) const {
    if (i > count || -i > count)
      fail(std::string(kind_name(k)) + " index " + std::to_string(i) + " out of range (" + count_text(k, count) +
           (so_far ? " so far)" : ")"));
  }

  std::string name_;
  size_t line_ = 0;
  long long counts_[3] = {0, 0, 0};
  std::vector<Forward> forward_;
};

// Rodrigues' rotation of v about the unit axis k by angle a.
Vec3 rotate(const Vec3& v, const Vec3& k, Float cos_a, Float sin_a) {
  return v * cos_a + cross(k, v) * sin_a + k * (dot(k, v) * (1 - cos_a));
}

}  // namespace

Mesh load_obj_mesh(const std::string& path, const MeshTransform& t, const std::string& where) {
  auto fail = [&](const std::string& msg) -> void { throw InputError(where + ": " + path + ": " + msg); };
  std::string text;
  try {
    text = read_text_file(path, kMaxObjFileBytes, "an OBJ mesh");
    ObjChecker(path).check(text);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // No material library (mtllib and usemtl are refused above): gonio takes the material
  // from the scene.
  if (!reader.ParseFromString(text, "", config)) {
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
