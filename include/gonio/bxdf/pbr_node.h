#pragma once
// MaterialX pbrlib's BSDF composition (MaterialX PBR specification, "Utility Nodes":
// mix, layer, add, multiply; reference code libraries/pbrlib/genglsl/mx_*_bsdf.glsl).
// A MaterialX BSDF is a pair (response, throughput): the throughput T(v) is what a node
// lets through to a base layered under it, a function of the view direction v only:
//   leaf node    f = s f_lobe,            T = 1 − w E(μv)  (layerable: dielectric,
//                                                            generalized_schlick, sheen)
//                                         T = 0            (the others: opaque)
//   multiply     f = c f_in,              T = T_in         (c clamped to [0, 1])
//   add          f = f1 + f2,             T = max(T1 + T2 − 1, 0)
//   mix          f = m f_fg + (1 − m) f_bg, T = m T_fg + (1 − m) T_bg
//   layer        f = f_top + T_top(v) f_base,  T = T_top T_base
// where w is the node's weight, s = w × its tint (or colour, where MaterialX applies it
// outside the lobe) and E(μv) the directional albedo of the node's untinted reflection
// lobe (MaterialX's dirAlbedo), tabulated once per material (PbrAlbedoTable). Each gonio
// lobe is one of gonio's models (the conductor_bsdf a roughconductor, ...), held in
// parts[0]; operators hold their two inputs in parts.
//
// v is the direction towards the viewer: wo in radiance mode, wi in importance mode (the
// adjoint, SPEC §1), so `layer` is not reciprocal (MaterialX's albedo scaling keys the
// base's weight on v alone); docs/materialx.md measures how far.
//
// Sampling: a leaf and multiply sample their input; add picks an input with probability
// 1/2, mix with m, layer the top with q(wo) = clamp(1 − mean T_top(wo), 0.1, 0.9); the pdf
// is that mixture's, the weight f |cos θi| / pdf of the whole node (a delta sample keeps
// its part's weight, scaled by its coefficient over its choice probability).
// Polarized mode: depolarizing (no polarizing form).

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"

namespace gonio {

template <typename C>
class BxDFT;

// E(μ) of a layerable node's lobe on a grid uniform in √μ, μ = (i / (kSize − 1))², dense
// towards grazing where a sheen's albedo climbs steeply (Charlie sheen r 0.4: 0.49 at 80°,
// 0.79 at 89.94°), linear between nodes; its channels averaged (MaterialX's throughputs
// are grey but for generalized_schlick's, which averages them too); made by
// src/material.cpp (pbr_albedo_table).
struct PbrAlbedoTable {
  static constexpr int kSize = 65;
  std::array<Float, kSize> e{};
  Float at(Float mu) const {
    const Float x = std::sqrt(std::clamp(std::abs(mu), Float(0), Float(1))) * (kSize - 1);
    const int i = std::min(int(x), kSize - 2);
    const Float t = x - Float(i);
    return e[size_t(i)] * (1 - t) + e[size_t(i) + 1] * t;
  }
};

enum class PbrOp : unsigned char { Scale, Add, Mix, Layer };
// What a Scale node lets through: nothing (an opaque lobe), 1 − w E(μv) (a layerable
// lobe), or its input's throughput (multiply).
enum class PbrThroughput : unsigned char { Opaque, Albedo, Input };

template <typename C>
struct PbrNodeBxDFT {
  using color_type = C;
  using Parts = std::array<BxDFT<C>, 2>;
  static constexpr std::string_view kName = "materialx";
  PbrOp op = PbrOp::Scale;
  PbrThroughput through = PbrThroughput::Opaque;
  C scale = C(1);       // Scale: the factor on its input's f
  Float weight = 1;     // Scale with Albedo: w in 1 − w E; Mix: m, the weight of parts[0] (fg)
  const PbrAlbedoTable* albedo_table = nullptr;  // Scale with Albedo
  std::shared_ptr<const PbrAlbedoTable> table_owner;  // keeps it alive in a parsed material
  const Parts* parts = nullptr;
  std::shared_ptr<const Parts> owner;

  static PbrNodeBxDFT make(PbrOp op, std::shared_ptr<const Parts> parts) {
    PbrNodeBxDFT n;
    n.op = op;
    n.parts = parts.get();
    n.owner = std::move(parts);
    return n;
  }

  // T(v), per channel, for the view direction v.
  C throughput(const Vec3& v) const;

  BxDFFlags flags() const;
  Float relative_eta() const;
  bool is_isotropic() const;
  std::string_view nonreciprocal_reason() const;
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode) const { return eval(wo, wi, mode).f; }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2, TransportMode mode) const;
  std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& wo, TransportMode mode) const;

 private:
  // Probability of sampling parts[0] (Add, Mix, Layer).
  Float first_probability(const Vec3& wo) const;
};
using PbrNodeBxDF = PbrNodeBxDFT<Color>;

}  // namespace gonio
