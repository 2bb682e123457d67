#pragma once
// gltf_pbr: the glTF 2.0 metallic-roughness BRDF (glTF 2.0 specification, Appendix B) with
// the KHR_materials_* extensions, under MaterialX's gltf_pbr input names (SPEC §2,
// "Wave 4"; parameters in gltf_pbr_params.h; formulas and figures in docs/gltf_pbr.md).
//
// With V = wo, L = wi, H their half vector, c = |V·H|, w(c) = (1 − c)⁵ and the microfacet
// lobe spec = D(H) G2 / (4 |N·V| |N·L|) (GGX, α = roughness²; App. B.3.2, B.3.3 — gonio's
// D and height-correlated G2, microfacet.h):
//   metal       = spec · (base_color + (1 − base_color) w(c))                   (App. B.2.2)
//   dielectric  = F_d spec + (1 − max F_d) · base                               (App. B.2.3, KHR_materials_specular)
//     F_d = f0 + (f90 − f0) w(c), f0 = min(((ior−1)/(ior+1))² specular_color, 1) specular,
//     f90 = specular                       (KHR_materials_specular "Implementation", KHR_materials_ior)
//     base = (1 − transmission) [(1 − dt) base_color/π + dt · dt_color/π (other side)]
//            + transmission · base_color · btdf                       (KHR_materials_transmission,
//                                                                        KHR_materials_diffuse_transmission)
//   material    = (1 − metallic) dielectric + metallic · metal                   (App. B.2.5)
//   sheen layer = sheen_color D_s V_s + material · min(1 − max(sheen_color) E(μo), 1 − max(sheen_color) E(μi))
//                 (KHR_materials_sheen: Charlie D and V of Estevez & Kulla 2017, "albedo scaling")
//   coat        = clearcoat F_c spec_c + (1 − clearcoat F_c) · sheen layer,  F_c = 0.04 + 0.96 w(c)
//                 (KHR_materials_clearcoat "Implementation")
//   f           = a · coat, and a pass-through δ(wi = −wo) of weight 1 − a (alpha, alpha_mode).
// Every Fresnel factor is taken at V·H = L·H, as the specifications write them (the sample
// viewer's N·V is not reciprocal); so f is reciprocal.
//
// The btdf: thin-walled (thickness 0) the transmission lobe is spec with L mirrored through
// the surface (KHR_materials_transmission "Implementation": no refraction); with a volume
// (thickness > 0, KHR_materials_volume) it is Walter et al. 2007's refraction at ior (eq. 21
// without F; F is the (1 − max F_d) above, at the refraction half vector). A transmission's
// Fresnel, coat and sheen factors are read from the outside direction, so that the pair
// is reciprocal. Thin-walled, the material is two-sided (wo below mirrors both directions).
// With a volume, the inside sees the glass: reflection F_exact(ior) spec (total internal
// reflection included) and the same transmission back out.
//
// Roughness below kMinAlpha's square root is taken as that: every lobe is glossy, none a δ
// (docs/gltf_pbr.md). Not modelled here (the renderer's): normal, clearcoat_normal,
// occlusion, emission (kept in params), the volume's absorption (the interior medium).

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/charlie_distribution.h"
#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/gltf_pbr_params.h"
#include "gonio/fresnel.h"
#include "gonio/microfacet.h"
#include "gonio/math/warp.h"

namespace gonio {

namespace gltf_pbr {

// Smallest microfacet α of every glossy lobe (roughness ≈ 0.045): below it the lobes would be
// δ lobes, which this model does not have (see above).
inline constexpr Float kMinAlpha = Float(2e-3);
// Smallest Charlie α: the sheen roughness below it is taken as it (E's table starts there).
inline constexpr Float kMinSheenAlpha = Float(0.07);
// Directions this close to the tangent plane carry nothing (as the other glossy models).
inline constexpr Float kGrazing = Float(1e-7);

inline Float schlick_weight(Float c) {
  const Float m = std::clamp(1 - c, Float(0), Float(1));
  const Float m2 = m * m;
  return m2 * m2 * m;
}

// The Charlie distribution D: charlie_distribution.h (KHR_materials_sheen "Sheen distribution").
// Its Λ fit (Estevez & Kulla 2017, §3, Table 1 interpolated by (1 − α)²; KHR_materials_sheen
// "Sheen visibility").
inline Float charlie_l(Float x, Float alpha) {
  const Float t = (1 - alpha) * (1 - alpha);
  const Float a = Float(21.5473) + (Float(25.3245) - Float(21.5473)) * t;
  const Float b = Float(3.82987) + (Float(3.32435) - Float(3.82987)) * t;
  const Float c = Float(0.19823) + (Float(0.16801) - Float(0.19823)) * t;
  const Float d = Float(-1.97760) + (Float(-1.27393) + Float(1.97760)) * t;
  const Float e = Float(-4.32054) + (Float(-4.85967) + Float(4.32054)) * t;
  return a / (1 + b * std::pow(x, c)) + d * x + e;
}
inline Float charlie_lambda(Float mu, Float alpha) {
  mu = std::abs(mu);
  return mu < Float(0.5) ? std::exp(charlie_l(mu, alpha))
                         : std::exp(2 * charlie_l(Float(0.5), alpha) - charlie_l(1 - mu, alpha));
}
// f_sheen / sheen_color = D V, V = 1 / ((1 + Λ(μo) + Λ(μi)) 4 μo μi), for both directions
// above the surface and h their half vector.
inline Float charlie_brdf(Float mu_o, Float mu_i, Float cos_h, Float alpha) {
  return charlie_d(cos_h, alpha) / ((1 + charlie_lambda(mu_o, alpha) + charlie_lambda(mu_i, alpha)) * 4 * mu_o * mu_i);
}
// E(μ, α) = ∫ charlie_brdf cos θi dωi, the sheen's directional albedo (the table the
// albedo scaling reads), tabulated once by quadrature (src/bxdf/gltf_pbr_sheen.cpp).
Float charlie_albedo(Float mu, Float alpha);

inline Float sheen_alpha(Float roughness) { return std::clamp(roughness, kMinSheenAlpha, Float(1)); }

// Refraction of w (pointing away, on the side of n) through the facet normal n (n·w > 0),
// e = n(far) / n(near): nullopt under total internal reflection.
inline std::optional<Vec3> refract_through(const Vec3& w, const Vec3& n, Float e) {
  const Float c = dot(w, n);
  const Float s2 = std::max(Float(0), 1 - c * c) / (e * e);
  if (s2 >= 1) return std::nullopt;
  const Float ct = std::sqrt(1 - s2);
  return normalize(-w / e + n * (c / e - ct));
}

}  // namespace gltf_pbr

template <typename C>
struct GltfPbrBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "gltf_pbr";
  GltfPbrParams<C> params;

  static GltfPbrBxDFT make(const GltfPbrParams<C>& p) {
    GltfPbrBxDFT m;
    m.params = p;
    return m;
  }

  // Coverage: alpha_mode 0 (OPAQUE) ignores alpha, 1 (MASK) cuts at alpha_cutoff, 2 (BLEND)
  // is alpha (glTF 2.0 §3.9.4 "Alpha Coverage").
  Float coverage() const {
    const Float a = std::clamp(params.alpha, Float(0), Float(1));
    if (params.alpha_mode < Float(0.5)) return 1;
    if (params.alpha_mode < Float(1.5)) return a >= params.alpha_cutoff ? Float(1) : Float(0);
    return a;
  }
  bool volume() const { return params.thickness > 0 && params.transmission > 0; }
  Float relative_eta() const { return volume() ? params.ior : Float(1); }
  bool is_isotropic() const { return !(params.anisotropy_strength > 0); }

  BxDFFlags flags() const {
    BxDFFlags f = BxDFFlags::None;
    const Float a = coverage();
    if (a > 0) {
      f = f | BxDFFlags::GlossyReflection;
      if (diffuse_weight() > 0 || params.sheen_color.max_component() > 0) f = f | BxDFFlags::DiffuseReflection;
      if (params.transmission > 0 && params.metallic < 1) f = f | BxDFFlags::GlossyTransmission;
      if (dt_weight() > 0) f = f | BxDFFlags::DiffuseTransmission;
    }
    if (a < 1) f = f | BxDFFlags::SpecularTransmission;
    return f;
  }

  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < gltf_pbr::kGrazing || std::abs(wi.z) < gltf_pbr::kGrazing) return {};
    const Float a = coverage();
    if (!(a > 0)) return {};
    const Lobes l = lobes(wo);
    BSDFEvalT<C> e = evaluate(wo, wi, mode, l);
    e.f *= a;
    e.pdf *= a;
    return e;
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const { return eval(wo, wi, mode).f; }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).pdf;
  }

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < gltf_pbr::kGrazing) return std::nullopt;
    const Float a = coverage();
    if (u_lobe >= a) {  // the pass-through: f = (1 − a) δ(wi = −wo) / |cos θi|, chosen with 1 − a
      return BSDFSampleT<C>{-wo, C(1), 1 - a, true, Lobe::Transmission, 1};
    }
    u_lobe = std::min(u_lobe / a, kOneMinusEpsilon);
    const Lobes l = lobes(wo);
    // Choose a lobe by u_lobe over the cumulative probabilities.
    int k = 0;
    Float acc = 0;
    for (; k < kLobeCount - 1; ++k) {
      if (u_lobe < acc + l.p[k]) break;
      acc += l.p[k];
    }
    const std::optional<Vec3> d = sample_lobe(k, wo, u1, u2);
    if (!d) return std::nullopt;
    const Vec3 wi = *d;
    if (std::abs(wi.z) < gltf_pbr::kGrazing) return std::nullopt;
    BSDFEvalT<C> e = evaluate(wo, wi, mode, l);
    if (!(e.pdf > 0)) return std::nullopt;
    e.pdf *= a;
    const bool transmit = (wi.z > 0) != (wo.z > 0);
    const Float crossed = transmit && volume() ? (wo.z > 0 ? params.ior : 1 / params.ior) : Float(1);
    return BSDFSampleT<C>{wi, e.f * (a * std::abs(wi.z) / e.pdf), e.pdf, false,
                          transmit ? Lobe::Transmission : Lobe::Reflection, crossed};
  }

  // The emitted radiance (glTF 2.0 §3.9.3 emissiveFactor, KHR_materials_emissive_strength):
  // uniform over directions, times the coverage (a hole emits nothing).
  C emission() const { return params.emissive * (params.emissive_strength * coverage()); }

  // --- the pieces (public for tests and docs) ------------------------------------------

  // The dielectric Fresnel F_d(c) (KHR_materials_specular with KHR_materials_ior).
  C dielectric_fresnel(Float c) const {
    const Float r = (params.ior - 1) / (params.ior + 1);
    C f0 = params.specular_color * (r * r);
    for (int i = 0; i < C::size(); ++i) f0[i] = std::min(f0[i], Float(1));
    f0 *= params.specular;
    return f0 + (C(params.specular) - f0) * gltf_pbr::schlick_weight(c);
  }
  // The metal's Fresnel (App. B.2.2 conductor_fresnel: Schlick with F0 = base_color).
  C metal_fresnel(Float c) const {
    return params.base_color + (C(1) - params.base_color) * gltf_pbr::schlick_weight(c);
  }
  // The coat's Fresnel (KHR_materials_clearcoat: Schlick with F0 = 0.04, ior 1.5).
  static Float coat_fresnel(Float c) { return Float(0.04) + Float(0.96) * gltf_pbr::schlick_weight(c); }

  // The base's lobe microfacet distribution (KHR_materials_anisotropy: α_t = mix(α, 1, s²),
  // α_b = α along the direction turned by anisotropy_rotation from the tangent).
  MicrofacetDistribution distribution() const {
    const Float alpha = std::max(params.roughness * params.roughness, gltf_pbr::kMinAlpha);
    const Float s = std::clamp(params.anisotropy_strength, Float(0), Float(1));
    MicrofacetDistribution d;
    d.alpha_x = alpha + (1 - alpha) * s * s;
    d.alpha_y = alpha;
    return d;
  }
  MicrofacetDistribution coat_distribution() const {
    MicrofacetDistribution d;
    d.alpha_x = d.alpha_y = std::max(params.clearcoat_roughness * params.clearcoat_roughness, gltf_pbr::kMinAlpha);
    return d;
  }

 private:
  static constexpr int kLobeCount = 6;
  enum LobeIndex { kSpecular = 0, kCoat, kDiffuse, kSheen, kTransmission, kDiffuseTransmission };
  struct Lobes {
    Float p[kLobeCount] = {};
  };

  Float diffuse_weight() const {
    return (1 - params.metallic) * (1 - params.transmission) * (1 - params.diffuse_transmission);
  }
  Float dt_weight() const {
    return (1 - params.metallic) * (1 - params.transmission) * params.diffuse_transmission *
           params.diffuse_transmission_color.max_component();
  }

  // Rotation into the anisotropy frame (x along the anisotropy direction).
  Vec3 to_aniso(const Vec3& w) const {
    if (!(params.anisotropy_strength > 0) || params.anisotropy_rotation == 0) return w;
    const Float c = std::cos(params.anisotropy_rotation), s = std::sin(params.anisotropy_rotation);
    return {c * w.x + s * w.y, -s * w.x + c * w.y, w.z};
  }
  Vec3 from_aniso(const Vec3& w) const {
    if (!(params.anisotropy_strength > 0) || params.anisotropy_rotation == 0) return w;
    const Float c = std::cos(params.anisotropy_rotation), s = std::sin(params.anisotropy_rotation);
    return {c * w.x - s * w.y, s * w.x + c * w.y, w.z};
  }

  // The lobe-selection probabilities for wo: rough estimates of each lobe's share of the
  // albedo, every lobe that can be non-zero kept at 2 % or more.
  Lobes lobes(const Vec3& wo_in) const {
    Lobes l;
    const Float mu = std::abs(wo_in.z);
    if (wo_in.z < 0 && volume()) {  // inside the glass: its reflection and transmission
      const Float fr = fresnel_dielectric(mu, 1 / params.ior);
      l.p[kSpecular] = std::clamp(fr, Float(0.1), Float(0.9));
      const Float dt = dt_weight() > 0 ? Float(0.1) : Float(0);
      l.p[kTransmission] = (1 - l.p[kSpecular]) * (1 - dt);
      l.p[kDiffuseTransmission] = (1 - l.p[kSpecular]) * dt;
      return l;
    }
    const auto floor = [](Float s, bool on) { return on ? std::max(s, Float(0.02)) : Float(0); };
    const Float cc = std::clamp(params.clearcoat, Float(0), Float(1));
    const Float s_coat = cc * coat_fresnel(mu);
    const Float sheen = params.sheen_color.max_component();
    const Float s_sheen = sheen > 0 ? sheen * gltf_pbr::charlie_albedo(mu, gltf_pbr::sheen_alpha(params.sheen_roughness)) : 0;
    const Float rest = (1 - s_coat) * (1 - s_sheen);
    const Float fd = dielectric_fresnel(mu).max_component();
    const Float m = params.metallic;
    const Float dielectric_rest = rest * (1 - m) * (1 - fd);
    l.p[kSpecular] = floor(rest * (m + (1 - m) * fd), true);
    l.p[kCoat] = floor(s_coat, cc > 0);
    l.p[kSheen] = floor(s_sheen, sheen > 0);
    const Float base = params.base_color.average();
    l.p[kDiffuse] = floor(dielectric_rest * (1 - params.transmission) * (1 - params.diffuse_transmission) * base,
                          diffuse_weight() > 0);
    l.p[kTransmission] = floor(dielectric_rest * params.transmission * base, params.transmission > 0 && m < 1);
    l.p[kDiffuseTransmission] = floor(dielectric_rest * (1 - params.transmission) * params.diffuse_transmission *
                                          params.diffuse_transmission_color.average(),
                                      dt_weight() > 0);
    Float sum = 0;
    for (Float p : l.p) sum += p;
    for (Float& p : l.p) p /= sum;
    return l;
  }

  // A direction from lobe k for wo (any side).
  std::optional<Vec3> sample_lobe(int k, const Vec3& wo, Float u1, Float u2) const {
    const bool inside_volume = wo.z < 0 && volume();
    const bool flip = wo.z < 0 && !inside_volume;
    Vec3 v = wo;
    if (flip) v.z = -v.z;
    Vec3 wi;
    switch (k) {
      case kSpecular:
      case kCoat: {
        const MicrofacetDistribution d = k == kCoat ? coat_distribution() : distribution();
        const bool aniso = k == kSpecular;
        Vec3 va = aniso ? to_aniso(v) : v;
        if (inside_volume) va = -va;  // the glass seen from inside: the normals visible from −wo
        const Vec3 h = d.sample_visible(va, u1, u2);
        Vec3 r = reflect(va, h);
        if (!(r.z > 0)) return std::nullopt;  // below the horizon: not this lobe's (its pdf counts none there)
        if (inside_volume) r = -r;
        wi = aniso ? from_aniso(r) : r;
        break;
      }
      case kDiffuse: wi = square_to_cosine_hemisphere(u1, u2); break;
      case kSheen: wi = square_to_uniform_hemisphere(u1, u2); break;
      case kDiffuseTransmission: {
        wi = square_to_cosine_hemisphere(u1, u2);
        wi.z = -wi.z;
        if (inside_volume) wi.z = -wi.z;
        break;
      }
      case kTransmission: {
        const MicrofacetDistribution d = distribution();
        Vec3 va = to_aniso(v);
        if (!volume()) {  // thin: the reflection, mirrored through the surface
          const Vec3 h = d.sample_visible(va, u1, u2);
          Vec3 r = reflect(va, h);
          if (!(r.z > 0)) return std::nullopt;
          r.z = -r.z;
          wi = from_aniso(r);
          break;
        }
        const bool outside = va.z > 0;
        const Vec3 vv = outside ? va : -va;
        const Vec3 h = d.sample_visible(vv, u1, u2);  // h.z > 0
        const Float e = outside ? params.ior : 1 / params.ior;
        const auto t = gltf_pbr::refract_through(va, outside ? h : -h, e);
        if (!t || !((t->z > 0) != outside)) return std::nullopt;  // TIR, or not to the other side
        wi = from_aniso(*t);
        break;
      }
      default: return std::nullopt;
    }
    if (flip) wi.z = -wi.z;
    return wi;
  }

  // f and the mixture's pdf (without the coverage a).
  BSDFEvalT<C> evaluate(Vec3 wo, Vec3 wi, TransportMode mode, const Lobes& l) const {
    const bool vol = volume();
    if (vol && wo.z < 0 && wi.z < 0) return inside_reflection(wo, wi, l);
    if (!vol && wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    if (wi.z > 0 && wo.z > 0) return reflection(wo, wi, l);
    return transmission(wo, wi, mode, l);
  }

  // Sheen's albedo scaling for μo, μi (KHR_materials_sheen "Albedo-scaling technique").
  Float sheen_scaling(Float mu_o, Float mu_i, Float& alpha_s) const {
    alpha_s = gltf_pbr::sheen_alpha(params.sheen_roughness);
    const Float s = params.sheen_color.max_component();
    if (!(s > 0)) return 1;
    return std::min(1 - s * gltf_pbr::charlie_albedo(mu_o, alpha_s), 1 - s * gltf_pbr::charlie_albedo(mu_i, alpha_s));
  }

  BSDFEvalT<C> reflection(const Vec3& wo, const Vec3& wi, const Lobes& l) const {
    const Vec3 hu = wo + wi;
    const Float h2 = length_squared(hu);
    if (!(h2 > 0)) return {};
    const Vec3 h = hu * (1 / std::sqrt(h2));
    // A facet that faces away from wo (and wi: wo·h = wi·h) reflects nothing (as D_visible).
    const bool facing = dot(wo, h) > 0 && dot(wi, h) > 0;
    // wo·h = wi·h = |wo + wi| / 2 for unit directions: the same number for (wo, wi) and (wi, wo).
    const Float c = facing ? std::min(Float(0.5) * std::sqrt(h2), Float(1)) : Float(0);
    const Float mu_o = wo.z, mu_i = wi.z;
    // The base's microfacet lobe in the anisotropy frame.
    const MicrofacetDistribution d = distribution();
    const Vec3 ao = to_aniso(wo), ai = to_aniso(wi), ah = to_aniso(h);
    const Float D = facing ? d.D(ah) : Float(0);
    const Float spec = D * d.G2(ao, ai) / (4 * mu_o * mu_i);
    const C fd = dielectric_fresnel(c);
    const Float m = params.metallic;
    const Float diffuse = (1 - fd.max_component()) * (1 - params.transmission) * (1 - params.diffuse_transmission);
    C f = (fd * spec + params.base_color * (diffuse * kInvPi)) * (1 - m) + metal_fresnel(c) * (spec * m);
    Float alpha_s;
    const Float scale = sheen_scaling(mu_o, mu_i, alpha_s);
    f *= scale;
    if (params.sheen_color.max_component() > 0) f += params.sheen_color * gltf_pbr::charlie_brdf(mu_o, mu_i, h.z, alpha_s);
    const Float cc = std::clamp(params.clearcoat, Float(0), Float(1));
    Float pdf = l.p[kDiffuse] * mu_i * kInvPi + l.p[kSheen] * kInv2Pi;
    if (facing) pdf += l.p[kSpecular] * d.D_visible(ao, ah) / (4 * c);
    if (cc > 0 && facing) {
      const MicrofacetDistribution dc = coat_distribution();
      const Float fc = cc * coat_fresnel(c);
      f = f * (1 - fc) + C(fc * dc.D(h) * dc.G2(wo, wi) / (4 * mu_o * mu_i));
      pdf += l.p[kCoat] * dc.D_visible(wo, h) / (4 * c);
    }
    return {f, pdf};
  }

  // wo and wi on opposite sides; thin-walled, wo is above (evaluate() mirrored it).
  BSDFEvalT<C> transmission(const Vec3& wo, const Vec3& wi, TransportMode mode, const Lobes& l) const {
    const bool wo_out = wo.z > 0;
    const Vec3& a = wo_out ? wo : wi;  // the outside direction
    const Vec3& b = wo_out ? wi : wo;  // the inside one
    const Float mu_a = a.z, mu_b = -b.z;
    const Float m = params.metallic, T = params.transmission;
    Float alpha_s;
    const Float scale = sheen_scaling(mu_a, mu_b, alpha_s);
    const Float cc = std::clamp(params.clearcoat, Float(0), Float(1));
    // The mirrored half vector: thin transmission's and diffuse transmission's.
    const Vec3 bm{b.x, b.y, -b.z};
    const Vec3 hm = normalize(a + bm);
    const Float cm = std::clamp(dot(a, hm), Float(0), Float(1));
    const auto weight = [&](Float c) {  // (1 − m)(1 − max F_d)(1 − cc F_c) · sheen scaling
      return (1 - m) * (1 - dielectric_fresnel(c).max_component()) * (1 - cc * coat_fresnel(c)) * scale;
    };
    C f{};
    Float pdf = 0;
    const Float dtw = (1 - T) * params.diffuse_transmission;
    if (dtw > 0) {
      f += params.diffuse_transmission_color * (dtw * weight(cm) * kInvPi);
      pdf += l.p[kDiffuseTransmission] * std::abs(wi.z) * kInvPi;
    }
    if (T > 0 && m < 1) {
      const MicrofacetDistribution d = distribution();
      const Vec3 ao = to_aniso(wo), ai = to_aniso(wi);
      if (!volume() && cm > 0 && dot(bm, hm) > 0) {
        const Vec3 ahm = to_aniso(hm), aim{ai.x, ai.y, -ai.z};
        const Float spec = d.D(ahm) * d.G2(ao, aim) / (4 * mu_a * mu_b);
        f += params.base_color * (T * weight(cm) * spec);
        pdf += l.p[kTransmission] * d.D_visible(ao, ahm) / (4 * cm);
      } else if (volume()) {
        // Walter et al. 2007: h ∝ a + η b (eq. 16), turned outwards.
        const Float eta = params.ior;
        Vec3 h = a + b * eta;
        const Float hl = length_squared(h);
        if (hl > 0) {
          h = h * (1 / std::sqrt(hl));
          if (h.z < 0) h = -h;
          const Float ha = dot(a, h), hb = dot(b, h);
          if (ha > 0 && hb < 0) {
            const Vec3 ah = to_aniso(h);
            const Float den = ha + eta * hb;
            const Float den2 = den * den;
            // K = |a·h||b·h| D G2 / (|a.z||b.z| (a·h + η b·h)²); radiance: f = n_wo² K.
            const Float k = ha * -hb * d.D(ah) * d.G2(ao, ai) / (mu_a * mu_b * den2);
            const Float n_wo2 = wo_out ? Float(1) : eta * eta;
            const Float n_wi2 = wo_out ? eta * eta : Float(1);
            const Float nf = mode == TransportMode::Radiance ? n_wo2 : n_wi2;
            f += params.base_color * (T * weight(ha) * k * nf);
            // pdf = D_wo(h) n_wi² |wi·h| / (n_wo wo·h + n_wi wi·h)²
            const Float n_wo = wo_out ? 1 : eta, n_wi = wo_out ? eta : 1;
            const Float wo_h = dot(wo, h), wi_h = dot(wi, h);
            const Float jd = n_wo * wo_h + n_wi * wi_h;
            const Vec3 vis = wo_out ? ao : -ao;
            if (jd * jd > 0) pdf += l.p[kTransmission] * d.D_visible(vis, ah) * n_wi * n_wi * std::abs(wi_h) / (jd * jd);
          }
        }
      }
    }
    return {f, pdf};
  }

  // Inside the glass (volume): its reflection, exact Fresnel from the dense side.
  BSDFEvalT<C> inside_reflection(const Vec3& wo, const Vec3& wi, const Lobes& l) const {
    const Vec3 vo = -wo, vi = -wi;
    const Vec3 hu = vo + vi;
    const Float h2 = length_squared(hu);
    if (!(h2 > 0)) return {};
    const Vec3 h = hu * (1 / std::sqrt(h2));
    if (!(dot(vo, h) > 0 && dot(vi, h) > 0)) return {};
    const Float c = std::min(Float(0.5) * std::sqrt(h2), Float(1));  // symmetric, as in reflection()
    const MicrofacetDistribution d = distribution();
    const Vec3 ao = to_aniso(vo), ai = to_aniso(vi), ah = to_aniso(h);
    const Float spec = d.D(ah) * d.G2(ao, ai) / (4 * vo.z * vi.z);
    const Float fr = fresnel_dielectric(c, 1 / params.ior);
    const Float pdf = c > 0 ? l.p[kSpecular] * d.D_visible(ao, ah) / (4 * c) : Float(0);
    return {C(fr * spec), pdf};
  }
};

using GltfPbrBxDF = GltfPbrBxDFT<Color>;

}  // namespace gonio
