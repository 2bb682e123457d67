// Property "isotropy" (lecture §3.4, eq. 5): an isotropic model depends on the azimuths
// only through φi − φo, so rotating both directions about N changes nothing.

#include <algorithm>

#include "common.h"

namespace gonio {

using namespace validation;

namespace {
Vec3 rotate_z(const Vec3& w, Float angle) {
  const Float c = std::cos(angle), s = std::sin(angle);
  return normalize(Vec3{c * w.x - s * w.y, s * w.x + c * w.y, w.z});
}
// About x: a fibre's axis (bxdf/hair.h).
Vec3 rotate_x(const Vec3& w, Float angle) {
  const Float c = std::cos(angle), s = std::sin(angle);
  return normalize(Vec3{w.x, c * w.y - s * w.z, s * w.y + c * w.z});
}
}  // namespace

// Two kinds of rotation: quarter turns (exact in floating point) and arbitrary angles.
// Sharp lobes (a Phong exponent of 10⁴, say) amplify rounding of the inputs into
// relative changes of f near 10⁻³ whatever the model, so each pair's error is taken in
// excess of its own sensitivity, measured by rotations of ±10⁻⁵ rad (which changes an
// isotropic model only through rounding, and an anisotropic one only by ~10⁻⁵). The
// figure is the larger of the worst quarter-turn excess and the 99th percentile of the
// arbitrary-angle excess; an anisotropic model declared isotropic fails by far.
PropertyResult check_isotropy(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"isotropy", std::nullopt, 1e-3, true, "anisotropic by declaration"};
  // A fibre is symmetric about its axis x, not about z: isotropy about z does not apply;
  // the same test about x is measured and must hold.
  const bool fibre = bxdf.is_fibre();
  if (!bxdf.is_isotropic() && !fibre) return r;
  const auto turn_about = [fibre](const Vec3& w, Float angle) { return fibre ? rotate_x(w, angle) : rotate_z(w, angle); };
  Pcg32 rng = rng_for(opt, 6);
  const std::uint64_t n = scaled(opt, 100'000);
  std::vector<double> random_errors;
  random_errors.reserve(n);
  double worst_quarter = 0;
  std::string quarter_detail, random_detail;
  double worst_random = -1;
  auto error_between = [&](const Vec3& wo, const Vec3& wi, const Vec3& ro, const Vec3& ri, Float u0, Float u1,
                           Float u2, auto&& rotate) {
    // A fibre's f = S/|wi.z| (SPEC §2): S is what is symmetric about its axis.
    const Color f = bxdf.f(wo, wi) * (fibre ? std::abs(wi.z) : Float(1)),
                fr = bxdf.f(ro, ri) * (fibre ? std::abs(ri.z) : Float(1));
    double e = color_relative_error(f, fr, 1e-4 * std::max(1.0, double(f.max_component())));
    const Float p = bxdf.pdf(wo, wi), pr = bxdf.pdf(ro, ri);
    if (std::max(p, pr) > 1e-4f * std::max(Float(1), p)) e = std::max(e, relative_error(p, pr));
    // Delta lobes: the same lobe choice gives the same weight, and the direction turns along.
    const auto s = bxdf.sample(wo, u0, u1, u2), sr = bxdf.sample(ro, u0, u1, u2);
    if (s && sr && s->delta && sr->delta) {
      e = std::max(e, color_relative_error(s->weight, sr->weight, 1e-6));
      e = std::max(e, double(length(rotate(s->wi) - sr->wi)));
    }
    return e;
  };
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    if (auto s = bxdf.sample(wo, u0, u1, u2); s && (i & 1)) wi = s->wi;
    auto nudge_p = [&](const Vec3& w) { return turn_about(w, Float(1e-5)); };
    auto nudge_m = [&](const Vec3& w) { return turn_about(w, Float(-1e-5)); };
    const double sensitivity = std::max(error_between(wo, wi, nudge_p(wo), nudge_p(wi), u0, u1, u2, nudge_p),
                                        error_between(wo, wi, nudge_m(wo), nudge_m(wi), u0, u1, u2, nudge_m));
    auto quarter = [fibre](const Vec3& w) { return fibre ? Vec3{w.x, -w.z, w.y} : Vec3{-w.y, w.x, w.z}; };
    const double eq =
        std::max(0.0, error_between(wo, wi, quarter(wo), quarter(wi), u0, u1, u2, quarter) - 10 * sensitivity);
    if (eq > worst_quarter) {
      worst_quarter = eq;
      quarter_detail = "quarter turn of wo " + describe(wo) + ", wi " + describe(wi);
    }
    const Float angle = 2 * kPi * rng.next_float();
    auto turn = [&](const Vec3& w) { return turn_about(w, angle); };
    const double er = std::max(0.0, error_between(wo, wi, turn(wo), turn(wi), u0, u1, u2, turn) - 10 * sensitivity);
    random_errors.push_back(er);
    if (er > worst_random) {
      worst_random = er;
      random_detail = "rotation by " + fmt(angle) + " rad of wo " + describe(wo) + ", wi " + describe(wi);
    }
  }
  const size_t k = std::min(random_errors.size() - 1, size_t(0.99 * double(random_errors.size())));
  std::nth_element(random_errors.begin(), random_errors.begin() + std::ptrdiff_t(k), random_errors.end());
  const double p99 = random_errors[k];
  r.figure = std::max(worst_quarter, p99);
  r.pass = *r.figure <= r.threshold;
  r.detail = worst_quarter >= p99 ? "worst: " + quarter_detail
                                  : "99th percentile " + fmt(p99) + " over arbitrary angles; worst: " + random_detail;
  if (fibre) {
    r.applicable = false;
    r.detail = "not applicable: a fibre is symmetric about its axis x, not about z; about x the error is " +
               fmt(*r.figure) + (r.pass ? "" : " (FAILS)") + " (" + r.detail + ")";
    r.figure = std::nullopt;
  }
  return r;
}

}  // namespace gonio
