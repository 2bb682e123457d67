// Property "energy" (lecture §3.4, §4): for light arriving from any direction, the
// scattered fraction ρ_dh (importance mode) is at most 1. A model that is not reciprocal
// (BxDF::nonreciprocal_reason()) bounds only its radiance-mode albedo: that is checked,
// and its importance-mode albedo is measured and given in the detail.

#include "common.h"
#include "gonio/reflectance.h"

namespace gonio {

using namespace validation;

namespace {
// ∫ f(wo, wi) (n_wi/n_wo)² |cos θi| dωi in radiance mode: exact where the model has a
// closed form, else the mean weight of n radiance-mode samples. Radiance crossing an
// interface is scaled by (n_wo/n_wi)² (lecture §5.3: what is conserved is L/n², the basic
// radiance, Veach 1997 §5.2), so a refraction from inside legitimately returns more than
// the light it received; the bound ≤ 1 holds for the basic radiance: a transmitted
// sample's weight times eta² (BSDFSample::eta = n_wi/n_wo, transmission_scale's inverse).
AlbedoEstimate radiance_albedo(const BxDF& bxdf, const Vec3& wo, std::uint64_t n, std::uint64_t seed) {
  AlbedoEstimate e;
  if (const auto exact = bxdf.exact_albedo(wo, TransportMode::Radiance)) {
    e.albedo = exact->reflectance + exact->transmittance;
    e.exact = true;
    return e;
  }
  Pcg32 rng(seed, 0x2545f4914f6cdd1dULL);
  double sum[kColorChannels] = {}, sum2[kColorChannels] = {};
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Radiance);
    if (!s) continue;
    const double k = s->lobe == Lobe::Transmission ? double(s->eta) * double(s->eta) : 1.0;
    for (int c = 0; c < kColorChannels; ++c) {
      const double w = double(s->weight[c]) * k;
      sum[c] += w;
      sum2[c] += w * w;
    }
  }
  for (int c = 0; c < kColorChannels; ++c) {
    const double mean = sum[c] / double(n), var = std::max(0.0, sum2[c] / double(n) - mean * mean);
    e.albedo[c] = Float(mean);
    e.se_albedo[c] = Float(std::sqrt(var / double(n)));
  }
  return e;
}
}  // namespace

PropertyResult check_energy(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"energy", 0.0, 1, true, ""};
  const bool aniso = !bxdf.is_isotropic();
  // 16 polar angles per side (8 × 8 azimuths when anisotropic): about 3·10⁶ samples.
  const int n_theta = aniso ? 8 : 16, n_phi = aniso ? 8 : 1;
  const std::uint64_t n = scaled(opt, aniso ? 50'000 : 100'000, 2000);
  double worst_margin = -1e300, worst_albedo = 0, worst_threshold = 1;
  const bool reciprocal = bxdf.nonreciprocal_reason().empty();
  double worst_importance = 0;
  std::string importance_where;
  int k = 0;
  for (int side = 0; side < 2; ++side) {
    for (int it = 0; it < n_theta; ++it) {
      // cos θ from 1 to nearly 0, denser towards grazing where models misbehave.
      const double mu = 1 - (1 - 1e-3) * std::pow(it / double(n_theta - 1), 0.7);
      for (int ip = 0; ip < n_phi; ++ip) {
        const double ph = aniso ? ip * kPiD / n_phi : 0.3;
        const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
        const Vec3 wo{Float(s * std::cos(ph)), Float(s * std::sin(ph)), Float(side ? -mu : mu)};
        const AlbedoEstimate imp = directional_albedo(bxdf, wo, {n, opt.seed + std::uint64_t(++k)});
        const AlbedoEstimate e = reciprocal ? imp : radiance_albedo(bxdf, wo, n, opt.seed + std::uint64_t(k));
        if (!reciprocal && imp.albedo.max_component() > worst_importance) {
          worst_importance = imp.albedo.max_component();
          importance_where = fmt(std::acos(mu) * 180 / kPiD) + " deg";
        }
        for (int c = 0; c < Color::size(); ++c) {
          const double threshold = 1 + 3 * double(e.se_albedo[c]) + 2e-3;
          const double margin = double(e.albedo[c]) - threshold;
          if (margin > worst_margin) {
            worst_margin = margin;
            worst_albedo = e.albedo[c];
            worst_threshold = threshold;
            r.detail = "albedo " + fmt(e.albedo[c]) + " ± " + fmt(e.se_albedo[c]) + " at theta " +
                       fmt(std::acos(mu) * 180 / kPiD) + " deg" + (aniso ? ", phi " + fmt(ph * 180 / kPiD) : "") +
                       (side ? " (inside)" : "") + ", channel " + std::to_string(c);
          }
        }
      }
    }
  }
  r.figure = worst_albedo;
  r.threshold = worst_threshold;
  r.pass = worst_margin <= 0;
  if (!reciprocal)
    r.detail = "radiance mode (not reciprocal): " + r.detail + "; importance mode (light arriving along wo) reaches " +
               fmt(worst_importance) + " at theta " + importance_where;
  return r;
}

}  // namespace gonio
