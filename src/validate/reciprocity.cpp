// Property "reciprocity" (lecture §3.4; Veach 1997, §5.2 for transmission); for a
// polarizing model also in Mueller form (issue 15).

#include "common.h"
#include "gonio/polarization/polarized_bxdf.h"

namespace gonio {

using namespace validation;

PropertyResult check_reciprocity(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"reciprocity", std::nullopt, 1e-3, true, "delta lobes only: nothing to evaluate"};
  if (is_delta_only(bxdf.flags())) return r;
  // A measured table (rgl) is held to its documented interpolation error (SPEC §2).
  if (const Float tol = bxdf.reciprocity_tolerance(); tol > 0) r.threshold = tol;
  const Float eta = bxdf.relative_eta();
  Pcg32 rng = rng_for(opt, 2);
  double worst = 0;
  // A model not reciprocal by construction: the error is measured and reported, only
  // the adjoint check below is held to the threshold.
  const std::string_view reason = bxdf.nonreciprocal_reason();
  const bool fibre = bxdf.is_fibre();
  double worst_adjoint = 0;
  std::string adjoint_detail;
  const PolarizedBxDF pol(bxdf);
  // M(wo, wi)/n_wo² = Q M(wi, wo)ᵀ Q / n_wi², Q = diag(1, 1, −1, 1): reciprocity of the
  // scattering amplitudes in the frames of polarization/fresnel_factor.h (the Stokes
  // frames of the reversed path mirror U; e.g. Sekera 1966, J. Opt. Soc. Am. 56, 1732).
  // Entries are compared relative to M00 (the largest entry of a realizable matrix).
  auto check_mueller = [&](const Vec3& wo, const Vec3& wi, Float no, Float ni) {
    const MuellerT<Color> a = pol.f(wo, wi, TransportMode::Radiance);
    const MuellerT<Color> b = pol.f(wi, wo, TransportMode::Radiance);
    for (int ch = 0; ch < Color::size(); ++ch) {
      const double m00 = double(a(0, 0)[ch]) / (no * no);
      const double floor = 1e-5 * std::max(1.0, m00);
      for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 4; ++y) {
          const double q = (x == 2) != (y == 2) ? -1 : 1;
          const double d = std::abs(double(a(x, y)[ch]) / (no * no) - q * double(b(y, x)[ch]) / (ni * ni));
          const double e = d / std::max(std::abs(m00), floor);
          if (e > worst && d > floor) {
            worst = e;
            r.detail = "Mueller form, entry (" + std::to_string(x) + "," + std::to_string(y) + ") at wo " + describe(wo) +
                       ", wi " + describe(wi);
          }
        }
    }
  };
  auto check = [&](const Vec3& wo, const Vec3& wi) {
    // Radiance-mode f(wo, wi)/n_wo² = f(wi, wo)/n_wi²; for reflection both n are equal.
    const Float no = index_on_side(wo, eta), ni = index_on_side(wi, eta);
    if (pol.polarizing()) check_mueller(wo, wi, no, ni);
    const Color a = bxdf.f(wo, wi, TransportMode::Radiance) / (no * no);
    const Color b = bxdf.f(wi, wo, TransportMode::Radiance) / (ni * ni);
    // Values tiny in both directions are round-off, not a failure of the model.
    const double e = color_relative_error(a, b, 1e-5 * std::max(1.0, double(a.max_component())));
    if (e > worst) {
      worst = e;
      r.detail = "wo " + describe(wo) + ", wi " + describe(wi) + ": " + fmt(a.max_component()) + " vs " +
                 fmt(b.max_component());
    }
    // Importance mode is the adjoint: f_imp(wo, wi) = f_rad(wi, wo) (SPEC §1); for a fibre
    // (bxdf/hair.h) the adjoint of its kernel S = f |wi.z|: f_imp(wo, wi) |wi.z| = S(wi, wo).
    const Color imp = bxdf.f(wo, wi, TransportMode::Importance);
    Color adj = bxdf.f(wi, wo, TransportMode::Radiance);
    if (fibre) {
      if (std::abs(wo.z) < 1e-6f || std::abs(wi.z) < 1e-6f) return;  // |z| is clamped there
      adj = adj * (std::abs(wo.z) / std::abs(wi.z));
    }
    const double ea = color_relative_error(imp, adj, 1e-5 * std::max(1.0, double(adj.max_component())));
    if (ea > worst_adjoint) {
      worst_adjoint = ea;
      adjoint_detail = "largest in the adjoint check (importance mode vs radiance mode swapped) at wo " +
                       describe(wo) + ", wi " + describe(wi);
    }
  };
  const auto adv = adversarial_directions(eta);
  for (const auto& wo : adv)
    for (const auto& wi : adv) check(wo, wi);
  const std::uint64_t n = scaled(opt, 200'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    // Half the pairs from the model's own sampling, so that they land on its lobes.
    Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    if (i & 1) {
      if (auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float()); s && !s->delta)
        wi = s->wi;
    }
    check(wo, wi);
  }
  if (!reason.empty()) {
    r.applicable = false;
    r.figure = std::nullopt;
    r.pass = worst_adjoint <= r.threshold;
    r.detail = "not applicable: " + std::string(reason) + "; largest error measured " + fmt(worst) + " (" + r.detail +
               ")" + (r.pass ? "; its adjoint (importance mode) holds to " + fmt(worst_adjoint)
                             : "; its adjoint FAILS: " + fmt(worst_adjoint) + ", " + adjoint_detail);
    return r;
  }
  if (worst_adjoint > worst) {
    worst = worst_adjoint;
    r.detail = adjoint_detail;
  }
  r.figure = worst;
  r.pass = worst <= r.threshold;
  if (worst == 0) r.detail = std::to_string(n) + " pairs, exact";
  return r;
}

}  // namespace gonio
