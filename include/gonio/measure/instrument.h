#pragma once
// What every measurement of the virtual gonioreflectometer shares: the run's options
// (rays, threads, seed, progress), the tally of how the rays ended, and the light's
// directions. The gantry (gantry.h) and the MERL table (table.h) build on it.
//
// Determinism: the rays are cut into fixed blocks (kBlockRays), each with its own PCG32
// stream derived from (seed, measurement, block); partial sums are added block by block
// in block order, so a run gives the same bits whatever the thread count.

#include <cstdint>
#include <functional>

#include "gonio/math/vec3.h"
#include "gonio/measure/microsurface.h"
#include "gonio/rng.h"

namespace gonio::measure {

struct RunOptions {
  std::uint64_t samples = 10'000'000;  // total rays launched from the light
  int threads = 0;                     // 0: all cores
  std::uint64_t seed = 0;
  // Fraction done in [0, 1], called from the calling thread between batches of blocks.
  std::function<void(double)> progress;
};

// Rays per block (one RNG stream each).
inline constexpr std::uint64_t kBlockRays = 8192;  // = 128 × 64 strata (entry_point)

struct RayCounts {
  std::uint64_t launched = 0, up = 0, down = 0, absorbed = 0, capped = 0, lost = 0;
  std::uint64_t segments = 0;  // traced segments (Embree queries, wraps included)
  std::uint64_t bounces = 0;   // facet interactions

  void add(const TraceResult& r) {
    ++launched;
    segments += r.segments;
    bounces += r.bounces;
    switch (r.fate) {
      case Fate::Up: ++up; break;
      case Fate::Down: ++down; break;
      case Fate::Absorbed: ++absorbed; break;
      case Fate::Capped: ++capped; break;
      case Fate::Lost: ++lost; break;
    }
  }
  RayCounts& operator+=(const RayCounts& o) {
    launched += o.launched, up += o.up, down += o.down, absorbed += o.absorbed;
    capped += o.capped, lost += o.lost, segments += o.segments, bounces += o.bounces;
    return *this;
  }
};

// Where ray k of a block enters the patch, in [0, 1)²: a full block covers the patch with
// one jittered sample in each cell of a 128 × 64 stratification, visited in Morton
// (Z-curve) order, so consecutive rays land close together and share Embree's BVH nodes
// in cache (twice the segments per second of independent positions on a 512² surface).
// Each ray's position is still uniform; the standard errors, which treat the rays as
// independent, are then conservative (stratification only lowers the variance). A last,
// partial block uses independent uniform positions.
void entry_point(std::uint64_t k, bool full_block, Pcg32& rng, double& u, double& v);

// The unit direction at polar angle θ and azimuth φ (radians; SPEC §1).
Vec3 spherical_direction(double theta, double phi);

// The PCG32 stream of block `block` of measurement `task` (an incidence, or the table).
std::uint64_t block_stream(std::uint64_t task, std::uint64_t block);

}  // namespace gonio::measure
