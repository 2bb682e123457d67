// Property "finite": no NaN, Inf or negative value from f, pdf or sample, and no
// unbounded sample weight, over random pairs and the extremes that break careless code:
// |cos θ| log-uniform from 10⁻⁴⁵ (denormal floats) to 10⁻², ±0, denormal tangential
// components, u = 0 and u = 1 − ulp, wi = wo, wi = −wo and the mirror direction, on both
// sides and in both transport modes.

#include <limits>

#include "common.h"

namespace gonio {

using namespace validation;

namespace {

// A weight is the energy one sample carries (importance mode; radiance mode divided by
// its (n_wo/n_wi)²). A correct sampler of an energy-conserving model keeps it near the
// albedo, ≤ 1; the property "weights" holds it to that statistically. Here only a
// runaway is caught — the 1/cos θ of an unguarded denominator that grows without bound
// towards grazing — with a cap that no sound model approaches.
constexpr double kWeightCap = 1e6;

// A direction at polar cosine z (possibly ±0 or denormal) and azimuth phi.
Vec3 at_cosine(Float z, Float phi) {
  const Float s = std::sqrt(std::max(Float(0), 1 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// |cos θ| log-uniform over [10⁻⁴⁵, 10⁻²]: in float that reaches the smallest denormal.
Float extreme_cosine(Pcg32& rng) {
  const double l = -45 + 43 * double(rng.next_float());
  return std::max(Float(std::pow(10.0, l)), std::numeric_limits<Float>::denorm_min());
}

// The probe's fixed set: cosines 10^k and 3·10^k for k = −45 … −3, ±0, the smallest
// denormal and the smallest normal float, 10⁻⁷ (where the glossy models' guards sit), on
// both sides; exact normals with signed zero tangents; denormal tangential components.
std::vector<Vec3> extreme_directions() {
  std::vector<Vec3> v;
  std::vector<Float> cosines = {Float(0), Float(-0.0), std::numeric_limits<Float>::denorm_min(),
                                std::numeric_limits<Float>::min(), Float(1e-7), Float(0.01)};
  for (int k = -45; k <= -3; ++k)
    for (double m : {1.0, 3.0}) cosines.push_back(Float(m * std::pow(10.0, k)));
  int i = 0;
  for (Float z : cosines) {
    v.push_back(at_cosine(z, Float(0.37) + Float(0.61) * Float(i++ % 7)));
    v.push_back(at_cosine(-z, Float(2.1) + Float(0.43) * Float(i % 5)));
  }
  const Float dn = std::numeric_limits<Float>::denorm_min(), tiny = Float(1e-40);
  for (Float z : {Float(1), Float(-1)}) {
    v.push_back({Float(0.0), Float(0.0), z});
    v.push_back({Float(-0.0), Float(-0.0), z});
    v.push_back({dn, Float(-0.0), z});
    v.push_back({tiny, -tiny, z});
  }
  return v;
}

}  // namespace

PropertyResult check_finite(const BxDF& bxdf, const ValidationOptions& opt) {
  PropertyResult r{"finite", 0.0, 0, true, ""};
  Pcg32 rng = rng_for(opt, 1);
  const double eta = bxdf.relative_eta();
  std::uint64_t bad = 0;
  // Counts a bad value; `what` describes it, built only for the first one.
  auto report = [&](const auto& what) {
    if (bad++ == 0) r.detail = what();
  };
  auto check_pair = [&](const Vec3& wo, const Vec3& wi) {
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const BSDFEval e = bxdf.eval(wo, wi, mode);
      const Color f = bxdf.f(wo, wi, mode);
      const Float p = bxdf.pdf(wo, wi, mode);
      if (!e.f.is_finite() || e.f.min_component() < 0 || !f.is_finite() || f.min_component() < 0)
        report([&] { return "f not finite and >= 0 at wo " + describe(wo) + ", wi " + describe(wi); });
      if (!std::isfinite(e.pdf) || e.pdf < 0 || !std::isfinite(p) || p < 0)
        report([&] { return "pdf not finite and >= 0 at wo " + describe(wo) + ", wi " + describe(wi); });
    }
  };
  auto check_sample = [&](const Vec3& wo, Float u0, Float u1, Float u2) {
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const auto s = bxdf.sample(wo, u0, u1, u2, mode);
      if (!s) continue;
      const bool ok = s->weight.is_finite() && s->weight.min_component() >= 0 &&
                      std::isfinite(s->pdf) && s->pdf > 0 && is_finite(s->wi) &&
                      std::abs(length(s->wi) - 1) < 1e-3f && std::isfinite(s->eta) && s->eta > 0;
      auto where = [&] { return "at wo " + describe(wo) + ", u (" + fmt(u0) + ", " + fmt(u1) + ", " + fmt(u2) +
                                ") gave wi " + describe(s->wi) + ", weight " + fmt(s->weight.max_component()) +
                                ", pdf " + fmt(s->pdf); };
      if (!ok) {
        report([&] { return "sample " + where(); });
        continue;
      }
      // Energy per sample: a transmission in radiance mode carries (n_wo/n_wi)², which
      // the declared index divides out (SPEC §1).
      double w = s->weight.max_component();
      if (mode == TransportMode::Radiance && s->lobe == Lobe::Transmission) {
        // n_wo / n_wi from wo's side alone (wi may sit in the tangent plane).
        const double n_ratio = wo.z > 0 ? 1 / eta : eta;
        w /= n_ratio * n_ratio;
      }
      if (w > kWeightCap) report([&] { return "unbounded weight: sample " + where(); });
    }
  };

  // Fixed probes: the adversarial directions (normal, grazing, critical angles) and the
  // extreme cosines, every pair with wi, −wi and the mirror of wo, and every sample with
  // u in {0, 1/2, 1 − ulp}.
  auto probe = adversarial_directions(bxdf.relative_eta());
  for (const auto& w : extreme_directions()) probe.push_back(w);
  const Float us[3] = {Float(0), Float(0.5), kOneMinusEpsilon};
  for (const auto& wo : probe) {
    check_pair(wo, wo);
    check_pair(wo, -wo);
    check_pair(wo, {-wo.x, -wo.y, wo.z});
    for (const auto& wi : probe) {
      check_pair(wo, wi);
      check_pair(wo, -wi);
    }
    for (Float u0 : us)
      for (Float u1 : us)
        for (Float u2 : us) check_sample(wo, u0, u1, u2);
  }
  // Random pairs: each direction uniform on the sphere or at an extreme cosine (either
  // side); wi also wo, −wo or the mirror of wo; u sometimes exactly 0 or 1 − ulp.
  auto random_direction = [&]() -> Vec3 {
    if (rng.next_float() < 0.5f) return square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Float z = extreme_cosine(rng);
    return at_cosine(rng.next_float() < 0.5f ? z : -z, Float(2 * kPiD) * rng.next_float());
  };
  auto random_u = [&]() -> Float {
    const Float u = rng.next_float();
    const Float pick = rng.next_float();
    return pick < 0.05f ? Float(0) : pick < 0.1f ? kOneMinusEpsilon : u;
  };
  const std::uint64_t n = scaled(opt, 1'000'000);
  for (std::uint64_t i = 0; i < n; ++i) {
    const Vec3 wo = random_direction();
    const unsigned k = i & 7;
    const Vec3 wi = k == 0 ? wo : k == 1 ? -wo : k == 2 ? Vec3{-wo.x, -wo.y, wo.z} : random_direction();
    check_pair(wo, wi);
    const Float u0 = random_u(), u1 = random_u(), u2 = random_u();
    check_sample(wo, u0, u1, u2);
  }
  r.figure = double(bad);
  r.pass = bad == 0;
  const std::uint64_t pairs = probe.size() * (2 * probe.size() + 3);
  if (r.pass) r.detail = std::to_string(n) + " random and " + std::to_string(pairs) + " adversarial pairs";
  else r.detail = std::to_string(bad) + " bad values; first: " + r.detail;
  return r;
}

}  // namespace gonio
