// The closed-mesh check of the random walk (subsurface_walk.h).

#include "gonio/render/subsurface_walk.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace gonio::render {
namespace {

struct PositionKey {
  std::uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = k.x;
    h = h * 0x9e3779b97f4a7c15ULL ^ k.y;
    h = h * 0x9e3779b97f4a7c15ULL ^ k.z;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
std::uint32_t bits(Float v) {
  if (v == 0) v = 0;  // −0 and +0 are one position
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

}  // namespace

MeshClosure mesh_closure(const Mesh& mesh) {
  // Weld: one id per distinct position.
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> ids;
  std::vector<std::uint32_t> weld(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    weld[i] = ids.emplace(PositionKey{bits(p.x), bits(p.y), bits(p.z)}, static_cast<std::uint32_t>(ids.size())).first->second;
  }
  // Per undirected edge: how often it is run a → b with a < b, and b → a.
  struct Uses {
    std::uint32_t forward = 0, backward = 0;
  };
  std::unordered_map<std::uint64_t, Uses> edges;
  MeshClosure c;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t v[3] = {weld[mesh.indices[t]], weld[mesh.indices[t + 1]], weld[mesh.indices[t + 2]]};
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = v[e], b = v[(e + 1) % 3];
      if (a == b) continue;  // a degenerate triangle's collapsed edge bounds nothing
      Uses& u = edges[(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
      (a < b ? u.forward : u.backward)++;
    }
    // Signed volume of the tetrahedron (origin, p0, p1, p2): their sum is the volume
    // enclosed by a closed, consistently wound surface (divergence theorem).
    const Vec3 &p0 = mesh.positions[mesh.indices[t]], &p1 = mesh.positions[mesh.indices[t + 1]],
               &p2 = mesh.positions[mesh.indices[t + 2]];
    c.volume += double(dot(p0, cross(p1, p2))) / 6;
  }
  c.edges = edges.size();
  for (const auto& [key, u] : edges) {
    if (u.forward + u.backward != 2) ++c.open_edges;
    else if (u.forward != 1) ++c.inconsistent_edges;
  }
  return c;
}

}  // namespace gonio::render
