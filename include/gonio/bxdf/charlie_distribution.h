#pragma once
// The "Charlie" sheen distribution of Estevez & Kulla ("Production Friendly Microfacet
// Sheen BRDF", SIGGRAPH 2017, eq. 2), shared by the sheens built on it: glTF's
// KHR_materials_sheen (gltf_pbr.h, with Estevez & Kulla's Λ) and MaterialX's sheen_bsdf in
// mode conty_kulla (charlie_sheen.h, with the "smoother denominator"):
//   D(θh) = (2 + 1/α) sin^(1/α) θh / (2π),   normalised: ∫ D cos θh dω = 1.

#include <algorithm>
#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

// D from cos θh; α > 0 (the callers floor it).
inline Float charlie_d(Float cos_h, Float alpha) {
  const Float sin2 = std::max(Float(0), 1 - cos_h * cos_h);
  const Float inv = 1 / alpha;
  return (2 + inv) * std::pow(sin2, Float(0.5) * inv) * kInv2Pi;
}

}  // namespace gonio
