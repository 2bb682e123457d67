// Property "isotropy" (lecture §3.4, eq. 5): an isotropic model depends on the azimuths
// only through φi − φo, so rotating both directions about N changes nothing.

#include "common.h"

namespace gonio {

using namespace validation;

namespace {
Vec3 rotate_z(const Vec3& w, Float angle) {
  const Float c = std::cos(angle), s = std::sin(angle);
  return normalize(Vec3{c * w.x - s * w.y, s * w.x + c * w.y, w.z});
}
}  // namespace

PropertyResult check_isotropy(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"isotropy", std::nullopt, 1e-3, true, "anisotropic by declaration"};
  if (!bxdf.is_isotropic()) return r;
  Pcg32 rng = rng_for(opt, 6);
  double worst = 0;
  const std::uint64_t n = scaled(opt, 100'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    if (auto s = bxdf.sample(wo, u0, u1, u2); s && (i & 1)) wi = s->wi;
    const Float angle = 2 * kPi * rng.next_float();
    const Vec3 ro = rotate_z(wo, angle), ri = rotate_z(wi, angle);
    const Color f = bxdf.f(wo, wi), fr = bxdf.f(ro, ri);
    double e = color_relative_error(f, fr, 1e-4 * std::max(1.0, double(f.max_component())));
    const Float p = bxdf.pdf(wo, wi), pr = bxdf.pdf(ro, ri);
    if (std::max(p, pr) > 1e-4f * std::max(Float(1), p)) e = std::max(e, relative_error(p, pr));
    // Delta lobes: the same lobe choice gives the same weight, and the direction rotates along.
    const auto s = bxdf.sample(wo, u0, u1, u2), sr = bxdf.sample(ro, u0, u1, u2);
    if (s && sr && s->delta && sr->delta) {
      e = std::max(e, color_relative_error(s->weight, sr->weight, 1e-6));
      e = std::max(e, double(length(rotate_z(s->wi, angle) - sr->wi)));
    }
    if (e > worst) {
      worst = e;
      r.detail = "wo " + describe(wo) + ", wi " + describe(wi) + " rotated by " + fmt(angle) + " rad";
    }
  }
  r.figure = worst;
  r.pass = worst <= r.threshold;
  if (r.pass && r.detail.empty()) r.detail = std::to_string(n) + " rotated pairs";
  return r;
}

PropertyResult check_linearity(const BxDF&, const ValidationOptions&) {
  // Applies to blends of models; gonio has no blend model yet.
  return {"linearity", std::nullopt, 1e-4, true, "not a blend"};
}

}  // namespace gonio
