#pragma once
// Directional albedo E(ωo) of the single-scattering microfacet BRDF with F = 1,
//   E(ωo) = ∫ D G2 / (4 cos θo cos θi) cos θi dωi   (Walter et al. 2007, eq. 20),
// for ANISOTROPIC roughness (αx ≠ αy), which depends on the azimuth of ωo as well as on
// its cosine: the multiple-scattering compensation of Kulla & Conty (2017) needs E(ωo) of
// the distribution itself, and no isotropic α stands in for it (the roughness projected on
// ωo's azimuth, Heitz 2014 eq. 86, which fixes Λ exactly, misses E by up to 0.3 at normal
// incidence for α = [0.05, 0.5]: docs/openpbr.md, "Anisotropic metal").
//
// Tabulated once per distribution by quadrature: at kMu × kPhi nodes (μ uniform in μ^¼, as
// the isotropic tables are: E changes fastest near grazing, on the scale of the roughness;
// φ uniform in [0, π/2], to which the symmetries φ → −φ and φ → π − φ of an axis-aligned
// distribution fold every azimuth), E is the mean of G2/G1(ωo) over the visible normals
// (Heitz 2018, whose density D_ωo = G1 (ωo·h) D / cos θo turns the integrand into that
// ratio, 0 where the reflected direction falls below the horizon) on a kGrid × kGrid
// stratified grid. E is read bilinearly; its cosine-weighted mean Ē over the hemisphere is
// that of the interpolant, so that the compensation lobe returns 1 − E(ωo) exactly for
// the table's E.
//
// A table costs 20–30 ms, too much to make at every shading point of a textured roughness
// (with_params). So the models read E through AnisotropicAlbedoBlend: tables at the nodes
// of a fixed grid in (log₂ αx, log₂ αy), four nodes per octave, each made once per
// process on first use and kept, and E read bilinearly between the four nodes around
// (αx, αy). Ē blends with the same weights, so it is still the mean of the E read, and
// the lobe still returns 1 − E(ωo) exactly; what the blend changes is E itself, by the
// interpolation error in α (the white furnace of docs/openpbr.md, "Anisotropic metal",
// and the tests that hold it).

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "gonio/fresnel.h"
#include "gonio/math/constants.h"
#include "gonio/math/vec3.h"
#include "gonio/microfacet.h"

namespace gonio {

class AnisotropicAlbedo {
 public:
  static constexpr int kMu = 32, kPhi = 13, kGrid = 20;

  // Tabulates E for `d` (1.7 KB; AnisotropicAlbedoBlend keeps one per grid node).
  static std::unique_ptr<AnisotropicAlbedo> make(const MicrofacetDistribution& d) {
    auto t = std::make_unique<AnisotropicAlbedo>();
    for (int j = 0; j < kMu; ++j) {
      // μ = 0 itself is a direction in the tangent plane: its limit, at μ = 1e-6.
      const double s = double(j) / (kMu - 1), mu = std::max(s * s * s * s, 1e-6);
      const double sin_t = std::sqrt(1 - mu * mu);
      for (int k = 0; k < kPhi; ++k) {
        const double phi = double(k) / (kPhi - 1) * kPiD / 2;
        const Vec3 wo{Float(sin_t * std::cos(phi)), Float(sin_t * std::sin(phi)), Float(mu)};
        const double g1 = double(d.G1(wo));
        double sum = 0;
        for (int a = 0; a < kGrid; ++a)
          for (int b = 0; b < kGrid; ++b) {
            const Vec3 h = d.sample_visible(wo, (Float(a) + Float(0.5)) / kGrid, (Float(b) + Float(0.5)) / kGrid);
            const Vec3 wi = reflect(wo, h);
            if (wi.z > 0) sum += double(d.G2(wo, wi)) / g1;
          }
        t->e_[size_t(j * kPhi + k)] = Float(std::clamp(sum / (kGrid * kGrid), 0.0, 1.0));
      }
    }
    // Ē = (1/π) ∫ E cos θ dω = (4/π) ∫₀^{π/2} ∫₀¹ E(μ, φ) μ dμ dφ, of the interpolant by the
    // midpoint rule (fine enough that its error is far below the table's).
    constexpr int kAvgMu = 256, kAvgPhi = 32;
    double avg = 0;
    for (int k = 0; k < kAvgPhi; ++k) {
      const double phi = (k + 0.5) / kAvgPhi * kPiD / 2;
      for (int j = 0; j < kAvgMu; ++j) {
        const double mu = (j + 0.5) / kAvgMu, sin_t = std::sqrt(1 - mu * mu);
        avg += double(t->E(Vec3{Float(sin_t * std::cos(phi)), Float(sin_t * std::sin(phi)), Float(mu)})) * mu;
      }
    }
    t->avg_ = Float(avg * 2 / (kAvgMu * kAvgPhi));
    return t;
  }

  // E(ω) for a direction on either side (|cos θ| is taken), in the distribution's frame.
  Float E(const Vec3& w) const {
    const Float mu = std::clamp(std::abs(w.z), Float(0), Float(1));
    const Float s = std::sqrt(std::sqrt(mu)) * Float(kMu - 1);
    const int j = std::min(int(s), kMu - 2);
    const Float tj = s - Float(j);
    const Float ax = std::abs(w.x), ay = std::abs(w.y);
    const Float p = (ax > 0 || ay > 0 ? std::atan2(ay, ax) : Float(0)) * Float(2 / kPiD) * Float(kPhi - 1);
    const int k = std::clamp(int(p), 0, kPhi - 2);
    const Float tk = std::clamp(p - Float(k), Float(0), Float(1));
    const auto at = [&](int jj, int kk) { return e_[size_t(jj * kPhi + kk)]; };
    const Float lo = at(j, k) * (1 - tk) + at(j, k + 1) * tk;
    const Float hi = at(j + 1, k) * (1 - tk) + at(j + 1, k + 1) * tk;
    return lo * (1 - tj) + hi * tj;
  }
  // Ē, the cosine-weighted mean of E over the hemisphere.
  Float average() const { return avg_; }

 private:
  std::array<Float, size_t(kMu * kPhi)> e_{};
  Float avg_ = 0;
};

// E and Ē at any (αx, αy): the grid nodes' tables blended bilinearly in (log₂ αx, log₂ αy)
// (above). A value: four pointers to tables that live as long as the process, and their
// weights; copying it allocates nothing.
struct AnisotropicAlbedoBlend {
  // Four nodes per octave, from α = 2^-10 (below MicrofacetDistribution::kSmoothAlpha, where
  // no compensation is made) to 2^4 (above the largest α a material accepts, 10).
  static constexpr int kNodesPerOctave = 4, kLowestOctave = -10, kHighestOctave = 4;
  static constexpr int kNodes = (kHighestOctave - kLowestOctave) * kNodesPerOctave + 1;

  std::array<const AnisotropicAlbedo*, 4> table{};  // null: no table (E reads 0)
  std::array<Float, 4> weight{};
  Float avg = 0;

  // Makes the tables of the four nodes around (αx, αy) on first use (thread-safe).
  static AnisotropicAlbedoBlend at(const MicrofacetDistribution& d);

  bool active() const { return table[0] != nullptr; }
  Float E(const Vec3& w) const {
    Float e = 0;
    for (size_t i = 0; i < 4; ++i)
      if (weight[i] > 0) e += weight[i] * table[i]->E(w);
    return e;
  }
  Float average() const { return avg; }
};

}  // namespace gonio
