// Reflectance between solid-angle domains (lecture §4, eq. 12) and the albedos of
// SPEC §3. See include/gonio/reflectance.h for the definitions.

#include "gonio/reflectance.h"

#include <array>
#include <cmath>

#include "gonio/error.h"
#include "gonio/hemispherical_average.h"
#include "gonio/math/frame.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/rng.h"

namespace gonio {
namespace {

// Per-channel mean and standard error of the mean, accumulated in double.
template <typename C>
class ChannelStats {
 public:
  void add(const C& c) {
    for (int i = 0; i < C::size(); ++i) {
      sum_[i] += c[i];
      sum2_[i] += double(c[i]) * double(c[i]);
    }
  }
  C mean(std::uint64_t n) const {
    C m;
    for (int i = 0; i < C::size(); ++i) m[i] = static_cast<Float>(sum_[size_t(i)] / double(n));
    return m;
  }
  C standard_error(std::uint64_t n) const {
    C se;
    if (n < 2) return se;
    for (int i = 0; i < C::size(); ++i) {
      const double mean = sum_[i] / double(n);
      const double var = std::max(0.0, (sum2_[i] / double(n) - mean * mean)) * double(n) / double(n - 1);
      se[i] = static_cast<Float>(std::sqrt(var / double(n)));
    }
    return se;
  }

 private:
  std::array<double, size_t(C::size())> sum_{}, sum2_{};
};
using ColorStats = ChannelStats<Color>;

Vec3 unit_or_throw(const Vec3& w, const char* what) {
  const Vec3 n = normalize(w);
  if (!is_finite(w) || length_squared(n) == 0)
    throw InputError(std::string(what) + " must be a finite, non-zero vector");
  return n;
}

// A cone domain prepared for sampling: its frame, cos of the half angle, projected solid
// angle Ψ = π sin²α |cos θaxis| (exact for a cone that does not cross the tangent plane).
struct PreparedCone {
  Frame frame;
  double cos_half = 1, psi = 0;
  bool upper = true;
};

PreparedCone prepare_cone(const ConeDomain& c, const char* what) {
  const Vec3 axis = unit_or_throw(c.axis, what);
  if (!(c.half_angle > 0 && c.half_angle <= kPiD / 2))
    throw InputError(std::string(what) + ": cone half angle must be in (0, 90] degrees");
  const double axis_polar = std::acos(std::min(1.0, std::abs(double(axis.z))));
  if (axis_polar + c.half_angle > kPiD / 2 + 1e-9)
    throw InputError(std::string(what) + ": cone crosses the tangent plane");
  PreparedCone p;
  p.frame = Frame::from_normal(axis);
  p.cos_half = std::cos(c.half_angle);
  p.psi = kPiD * std::sin(c.half_angle) * std::sin(c.half_angle) * std::abs(double(axis.z));
  p.upper = axis.z > 0;
  return p;
}

bool in_domain(const Vec3& w, const SolidAngleDomain& d, const PreparedCone* cone) {
  if (const auto* h = std::get_if<HemisphereDomain>(&d)) return h->upper ? w.z > 0 : w.z < 0;
  if (cone) return dot(w, cone->frame.n) >= cone->cos_half;
  return false;  // a single direction has measure zero
}

// Exact ∫ over a hemisphere of f(ωi → ωr) cos θr dωr, from the model's closed form.
std::optional<Color> exact_inner(const BxDF& bxdf, const Vec3& wi, bool exitant_upper) {
  const auto a = bxdf.exact_albedo(wi, TransportMode::Importance);
  if (!a) return std::nullopt;
  if (wi.z == 0) return Color{};
  const bool reflection = (wi.z > 0) == exitant_upper;
  return reflection ? a->reflectance : a->transmittance;
}

Vec3 direction_at_mu(double mu, bool upper) {
  const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  return {Float(s), 0, Float(upper ? mu : -mu)};
}

}  // namespace

ReflectanceEstimate reflectance(const BxDF& bxdf, const SolidAngleDomain& incident,
                                const SolidAngleDomain& exitant, const ReflectanceOptions& opt) {
  if (opt.samples == 0) throw InputError("reflectance: samples must be > 0");
  std::optional<PreparedCone> in_cone, out_cone;
  if (const auto* c = std::get_if<ConeDomain>(&incident)) in_cone = prepare_cone(*c, "incident cone");
  if (const auto* c = std::get_if<ConeDomain>(&exitant)) out_cone = prepare_cone(*c, "exitant cone");
  const auto* out_dir = std::get_if<DirectionDomain>(&exitant);
  const Vec3 wr = out_dir ? unit_or_throw(out_dir->w, "exitant direction") : Vec3{};
  const auto* out_hemi = std::get_if<HemisphereDomain>(&exitant);

  // g(ωi) = ∫Γr f(ωi → ωr) cos θr dωr, estimated with one model sample (or exactly).
  auto inner = [&](const Vec3& wi, Pcg32& rng, bool& exact) -> Color {
    if (out_dir) {
      exact = true;  // reflectance factor: π f(ωi → ωr) = π f_radiance(wo = ωr, wi = ωi)
      return bxdf.f(wr, wi, TransportMode::Radiance) * kPi;
    }
    if (out_hemi) {
      if (auto e = exact_inner(bxdf, wi, out_hemi->upper)) {
        exact = true;
        return *e;
      }
    }
    exact = false;
    const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    const auto s = bxdf.sample(wi, u0, u1, u2, TransportMode::Importance);
    if (!s || !in_domain(s->wi, exitant, out_cone ? &*out_cone : nullptr)) return Color{};
    return s->weight;
  };

  Pcg32 rng(opt.seed, 0x9e3779b97f4a7c15ULL);
  if (const auto* d = std::get_if<DirectionDomain>(&incident)) {
    const Vec3 wi = unit_or_throw(d->w, "incident direction");
    bool exact = false;
    Color first = inner(wi, rng, exact);
    if (exact) return {first, Color{}, true};
    ColorStats stats;
    stats.add(first);
    for (std::uint64_t i = 1; i < opt.samples; ++i) stats.add(inner(wi, rng, exact));
    return {stats.mean(opt.samples), stats.standard_error(opt.samples), false};
  }

  if (const auto* h = std::get_if<HemisphereDomain>(&incident)) {
    // Isotropic models with a closed-form inner integral: deterministic quadrature.
    if (bxdf.is_isotropic() && (out_dir == nullptr)) {
      bool exact_probe = false;
      Pcg32 probe(1);
      inner(direction_at_mu(0.5, h->upper), probe, exact_probe);
      if (exact_probe) {
        const auto avg = cosine_weighted_average([&](double mu) {
          bool e = false;
          Pcg32 unused(1);
          const Color c = inner(direction_at_mu(mu, h->upper), unused, e);
          std::array<double, kColorChannels> v{};
          for (int i = 0; i < Color::size(); ++i) v[size_t(i)] = c[i];
          return v;
        });
        Color value;
        for (int i = 0; i < Color::size(); ++i) value[i] = Float(avg[size_t(i)]);
        return {value, Color{}, true};
      }
    }
    ColorStats stats;
    for (std::uint64_t i = 0; i < opt.samples; ++i) {
      Vec3 wi = square_to_cosine_hemisphere(rng.next_float(), rng.next_float());
      if (!h->upper) wi.z = -wi.z;
      bool e = false;
      stats.add(inner(wi, rng, e));  // cosine-weighted: the weight (cos/pdf)/Ψ is 1
    }
    return {stats.mean(opt.samples), stats.standard_error(opt.samples), false};
  }

  // Incident cone: uniform directions in the cone, weight |cos θi| / (pdf Ψi).
  const PreparedCone& c = *in_cone;
  const double pdf = 1.0 / (2 * kPiD * (1 - c.cos_half));
  ColorStats stats;
  for (std::uint64_t i = 0; i < opt.samples; ++i) {
    const Vec3 local = square_to_uniform_cone(rng.next_float(), rng.next_float(), Float(c.cos_half));
    const Vec3 wi = normalize(c.frame.to_world(local));
    bool e = false;
    const Color g = inner(wi, rng, e);
    stats.add(g * Float(std::abs(double(wi.z)) / (pdf * c.psi)));
  }
  return {stats.mean(opt.samples), stats.standard_error(opt.samples), false};
}

namespace {

// Splits one sample from wo into reflected and transmitted parts. Radiance mode is the view's
// figure (SPEC §3): a transmitted sample's weight f |cos θi| / pdf times (n_wi/n_wo)²
// (BSDFSample::eta = n_wi/n_wo) removes the refraction's radiance scaling (lecture §5.3:
// L/n² is conserved; Veach 1997, §5.2). Importance mode is the light's figure, whose
// weight is already an energy ratio.
template <typename C>
void add_albedo_sample(const BxDFT<C>& bxdf, const Vec3& wo, TransportMode mode, Pcg32& rng, ChannelStats<C>& r,
                       ChannelStats<C>& t, ChannelStats<C>& a) {
  const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
  const auto s = bxdf.sample(wo, u0, u1, u2, mode);
  if (!s || s->wi.z == 0) return;  // no direction: contributes 0 to every sum
  C w = s->weight;
  const bool reflected = same_hemisphere(s->wi, wo);
  if (!reflected && mode == TransportMode::Radiance) w = w * (s->eta * s->eta);
  if (reflected) r.add(w);
  else t.add(w);
  a.add(w);
}

template <typename C>
AlbedoSplitT<C> finish(const ChannelStats<C>& r, const ChannelStats<C>& t, const ChannelStats<C>& a,
                       std::uint64_t n) {
  AlbedoSplitT<C> e;
  e.reflectance = r.mean(n);
  e.transmittance = t.mean(n);
  e.albedo = a.mean(n);
  e.se_reflectance = r.standard_error(n);
  e.se_transmittance = t.standard_error(n);
  e.se_albedo = a.standard_error(n);
  return e;
}

template <typename C>
AlbedoSplitT<C> exact_split(const DirectionalAlbedoT<C>& x) {
  AlbedoSplitT<C> e;
  e.reflectance = x.reflectance;
  e.transmittance = x.transmittance;
  e.albedo = x.reflectance + x.transmittance;
  return e;
}

// A model's closed-form albedo in `mode`, where it has one and it is the figure wanted: in
// importance mode always; in radiance mode only without transmission (the closed forms
// include the refraction's radiance scaling, which the view's figure removes).
template <typename C>
std::optional<AlbedoSplitT<C>> exact_figure(const BxDFT<C>& bxdf, const Vec3& wo, TransportMode mode) {
  const auto x = bxdf.exact_albedo(wo, mode);
  if (!x) return std::nullopt;
  if (mode == TransportMode::Radiance)
    for (int i = 0; i < C::size(); ++i)
      if (x->transmittance[i] != 0) return std::nullopt;
  return exact_split(*x);
}

// wo at θ = 90° (|cos θ| below kGrazingAlbedoCosine) moved to the limit's cosine (reflectance.h).
Vec3 at_grazing_limit(const Vec3& wo) {
  if (std::abs(wo.z) >= kGrazingAlbedoCosine) return wo;
  const double c = double(kGrazingAlbedoCosine), h = std::hypot(double(wo.x), double(wo.y));
  if (!(h > 0)) return wo;
  const double s = std::sqrt(1 - c * c) / h;
  return {Float(double(wo.x) * s), Float(double(wo.y) * s), Float(std::signbit(double(wo.z)) ? -c : c)};
}

}  // namespace

// For a reciprocal model the view's figure equals the light's (f_imp(wo, wi) = f_rad(wi, wo)
// = f_rad(wo, wi) (n_wi/n_wo)², SPEC §1), which is estimated in importance mode, whose
// closed forms every model with one provides; a model that is not reciprocal is estimated
// in both modes.
template <typename C>
AlbedoEstimateT<C> directional_albedo(const BxDFT<C>& bxdf, const Vec3& wo_in, const ReflectanceOptions& opt) {
  if (opt.samples == 0) throw InputError("albedo: samples must be > 0");
  const Vec3 wo = at_grazing_limit(unit_or_throw(wo_in, "albedo: wo"));
  const bool reciprocal = bxdf.nonreciprocal_reason().empty();
  const auto figure = [&](TransportMode mode, std::uint64_t stream, bool& exact) {
    if (const auto x = exact_figure(bxdf, wo, mode)) {
      exact = true;
      return *x;
    }
    exact = false;
    Pcg32 rng(opt.seed, stream);
    ChannelStats<C> r, t, a;
    for (std::uint64_t i = 0; i < opt.samples; ++i) add_albedo_sample(bxdf, wo, mode, rng, r, t, a);
    return finish(r, t, a, opt.samples);
  };
  AlbedoEstimateT<C> e;
  bool exact_view = false, exact_light = false;
  if (reciprocal) {
    static_cast<AlbedoSplitT<C>&>(e) = figure(TransportMode::Importance, 0x2545f4914f6cdd1dULL, exact_view);
    e.exact = exact_view;
    return e;
  }
  static_cast<AlbedoSplitT<C>&>(e) = figure(TransportMode::Radiance, 0x2545f4914f6cdd1dULL, exact_view);
  e.light = figure(TransportMode::Importance, 0x6a09e667f3bcc909ULL, exact_light);
  e.exact = exact_view && exact_light;
  return e;
}

namespace {
// The cosine-weighted average over μ of a model's closed forms in `mode` (nullopt when it
// has none).
template <typename C>
std::optional<AlbedoSplitT<C>> exact_hemispherical(const BxDFT<C>& bxdf, bool upper, TransportMode mode) {
  if (!bxdf.is_isotropic() || !exact_figure(bxdf, direction_at_mu(0.5, upper), mode)) return std::nullopt;
  const auto avg = cosine_weighted_average([&](double mu) {
    const auto ex = exact_figure(bxdf, direction_at_mu(mu, upper), mode);
    std::array<double, 2 * size_t(C::size())> v{};
    if (!ex) return v;
    for (int i = 0; i < C::size(); ++i) {
      v[size_t(i)] = ex->reflectance[i];
      v[size_t(C::size() + i)] = ex->transmittance[i];
    }
    return v;
  });
  AlbedoSplitT<C> e;
  for (int i = 0; i < C::size(); ++i) {
    e.reflectance[i] = Float(avg[size_t(i)]);
    e.transmittance[i] = Float(avg[size_t(C::size() + i)]);
  }
  e.albedo = e.reflectance + e.transmittance;
  return e;
}
}  // namespace

template <typename C>
AlbedoEstimateT<C> hemispherical_albedo(const BxDFT<C>& bxdf, bool inside, const ReflectanceOptions& opt) {
  if (opt.samples == 0) throw InputError("albedo: samples must be > 0");
  const bool upper = !inside;
  const bool reciprocal = bxdf.nonreciprocal_reason().empty();
  const auto figure = [&](TransportMode mode, std::uint64_t stream, bool& exact) {
    if (const auto x = exact_hemispherical(bxdf, upper, mode)) {
      exact = true;
      return *x;
    }
    exact = false;
    Pcg32 rng(opt.seed, stream);
    ChannelStats<C> r, t, a;
    for (std::uint64_t i = 0; i < opt.samples; ++i) {
      Vec3 wo = square_to_cosine_hemisphere(rng.next_float(), rng.next_float());
      if (wo.z == 0) continue;  // measure zero; counts as a zero sample
      if (inside) wo.z = -wo.z;
      add_albedo_sample(bxdf, wo, mode, rng, r, t, a);
    }
    return finish(r, t, a, opt.samples);
  };
  AlbedoEstimateT<C> e;
  bool exact_view = false, exact_light = false;
  static_cast<AlbedoSplitT<C>&>(e) =
      figure(reciprocal ? TransportMode::Importance : TransportMode::Radiance, 0x5851f42d4c957f2dULL, exact_view);
  e.exact = exact_view;
  if (!reciprocal) {
    e.light = figure(TransportMode::Importance, 0xbb67ae8584caa73bULL, exact_light);
    e.exact = exact_view && exact_light;
  }
  return e;
}

template AlbedoEstimateT<Color> directional_albedo(const BxDF&, const Vec3&, const ReflectanceOptions&);
template AlbedoEstimateT<SampledSpectrum> directional_albedo(const SpectralBxDF&, const Vec3&, const ReflectanceOptions&);
template AlbedoEstimateT<Color> hemispherical_albedo(const BxDF&, bool, const ReflectanceOptions&);
template AlbedoEstimateT<SampledSpectrum> hemispherical_albedo(const SpectralBxDF&, bool, const ReflectanceOptions&);

}  // namespace gonio
