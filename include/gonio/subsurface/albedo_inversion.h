#pragma once
// From the artist's `albedo` to the single-scattering albedo ϖ (issue 14, SPEC §2).
//
// The artist's albedo of a `subsurface` material is the fraction of the light entering a
// semi-infinite slab at normal incidence that leaves it again: A = Rd / (1 − F(0)), Rd as
// `gonio subsurface` reports it (relative to the incident power, SPEC §3) and F(0) the
// Fresnel reflectance of the boundary's η at normal incidence. A depends on ϖ, η, g and
// the boundary's roughness, not on σt (distances scale with 1/σt).
//
// One simulation gives A(ϖ) for every ϖ: in a grey medium a path's geometry does not
// depend on ϖ, and each scattering event multiplies its weight by ϖ, so
//   Rd(ϖ) = E[w ϖ^n],
// with n the scattering events of a path walked without absorption and w its boundary
// weight. The table holds the mean weight of the paths that left after n events; A(ϖ)
// is a polynomial in ϖ with non-negative coefficients, smooth and increasing, and is
// inverted by bisection. The same random numbers serve every ϖ, so the curve has no
// jitter from one ϖ to the next; its error is the Monte Carlo error of the table
// (kAlbedoTablePaths paths, see docs/subsurface.md) plus the walks dropped at
// kAlbedoTableMaxSteps events (they weigh ϖ^2048 < e^{−2} for ϖ < 0.999).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gonio/bxdf.h"

namespace gonio {

inline constexpr std::uint64_t kAlbedoTablePaths = 1u << 13;
inline constexpr std::uint32_t kAlbedoTableMaxSteps = 2048;

class SlabAlbedoTable {
 public:
  // The table for this boundary and g, built on first use and cached under `key` (which
  // must identify the boundary and g: the parser passes its parameters). Thread-safe.
  static std::shared_ptr<const SlabAlbedoTable> get(const BxDF& boundary, Float eta, Float g, const std::string& key);
  // Builds one without the cache.
  SlabAlbedoTable(const BxDF& boundary, Float eta, Float g);

  // A(ϖ) = Rd(ϖ) / (1 − F(0)).
  double albedo(double single_scattering_albedo) const;
  // The ϖ in [0, 1] with A(ϖ) = albedo; 1 when albedo ≥ A(1) (the largest the table
  // reaches: about 1 − 2 % at η = 1.33, the walks dropped at the cap).
  double single_scattering_albedo(double albedo) const;

 private:
  std::vector<double> weight_;  // by scattering events n: the mean weight of paths that left after n
  double entering_ = 1;         // 1 − F(0)
};

}  // namespace gonio
