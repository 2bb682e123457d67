#pragma once
// A measured material in the RGL `.bsdf` format (SPEC §2 `rgl`; Dupuy & Jakob 2018):
// evaluated and sampled from its tables as rgl/data.h describes. The file's θi/φi axis is
// gonio's wo: f(wo, wi) = value(a = wo, b = wi)/cos θi (SPEC §2). Reflection only,
// two-sided like every reflecting model (SPEC §1: both directions mirrored to the upper
// side when wo is below). The table is shared: the model holds a pointer to it, `owner`
// keeps it alive in a parsed material.
//
// The file's value(a, b) = f(a, b)·cos θb is interpolated, so it does not vanish as b
// reaches the horizon, and value/cos θb grows without bound there (gonio check found
// f = 1e27 at cos θi = 1e-30, and a directional albedo of 17 at 89.9°). gonio therefore
// divides by the larger of the two cosines, reading the table from that side:
//   f(wo, wi) = value(wo, wi)/cos θi   if cos θi ≥ cos θo   (the file's own orientation)
//             = value(wi, wo)/cos θo   otherwise            (BRDF reciprocity)
// which is bounded and reciprocal by construction (importance mode, the adjoint, is the
// same function). Sampling always starts from wo, as the file's warps do (SPEC §2), and
// its weight is this f·cos θi/pdf. `gonio check` holds reciprocity to
// RglData::reciprocity_tolerance (docs/measured.md).
//
// Spectral mode: a spectral file at the path's wavelengths (linear between the file's
// wavelengths, clamped beyond); an RGB-only file's RGB upsampled as an unbounded spectrum
// (Jakob & Hanika 2019). RGB mode: the file's `rgb`, or its spectra reduced as
// src/rgl/data.cpp documents.

#include <memory>
#include <optional>
#include <string_view>
#include <type_traits>

#include "gonio/bxdf/contract.h"
#include "gonio/rgl/data.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

template <typename C>
struct RglBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "rgl";
  const RglData* data = nullptr;
  std::shared_ptr<const RglData> owner;
  SampledWavelengths wavelengths;  // spectral mode only

  static RglBxDFT make(std::shared_ptr<const RglData> table) {
    RglBxDFT m;
    m.data = table.get();
    m.owner = std::move(table);
    return m;
  }

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }
  bool is_isotropic() const { return !data || data->isotropic; }
  float reciprocity_tolerance() const { return data ? data->reciprocity_tolerance : 0.f; }

  C f(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!data || !same_side(wo, wi)) return C(0);
    return bounded_f(upper(wo, wo), upper(wo, wi));
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!data || !same_side(wo, wi)) return 0;
    RglData::Point p;
    return data->locate(upper(wo, wo), upper(wo, wi), p) ? p.pdf : 0;
  }
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (!data || !same_side(wo, wi)) return {C(0), 0};
    const Vec3 o = upper(wo, wo), i = upper(wo, wi);
    RglData::Point p;
    if (!data->locate(o, i, p)) return {C(0), 0};
    (void)mode;
    const C v = i.z >= o.z ? colour(p) / i.z : value(i, o) / o.z;
    return {v, p.pdf};
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float, Float u1, Float u2, TransportMode) const {
    if (!data || wo.z == 0 || !is_finite(wo)) return std::nullopt;
    const Vec3 o = upper(wo, wo);
    Vec3 i;
    RglData::Point p;
    if (!data->sample(o, u1, u2, i, p) || !(p.pdf > 0) || !is_finite(i)) return std::nullopt;
    // The value and pdf at the sampled direction as eval gives them (locate again inside
    // sample): sample's pdf equals pdf(wo, wi) bit for bit.
    const C fc = i.z >= o.z ? colour(p) : value(i, o) * (i.z / o.z);
    const Vec3 wi = wo.z > 0 ? i : Vec3{i.x, i.y, -i.z};
    return BSDFSampleT<C>{wi, fc / p.pdf, p.pdf, false, Lobe::Reflection, 1};
  }

 private:
  static bool same_side(const Vec3& wo, const Vec3& wi) { return wo.z * wi.z > 0; }
  static Vec3 upper(const Vec3& wo, const Vec3& w) { return wo.z > 0 ? w : Vec3{w.x, w.y, -w.z}; }
  C bounded_f(const Vec3& o, const Vec3& i) const { return i.z >= o.z ? value(o, i) / i.z : value(i, o) / o.z; }
  // value(a, b) = f(wo = a, wi = b)·cos θb (rgl/data.h).
  C value(const Vec3& a, const Vec3& b) const {
    RglData::Point p;
    return data->locate(a, b, p) ? colour(p) : C(0);
  }
  C colour(const RglData::Point& p) const {
    if constexpr (std::is_same_v<C, Color>) {
      return data->value_rgb(p);
    } else {
      if (!data->spectral) return rgb_unbounded(data->value_rgb(p), wavelengths);
      C s(0);
      for (int j = 0; j < kSpectrumSamples; ++j) s[j] = data->value_at(p, wavelengths[j]);
      return s;
    }
  }
};
using RglBxDF = RglBxDFT<Color>;

}  // namespace gonio
