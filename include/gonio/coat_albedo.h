#pragma once
// Directional albedo of a rough dielectric coat's reflection: E_coat(μ) of the
// single-scattering microfacet BRDF D G2 F / (4 cos θo cos θi) with dielectric Fresnel,
// light arriving from outside onto relative index η ≥ 1 (Walter et al. 2007, eq. 20;
// height-correlated G2, Heitz 2014), and its cosine-weighted mean Ē_coat = 2 ∫ E μ dμ.
// 1 − E_coat(μ) is what the coat lets through towards a base layer, and (1 − Ē_coat)/η²
// what it lets out of it (plastic.h). From tables computed at build time
// (tools/make_albedo_tables.cpp, layout in multiscatter_table_layout.h).
//
// An anisotropic coat is looked up at the roughness it presents to each direction, the
// projected roughness α(φ) = sqrt(αx² cos²φ + αy² sin²φ) that fixes Λ (Heitz 2014,
// eq. 86), and its mean is averaged over φ as well.

#include <algorithm>
#include <cmath>

#include "gonio/microfacet.h"
#include "gonio/multiscatter_table_layout.h"

namespace gonio {

// A coat prepared for lookups at one (distribution type, η): the η interpolation is done
// once, so a lookup is bilinear in (α, μ).
struct CoatAlbedo {
  MicrofacetType type = MicrofacetType::GGX;
  int k0 = 0;      // η node below
  Float tk = 0;    // fraction towards node k0 + 1
  // The α row of one roughness, found once (a logarithm) rather than per lookup.
  Float row_alpha = -1;
  int r0 = 0;
  Float tr = 0;

  static CoatAlbedo make(MicrofacetType type, Float eta);
  // Prepares lookups at roughness alpha (the coat's, or a texture's): lookups at another
  // α still work, finding their row each time.
  void prepare_roughness(Float alpha);
  // E_coat(μ) at isotropic roughness alpha (clamped to the table's [1e-3, 10]). Inline at
  // the prepared roughness: layered models (openpbr) look it up several times per call.
  Float E(Float alpha, Float mu) const { return alpha == row_alpha ? E_at_row(r0, tr, mu) : E_any_row(alpha, mu); }
  // Ē_coat at isotropic roughness alpha.
  Float average(Float alpha) const;

  // Sampling μ ∝ (1 − E_coat(μ)) μ at isotropic roughness alpha, the shape of the base
  // lobe under the coat (plastic.h): E_coat is bilinear in (α row, η node), so the density
  // is a mixture of four table rows' densities, each drawn by its tabulated CDF
  // (tools/make_albedo_tables.cpp). complement_loss is its normalisation
  // 2 ∫ (1 − E_coat) μ dμ (= 1 − Ē_coat up to the float rounding of Ē_coat), so that the
  // density per solid angle is (1 − E_coat(μ)) μ / (π complement_loss).
  Float complement_loss(Float alpha) const;
  Float sample_complement(Float alpha, Float u) const;

  // The same for the distribution's roughness seen from w (its projected roughness).
  Float E(const MicrofacetDistribution& d, const Vec3& w) const {
    return d.is_isotropic() ? E(d.alpha_x, std::abs(w.z)) : E_anisotropic(d, w);
  }
  // Ē_coat of the distribution: the mean over μ and φ.
  Float average(const MicrofacetDistribution& d) const;

  // E at α row r (fraction t towards r + 1): bilinear in (row, η node) of the rows' values
  // interpolated linearly in μ between their columns (uniform in s = μ^(1/4)).
  Float E_at_row(int r, Float t, Float mu) const {
    const auto& table = type == MicrofacetType::GGX ? tables::kGgxCoatAlbedo : tables::kBeckmannCoatAlbedo;
    using tables::kCoatCosineSize;
    const Float m = std::clamp(mu, Float(0), Float(1));
    const Float fs = std::sqrt(std::sqrt(m)) * Float(kCoatCosineSize - 1);
    const int m0 = std::min(int(fs), kCoatCosineSize - 2);
    const Float tm = std::clamp((m - tables::kCoatMuNodes.mu[m0]) * tables::kCoatMuNodes.inv_width[m0], Float(0), Float(1));
    auto at = [&](int a, int k) {
      const float* row = table[a][k];
      return row[m0] + (row[m0 + 1] - row[m0]) * tm;
    };
    const Float lo = at(r, k0) * (1 - tk) + at(r, k0 + 1) * tk;
    const Float hi = at(r + 1, k0) * (1 - tk) + at(r + 1, k0 + 1) * tk;
    return lo * (1 - t) + hi * t;
  }

 private:
  Float E_any_row(Float alpha, Float mu) const;
  Float E_anisotropic(const MicrofacetDistribution& d, const Vec3& w) const;
};

}  // namespace gonio
