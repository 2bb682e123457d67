#pragma once
// BSDF: a BxDF placed at a surface point. Converts world-space directions into the local
// shading frame (lecture §3.2: N, S, T of the DifferentialGeometry) and back.

#include <optional>

#include "gonio/bxdf.h"
#include "gonio/math/frame.h"

namespace gonio {

template <typename C>
class BSDFT {
 public:
  BSDFT(BxDFT<C> bxdf, const Frame& frame) : bxdf_(std::move(bxdf)), frame_(frame) {}

  // World-space directions need not be unit length: they are normalised here, so that a
  // caller's rounding error cannot push cosines past 1.
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return bxdf_.f(local(wo), local(wi), mode);
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return bxdf_.pdf(local(wo), local(wi), mode);
  }
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return bxdf_.eval(local(wo), local(wi), mode);
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    auto s = bxdf_.sample(local(wo), u_lobe, u1, u2, mode);
    if (s) s->wi = frame_.to_world(s->wi);
    return s;
  }
  BxDFFlags flags() const { return bxdf_.flags(); }
  const BxDFT<C>& bxdf() const { return bxdf_; }
  const Frame& frame() const { return frame_; }

 private:
  Vec3 local(const Vec3& w) const { return normalize(frame_.to_local(w)); }
  BxDFT<C> bxdf_;
  Frame frame_;
};
using BSDF = BSDFT<Color>;

}  // namespace gonio
