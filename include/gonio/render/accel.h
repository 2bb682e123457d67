#pragma once
// Ray–scene intersection through Embree (Wald et al. 2014, "Embree: A Kernel Framework
// for Efficient CPU Ray Tracing"). Embree finds the nearest primitive; this class turns
// Embree's hit into the surface record the integrator shades: position, geometric and
// shading normals, tangent and texture coordinates.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "gonio/render/ray.h"
#include "gonio/render/scene.h"

namespace gonio::render {

struct SurfaceHit {
  Float t = 0;
  Vec3 p;
  Vec3 ng;       // geometric normal: outward for spheres, from winding (or agreeing with
                 // the vertex normals) for meshes
  Vec3 ns;       // shading normal, on the same side as ng
  Vec3 tangent;  // direction of anisotropy (dP/du); may be zero
  Vec2 uv;
  int material = -1;
  int area_light = -1;
};

class Accel {
 public:
  explicit Accel(const Scene& scene);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  // The nearest hit with tnear < t < ray.tmax: intersect() resumed past a surface already
  // found, for walking along a segment.
  bool intersect_after(const Ray& ray, Float tnear, SurfaceHit& hit) const;
  // The all-hits query (subsurface probe rays, King et al. 2013): calls visit(hit) for
  // every surface the segment o + t·d, 0 < t < tmax, crosses, nearest first, at most
  // max_hits of them; returns how many. Each crossing is one query resumed just past the
  // previous one: crossings closer than 1e-6 of the segment's reach to the previous one are
  // merged with it (a shared edge of two triangles is reported once). visit returns false
  // to stop early.
  template <typename F>
  int for_each_hit(const Ray& ray, F&& visit, int max_hits = 256) const {
    const Float reach = std::isfinite(ray.tmax) ? ray.tmax : Float(1);
    const Float gap = Float(1e-6) * reach;
    Float tnear = 0;
    int n = 0;
    SurfaceHit hit;
    while (n < max_hits && intersect_after(ray, tnear, hit)) {
      ++n;
      if (!visit(static_cast<const SurfaceHit&>(hit))) break;
      tnear = std::max(std::nextafter(hit.t, std::numeric_limits<Float>::infinity()), hit.t + gap);
    }
    return n;
  }
  // True when anything lies on the segment o + t·d, 0 < t < tmax.
  bool occluded(const Vec3& o, const Vec3& d, Float tmax) const;
  // The distance from p to the nearest surface of the scene, or max_distance when none is
  // nearer (Embree's closest-point query; the random walk's distance bound, walk_distance_grid.h).
  Float distance_to_surface(const Vec3& p, Float max_distance) const;
  // The same query, also giving the nearest surface point (left as it is when no surface
  // is nearer than max_distance).
  Float closest_point(const Vec3& p, Float max_distance, Vec3& nearest) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gonio::render
