// Property "finite": no NaN, Inf or negative value from f, pdf or sample.

#include "common.h"

namespace gonio {

using namespace validation;

PropertyResult check_finite(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"finite", 0.0, 0, true, ""};
  Pcg32 rng = rng_for(opt, 1);
  std::uint64_t bad = 0;
  auto report = [&](const std::string& what) {
    if (bad++ == 0) r.detail = what;
  };
  auto check_pair = [&](const Vec3& wo, const Vec3& wi) {
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const BSDFEval e = bxdf.eval(wo, wi, mode);
      const Color f = bxdf.f(wo, wi, mode);
      const Float p = bxdf.pdf(wo, wi, mode);
      if (!e.f.is_finite() || e.f.min_component() < 0 || !f.is_finite() || f.min_component() < 0)
        report("f not finite and >= 0 at wo " + describe(wo) + ", wi " + describe(wi));
      if (!std::isfinite(e.pdf) || e.pdf < 0 || !std::isfinite(p) || p < 0)
        report("pdf not finite and >= 0 at wo " + describe(wo) + ", wi " + describe(wi));
    }
  };
  auto check_sample = [&](const Vec3& wo, Float u0, Float u1, Float u2) {
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const auto s = bxdf.sample(wo, u0, u1, u2, mode);
      if (!s) continue;
      const bool ok = s->weight.is_finite() && s->weight.min_component() >= 0 &&
                      std::isfinite(s->pdf) && s->pdf > 0 && is_finite(s->wi) &&
                      std::abs(length(s->wi) - 1) < 1e-3f && std::isfinite(s->eta) && s->eta > 0;
      if (!ok)
        report("sample at wo " + describe(wo) + ", u (" + fmt(u0) + ", " + fmt(u1) + ", " + fmt(u2) +
               ") gave wi " + describe(s->wi) + ", weight " + fmt(s->weight[0]) + ", pdf " + fmt(s->pdf));
    }
  };

  const auto adv = adversarial_directions(bxdf.relative_eta());
  for (const auto& wo : adv) {
    for (const auto& wi : adv) {
      check_pair(wo, wi);
      check_pair(wo, -wi);
    }
    for (Float u0 : {Float(0), Float(0.5), kOneMinusEpsilon})
      for (Float u1 : {Float(0), Float(0.5), kOneMinusEpsilon})
        for (Float u2 : {Float(0), Float(0.25), kOneMinusEpsilon}) check_sample(wo, u0, u1, u2);
  }
  const std::uint64_t n = scaled(opt, 1'000'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Vec3 wi = (i & 7) == 0 ? wo : ((i & 7) == 1 ? -wo : square_to_uniform_sphere(rng.next_float(), rng.next_float()));
    check_pair(wo, wi);
    check_sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
  }
  r.figure = double(bad);
  r.pass = bad == 0;
  if (r.pass) r.detail = std::to_string(n) + " random and " + std::to_string(adv.size() * adv.size() * 2) + " adversarial pairs";
  else r.detail = std::to_string(bad) + " bad values; first: " + r.detail;
  return r;
}

}  // namespace gonio
