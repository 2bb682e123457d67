#pragma once
// The volumetric random walk inside a homogeneous medium (issue 14): the exact method of
// `subsurface` (Chiang, Kutz & Burley 2016; Cycles and Arnold use the same). From a point
// inside, travelling along d, the walk samples free-flight distances and
// Henyey–Greenstein scattering until the path reaches the boundary, is absorbed, or is
// terminated. What happens at the boundary (reflection back inside, or leaving) is the
// caller's: it samples the boundary BxDF with wo = −d in the frame of the outward normal.
//
// Chromatic media: every channel has its own σt, so one distance is drawn with the σt of
// one channel, chosen with probability proportional to the path's throughput in it, and
// the estimate is weighted by the balance heuristic over all channels — the one-sample
// spectral MIS of Wrenninge, Villemin & Hery 2017 ("Path traced subsurface scattering
// using anisotropic phase functions and non-exponential free flights", Pixar TM 17-07,
// §4) and PBR 4th ed. §14.2.2 (there with uniform probabilities over wavelengths). With
// p_c = β_c / Σβ the weight of a scattering at distance t is
//   β_c ← β_c σs_c e^{−σt_c t} / Σ_k p_k σt_k e^{−σt_k t},
// and of reaching the boundary at t_b (a surface crossing, probability e^{−σt_k t_b})
//   β_c ← β_c e^{−σt_c t_b} / Σ_k p_k e^{−σt_k t_b}.
// Choosing by throughput keeps channels the path has already lost from being sampled.
//
// Generic in the colour type C (Color or SampledSpectrum); no allocation, no virtual call.

#include <cmath>
#include <cstdint>
#include <limits>

#include "gonio/math/vec3.h"
#include "gonio/rng.h"
#include "gonio/subsurface/henyey_greenstein.h"
#include "gonio/subsurface/medium.h"

namespace gonio {

// Scattering events after which a walk is terminated. In a semi-infinite slab with σa = 0
// a walk that returns after n events has probability ~ n^{-3/2} (a 3-D random walk's first
// return), so the cap stops a fraction ~ n^{-1/2} of such paths: 0.6 % at ϖ = 1. The
// slab of `gonio subsurface` counts them by their diffusion escape probability
// (slab_path.h); elsewhere their energy is lost. With absorption ϖ^n makes them
// negligible (ϖ = 0.999: e^{−65.5}). Inside a closed mesh walks leave long before.
inline constexpr std::uint32_t kMaxWalkSteps = 1u << 16;

struct WalkStats {
  std::uint64_t steps = 0;  // scattering events (for the speed report)
};

// Whether the step from p along d over distance t meets the boundary (hit filled when it
// does): the boundary's `within` when it has one (the renderer's SceneBoundary answers
// most steps deep inside a medium without a ray: render/walk_distance_grid.h), else its
// nearest crossing compared with t.
template <typename Boundary>
bool boundary_within(const Boundary& boundary, const Vec3& p, const Vec3& d, double t, typename Boundary::Hit& hit) {
  if constexpr (requires { boundary.within(p, d, t, hit); }) {
    return boundary.within(p, d, t, hit);
  } else {
    return boundary.nearest(p, d, hit) && double(hit.t) <= t;
  }
}

// A Boundary has `using Hit = ...;` (with a member `Float t`, the distance along the ray)
// and `bool nearest(const Vec3& o, const Vec3& d, Hit& hit) const` (the first boundary
// crossing along o + t d, d unit; false if none).
//
// From p travelling along d (unit) inside `medium`: returns true with `hit` (the
// boundary crossing reached from the last scattering point) and beta multiplied by the
// path's weight; false when the path is absorbed, terminated by Russian roulette or by
// kMaxWalkSteps, or escapes where there is no boundary. The direction of travel at the
// crossing is the `d` of the last `nearest` call: a Boundary may record it (and the
// point) in its Hit, or the caller passes `d_out` to receive it.
// walk_to_boundary with its own cap on scattering events (the albedo table's walks,
// albedo_inversion.h, stop earlier than kMaxWalkSteps). When the cap ends the walk and
// `capped` is given, it receives the last scattering point (beta is the path's weight
// there): a caller that knows its geometry may estimate what the path would still bring
// (the slab's diffusion tail, slab_path.h).
struct WalkCapped {
  bool reached = false;
  Vec3 point;
};
template <typename C, typename Boundary>
bool walk_to_boundary_capped(const MediumT<C>& medium, const Boundary& boundary, Vec3 p, Vec3 d, C& beta, Pcg32& rng,
                             typename Boundary::Hit& hit, WalkStats* stats, Vec3* d_out, std::uint32_t max_steps,
                             WalkCapped* capped = nullptr) {
  constexpr int N = C::size();
  const C sigma_t = medium.sigma_t();
  for (std::uint32_t step = 0; step <= max_steps; ++step) {
    // The channel whose σt draws the distance, with probability ∝ β_c.
    Float total = 0;
    for (int c = 0; c < N; ++c) total += std::max(beta[c], Float(0));
    if (!(total > 0) || !std::isfinite(total)) return false;
    const Float pick = rng.next_float() * total;
    int ch = N - 1;
    Float acc = 0;
    for (int c = 0; c < N; ++c) {
      acc += std::max(beta[c], Float(0));
      if (pick < acc) { ch = c; break; }
    }
    const Float u = rng.next_float();
    const Float t = sigma_t[ch] > 0 ? -std::log1p(-u) / sigma_t[ch] : std::numeric_limits<Float>::infinity();

    // The weights' denominators Σ β_k X_k / Σ β_k are formed in double (one division per
    // event) and each channel's factor rounded to float once: with equal channels a factor that is 1 (σa = 0) then comes out
    // exactly 1. In float, β_k/Σβ = 1/3 rounded up made it 1 − 3e-8 per event: over the
    // ~1,300 events of a path in a conservative half-space, Rd fell 1.5–3.3e-5 short of 1.
    const double total_d = double(total);
    if (boundary_within(boundary, p, d, double(t), hit)) {
      // Reached the boundary: weight e^{−σt_c t_b} / Σ p_k e^{−σt_k t_b}.
      double denom = 0;
      C tr;
      for (int c = 0; c < N; ++c) {
        tr[c] = std::exp(-sigma_t[c] * hit.t);
        denom += double(std::max(beta[c], Float(0))) * tr[c];
      }
      if (!(denom > 0)) return false;
      const double inv = total_d / denom;
      for (int c = 0; c < N; ++c) beta[c] *= Float(tr[c] * inv);
      if (d_out) *d_out = d;
      return beta.is_finite();
    }
    if (!std::isfinite(t)) return false;  // no boundary ahead and nothing to scatter from
    if (step == max_steps) {
      if (capped) capped->reached = true, capped->point = p;
      return false;
    }

    // A scattering event at p + t d: weight σs_c e^{−σt_c t} / Σ p_k σt_k e^{−σt_k t}.
    p = p + d * t;
    double denom = 0;
    C w;
    for (int c = 0; c < N; ++c) {
      const Float tr = std::exp(-sigma_t[c] * t);
      w[c] = medium.sigma_s[c] * tr;
      denom += double(std::max(beta[c], Float(0))) * sigma_t[c] * tr;
    }
    if (!(denom > 0)) return false;
    const double inv = total_d / denom;
    for (int c = 0; c < N; ++c) beta[c] *= Float(w[c] * inv);
    if (stats) ++stats->steps;

    // Russian roulette (Arvo & Kirk 1990): a path whose largest channel fell below 1 goes
    // on with that probability and is divided by it, so the estimate stays unbiased and
    // a grey medium of albedo ϖ ends after ~1/(1 − ϖ) events on average.
    const Float m = beta.max_component();
    if (!(m > 0)) return false;
    if (m < 1) {
      if (rng.next_float() >= m) return false;
      beta *= 1 / m;
    }
    const Float u1 = rng.next_float(), u2 = rng.next_float();
    d = hg_sample(d, medium.g, u1, u2);
  }
  return false;
}

// The walk described above, ended after kMaxWalkSteps scattering events.
template <typename C, typename Boundary>
bool walk_to_boundary(const MediumT<C>& medium, const Boundary& boundary, Vec3 p, Vec3 d, C& beta, Pcg32& rng,
                      typename Boundary::Hit& hit, WalkStats* stats = nullptr, Vec3* d_out = nullptr) {
  return walk_to_boundary_capped(medium, boundary, p, d, beta, rng, hit, stats, d_out, kMaxWalkSteps);
}

}  // namespace gonio
