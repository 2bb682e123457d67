#pragma once
// The methods of PbrNodeBxDFT (pbr_node.h), included by bxdf.h once BxDFT is complete.
// Formulas: MaterialX genglsl mx_layer_bsdf, mx_add_bsdf, mx_mix_bsdf,
// mx_multiply_bsdf_color3 (response and throughput), as pbr_node.h lists them.

#include <algorithm>
#include <cmath>
#include <variant>

#include "gonio/bxdf/pbr_node.h"

namespace gonio {

// T(v) of any material: a pbrlib node's own, 0 for a gonio model that is not one (it is
// opaque to what lies under it).
template <typename C>
C pbr_throughput(const BxDFT<C>& b, const Vec3& v) {
  if (const auto* n = std::get_if<PbrNodeBxDFT<C>>(&b.models())) return n->throughput(v);
  return C(0);
}

template <typename C>
C PbrNodeBxDFT<C>::throughput(const Vec3& v) const {
  switch (op) {
    case PbrOp::Scale:
      if (through == PbrThroughput::Opaque) return C(0);
      if (through == PbrThroughput::Input) return pbr_throughput((*parts)[0], v);
      return C(std::max(Float(0), 1 - weight * albedo_table->at(v.z)));
    case PbrOp::Add:
      return map(pbr_throughput((*parts)[0], v) + pbr_throughput((*parts)[1], v),
                 [](Float t) { return std::max(Float(0), t - 1); });
    case PbrOp::Mix:
      return pbr_throughput((*parts)[0], v) * weight + pbr_throughput((*parts)[1], v) * (1 - weight);
    case PbrOp::Layer:
      return pbr_throughput((*parts)[0], v) * pbr_throughput((*parts)[1], v);
  }
  return C(0);
}

template <typename C>
BxDFFlags PbrNodeBxDFT<C>::flags() const {
  return op == PbrOp::Scale ? (*parts)[0].flags() : (*parts)[0].flags() | (*parts)[1].flags();
}
template <typename C>
Float PbrNodeBxDFT<C>::relative_eta() const {
  const Float a = (*parts)[0].relative_eta();
  return a != 1 || op == PbrOp::Scale ? a : (*parts)[1].relative_eta();
}
template <typename C>
bool PbrNodeBxDFT<C>::is_isotropic() const {
  return (*parts)[0].is_isotropic() && (op == PbrOp::Scale || (*parts)[1].is_isotropic());
}
template <typename C>
std::string_view PbrNodeBxDFT<C>::nonreciprocal_reason() const {
  if (op == PbrOp::Layer)
    return "MaterialX's layer scales the base by the top's throughput 1 - E_top(v), a function of the view "
           "direction alone (albedo scaling)";
  const std::string_view a = (*parts)[0].nonreciprocal_reason();
  return a.empty() && op != PbrOp::Scale ? (*parts)[1].nonreciprocal_reason() : a;
}

template <typename C>
Float PbrNodeBxDFT<C>::first_probability(const Vec3& wo) const {
  switch (op) {
    case PbrOp::Add: return Float(0.5);
    case PbrOp::Mix: return weight;
    case PbrOp::Layer:
      return std::clamp(1 - pbr_throughput((*parts)[0], wo).average(), Float(0.1), Float(0.9));
    case PbrOp::Scale: break;
  }
  return 1;
}

template <typename C>
BSDFEvalT<C> PbrNodeBxDFT<C>::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  const BSDFEvalT<C> a = (*parts)[0].eval(wo, wi, mode);
  if (op == PbrOp::Scale) return {a.f * scale, a.pdf};
  const BSDFEvalT<C> b = (*parts)[1].eval(wo, wi, mode);
  const Float p = first_probability(wo);
  const Float pdf = p * a.pdf + (1 - p) * b.pdf;
  switch (op) {
    case PbrOp::Add: return {a.f + b.f, pdf};
    case PbrOp::Mix: return {a.f * weight + b.f * (1 - weight), pdf};
    case PbrOp::Layer: {
      const Vec3& v = mode == TransportMode::Radiance ? wo : wi;
      return {a.f + pbr_throughput((*parts)[0], v) * b.f, pdf};
    }
    case PbrOp::Scale: break;
  }
  return {C(0), 0};
}

template <typename C>
Float PbrNodeBxDFT<C>::pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  if (op == PbrOp::Scale) return (*parts)[0].pdf(wo, wi, mode);
  const Float p = first_probability(wo);
  return p * (*parts)[0].pdf(wo, wi, mode) + (1 - p) * (*parts)[1].pdf(wo, wi, mode);
}

template <typename C>
std::optional<BSDFSampleT<C>> PbrNodeBxDFT<C>::sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                                     TransportMode mode) const {
  if (op == PbrOp::Scale) {
    auto s = (*parts)[0].sample(wo, u_lobe, u1, u2, mode);
    if (s) s->weight = s->weight * scale;
    return s;
  }
  const Float p = first_probability(wo);
  const bool second = u_lobe >= p;
  const Float p_part = second ? 1 - p : p;
  if (!(p_part > 0)) return std::nullopt;
  // Reuse u_lobe, rescaled to [0, 1) within the chosen part.
  const Float u = second ? (u_lobe - p) / (1 - p) : u_lobe / p;
  auto s = (*parts)[second ? 1 : 0].sample(wo, std::min(u, kOneMinusEpsilon), u1, u2, mode);
  if (!s) return std::nullopt;
  if (s->delta) {
    // The part's coefficient in f over its choice probability.
    C coefficient(1);
    if (op == PbrOp::Mix) coefficient = C(second ? 1 - weight : weight);
    if (op == PbrOp::Layer && second)
      coefficient = pbr_throughput((*parts)[0], mode == TransportMode::Radiance ? wo : s->wi);
    s->weight = s->weight * coefficient / p_part;
    s->pdf *= p_part;
    return s;
  }
  const BSDFEvalT<C> e = eval(wo, s->wi, mode);
  if (!(e.pdf > 0)) return std::nullopt;
  s->weight = e.f * (std::abs(s->wi.z) / e.pdf);
  s->pdf = e.pdf;
  return s;
}

template <typename C>
std::optional<DirectionalAlbedoT<C>> PbrNodeBxDFT<C>::albedo(const Vec3& wo, TransportMode mode) const {
  const auto a = (*parts)[0].exact_albedo(wo, mode);
  if (!a) return std::nullopt;
  if (op == PbrOp::Scale) return DirectionalAlbedoT<C>{a->reflectance * scale, a->transmittance * scale};
  const auto b = (*parts)[1].exact_albedo(wo, mode);
  if (!b) return std::nullopt;
  C wa(1), wb(1);
  if (op == PbrOp::Mix) {
    wa = C(weight);
    wb = C(1 - weight);
  } else if (op == PbrOp::Layer) {
    if (mode != TransportMode::Radiance) return std::nullopt;  // T keyed on wi: no closed form
    wb = pbr_throughput((*parts)[0], wo);
  }
  return DirectionalAlbedoT<C>{a->reflectance * wa + b->reflectance * wb,
                               a->transmittance * wa + b->transmittance * wb};
}

}  // namespace gonio
