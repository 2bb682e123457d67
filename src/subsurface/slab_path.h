#pragma once
// One path of the slab estimator (slab_walk.h), shared by slab_random_walk and the albedo
// table (albedo_inversion.h). Internal to src/subsurface.

#include <cmath>
#include <cstdint>

#include "gonio/bxdf.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/random_walk.h"
#include "gonio/subsurface/slab_walk.h"

namespace gonio::detail {

// The plane z = 0 seen from below (z < 0): a ray crosses it only when it rises.
struct PlaneBoundary {
  struct Hit {
    Float t = 0;
    Vec3 p, d;  // the crossing and the direction of travel there
  };
  bool nearest(const Vec3& o, const Vec3& d, Hit& hit) const {
    if (!(d.z > 0)) return false;
    hit.t = std::max(Float(0), -o.z / d.z);
    hit.p = {o.x + d.x * hit.t, o.y + d.y * hit.t, 0};
    hit.d = d;
    return true;
  }
};

// A path from the beam at the origin (normal incidence) to where it leaves: its
// contribution to Rd (0 if the first-surface reflection, absorbed or dropped) and the
// radius where it left in r_out (−1: it did not). stats.steps counts its scattering events.
// With `tail`, a path stopped at max_steps brings its weight times the share of a point
// source at its depth that would leave (diffusion.h, DipoleEscape) to Rd, and nothing to
// the profile (r_out = −1: where it would leave is not known; after 65,536 events about
// √65536 = 256 mean free paths away, beyond the profile's 20). Without, it is dropped.
inline Color trace_slab_path(const BxDF& boundary, const Medium& medium, Pcg32& rng, Float& r_out, WalkStats& stats,
                             std::uint32_t max_steps = kMaxWalkSteps, const DipoleEscape* tail = nullptr) {
  r_out = -1;
  // Entering: light arriving along −z, so wo = +z on the outside; particles carry power,
  // hence importance transport (SPEC §1: transmission weighted without the η² factor).
  const Vec3 up{0, 0, 1};
  const Float ul = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
  const auto entry = boundary.sample(up, ul, u1, u2, TransportMode::Importance);
  if (!entry || entry->wi.z >= 0) return Color(0);  // the first-surface reflection is not counted
  Color beta = entry->weight;
  Vec3 p{0, 0, 0}, d = entry->wi;
  const PlaneBoundary plane;
  PlaneBoundary::Hit hit;
  for (int bounce = 0; bounce < kMaxSlabBounces; ++bounce) {
    WalkCapped capped;
    if (!walk_to_boundary_capped(medium, plane, p, d, beta, rng, hit, &stats, nullptr, max_steps, &capped)) {
      if (!capped.reached || !tail) return Color(0);
      const Color rest = beta * (*tail)(-capped.point.z);
      return rest.is_finite() ? rest : Color(0);
    }
    // At the surface from inside: wo = −d (wo.z < 0) in the frame of the outward normal.
    const Float vl = rng.next_float(), v1 = rng.next_float(), v2 = rng.next_float();
    const auto out = boundary.sample(-hit.d, vl, v1, v2, TransportMode::Importance);
    if (!out) return Color(0);
    beta *= out->weight;
    if (out->wi.z > 0) {  // transmitted: leaves the slab
      r_out = std::sqrt(hit.p.x * hit.p.x + hit.p.y * hit.p.y);
      return beta.is_finite() ? beta : Color(0);
    }
    p = hit.p;
    d = out->wi;
  }
  return Color(0);
}

}  // namespace gonio::detail
