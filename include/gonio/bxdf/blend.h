#pragma once
// Linear blend of two models (lecture §2: "real-world materials are usually a
// combination of several types of reflection models"; lecture §3.4, linearity):
//   f = (1 − w) f0 + w f1,  pdf = (1 − w) pdf0 + w pdf1,
// sampled by choosing part 1 with probability w. Delta samples of a part keep their
// weight (the choice probability cancels the blend weight); others are weighted by the
// blended f and pdf. A blend is itself a BxDF, so its parts live elsewhere: `parts`
// points at them, and `owner` keeps them alive when the blend owns them (a parsed
// material); a spectral blend made per shading point points into the caller's scratch
// space instead, so that making it allocates nothing. The methods are defined in bxdf.h,
// where BxDFT is complete.

#include <array>
#include <memory>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"

namespace gonio {

template <typename C>
class BxDFT;

template <typename C>
struct BlendBxDFT {
  using color_type = C;
  using Parts = std::array<BxDFT<C>, 2>;
  static constexpr std::string_view kName = "blend";
  Float weight = 0.5f;
  const Parts* parts = nullptr;
  std::shared_ptr<const Parts> owner;

  static BlendBxDFT make(Float weight, std::shared_ptr<const Parts> parts) {
    BlendBxDFT b;
    b.weight = weight;
    b.parts = parts.get();
    b.owner = std::move(parts);
    return b;
  }

  BxDFFlags flags() const;
  Float relative_eta() const;
  bool is_isotropic() const;
  std::string_view nonreciprocal_reason() const;
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2, TransportMode mode) const;
  std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& wo, TransportMode mode) const;
};
using BlendBxDF = BlendBxDFT<Color>;

}  // namespace gonio
