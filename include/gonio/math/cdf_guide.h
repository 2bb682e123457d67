#pragma once
// Inverting a tabulated CDF in constant expected time: a guide table (Chen & Asau 1974,
// "On generating random variates from an empirical distribution"; Devroye 1986,
// "Non-Uniform Random Variate Generation", ch. III)
// stores, for each of G equal steps of u, the interval that holds the step's lower end;
// the search for u starts there and walks forward. It returns exactly what the binary
// search does (cdf_interval), so a sampler changes speed, not samples. In a sampler the
// binary search is a chain of dependent loads and compares (six for 64 intervals) on the
// critical path; with G = 2n the walk takes less than one step on average.

#include <algorithm>
#include <cstdint>

#include "gonio/math/constants.h"

namespace gonio {

// The index i of the interval [cdf[i], cdf[i+1]) holding u, for a CDF of n intervals
// (cdf[0] = 0 ≤ … ≤ cdf[n] = 1): std::upper_bound over cdf[1 .. n], less one, so that
// empty intervals are skipped, clamped to [0, n − 1].
inline int cdf_interval(const float* cdf, int n, Float u) {
  const float* above = std::upper_bound(cdf + 1, cdf + n + 1, float(u));
  return std::clamp(int(above - cdf) - 1, 0, n - 1);
}

// guide[g] = cdf_interval(cdf, N, g / G) for g = 0 .. G − 1, for a CDF of N intervals.
// N and G are compile-time: the entries are one byte each, so N ≤ 256 is checked here.
template <int N, int G>
void build_cdf_guide(const float* cdf, std::uint8_t* guide) {
  static_assert(N > 0 && N <= 256, "guide entries are one byte");
  static_assert(G > 0 && (G & (G - 1)) == 0, "G a power of two, so that u·G and g/G are exact");
  for (int g = 0; g < G; ++g) guide[g] = std::uint8_t(cdf_interval(cdf, N, Float(g) / Float(G)));
}

// cdf_interval(cdf, N, u) through the guide. u·G is exact (G a power of two), so the
// guide's entry lies at or before the answer for every u in [0, 1]; the two agree there,
// above 1 and for NaN (N − 1). Below 0 the guided search gives guide[0], the binary
// search 0; both are indices in [0, N − 1].
template <int N, int G>
inline int cdf_interval_guided(const float* cdf, const std::uint8_t* guide, Float u) {
  const Float step = u * Float(G);
  const int g = step > 0 ? int(std::min(step, Float(G - 1))) : 0;  // NaN: 0
  int i = guide[g];
  while (i + 1 < N && !(u < cdf[i + 1])) ++i;
  return i;
}

}  // namespace gonio
