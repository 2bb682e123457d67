#pragma once
// BxDF: one value that holds any model, built-in or the user's, dispatched through
// std::variant (a jump table, no virtual call and no allocation for built-in models).
// New built-in models are added to Models below and nowhere else.

#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "gonio/bxdf/conductor.h"
#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/custom.h"
#include "gonio/bxdf/dielectric.h"
#include "gonio/bxdf/diffuse.h"
#include "gonio/bxdf/mirror.h"
#include "gonio/bxdf/roughconductor.h"
#include "gonio/bxdf/roughdielectric.h"

namespace gonio {

class BxDF {
 public:
  using Models = std::variant<DiffuseBxDF, MirrorBxDF, ConductorBxDF, DielectricBxDF,
                              RoughConductorBxDF, RoughDielectricBxDF, UserBxDF>;

  BxDF() = default;
  template <typename M>
    requires BxDFModel<std::decay_t<M>> && std::is_constructible_v<Models, M&&>
  BxDF(M&& model) : m_(std::forward<M>(model)) {}  // NOLINT: implicit by design

  Color f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) { return m.f(wo, wi, mode); }, m_);
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit([&](const auto& m) { return m.pdf(wo, wi, mode); }, m_);
  }
  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit(
        [&](const auto& m) -> BSDFEval {
          if constexpr (requires { m.eval(wo, wi, mode); }) return m.eval(wo, wi, mode);
          else return {m.f(wo, wi, mode), m.pdf(wo, wi, mode)};
        },
        m_);
  }
  std::optional<BSDFSample> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
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
  bool is_isotropic() const {
    return std::visit(
        [](const auto& m) -> bool {
          if constexpr (requires { m.is_isotropic(); }) return m.is_isotropic();
          else return true;
        },
        m_);
  }
  // The exact directional albedo where the model has a closed form.
  std::optional<DirectionalAlbedo> exact_albedo(const Vec3& wo, TransportMode mode) const {
    return std::visit(
        [&](const auto& m) -> std::optional<DirectionalAlbedo> {
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

}  // namespace gonio
