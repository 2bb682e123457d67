#pragma once
// A material in polarized mode (issue 15): eval and sample return a Mueller matrix per
// colour channel (MuellerT<C>), from the frame of the incident beam (travelling along −wi)
// to that of the outgoing one (along wo), each the s/p frame of its direction's plane of
// incidence (polarization/fresnel_factor.h, SPEC §3). The polarizing models — conductor,
// dielectric, roughconductor, roughdielectric, plastic, thindielectric, openpbr (its lobes that polarize) — are the very same templates as in
// unpolarized mode, instantiated with C = MuellerT<colour>: their one Fresnel customization
// point (fresnel_factor) turns into the interface's Mueller matrix there. Every other model
// depolarizes: M = f · diag(1, 0, 0, 0). M00 is always exactly the unpolarized value, and
// the sampled directions are exactly the unpolarized model's.
//
// Made once per material (a copy of the model's parameters), not per evaluation.

#include <optional>
#include <type_traits>
#include <variant>

#include "gonio/bxdf.h"
#include "gonio/polarization/mueller.h"

namespace gonio {

template <typename C>
class PolarizedBxDFT {
 public:
  using color_type = MuellerT<C>;
  using Polarizing = std::variant<std::monostate, ConductorBxDFT<MuellerT<C>>, DielectricBxDFT<MuellerT<C>>,
                                  RoughConductorBxDFT<MuellerT<C>>, RoughDielectricBxDFT<MuellerT<C>>,
                                  PlasticBxDFT<MuellerT<C>>, ThinDielectricBxDFT<MuellerT<C>>,
                                  OpenPbrBxDFT<MuellerT<C>>>;

  explicit PolarizedBxDFT(const BxDFT<C>& model) : base_(model) {
    using P = MuellerT<C>;
    std::visit(
        [&](const auto& m) {
          using M = std::decay_t<decltype(m)>;
          if constexpr (std::is_same_v<M, ConductorBxDFT<C>>) polar_ = ConductorBxDFT<P>{m.fresnel};
          else if constexpr (std::is_same_v<M, DielectricBxDFT<C>>) polar_ = DielectricBxDFT<P>{m.eta, m.film};
          else if constexpr (std::is_same_v<M, RoughConductorBxDFT<C>>)
            polar_ = RoughConductorBxDFT<P>{m.distribution, m.fresnel, m.multiscatter};
          else if constexpr (std::is_same_v<M, RoughDielectricBxDFT<C>>)
            polar_ = RoughDielectricBxDFT<P>{m.distribution, m.eta, m.multiscatter, m.film};
          else if constexpr (std::is_same_v<M, PlasticBxDFT<C>>)
            polar_ = PlasticBxDFT<P>::make(static_cast<const PlasticCoat&>(m), m.reflectance);
          else if constexpr (std::is_same_v<M, ThinDielectricBxDFT<C>>)
            polar_ = ThinDielectricBxDFT<P>{m.eta, m.film};
          else if constexpr (std::is_same_v<M, OpenPbrBxDFT<C>>) {
            const openpbr::Solved solved = m.solved();
            polar_ = OpenPbrBxDFT<P>::make(m.params, m.film, &solved, {m.metal.fresnel.film, m.glass.film});
          }
        },
        model.models());
  }

  // True when the model has a polarizing form (else it depolarizes).
  bool polarizing() const { return polar_.index() != 0; }
  const BxDFT<C>& unpolarized() const { return base_; }
  BxDFFlags flags() const { return base_.flags(); }
  Float relative_eta() const { return base_.relative_eta(); }

  BSDFEvalT<MuellerT<C>> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return std::visit(
        [&](const auto& m) -> BSDFEvalT<MuellerT<C>> {
          if constexpr (std::is_same_v<std::decay_t<decltype(m)>, std::monostate>) {
            const BSDFEvalT<C> e = base_.eval(wo, wi, mode);
            return {MuellerT<C>(e.f), e.pdf};
          } else if constexpr (requires { m.eval(wo, wi, mode); }) {
            return m.eval(wo, wi, mode);
          } else {
            return {m.f(wo, wi, mode), m.pdf(wo, wi, mode)};
          }
        },
        polar_);
  }
  MuellerT<C> f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }

  std::optional<BSDFSampleT<MuellerT<C>>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                                 TransportMode mode = TransportMode::Radiance) const {
    return std::visit(
        [&](const auto& m) -> std::optional<BSDFSampleT<MuellerT<C>>> {
          if constexpr (std::is_same_v<std::decay_t<decltype(m)>, std::monostate>) {
            const auto s = base_.sample(wo, u_lobe, u1, u2, mode);
            if (!s) return std::nullopt;
            return BSDFSampleT<MuellerT<C>>{s->wi, MuellerT<C>(s->weight), s->pdf, s->delta, s->lobe, s->eta};
          } else {
            return m.sample(wo, u_lobe, u1, u2, mode);
          }
        },
        polar_);
  }

 private:
  BxDFT<C> base_;
  Polarizing polar_;
};

using PolarizedBxDF = PolarizedBxDFT<Color>;
using PolarizedSpectralBxDF = PolarizedBxDFT<SampledSpectrum>;

}  // namespace gonio

// Where the polarizing models' code is generated (once, in the library).
#include "gonio/polarization/instances.h"  // IWYU pragma: export
