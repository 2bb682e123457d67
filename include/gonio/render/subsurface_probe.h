#pragma once
// Exit-point sampling for the diffusion method by probe rays (King, Kulla, Conty &
// Fajardo 2013, "BSSRDF importance sampling", SIGGRAPH talk; pbrt-v3 §15.4.1): a disc
// around the entry point perpendicular to one axis of its frame (the normal with
// probability 1/2, each tangent 1/4), a radius from the profile of one channel, and a
// probe chord along the axis through the profile's sphere of radius r_max; one of the
// chord's crossings of the same material is picked uniformly. The weight divides Sp by
// the density of that point over the surface, summed over the three axes and the channels
// (one-sample MIS, balance heuristic), each axis's planar density times the projection
// cosine |n · axis| of the surface found, and multiplies by the number of crossings.

#include <optional>

#include "gonio/math/frame.h"
#include "gonio/render/accel.h"
#include "gonio/rng.h"
#include "gonio/subsurface/diffusion.h"

namespace gonio::render {

template <typename C>
struct ProbeExit {
  SurfaceHit hit;
  C weight;  // Sp(‖xo − xi‖) / pdf(xo): per unit entered power, per channel
};

// Given the entry point and its frame (n = the surface normal, outward), samples where the
// light that entered there leaves. nullopt: no exit found (the path ends).
std::optional<ProbeExit<Color>> sample_probe_exit(const Accel& accel, const SurfaceHit& entry, const Frame& frame,
                                                  const DiffusionProfile& profile, Pcg32& rng);

// The density per unit area with which sample_probe_exit picks `exit` (before the 1/count
// of the uniform pick): the MIS sum over axes and channels. For tests and for MIS.
Float probe_exit_pdf(const SurfaceHit& entry, const Frame& frame, const DiffusionProfile& profile,
                     const SurfaceHit& exit);

}  // namespace gonio::render
