#pragma once
// BxDF: one value that holds any model, built-in or the user's, dispatched through
// std::variant (a jump table, no virtual call and no allocation for built-in models).
// New built-in models are added to Models below and nowhere else.

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "gonio/bxdf/ashikhminshirley.h"
#include "gonio/bxdf/blend.h"
#include "gonio/bxdf/blinnphong.h"
#include "gonio/bxdf/charlie_sheen.h"
#include "gonio/bxdf/conductor.h"
#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/custom.h"
#include "gonio/bxdf/dielectric.h"
#include "gonio/bxdf/diffuse.h"
#include "gonio/bxdf/eon.h"
#include "gonio/bxdf/gltf_pbr.h"
#include "gonio/bxdf/hair.h"
#include "gonio/bxdf/layered.h"
#include "gonio/bxdf/measured.h"
#include "gonio/bxdf/mirror.h"
#include "gonio/bxdf/openpbr.h"
#include "gonio/bxdf/orennayar.h"
#include "gonio/bxdf/pbr_node.h"
#include "gonio/bxdf/phong.h"
#include "gonio/bxdf/plastic.h"
#include "gonio/bxdf/roughconductor.h"
#include "gonio/bxdf/roughdielectric.h"
#include "gonio/bxdf/rgl.h"
#include "gonio/bxdf/sheen.h"
#include "gonio/bxdf/thindielectric.h"
#include "gonio/bxdf/ward.h"

namespace gonio {

// The models for one colour type C: BxDF (RGB) or SpectralBxDF (the 4 wavelengths of a
// path, spectrum/wavelengths.h). Each model is one template for both.
template <typename C>
class BxDFT {
 public:
  using color_type = C;
  using Models = std::variant<DiffuseBxDFT<C>, MirrorBxDFT<C>, ConductorBxDFT<C>, DielectricBxDFT<C>,
                              RoughConductorBxDFT<C>, RoughDielectricBxDFT<C>, OrenNayarBxDFT<C>, PhongBxDFT<C>,
                              BlinnPhongBxDFT<C>, WardBxDFT<C>, AshikhminShirleyBxDFT<C>, PlasticBxDFT<C>,
                              MeasuredBxDFT<C>, BlendBxDFT<C>, UserBxDFT<C>, SheenBxDFT<C>, EonBxDFT<C>,
                              ThinDielectricBxDFT<C>, LayeredBxDFT<C>, OpenPbrBxDFT<C>, GltfPbrBxDFT<C>,
                              PbrNodeBxDFT<C>, CharlieSheenBxDFT<C>, HairBxDFT<C>, RglBxDFT<C>>;

  BxDFT() = default;
  template <typename M>
    requires BxDFModel<std::decay_t<M>> && std::is_constructible_v<Models, M&&>
  BxDFT(M&& model) : m_(std::forward<M>(model)) {}  // NOLINT: implicit by design

  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) { return m.f(wo, wi, mode); }, m_);
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) { return m.pdf(wo, wi, mode); }, m_);
  }
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) -> BSDFEvalT<C> { return model_eval(m, wo, wi, mode); }, m_);
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) { return m.sample(wo, u_lobe, u1, u2, mode); }, m_);
  }
  BxDFFlags flags() const {
    return std::visit([](const auto& m) { return m.flags(); }, m_);
  }
  // n_inside / n_outside; 1 for models that do not refract.
  Float relative_eta() const {
    return std::visit(
        [](const auto& m) -> Float {
          if constexpr (requires { m.relative_eta(); }) return m.relative_eta();
          else return 1;
        },
        m_);
  }
  // A fibre (hair.h): its frame's x is the fibre's axis, z no normal; `check` tests it
  // over the whole sphere and reports isotropy about z as not applicable.
  bool is_fibre() const {
    return std::visit(
        [](const auto& m) -> bool {
          if constexpr (requires { m.is_fibre(); }) return m.is_fibre();
          else return false;
        },
        m_);
  }
  bool is_isotropic() const {
    return std::visit(
        [](const auto& m) -> bool {
          if constexpr (requires { m.is_isotropic(); }) return m.is_isotropic();
          else return true;
        },
        m_);
  }
  // Why the model is not reciprocal (one that declares kReciprocal = false, or a blend
  // with such a part); empty for a reciprocal model. The validator reports reciprocity
  // as not applicable with this reason.
  std::string_view nonreciprocal_reason() const {
    return std::visit(
        [](const auto& m) -> std::string_view {
          using M = std::decay_t<decltype(m)>;
          if constexpr (requires { m.nonreciprocal_reason(); }) return m.nonreciprocal_reason();
          else if constexpr (requires { M::kReciprocal; }) return M::kReciprocal ? std::string_view{} : M::kNonReciprocalReason;
          else return {};
        },
        m_);
  }
  // The reciprocity threshold of a model reciprocal only up to a documented error (a
  // measured table's interpolation error, `rgl`); 0 for the others (the validator's own).
  Float reciprocity_tolerance() const {
    return std::visit(
        [](const auto& m) -> Float {
          if constexpr (requires { m.reciprocity_tolerance(); }) return m.reciprocity_tolerance();
          else return 0;
        },
        m_);
  }
  // The exact directional albedo where the model has a closed form.
  std::optional<DirectionalAlbedoT<C>> exact_albedo(const Vec3& wo, TransportMode mode) const {
    return std::visit(
        [&](const auto& m) -> std::optional<DirectionalAlbedoT<C>> {
          if constexpr (requires { m.albedo(wo, mode); }) return m.albedo(wo, mode);
          else return std::nullopt;
        },
        m_);
  }
  std::string name() const {
    return std::visit(
        [](const auto& m) -> std::string {
          if constexpr (requires { std::decay_t<decltype(m)>::kName; })
            return std::string(std::decay_t<decltype(m)>::kName);
          else return m.model->name();
        },
        m_);
  }

  const Models& models() const { return m_; }

 private:
  Models m_;
};
using BxDF = BxDFT<Color>;
using SpectralBxDF = BxDFT<SampledSpectrum>;

// --- BlendBxDF, now that BxDF is complete ------------------------------------------

template <typename C>
BxDFFlags BlendBxDFT<C>::flags() const { return (*parts)[0].flags() | (*parts)[1].flags(); }
template <typename C>
Float BlendBxDFT<C>::relative_eta() const {
  // Parts that refract share one index (the material loader insists); else 1.
  const Float a = (*parts)[0].relative_eta();
  return a != 1 ? a : (*parts)[1].relative_eta();
}
template <typename C>
bool BlendBxDFT<C>::is_isotropic() const { return (*parts)[0].is_isotropic() && (*parts)[1].is_isotropic(); }
template <typename C>
std::string_view BlendBxDFT<C>::nonreciprocal_reason() const {
  const std::string_view a = (*parts)[0].nonreciprocal_reason();
  return a.empty() ? (*parts)[1].nonreciprocal_reason() : a;
}
template <typename C>
BSDFEvalT<C> BlendBxDFT<C>::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  const BSDFEvalT<C> a = (*parts)[0].eval(wo, wi, mode), b = (*parts)[1].eval(wo, wi, mode);
  return {a.f * (1 - weight) + b.f * weight, (1 - weight) * a.pdf + weight * b.pdf};
}
template <typename C>
C BlendBxDFT<C>::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  return (*parts)[0].f(wo, wi, mode) * (1 - weight) + (*parts)[1].f(wo, wi, mode) * weight;
}
template <typename C>
Float BlendBxDFT<C>::pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  return (1 - weight) * (*parts)[0].pdf(wo, wi, mode) + weight * (*parts)[1].pdf(wo, wi, mode);
}
template <typename C>
std::optional<BSDFSampleT<C>> BlendBxDFT<C>::sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                                   TransportMode mode) const {
  const bool second = u_lobe >= 1 - weight;
  // Reuse u_lobe, rescaled to [0, 1) within the chosen part.
  const Float u = second ? (u_lobe - (1 - weight)) / weight : u_lobe / (1 - weight);
  const Float p_part = second ? weight : 1 - weight;
  auto s = (*parts)[second ? 1 : 0].sample(wo, std::min(u, kOneMinusEpsilon), u1, u2, mode);
  if (!s) return std::nullopt;
  if (s->delta) {
    s->pdf *= p_part;  // the discrete probability of this delta direction
    return s;
  }
  const BSDFEvalT<C> e = eval(wo, s->wi, mode);
  if (!(e.pdf > 0)) return std::nullopt;
  s->weight = e.f * (std::abs(s->wi.z) / e.pdf);
  s->pdf = e.pdf;
  return s;
}
template <typename C>
std::optional<DirectionalAlbedoT<C>> BlendBxDFT<C>::albedo(const Vec3& wo, TransportMode mode) const {
  const auto a = (*parts)[0].exact_albedo(wo, mode), b = (*parts)[1].exact_albedo(wo, mode);
  if (!a || !b) return std::nullopt;
  return DirectionalAlbedoT<C>{a->reflectance * (1 - weight) + b->reflectance * weight,
                           a->transmittance * (1 - weight) + b->transmittance * weight};
}

}  // namespace gonio

// LayeredBxDF, now that BxDF is complete.
#include "gonio/bxdf/layered_impl.h"  // IWYU pragma: export
// PbrNodeBxDF (MaterialX's operators), likewise.
#include "gonio/bxdf/pbr_node_impl.h"  // IWYU pragma: export
// Where the models' code is generated (once, in the library).
#include "gonio/bxdf/instances.h"  // IWYU pragma: export
