// Property "energy" (lecture §3.4, §4): for light arriving from any direction, the
// scattered fraction ρ_dh (importance mode) is at most 1. A model that is not reciprocal
// (BxDF::nonreciprocal_reason()) bounds only its radiance-mode albedo: that is checked,
// and its importance-mode albedo is measured and given in the detail.

#include "common.h"
#include "gonio/reflectance.h"

namespace gonio {

using namespace validation;

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
        // The view's albedo (radiance mode, the refraction scaling removed: reflectance.h);
        // a model that is not reciprocal also gives the light's.
        const AlbedoEstimate e = directional_albedo(bxdf, wo, {n, opt.seed + std::uint64_t(++k)});
        const Float light = e.light ? (e.light->reflectance + e.light->transmittance).max_component() : Float(0);
        if (!reciprocal && light > worst_importance) {
          worst_importance = light;
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
