#pragma once
// Linear blend of two models (lecture §2: "real-world materials are usually a
// combination of several types of reflection models"; lecture §3.4, linearity):
//   f = (1 − w) f0 + w f1,  pdf = (1 − w) pdf0 + w pdf1,
// sampled by choosing part 1 with probability w. Delta samples of a part keep their
// weight (the choice probability cancels the blend weight); others are weighted by the
// blended f and pdf. The parts live behind a shared pointer because a blend is itself
// a BxDF; the methods are defined in bxdf.h, where BxDF is complete.

#include <array>
#include <memory>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"

namespace gonio {

class BxDF;

struct BlendBxDF {
  static constexpr std::string_view kName = "blend";
  Float weight = 0.5f;
  std::shared_ptr<const std::array<BxDF, 2>> parts;

  BxDFFlags flags() const;
  Float relative_eta() const;
  bool is_isotropic() const;
  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  Color f(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  std::optional<BSDFSample> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2, TransportMode mode) const;
  std::optional<DirectionalAlbedo> albedo(const Vec3& wo, TransportMode mode) const;
};

}  // namespace gonio
