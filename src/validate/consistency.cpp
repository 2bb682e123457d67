// Property "consistency": what sample() reports agrees with f() and pdf() (SPEC §1:
// weight = f |cos θi| / pdf), and each lobe's mean weight equals the model's exact
// albedo where it has one (for delta lobes: F, or (1 − F)(n_wo/n_wi)² for refraction in
// radiance mode). The figure is the worst error in units of its allowance: a relative
// error of 10⁻³ per sample, 4 standard errors (+10⁻⁵) for a lobe's mean weight.

#include "common.h"

namespace gonio {

using namespace validation;

PropertyResult check_consistency(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"consistency", 0.0, 1, true, ""};
  constexpr double kRelTolerance = 1e-3;
  Pcg32 rng = rng_for(opt, 5);
  double worst = 0;
  const auto dirs = test_outgoing_directions(bxdf);
  const std::uint64_t n = scaled(opt, 100'000, 5000);
  for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
    for (const auto& wo : dirs) {
      // Weights summed by lobe, compared with the exact albedo below where there is one.
      double sum_r[kColorChannels] = {}, sum_t[kColorChannels] = {};
      double sum_r2[kColorChannels] = {}, sum_t2[kColorChannels] = {};
      double max_r[kColorChannels] = {}, max_t[kColorChannels] = {};
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), mode);
        if (!s) continue;
        for (int c = 0; c < Color::size(); ++c) {
          const double w = s->weight[c];
          (s->lobe == Lobe::Reflection ? sum_r : sum_t)[c] += w;
          (s->lobe == Lobe::Reflection ? sum_r2 : sum_t2)[c] += w * w;
          double& mx = (s->lobe == Lobe::Reflection ? max_r : max_t)[c];
          mx = std::max(mx, w);
        }
        if (s->delta) continue;
        const Float pdf = bxdf.pdf(wo, s->wi, mode);
        const Color f = bxdf.f(wo, s->wi, mode);
        const double ep = relative_error(s->pdf, pdf) / kRelTolerance;
        if (ep > worst) {
          worst = ep;
          r.detail = "sample pdf " + fmt(s->pdf) + " but pdf() " + fmt(pdf) + " at wo " + describe(wo) +
                     ", wi " + describe(s->wi);
        }
        if (pdf > 0) {
          const Color expect = f * (std::abs(s->wi.z) / pdf);
          const double ew = color_relative_error(s->weight, expect, 1e-6) / kRelTolerance;
          if (ew > worst) {
            worst = ew;
            r.detail = "weight " + fmt(s->weight.max_component()) + " but f|cos|/pdf " +
                       fmt(expect.max_component()) + " at wo " + describe(wo) + ", wi " + describe(s->wi);
          }
        }
        const bool reflected = same_hemisphere(wo, s->wi);
        if (reflected != (s->lobe == Lobe::Reflection)) {
          worst = std::max(worst, 1e6);
          r.detail = "lobe label disagrees with the side of wi at wo " + describe(wo);
        }
      }
      // The mean weight of each lobe is its directional albedo: for delta lobes the
      // lobe's reflectance (e.g. F, or (1 − F)(n_wo/n_wi)² for refraction in radiance
      // mode); this also proves a model's closed-form albedo against its own sampling.
      if (const auto exact = bxdf.exact_albedo(wo, mode)) {
        for (int c = 0; c < Color::size(); ++c) {
          for (int lobe = 0; lobe < 2; ++lobe) {
            const double sum = lobe ? sum_t[c] : sum_r[c], sum2 = lobe ? sum_t2[c] : sum_r2[c];
            const double mean = sum / double(n);
            const double want = lobe ? exact->transmittance[c] : exact->reflectance[c];
            // The sample's standard error, but no less than the bound want (W − want)
            // on the variance of a contribution in [0, W]: a rare lobe that no sample
            // happened to hit must not make the estimate look exact.
            const double w_max = std::max(lobe ? max_t[c] : max_r[c], want);
            const double var = std::max(sum2 / double(n) - mean * mean, want * (w_max - want));
            const double se = std::sqrt(std::max(0.0, var) / double(n));
            // Deviation in units of the allowed error (4 standard errors + float round-off).
            const double allowed = 4 * se + 1e-5;
            const double e = std::abs(mean - want) / allowed;
            if (e > worst) {
              worst = e;
              r.detail = std::string(lobe ? "transmission" : "reflection") + " lobe: mean weight " +
                         fmt(mean) + ", exact " + fmt(want) + " at wo " + describe(wo) +
                         (mode == TransportMode::Radiance ? " (radiance)" : " (importance)");
            }
          }
        }
      }
    }
  }
  r.figure = worst;
  r.pass = worst <= r.threshold;
  if (worst == 0) r.detail = "exact agreement";
  return r;
}

}  // namespace gonio
