#pragma once
// Ray–scene intersection through Embree (Wald et al. 2014, "Embree: A Kernel Framework
// for Efficient CPU Ray Tracing"). Embree finds the nearest primitive; this class turns
// Embree's hit into the surface record the integrator shades: position, geometric and
// shading normals, tangent and texture coordinates.

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
  // True when anything lies on the segment o + t·d, 0 < t < tmax.
  bool occluded(const Vec3& o, const Vec3& d, Float tmax) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gonio::render
