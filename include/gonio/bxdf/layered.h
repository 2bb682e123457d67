#pragma once
// Layered BSDF: a dielectric interface (`top`, smooth or rough) over any reflecting
// material (`bottom`), with an optional homogeneous medium between them (optical depth
// `thickness`, σt = 1; single-scattering `albedo`; Henyey–Greenstein `g`). Evaluated by
// the stochastic position-free random walk of Guo, Hašan & Zhao 2018, "Position-Free
// Monte Carlo Simulation for Arbitrary Layered BSDFs" (SIGGRAPH Asia; §4–5), in the form
// of pbrt-v4's LayeredBxDF (Pharr, Jakob & Humphreys, 4th ed., §14.3.2): a path enters
// through the top (a transmission sample from wo), walks between the interfaces and the
// medium, and at each vertex is connected to wi through the top by a transmission sample
// drawn from wi (next-event estimation), combined by the power heuristic with the path's
// own continuation where the top is rough (Veach 1997, §9.2).
//
// What gonio adds so that the validator's properties hold exactly (issue 34, item 6):
//  - f is deterministic for a pair: the walk's generator (rng.h, a value on the stack) is
//    seeded by a hash of the UNORDERED pair {wo, wi} of bit patterns, and the estimator is
//    run from both ends with that seed and averaged, f = (E(wo, wi) + E(wi, wo)) / 2, so
//    f(wo, wi) = f(wi, wo) to the last bit. f is an unbiased estimate of the stack's BSDF.
//    An isotropic stack hashes the pair's rotation invariants instead (quantised to 2⁻¹²)
//    and walks in a frame turned to the first direction's azimuth, so that turning both
//    directions about N leaves f unchanged (layered_impl.h, canonical_turn).
//  - A stack whose bottom reflects only is two-sided: wo below the surface sees the same
//    stack mirrored, and f in importance mode equals f in radiance mode. A bottom that
//    transmits (a dielectric, a sheet, a blend with one) makes the stack transmit: light
//    enters and leaves through either interface (the walk's entry and exit interfaces, as
//    pbrt-v4's), wo below sees the bottom first, and the two ends of the symmetric
//    estimator are related by Veach's reciprocity for transmission, f(wo, wi)/n_wo² =
//    f(wi, wo)/n_wi² (Veach 1997, eq. 5.14), the index below being the top's times the
//    bottom's relative index.
//  - sample() draws wi from a closed-form mixture whose density is exactly pdf(): the
//    top's own microfacet reflection lobe and a wider copy (rough top), the bottom's own
//    sampling seen through the top's macroscopic refraction (a non-delta bottom), the
//    medium's phase function once about the refracted wo, folded up at the bottom and
//    refracted out (a scattering medium: its backward peak is a retroreflection, its
//    forward one a mirror reflection), and a cosine lobe; the weight is f |cos θi| / pdf
//    with the stochastic f. A smooth top has a
//    delta reflection: its weight is an unbiased estimate of the whole specular chain
//    (F + (1 − F)² Tr² R_b / (1 − F Tr² R_b) for a specular bottom of reflectance R_b,
//    summed path by path), seeded per sample.
//  - The two ends are weighted by w(wo, wi) = cos²θi / (cos²θo + cos²θi) and its mirror
//    (weights that sum to 1 keep the average unbiased, and swapping the directions swaps
//    the two products, so reciprocity stays exact): the walk that leaves towards a grazing
//    direction connects through a transmission drawn from it, whose 1/|cos| next to a
//    vertex just under the top makes rare huge estimates (weights of 400 × the albedo at
//    89.99°, gonio check); the walk that enters there does not.
// The top: a dielectric (smooth or rough, with its thin film) or a thin dielectric sheet
// (`thin_top`: light crosses it straight, wi = −wo, and it reflects 2r/(1 + r) from both
// sides, thindielectric.h; `top` then holds the sheet's eta and film, and is smooth).
// Polarized mode: depolarizing (the walk sums unpolarized energy; docs/polarization.md).
// The bottom is held as the blend holds its parts (blend.h): `bottom` points at it and
// `owner` keeps it alive when the model owns it; spectral models made per shading point
// point into the caller's scratch space. The methods are defined in layered_impl.h,
// where BxDFT is complete.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/roughdielectric.h"

namespace gonio {

template <typename C>
class BxDFT;

template <typename C>
struct LayeredBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "layered";
  // A smooth top is a RoughDielectricBxDFT below the smoothness threshold (specular()).
  RoughDielectricBxDFT<C> top;
  bool thin_top = false;
  const BxDFT<C>* bottom = nullptr;
  std::shared_ptr<const BxDFT<C>> owner;
  Float thickness = 0.01f;  // optical depth of the medium (σt = 1); 0: no medium
  C albedo{};               // single-scattering albedo of the medium (0: absorbing only)
  Float g = 0;              // Henyey–Greenstein asymmetry
  int max_depth = 100;
  int samples = 1;

  static LayeredBxDFT make(const RoughDielectricBxDFT<C>& top, bool thin_top, std::shared_ptr<const BxDFT<C>> bottom,
                           Float thickness, const C& albedo, Float g, int max_depth, int samples) {
    LayeredBxDFT m;
    m.top = top;
    m.thin_top = thin_top;
    m.bottom = bottom.get();
    m.owner = std::move(bottom);
    m.thickness = thickness;
    m.albedo = albedo;
    m.g = g;
    m.max_depth = max_depth;
    m.samples = samples;
    return m;
  }

  BxDFFlags flags() const;
  bool is_isotropic() const;
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const;

  // The bottom transmits, and so does the stack.
  bool transmits() const;
  // n(below the stack) / n(above): 1 unless the stack transmits.
  Float relative_eta() const;

  // --- the parts of the walk (layered_impl.h) ---
  bool scatters() const { return thickness > 0 && !albedo.is_black(); }
  // One estimate of the stack's BSDF (radiance mode) for wo, wi on either side (the upper
  // side only for a bottom that reflects only), from the generator state `seed` (both ends
  // of the symmetric estimator use the same seed).
  C walk(const Vec3& wo, const Vec3& wi, std::uint64_t seed) const;
  // The two interfaces as the walk sees them, in the stack's frame (the top at depth
  // `thickness`, the bottom at 0): whether every lobe is a delta, f and pdf of the
  // non-delta part, and a reflection (`reflect`) or a transmission drawn from w: none
  // when the other kind was drawn, whose probability the drawn kind's weight carries.
  bool interface_delta(bool at_top) const;
  BSDFEvalT<C> interface_eval(bool at_top, const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  Float interface_pdf(bool at_top, const Vec3& wo, const Vec3& wi, TransportMode mode) const;
  template <typename Rand>
  std::optional<BSDFSampleT<C>> interface_sample(bool at_top, const Vec3& w, bool reflect, TransportMode mode,
                                                 Rand& r) const;
  // Where both interfaces are deltas: from a scattering vertex at depth zp (travelling
  // along w) to the exit along w_exit, unscattered, directly and by the other interface,
  // with every round trip between them: the phase function times transmittances and
  // reflectances, an unbiased estimate.
  template <typename Rand>
  C delta_legs_to_exit(const Vec3& w, Float zp, const Vec3& w_exit, bool exit_top, Rand& r) const;
  // An unbiased estimate of the smooth top's specular chain for wo (upper side): the
  // stack's delta reflectance in the mirror direction (a bottom that reflects only).
  C specular_chain(const Vec3& wo, std::uint64_t seed) const;
  // The delta chains of a transmitting stack for wo on either side, one random path: the
  // delta reflectance (mirror direction) and transmittance (direction `wt`, set when
  // `transmitted`), each an unbiased estimate.
  struct Chain {
    C reflection{}, transmission{};
    Vec3 wt{};
    bool transmitted = false;
  };
  Chain transmitting_chain(const Vec3& wo, TransportMode mode, std::uint64_t seed) const;
  // The smooth top (or sheet) seen by light along w (w.z < 0: from inside): its
  // reflectance per channel, and its crossing, the direction beyond it (refracted, or
  // straight through a sheet) with the share carried, (1 − R) times the mode's radiance
  // scaling (none under total internal reflection).
  C smooth_reflectance(const Vec3& w) const;
  struct Crossing {
    Vec3 w;
    C weight;
  };
  std::optional<Crossing> cross_smooth_top(const Vec3& w, TransportMode mode) const;
  // The index that bends directions at the top: 1 for a sheet.
  Float geometric_eta() const { return thin_top ? Float(1) : top.eta; }
  // Mixture probabilities of sample() for wo (upper side).
  // (A transmitting stack adds `delta_t`, its delta transmission chain, `cosine_far`, a
  // cosine lobe on the far side, and `lobe_t`, a rough top's own transmission crossing a
  // delta bottom by Snell's law; seen from below, `delta` is the chain's reflection,
  // `base` the bottom's own sampling, refracted out through the top when it transmits.)
  struct Mixture {
    Float delta = 0, lobe = 0, wide = 0, base = 0, medium = 0, cosine = 0, delta_t = 0, cosine_far = 0, lobe_t = 0;
  };
  Mixture mixture(const Vec3& wo) const;
  Float mixture_pdf(const Mixture& p, const Vec3& wo, const Vec3& wi) const;
};
using LayeredBxDF = LayeredBxDFT<Color>;

}  // namespace gonio
