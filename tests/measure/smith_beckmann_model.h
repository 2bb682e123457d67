#pragma once
// The single-scattering Smith microfacet BRDF for Beckmann with white mirror facets
// (F = 1), written again for the instrument's tests from the papers, not taken from
// gonio's roughconductor:
//   f(i, o) = D(h) G(i, o) / (4 cos θi cos θo)                 Walter et al. 2007 eq. 20 (F = 1)
//   D(m)    = exp(−tan²θm / α²) / (π α² cos⁴θm)               Walter et al. 2007 eq. 25
//   G1(v)   = 2 / (1 + erf(a) + exp(−a²) / (a √π)),  a = 1 / (α tan θv)   Walter eq. 27
//   Λ(v)    = 1 / G1(v) − 1                                   (Heitz 2014 eq. 72)
//   separable:         G = G1(i) G1(o)                         Walter eq. 23
//   height-correlated: G = 1 / (1 + Λ(i) + Λ(o))               Heitz 2014 eq. 99

#include <cmath>

#include "gonio/math/constants.h"

namespace gonio::measure::smith_beckmann {

struct V {
  double x, y, z;
};
inline V dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Beckmann D (Walter eq. 25), with cos θm = m.z for a unit m.
inline double beckmann_d(double cos_m, double alpha) {
  if (cos_m <= 0) return 0;
  const double c2 = cos_m * cos_m, tan2 = (1 - c2) / c2;
  return std::exp(-tan2 / (alpha * alpha)) / (kPiD * alpha * alpha * c2 * c2);
}

// Smith Λ for Beckmann (Walter eq. 27 as 1/G1 − 1).
inline double beckmann_lambda(double cos_v, double alpha) {
  if (cos_v >= 1) return 0;
  const double tan_v = std::sqrt(1 - cos_v * cos_v) / cos_v;
  const double a = 1 / (alpha * tan_v);
  return (std::erf(a) - 1) / 2 + std::exp(-a * a) / (2 * a * std::sqrt(kPiD));
}

enum class Masking { Separable, HeightCorrelated };

// Walter eq. 20 with F = 1. Both directions above the surface; the half vector's facet
// must face both (χ⁺ of eq. 27), which holds for reflection with both above.
inline double model_f(const V& i, const V& o, double alpha, Masking g) {
  V h{i.x + o.x, i.y + o.y, i.z + o.z};
  const double len = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
  const double li = beckmann_lambda(i.z, alpha), lo = beckmann_lambda(o.z, alpha);
  const double G = g == Masking::Separable ? 1 / ((1 + li) * (1 + lo)) : 1 / (1 + li + lo);
  return beckmann_d(h.z / len, alpha) * G / (4 * i.z * o.z);
}

}  // namespace gonio::measure::smith_beckmann
