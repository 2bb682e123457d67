// Property "consistency": what sample() reports agrees with f() and pdf() (SPEC §1:
// weight = f |cos θi| / pdf), delta samples go where the laws of reflection and
// refraction send them, and each delta lobe's mean weight equals its reflectance as the
// validator computes it (delta_reference.h: F, (1 − F)(n_wo/n_wi)², total internal
// reflection — from its own Fresnel, not the model's). Where the model has a closed-form
// albedo, each lobe's mean weight must also equal it (this proves the closed form). The
// figure is the worst error in units of its allowance: a relative error of 10⁻³ per
// sample, 10⁻⁵ in a delta direction, 4 standard errors (+10⁻⁵) for a lobe's mean weight.

#include <algorithm>
#include <array>
#include <cmath>

#include "common.h"
#include "delta_reference.h"

namespace gonio {

using namespace validation;

namespace {

constexpr double kRelTolerance = 1e-3;
// Delta directions: float rounding of a unit vector is ~10⁻⁷; a direction off by more
// than 10⁻⁵ rad is a wrong direction, not round-off.
constexpr double kDirectionTolerance = 1e-5;

struct LobeSums {
  std::array<double, kColorChannels> sum{}, sum2{}, max{};
  std::uint64_t count = 0;
  void add(const Color& w) {
    ++count;
    for (int c = 0; c < kColorChannels; ++c) {
      sum[size_t(c)] += w[c];
      sum2[size_t(c)] += double(w[c]) * w[c];
      max[size_t(c)] = std::max(max[size_t(c)], double(w[c]));
    }
  }
};

// |mean − want| in units of 4 standard errors + 10⁻⁵. The standard error is no less than
// the bound want (W − want) on the variance of a contribution in [0, W]: a rare lobe that
// no sample happened to hit must not make the estimate look exact. A lobe no sample hit
// has no observed weight: W is then taken as 1, the weight of a sampler that picks the
// lobe with probability equal to its value (Fresnel-proportional choice), which misses a
// lobe of value `want` with probability (1 − want)^n. Such a lobe passes only while
// n·want ≤ 16 (a miss is then plausible: e^−16 at the limit); a lobe of larger value that
// is never sampled still fails. (The thin sheet at η = 10⁴ transmits 3.3·10⁻⁴: the
// sanitizer pass's tenfold smaller counts drew no transmission.)
double mean_error(const LobeSums& s, int c, double want, std::uint64_t n, double* mean_out) {
  const double mean = s.sum[size_t(c)] / double(n);
  const double w_max = std::max({s.max[size_t(c)], want, s.count == 0 ? 1.0 : 0.0});
  const double var = std::max(s.sum2[size_t(c)] / double(n) - mean * mean, want * (w_max - want));
  const double se = std::sqrt(std::max(0.0, var) / double(n));
  *mean_out = mean;
  return std::abs(mean - want) / (4 * se + 1e-5);
}

// The index the delta refraction must obey. It is the model's declared relative_eta() —
// the user's parameter, read, not computed by the code under test — rather than the
// index implied by the refracted direction: an index derived from sample()'s own output
// would let a sampler that refracts with a wrong index have its weights judged against
// the Fresnel of that wrong index. The refracted direction is instead held to Snell's law
// with the declared index (delta_direction_error), which ties the sampler's
// geometry, its weights and its declaration together; any disagreement fails.
//
// Error of a delta sample's direction in units of kDirectionTolerance (0 when exact).
double delta_direction_error(const Vec3& wo, const BSDFSample& s, double eta) {
  const double ox = wo.x, oy = wo.y, oz = wo.z, ix = s.wi.x, iy = s.wi.y, iz = s.wi.z;
  const double len_err = std::abs(std::sqrt(ix * ix + iy * iy + iz * iz) - 1) / kDirectionTolerance;
  if (s.lobe == Lobe::Reflection) {
    // The law of reflection: wi = (−wo.x, −wo.y, wo.z), on wo's side (lecture eq. 23).
    const double e = std::max({std::abs(ix + ox), std::abs(iy + oy), std::abs(iz - oz)}) / kDirectionTolerance;
    return std::max(e, len_err);
  }
  // Snell's law in vector form (lecture §5.3): n_o sin θo = n_t sin θt with the
  // tangential parts opposite, i.e. e · wi_xy = −wo_xy, e = n_t / n_o; wi on the far
  // side; and the sample's eta field must be e.
  const double e = oz > 0 ? eta : 1 / eta;
  const double snell = std::max(std::abs(e * ix + ox), std::abs(e * iy + oy)) / kDirectionTolerance;
  const double side = (iz * oz < 0) ? 0 : 1e6;
  const double eta_field = relative_error(s.eta, e) / kDirectionTolerance;
  return std::max({snell, side, len_err, eta_field});
}

std::string describe_delta_direction(const Vec3& wo, const BSDFSample& s, double eta) {
  if (s.lobe == Lobe::Reflection)
    return "delta reflection " + describe(s.wi) + " is not the mirror of wo " + describe(wo);
  const double e = wo.z > 0 ? eta : 1 / eta;
  const double so = std::hypot(double(wo.x), double(wo.y)), si = std::hypot(double(s.wi.x), double(s.wi.y));
  return "delta refraction " + describe(s.wi) + " of wo " + describe(wo) + " implies relative index " +
         fmt(si > 0 ? so / si : 0) + " (sample's eta field " + fmt(s.eta) + "), the model declares " + fmt(e) +
         (s.wi.z * wo.z < 0 ? "" : "; wi is not on the far side");
}

// A cut-out's pass-through (openpbr's geometry_opacity < 1, the δ(wi = −wo) of weight 1 − α):
// a delta transmission straight on, of index 1 whatever the model refracts with below it
// (a hole is not an interface). Only a model that declares one may have it.
bool has_cutout(const BxDF& bxdf) {
  if (const auto* g = std::get_if<GltfPbrBxDF>(&bxdf.models())) return g->coverage() < 1;
  const auto* m = std::get_if<OpenPbrBxDF>(&bxdf.models());
  return m && m->params.geometry_opacity < 1;
}
bool is_pass_through(const Vec3& wo, const BSDFSample& s) {
  return s.lobe == Lobe::Transmission && s.eta == 1 &&
         std::max({std::abs(double(s.wi.x) + wo.x), std::abs(double(s.wi.y) + wo.y), std::abs(double(s.wi.z) + wo.z)}) <=
             kDirectionTolerance;
}

}  // namespace

PropertyResult check_consistency(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"consistency", 0.0, 1, true, ""};
  Pcg32 rng = rng_for(opt, 5);
  double worst = 0;
  // Records the error e if it is the worst so far; `what` builds its description only then.
  auto note = [&](double e, const auto& what) {
    if (e > worst) {
      worst = e;
      r.detail = what();
    }
  };
  auto dirs = test_outgoing_directions(bxdf);
  const double eta = bxdf.relative_eta();
  const bool cutout = has_cutout(bxdf);
  if (is_transmissive(bxdf.flags())) {
    // Either side of the critical angle (total internal reflection starts there), on the
    // side where there is one: inside for η > 1, outside for η < 1.
    const double e_crit = eta > 1 ? 1 / eta : eta;
    if (eta != 1) {
      const double crit = std::asin(e_crit), d = 0.5 * kPiD / 180;
      for (double th : {crit - d, crit + d}) {
        if (!(th > 0.01 && th < kPiD / 2 - 0.001)) continue;
        const Vec3 w = direction_from_angles(Float(th), 0.9f);
        dirs.push_back(eta > 1 ? Vec3{w.x, w.y, -w.z} : w);
      }
    }
  }
  const std::uint64_t n = scaled(opt, 100'000, 5000);
  bool unknown_delta = false;
  for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
    const std::string mode_name = mode == TransportMode::Radiance ? " (radiance)" : " (importance)";
    for (const auto& wo : dirs) {
      LobeSums all[2], delta[2];  // by lobe: 0 reflection, 1 transmission
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto s = bxdf.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), mode);
        if (!s) continue;
        const int lobe = s->lobe == Lobe::Reflection ? 0 : 1;
        all[lobe].add(s->weight);
        const bool reflected = same_hemisphere(wo, s->wi);
        if (reflected != (s->lobe == Lobe::Reflection))
          note(1e6, [&] { return "lobe label disagrees with the side of wi at wo " + describe(wo); });
        if (s->delta) {
          delta[lobe].add(s->weight);
          if (cutout && is_pass_through(wo, *s)) continue;  // its weight is in the delta reference
          note(delta_direction_error(wo, *s, eta), [&] { return describe_delta_direction(wo, *s, eta) + mode_name; });
          continue;
        }
        const Float pdf = bxdf.pdf(wo, s->wi, mode);
        const Color f = bxdf.f(wo, s->wi, mode);
        note(relative_error(s->pdf, pdf) / kRelTolerance, [&] {
          return "sample pdf " + fmt(s->pdf) + " but pdf() " + fmt(pdf) + " at wo " + describe(wo) + ", wi " +
                 describe(s->wi);
        });
        if (pdf > 0) {
          const Color expect = f * (std::abs(s->wi.z) / pdf);
          note(color_relative_error(s->weight, expect, 1e-6) / kRelTolerance, [&] {
            return "weight " + fmt(s->weight.max_component()) + " but f|cos|/pdf " + fmt(expect.max_component()) +
                   " at wo " + describe(wo) + ", wi " + describe(s->wi);
          });
        }
      }
      const char* lobe_name[2] = {"reflection", "transmission"};
      // Delta lobes against the validator's own Fresnel.
      if (const auto ref = delta_reference(bxdf, wo, mode)) {
        for (int lobe = 0; lobe < 2; ++lobe)
          for (int c = 0; c < kColorChannels; ++c) {
            const double want = (lobe ? ref->transmission : ref->reflection)[size_t(c)];
            double mean = 0;
            const double e = mean_error(delta[lobe], c, want, n, &mean);
            note(e, [&] {
              return std::string("delta ") + lobe_name[lobe] + ": mean weight " + fmt(mean) + ", reference " +
                     fmt(want) + " at wo " + describe(wo) + mode_name + ", channel " + std::to_string(c);
            });
          }
      } else {
        unknown_delta = true;
      }
      // Each lobe against the model's closed-form albedo, where it has one.
      if (const auto exact = bxdf.exact_albedo(wo, mode)) {
        for (int lobe = 0; lobe < 2; ++lobe)
          for (int c = 0; c < kColorChannels; ++c) {
            const double want = lobe ? exact->transmittance[c] : exact->reflectance[c];
            double mean = 0;
            const double e = mean_error(all[lobe], c, want, n, &mean);
            note(e, [&] {
              return std::string(lobe_name[lobe]) + " lobe: mean weight " + fmt(mean) + ", closed-form albedo " +
                     fmt(want) + " at wo " + describe(wo) + mode_name;
            });
          }
      }
    }
  }
  r.figure = worst;
  r.pass = worst <= r.threshold;
  if (worst == 0) r.detail = "exact agreement";
  if (r.pass && unknown_delta) r.detail += "; delta lobes of a user model checked for direction only";
  return r;
}

}  // namespace gonio
