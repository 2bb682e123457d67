#pragma once
// A measured isotropic BRDF (SPEC §2 `measured`): the MERL table of a file, interpolated
// and importance-sampled as measured_data.h describes. Reflection only, two-sided like
// every reflecting model (SPEC §1). The table is shared: the model holds a pointer to it,
// and `owner` keeps it alive in a parsed material (a spectral model made per shading
// point points at the parsed material's table and owns nothing).
//
// Spectral mode: the table holds RGB; f at the path's wavelengths is that RGB upsampled as
// an unbounded spectrum (Jakob & Hanika 2019, scaled as pbrt-v4's RGBUnboundedSpectrum).

#include <memory>
#include <optional>
#include <string_view>
#include <type_traits>

#include "gonio/bxdf/contract.h"
#include "gonio/measured_data.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

template <typename C>
struct MeasuredBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "measured";
  const MeasuredData* data = nullptr;
  std::shared_ptr<const MeasuredData> owner;
  SampledWavelengths wavelengths;  // spectral mode only

  static MeasuredBxDFT make(std::shared_ptr<const MeasuredData> table) {
    MeasuredBxDFT m;
    m.data = table.get();
    m.owner = std::move(table);
    return m;
  }

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }

  C f(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!data || !same_side(wo, wi)) return C(0);
    return colour(data->lookup(upper(wo, wo), upper(wo, wi)));
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!data || !same_side(wo, wi)) return 0;
    return data->pdf(upper(wo, wo), upper(wo, wi));
  }
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!data || !same_side(wo, wi)) return {C(0), 0};
    const MeasuredData::Eval e = data->eval(upper(wo, wo), upper(wo, wi));
    return {colour(e.f), e.pdf};
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2, TransportMode) const {
    if (!data || wo.z == 0 || !is_finite(wo)) return std::nullopt;
    const Vec3 o = upper(wo, wo);
    const Vec3 i = data->sample(o, u_lobe, u1, u2);
    if (!(i.z > 0) || !is_finite(i)) return std::nullopt;
    // f and pdf together (eval shares their arctangents; bit for bit lookup and pdf).
    const MeasuredData::Eval e = data->eval(o, i);
    const Float p = e.pdf;
    if (!(p > 0)) return std::nullopt;
    const C value = colour(e.f);
    const Vec3 wi = wo.z > 0 ? i : Vec3{i.x, i.y, -i.z};
    return BSDFSampleT<C>{wi, value * (i.z / p), p, false, Lobe::Reflection, 1};
  }

 private:
  static bool same_side(const Vec3& wo, const Vec3& wi) { return wo.z * wi.z > 0; }
  // w mirrored to the upper side when wo is below (two-sided reflection, SPEC §1).
  static Vec3 upper(const Vec3& wo, const Vec3& w) { return wo.z > 0 ? w : Vec3{w.x, w.y, -w.z}; }
  C colour(const Color& rgb) const {
    if constexpr (std::is_same_v<C, Color>) return rgb;
    else return rgb_unbounded(rgb, wavelengths);
  }
};
using MeasuredBxDF = MeasuredBxDFT<Color>;

}  // namespace gonio
