#pragma once
// The estimator of the reflection equation along camera paths: unidirectional path
// tracing with next-event estimation, BSDF sampling and multiple importance sampling by
// the power heuristic (Veach & Guibas 1995; Veach 1997, ch. 9), and Russian roulette.
// Point lights are summed over exactly at every non-specular vertex (lecture eq. 2);
// area lights and the environment are sampled as the integral of eq. 1, one of them per
// vertex, chosen by the scene's light sampler (light_sampler.h) with a pmf the MIS weights
// use both where the light is sampled and where a BSDF sample hits it.
//
// Subsurface materials (issue 14): the boundary is an ordinary vertex, shaded with the
// boundary's BSDF. A direction sampled into the medium of a random-walk material starts
// a random walk (walk_to_boundary) instead of a ray; the boundary point where it ends is
// the next vertex, with wo inside: its BSDF sample reflects (another walk) or transmits
// (the path leaves). For a diffusion material the direction into the medium is replaced
// by an exit point sampled from the profile (sample_probe_exit), shaded with the exit
// lobe Sw (next-event estimation and the next direction), as pbrt-v3 §15.4 does.
// max_depth counts vertices: every boundary interaction and every diffusion exit is one;
// the steps of a walk are not (the walk ends by absorption, Russian roulette or its own
// step limit). RGB only for now: the constructor rejects a spectral render of a scene
// with a subsurface material.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "gonio/polarization/polarized_bxdf.h"
#include "gonio/render/sampler.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/wavelengths.h"
#include "gonio/render/accel.h"
#include "gonio/render/light_sampler.h"
#include "gonio/render/scene.h"
#include "gonio/render/walk_distance_grid.h"

namespace gonio::render {

struct PathStats {
  std::uint64_t rays = 0;  // closest-hit and shadow rays (a walk's boundary queries included)
  // Subsurface scattering (issue 14): random walks started inside a medium, their steps
  // (free flights, each ending in a scattering event or at the boundary), and the exits
  // sampled by the diffusion method.
  std::uint64_t walks = 0, walk_steps = 0, probe_exits = 0;
};

struct WalkNeeState;  // path_tracer.cpp
struct WalkNeePlane;  // path_tracer.cpp

class PathTracer {
 public:
  PathTracer(const Scene& scene, const Accel& accel);
  const LightSampler& light_sampler() const { return light_sampler_; }

  // Radiance arriving at the camera along `ray` (one sample of it).
  Color radiance(Ray ray, PixelSampler& sampler, PathStats& stats) const;
  // Spectral mode: the radiance at the path's wavelengths `w`, which a dispersive surface
  // may reduce to the hero (SampledWavelengths::terminate_secondary). `scratch` is one
  // per thread.
  SampledSpectrum radiance(Ray ray, SampledWavelengths& w, PixelSampler& sampler, PathStats& stats,
                           SpectralScratch& scratch) const;
  // Polarized mode (issue 15; scene.settings.polarized): the Stokes vector S0..S3 (each a
  // colour) of the light arriving along `ray`, in the image's frame (SPEC §1: Q = I_x − I_y,
  // x to the right, y up), through the camera's polarizer when it has one. The lights are
  // unpolarized; S0 estimates what radiance() does, with the same paths.
  std::array<Color, 4> stokes(Ray ray, PixelSampler& sampler, PathStats& stats) const;
  std::array<SampledSpectrum, 4> stokes(Ray ray, SampledWavelengths& w, PixelSampler& sampler, PathStats& stats,
                                        SpectralScratch& scratch) const;

 private:
  // The estimator for both colour modes (path_tracer.cpp).
  template <typename Shading>
  typename Shading::Radiance trace(Ray ray, PixelSampler& sampler, PathStats& stats, Shading& shading) const;
  // Light reaching the vertex from the lights, by next-event estimation weighted against
  // BSDF sampling.
  template <typename Shading, typename Model>
  typename Shading::C direct_light(const SurfaceHit& hit, const Frame& frame, const Model& bxdf, const Vec3& wo,
                                   const Vec3& wo_world, int depth, Float u_pick, PixelSampler& sampler, PathStats& stats,
                                   Shading& shading) const;
  bool occluded(const Vec3& p, const Vec3& ng, const Vec3& dir, Float dist, PathStats& stats) const;
  // A subsurface random walk under a smooth boundary (issue 38): next-event estimation from
  // its scattering events through the boundary (path_tracer.cpp, "Next-event estimation
  // from inside a medium"); WalkNeeState holds what one walk's estimates share.
  bool walk_nee_setup(const Material& material, const SurfaceHit& entry, WalkNeeState& w) const;
  Color walk_nee(const WalkNeeState& w, const Vec3& x, const Vec3& d_in, Pcg32& rng, PathStats& stats) const;
  WalkNeePlane walk_nee_plane(const WalkNeeState& w, const Vec3& x) const;
  Float walk_nee_density(const WalkNeeState& w, const WalkNeePlane& plane, const Vec3& d) const;
  Float walk_exit_weight(const WalkNeeState& w, const Vec3& x, const Vec3& d_in, const Vec3& d, Float s) const;

  void make_walk_grid();

  const Scene& scene_;
  const Accel& accel_;
  // The random walks' distance bound (null when no shape walks).
  std::unique_ptr<WalkDistanceGrid> walk_grid_;
  // Chooses the area light or the environment each next-event estimate samples (the
  // scene's "light_sampler"); its pmf is the selection's share of the MIS densities.
  LightSampler light_sampler_;
  // Polarized mode: the untextured materials' polarized models (made once; empty for a
  // textured one) and the camera's polarizer as a Mueller matrix per channel.
  std::vector<std::optional<PolarizedBxDF>> polarized_models_;
  // Per material with a medium: the Dwivedi κ and p(0) per channel (guided_walk.h), for
  // walk_nee's MIS weights (made once: 60 bisection steps each).
  std::vector<std::array<double, 6>> walk_dwivedi_;
  MuellerT<Color> polarizer_rgb_;
  MuellerT<SampledSpectrum> polarizer_spectral_;
};

}  // namespace gonio::render
