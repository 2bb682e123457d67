#pragma once
// The extension point: a user's own model, written as a class derived from CustomBxDF,
// goes everywhere a built-in model goes (BxDF, BSDF, reflectance, the validator, the
// renderer). Built-in models are dispatched without virtual calls; only user models pay
// for one.

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "gonio/bxdf/contract.h"

namespace gonio {

// A model for one colour type: CustomBxDF (RGB) or CustomBxDFT<SampledSpectrum>.
template <typename C>
class CustomBxDFT {
 public:
  using color_type = C;
  virtual ~CustomBxDFT() = default;
  virtual BxDFFlags flags() const = 0;
  virtual C f(const Vec3& wo, const Vec3& wi, TransportMode mode) const = 0;
  virtual Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const = 0;
  virtual std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                           TransportMode mode) const = 0;
  // Relative index n_inside / n_outside for models that refract; 1 otherwise.
  virtual Float relative_eta() const { return 1; }
  virtual bool is_isotropic() const { return true; }
  // The exact directional albedo, if the model has a closed form (the validator then
  // proves it against the model's sampling, and reflectance() uses it).
  virtual std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& /*wo*/, TransportMode /*mode*/) const {
    return std::nullopt;
  }
  virtual std::string name() const { return "custom"; }
};
using CustomBxDF = CustomBxDFT<Color>;

// Value-type holder so a CustomBxDF can sit in the BxDF variant (shared, immutable).
template <typename C>
struct UserBxDFT {
  using color_type = C;
  std::shared_ptr<const CustomBxDFT<C>> model;

  BxDFFlags flags() const { return model->flags(); }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode) const { return model->f(wo, wi, mode); }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const { return model->pdf(wo, wi, mode); }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode) const {
    return model->sample(wo, u_lobe, u1, u2, mode);
  }
  Float relative_eta() const { return model->relative_eta(); }
  bool is_isotropic() const { return model->is_isotropic(); }
  std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& wo, TransportMode mode) const {
    return model->albedo(wo, mode);
  }
};
using UserBxDF = UserBxDFT<Color>;

// The vtables' one home: src/custom_bxdf.cpp.
extern template class CustomBxDFT<Color>;
extern template class CustomBxDFT<SampledSpectrum>;

template <typename M, typename... Args>
UserBxDFT<typename M::color_type> make_user_bxdf(Args&&... args) {
  return UserBxDFT<typename M::color_type>{std::make_shared<const M>(std::forward<Args>(args)...)};
}

}  // namespace gonio
