#pragma once
// The validator: proves that a model is physically plausible and that its sampling
// matches its density (the `gonio check` subcommand; SPEC §3). Properties:
//
//   finite        f, pdf and sample weights finite and ≥ 0, no weight above 10⁶ (a
//                 runaway), over ≥ 10⁶ random pairs and the extremes: |cos θ| log-uniform
//                 from 10⁻⁴⁵ to 10⁻², ±0, denormals, u = 0 and 1 − ulp, wi = wo, −wo and
//                 the mirror of wo, normal incidence, critical angles; both sides, both modes.
//   reciprocity   f(wo, wi) = f(wi, wo) for reflection (lecture §3.4); for transmission
//                 in radiance mode f(wo, wi)/n_wo² = f(wi, wo)/n_wi² (Veach 1997, §5.2).
//                 A polarizing model (polarization/polarized_bxdf.h) must also obey it
//                 in Mueller form, M(wo, wi)/n_wo² = Q M(wi, wo)ᵀ Q / n_wi², Q = diag(1, 1, −1, 1).
//                 Not applicable to a model that is not reciprocal by construction
//                 (BxDF::nonreciprocal_reason(), e.g. the LTC sheen): it is reported so,
//                 with the reason and the largest error measured, and only importance
//                 mode's adjoint, f_imp(wo, wi) = f_rad(wi, wo), is held to the threshold.
//   energy        ρ_dh ≤ 1 + 3σ + 2·10⁻³ over a sweep of θ (and φ when anisotropic), in
//                 importance mode: light arriving from any direction (lecture §3.4, §4).
//                 A non-reciprocal model bounds only its radiance-mode albedo ∫ f(wo, wi)
//                 |cos θi| dωi (what a path tracer's weights carry): that is checked, and
//                 the largest importance-mode albedo is given in the detail.
//   chi2          Pearson χ² of sample() against pdf() on a (cos θ, φ) grid of the sphere.
//   pdf_integral  ∫ pdf dω equals the fraction of sample() calls that return a non-delta
//                 direction.
//   consistency   weight = f |cos θi| / pdf and pdf = pdf(wo, wi) for every sample; delta
//                 samples obey the laws of reflection and refraction (Snell with the
//                 declared index); each delta lobe's mean weight equals F, (1 − F)(n_wo/n_wi)²
//                 (radiance) or 1 − F (importance), with total internal reflection, from
//                 the validator's own Fresnel (not the model's); where a model has a
//                 closed-form albedo, each lobe's mean weight equals it.
//   isotropy      an isotropic model is invariant under rotation about N.
//   linearity     a blend equals the weighted sum of its parts, in f, pdf and the mean
//                 weight of its samples.
//   weights       in importance mode, the largest weight of 10⁶ samples per outgoing
//                 direction (the tested ones, and 89.9° and 89.99°) is at most 100 × the
//                 directional albedo (the mean weight): the relative variance of one
//                 sample is then ≤ 99, i.e. never worse than 100 samples of a perfect sampler.
//                 Radiance mode for a non-reciprocal model (its importance mode, the
//                 adjoint, is held only to `finite`'s bound).
//
// A property that does not apply to a model passes with no figure.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gonio/bxdf.h"

namespace gonio {

struct PropertyResult {
  std::string name;
  std::optional<double> figure;  // the measured quantity; none if not applicable
  double threshold = 0;          // the limit the figure is held to
  bool pass = true;
  std::string detail;            // where the worst case was, in words
  // False when the property does not apply to the model (figure is then empty and
  // detail says why); `gonio check` prints it as n/a.
  bool applicable = true;
};

struct ValidationReport {
  std::vector<PropertyResult> properties;
  bool pass() const {
    for (const auto& p : properties)
      if (!p.pass) return false;
    return true;
  }
};

struct ValidationOptions {
  std::uint64_t seed = 1;
  // Multiplies every sample count (the sanitizer pass of the tests uses < 1). The
  // statistical thresholds account for the counts, so results stay meaningful.
  double scale = 1;
};

// before_each_property (may be empty) is called before each property: a caller that must
// stop a long validation early (the explorer, when a newer one is asked for) throws from it.
ValidationReport validate(const BxDF& bxdf, const ValidationOptions& options = {},
                          const std::function<void()>& before_each_property = {});

// The properties one at a time (for tests that feed deliberately broken models).
PropertyResult check_finite(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_reciprocity(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_energy(const BxDF& bxdf, const ValidationOptions& options = {});
// χ² and the pdf integral come from the same samples and cell integrals.
std::vector<PropertyResult> check_sampling(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_consistency(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_isotropy(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_linearity(const BxDF& bxdf, const ValidationOptions& options = {});
PropertyResult check_weights(const BxDF& bxdf, const ValidationOptions& options = {});
// Linearity of any model claimed to be (1 − w) a + w b.
PropertyResult check_linearity(const BxDF& blend, const BxDF& a, const BxDF& b, Float w,
                               const ValidationOptions& options = {});

}  // namespace gonio
