#pragma once
// The random-walk estimate of `gonio subsurface` (SPEC §3): a semi-infinite slab (surface
// z = 0, medium below) under a collimated beam at normal incidence at the origin. Each
// path enters through the boundary BxDF (a first-surface reflection is not counted),
// walks (random_walk.h) to the plane, and there is reflected back inside or leaves, as
// the boundary BxDF samples it; what leaves is counted in Rd and in the profile's annulus
// at its distance from the origin.

#include <cstdint>

#include "gonio/subsurface/slab.h"
#include "gonio/subsurface/subsurface.h"

namespace gonio {

// Boundary crossings after which a path still inside is dropped (each is a total or
// Fresnel internal reflection; at η = 1.33 a path makes ~2 on average).
inline constexpr int kMaxSlabBounces = 256;

// Paths per block: each block has its own Pcg32 stream (seed, block index), and blocks
// are summed in order, so the result depends on the seed and not on the thread count.
inline constexpr std::uint64_t kSlabBlock = 4096;

struct SlabWalkOptions {
  int threads = 0;                  // 0: all cores
  std::uint64_t* steps = nullptr;   // if given, receives the total scattering events
};

// Rd with its standard error (per channel) and the profile at slab_profile_radii (the
// mean over each annulus). `samples` paths (at least 1).
SlabResult slab_random_walk(const Subsurface& s, std::uint64_t samples, std::uint64_t seed, int threads = 0);
SlabResult slab_random_walk(const Subsurface& s, std::uint64_t samples, std::uint64_t seed,
                            const SlabWalkOptions& options);

}  // namespace gonio
