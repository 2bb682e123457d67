#pragma once
// The estimator of the reflection equation along camera paths: unidirectional path
// tracing with next-event estimation, BSDF sampling and multiple importance sampling by
// the power heuristic (Veach & Guibas 1995; Veach 1997, ch. 9), and Russian roulette.
// Point lights are summed over exactly at every non-specular vertex (lecture eq. 2);
// area lights and the environment are sampled as the integral of eq. 1.

#include <cstdint>

#include "gonio/rng.h"
#include "gonio/render/accel.h"
#include "gonio/render/scene.h"

namespace gonio::render {

struct PathStats {
  std::uint64_t rays = 0;  // closest-hit and shadow rays
};

class PathTracer {
 public:
  PathTracer(const Scene& scene, const Accel& accel);

  // Radiance arriving at the camera along `ray` (one sample of it).
  Color radiance(Ray ray, Pcg32& rng, PathStats& stats) const;

 private:
  // Emitted radiance reaching the previous vertex, weighted against the BSDF sample that
  // found it.
  Color direct_light(const SurfaceHit& hit, const Frame& frame, const BxDF& bxdf, const Vec3& wo,
                     const Vec3& wo_world, Pcg32& rng, PathStats& stats) const;
  bool occluded(const Vec3& p, const Vec3& ng, const Vec3& dir, Float dist, PathStats& stats) const;

  const Scene& scene_;
  const Accel& accel_;
  int sampled_lights_ = 0;  // area lights + the environment when it is not black
  Float light_select_pdf_ = 0;
};

}  // namespace gonio::render
