#pragma once
// The complex index n + ik of a conductor whose exact Fresnel reflectance matches an
// F82-tint curve (fresnel_f82, SPEC §2) at normal incidence and at μ̄ = 1/7. A thin film on
// an F82-tint metal needs it: the film's Airy sum (thin_film.h) reads the substrate's complex
// index, which F82-tint does not define. SPEC-OPB "Thin-film iridescence" asks for "the best
// matching effective complex IOR, for example that described by [Gulbrandsen 2014]".
//
// Gulbrandsen, "Artist Friendly Metallic Fresnel", JCGT 3(4), 2014, §3: for a reflectivity r
// at normal incidence, the indices
//   n(g) = g n_min + (1 − g) n_max,   n_min = (1 − r)/(1 + r),   n_max = (1 + √r)/(1 − √r),
//   k(n) = sqrt((r (n + 1)² − (n − 1)²) / (1 − r))
// all reflect exactly r at normal incidence ((n − 1)² + k² = r ((n + 1)² + k²)); g ∈ [0, 1]
// (his "edge tint") runs from the dielectric of index n_max (g = 0, k = 0) to the most
// metallic member. Gulbrandsen fits g to an artist's edge colour; here g is instead solved so
// that the exact Fresnel at μ̄ = 1/7 equals F82-tint's there, F82(μ̄) = tint (r + (1 − r)(6/7)⁵)
// (Hoffman 2023; SPEC-OPB "Metal"): both values F82-tint is defined by are then matched
// exactly. F(μ̄) rises monotonically with g (checked for r from 0.02 to 0.99 in
// tests/unit/test_openpbr_substrate_films.cpp), so g is found by bracketed root finding; a tint
// beyond the family's reach (below the dielectric end: about 0.65 at r = 0.8, 0.87 at
// r = 0.95) takes the nearer end, g = 0 or 1.

#include <algorithm>
#include <cmath>

#include "gonio/fresnel.h"

namespace gonio {

struct ComplexIndex {
  double n = 1, k = 0;
};

namespace f82_index {

// Gulbrandsen's member g for reflectivity r (0 < r < 1).
inline ComplexIndex member(double r, double g) {
  const double sr = std::sqrt(r);
  const double n_min = (1 - r) / (1 + r), n_max = (1 + sr) / (1 - sr);
  const double n = g * n_min + (1 - g) * n_max;
  const double k2 = (r * (n + 1) * (n + 1) - (n - 1) * (n - 1)) / (1 - r);
  return {n, std::sqrt(std::max(0.0, k2))};
}

inline constexpr double kMuBar = 1.0 / 7;
// r above this is taken as this: n_max and k(n) divide by 1 − √r and 1 − r.
inline constexpr double kMaxReflectivity = 0.9999;

}  // namespace f82_index

// The effective index of the F82-tint curve (f0, tint), each in [0, 1] (clamped).
inline ComplexIndex f82_effective_index(double f0, double tint) {
  using namespace f82_index;
  const double r = std::clamp(std::isfinite(f0) ? f0 : 0.0, 0.0, kMaxReflectivity);
  if (!(r > 0)) return {1, 0};  // nothing reflects at normal incidence: the ambient index
  const double t = std::clamp(std::isfinite(tint) ? tint : 1.0, 0.0, 1.0);
  const double target = t * (r + (1 - r) * f82_tint::kBar5);
  const auto excess = [&](double g) {
    const ComplexIndex m = member(r, g);
    return fresnel_conductor(kMuBar, m.n, m.k) - target;
  };
  double lo = 0, hi = 1, f_lo = excess(lo), f_hi = excess(hi);
  if (f_lo >= 0) return member(r, lo);
  if (f_hi <= 0) return member(r, hi);
  // Illinois (modified regula falsi): superlinear, and never leaves the bracket.
  int side = 0;
  for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
    const double g = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    const double f = excess(g);
    if (std::abs(f) < 1e-12) return member(r, g);
    if (f < 0) {
      lo = g, f_lo = f;
      if (side == -1) f_hi /= 2;
      side = -1;
    } else {
      hi = g, f_hi = f;
      if (side == 1) f_lo /= 2;
      side = 1;
    }
  }
  return member(r, (lo + hi) / 2);
}

// Per channel of a colour type U: n and k of each channel's (f0, tint).
template <typename U>
void f82_effective_index(const U& f0, const U& tint, U& n, U& k) {
  for (int j = 0; j < U::size(); ++j) {
    const ComplexIndex c = f82_effective_index(double(f0[j]), double(tint[j]));
    n[j] = Float(c.n);
    k[j] = Float(c.k);
  }
}

}  // namespace gonio
