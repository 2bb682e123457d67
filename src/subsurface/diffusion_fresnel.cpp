// The Fresnel moments of the diffusion boundary and of Sw (sw_bxdf.h).

#include <cmath>

#include "gonio/fresnel.h"
#include "gonio/subsurface/sw_bxdf.h"

namespace gonio {

double fresnel_moment(int k, double eta) {
  if (!(eta > 0) || k < 0) return 0;
  // Light from the denser side (eta < 1) is totally reflected for μ below μc = √(1 − η²):
  // that part is ∫0^μc μ^k dμ exactly. Above μc, cos θt ~ √(μ − μc): μ = μc + (1 − μc) s²
  // makes the integrand smooth in s, and the midpoint rule converges as h².
  const double mu_c = eta < 1 ? std::sqrt(1 - eta * eta) : 0.0;
  double sum = std::pow(mu_c, k + 1) / (k + 1);
  constexpr int n = 8192;
  const double h = 1.0 / n, span = 1 - mu_c;
  double part = 0;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) * h;
    const double mu = mu_c + span * s * s;
    part += fresnel_dielectric(mu, eta) * std::pow(mu, k) * 2 * span * s;  // dμ = 2 span s ds
  }
  return sum + part * h;
}

}  // namespace gonio
