#pragma once
// The renderer's side of the random walk (issue 14): the scene as the walk's boundary, and
// the check that a mesh holding a medium is closed. A walk inside an open mesh would
// leave through the hole without meeting the boundary, so a scene whose random-walk
// material sits on an open mesh is rejected at load.

#include <cstddef>
#include <cstdint>

#include "gonio/render/accel.h"
#include "gonio/render/scene.h"
#include "gonio/render/walk_distance_grid.h"

namespace gonio::render {

// The Boundary of walk_to_boundary (gonio/subsurface/random_walk.h) over the scene's
// Embree acceleration structure: the first surface along o + t·d. The hit keeps the
// direction the walk arrived in, which is −wo of the boundary vertex it makes.
class SceneBoundary {
 public:
  struct Hit {
    Float t = 0;
    SurfaceHit surface;
    Vec3 d;  // the walk's direction when it met the surface
  };
  // grid: the bound that lets a step skip its ray (walk_distance_grid.h), or null.
  SceneBoundary(const Accel& accel, std::uint64_t& rays, const WalkDistanceGrid* grid = nullptr)
      : accel_(accel), rays_(rays), grid_(grid) {}

  bool nearest(const Vec3& o, const Vec3& d, Hit& hit) const {
    ++rays_;
    if (!accel_.intersect(Ray{o, d}, hit.surface)) return false;
    hit.t = hit.surface.t;
    hit.d = d;
    return true;
  }

  // Whether the walk's step from o along d over distance t meets a surface (the walk's
  // boundary_within): no ray when the step is shorter than the grid's bound at o.
  bool within(const Vec3& o, const Vec3& d, double t, Hit& hit) const {
    if (grid_ && t < double(grid_->lower_bound(o))) return false;
    return nearest(o, d, hit) && double(hit.t) <= t;
  }

 private:
  const Accel& accel_;
  std::uint64_t& rays_;
  const WalkDistanceGrid* grid_;
};

// A triangle mesh's edges, with vertices equal in position taken as one (an OBJ file
// repeats a position for each normal or texture coordinate it has there).
struct MeshClosure {
  std::size_t edges = 0;
  std::size_t open_edges = 0;           // used by one triangle, or by more than two
  std::size_t inconsistent_edges = 0;   // shared by two triangles that run it the same way
  double volume = 0;                    // signed, by the divergence theorem; > 0 when the
                                        // winding is counter-clockwise seen from outside
  bool closed() const { return open_edges == 0; }
};
MeshClosure mesh_closure(const Mesh& mesh);

}  // namespace gonio::render
