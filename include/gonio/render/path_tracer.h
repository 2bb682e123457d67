#pragma once
// The estimator of the reflection equation along camera paths: unidirectional path
// tracing with next-event estimation, BSDF sampling and multiple importance sampling by
// the power heuristic (Veach & Guibas 1995; Veach 1997, ch. 9), and Russian roulette.
// Point lights are summed over exactly at every non-specular vertex (lecture eq. 2);
// area lights and the environment are sampled as the integral of eq. 1.

#include <cstdint>

#include "gonio/rng.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/wavelengths.h"
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
  // Spectral mode: the radiance at the path's wavelengths `w`, which a dispersive surface
  // may reduce to the hero (SampledWavelengths::terminate_secondary). `scratch` is one
  // per thread.
  SampledSpectrum radiance(Ray ray, SampledWavelengths& w, Pcg32& rng, PathStats& stats,
                           SpectralScratch& scratch) const;

 private:
  // The estimator for both colour modes (path_tracer.cpp).
  template <typename Shading>
  typename Shading::C trace(Ray ray, Pcg32& rng, PathStats& stats, Shading& shading) const;
  // Light reaching the vertex from the lights, by next-event estimation weighted against
  // BSDF sampling.
  template <typename Shading, typename Model>
  typename Shading::C direct_light(const SurfaceHit& hit, const Frame& frame, const Model& bxdf, const Vec3& wo,
                                   const Vec3& wo_world, Pcg32& rng, PathStats& stats, Shading& shading) const;
  bool occluded(const Vec3& p, const Vec3& ng, const Vec3& dir, Float dist, PathStats& stats) const;

  const Scene& scene_;
  const Accel& accel_;
  int sampled_lights_ = 0;  // area lights + the environment when it is not black
  Float light_select_pdf_ = 0;
};

}  // namespace gonio::render
