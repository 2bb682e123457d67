// Tabulating a material into a MERL table (tabulate.h).

#include "gonio/tabulate.h"

#include "gonio/error.h"

namespace gonio {

MerlTable tabulate(const BxDF& model) {
  const std::string name = model.name();
  if (!model.is_isotropic())
    throw InputError(name + ": anisotropic; a MERL table holds isotropic BRDFs only");
  if (is_specular(model.flags()))
    throw InputError(name + ": has a delta (specular) lobe, which a table of f values cannot hold");
  MerlTable table;
  for (int i = 0; i < MerlTable::kThetaH; ++i) {
    const double theta_h = merl_theta_h(i);
    for (int j = 0; j < MerlTable::kThetaD; ++j) {
      const double theta_d = merl_theta_d(j);
      for (int k = 0; k < MerlTable::kPhiD; ++k) {
        const auto [wo, wi] = merl_directions(theta_h, theta_d, merl_phi_d(k));
        if (!(wo.z > 0) || !(wi.z > 0)) {
          table.set_missing(i, j, k);
          continue;
        }
        table.set(i, j, k, model.f(wo, wi, TransportMode::Radiance));
      }
    }
  }
  return table;
}

}  // namespace gonio
