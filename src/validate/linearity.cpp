// Property "linearity" (lecture §3.4): a blend (1 − w) A + w B must behave as the
// weighted sum of its parts — in f and pdf for every pair, and in what its sampling
// delivers: the mean sample weight (the albedo, delta lobes included) equals
// (1 − w) × A's + w × B's, within 4 standard errors.

#include "common.h"

namespace gonio {

using namespace validation;

namespace {

struct MeanWeight {
  double mean = 0, se = 0;
};

// Mean of the first channel of sample weights from wo (0 for no sample), and its
// standard error.
MeanWeight mean_weight(const BxDF& m, const Vec3& wo, std::uint64_t n, Pcg32& rng) {
  double sum = 0, sum2 = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto s = m.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
    const double w = s ? double(s->weight[0]) : 0.0;
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / double(n);
  return {mean, std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean) / double(n))};
}

}  // namespace

PropertyResult check_linearity(const BxDF& blend, const BxDF& a, const BxDF& b, Float w,
                               const ValidationOptions& opt) {
  PropertyResult r{"linearity", 0.0, 1, true, ""};
  Pcg32 rng = rng_for(opt, 8);
  double worst = 0;
  // f and pdf: relative error, allowed 1e-4.
  const std::uint64_t n = scaled(opt, 100'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    if (auto s = blend.sample(wo, rng.next_float(), rng.next_float(), rng.next_float()); s && (i & 1)) wi = s->wi;
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const Color f = blend.f(wo, wi, mode);
      const Color expect = a.f(wo, wi, mode) * (1 - w) + b.f(wo, wi, mode) * w;
      const double ef = color_relative_error(f, expect, 1e-6) / 1e-4;
      const double ep = relative_error(blend.pdf(wo, wi, mode), (1 - w) * a.pdf(wo, wi, mode) + w * b.pdf(wo, wi, mode)) / 1e-4;
      if (std::max(ef, ep) > worst) {
        worst = std::max(ef, ep);
        r.detail = (ef >= ep ? "f" : "pdf") + std::string(" is not the weighted sum at wo ") + describe(wo) +
                   ", wi " + describe(wi);
      }
    }
  }
  // What sampling delivers: mean weights, in units of 4 combined standard errors.
  const std::uint64_t m = scaled(opt, 200'000, 5000);
  for (const Vec3& wo : test_outgoing_directions(blend)) {
    const MeanWeight mb = mean_weight(blend, wo, m, rng), ma = mean_weight(a, wo, m, rng),
                     mbb = mean_weight(b, wo, m, rng);
    const double expect = (1 - w) * ma.mean + w * mbb.mean;
    const double se = std::sqrt(mb.se * mb.se + (1 - w) * (1 - w) * ma.se * ma.se + w * w * mbb.se * mbb.se);
    const double e = std::abs(mb.mean - expect) / (4 * se + 1e-6);
    if (e > worst) {
      worst = e;
      r.detail = "mean sample weight " + fmt(mb.mean) + ", weighted parts " + fmt(expect) + " at wo " + describe(wo);
    }
  }
  r.figure = worst;
  r.pass = worst <= r.threshold;
  if (r.pass && r.detail.empty()) r.detail = "exact";
  return r;
}

PropertyResult check_linearity(const BxDF& bxdf, const ValidationOptions& opt) {
  const auto* blend = std::get_if<BlendBxDF>(&bxdf.models());
  if (!blend) return {"linearity", std::nullopt, 1, true, "not a blend"};
  return check_linearity(bxdf, (*blend->parts)[0], (*blend->parts)[1], blend->weight, opt);
}

}  // namespace gonio
