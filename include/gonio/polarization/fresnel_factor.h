#pragma once
// The one customization point through which a model's Fresnel factor becomes its colour
// type (issue 15). A model is one template on its colour C (bxdf.h); instantiated with an
// unpolarized colour (Color, SampledSpectrum) fresnel_factor<C>(value, ...) is C(value) and
// nothing else is computed; with C = MuellerT<colour> it is the interface's Mueller matrix
// `shape()` (in the s/p basis of the plane of incidence of the facet, which holds wo and wi)
// scaled channel by channel so that M00 equals `value` exactly, and expressed in the frames
// of the two directions (Baek, Zeltner, Ku, Jakob 2018, "Simultaneous acquisition of
// polarimetric SVBRDF and normals", ACM TOG 37(6), §4; Mitsuba 3's polarized BSDFs):
//   M = R(β) M_facet R(α),
// α the turn about the incident beam (travelling along −wi) from its frame to the facet's,
// β the turn about wo from the facet's frame to wo's. `value` may carry any scalar factor
// of the model (D G2 / (4 cos cos), 1 / lobe probability, (n_wo/n_wi)²): the shape supplies
// the polarization, `value` the magnitude.
//
// The frame of a direction w (SPEC §3: "the s/p frames of the two directions' planes of
// incidence") has s = ẑ × w / |ẑ × w|, perpendicular to the plane holding w and the
// normal, and p = d × s for the beam's direction of travel d (wo for the outgoing beam,
// −wi for the incident one); along the normal itself s = ŷ.

#include <cmath>

#include "gonio/math/vec3.h"
#include "gonio/polarization/mueller.h"

namespace gonio {

// s of direction w's frame: ẑ × w normalised, ŷ along the normal.
inline Vec3 stokes_s_axis(const Vec3& w) {
  const Float r2 = w.x * w.x + w.y * w.y;
  if (!(r2 > Float(1e-30))) return {0, 1, 0};
  const Float inv = 1 / std::sqrt(r2);
  return {-w.y * inv, w.x * inv, 0};
}

namespace polarization_detail {

// (cos 2α, sin 2α) of the turn α about d that takes axis a to axis b (both ⊥ d):
// b = cos α a + sin α (d × a). Normalised, so that the rotation is exact.
inline void frame_turn(const Vec3& d, const Vec3& a, const Vec3& b, Float& c2, Float& s2) {
  const Float c = dot(a, b), s = dot(b, cross(d, a));
  const Float n = c * c + s * s;
  if (!(n > 0)) {
    c2 = 1;
    s2 = 0;
    return;
  }
  c2 = (c * c - s * s) / n;
  s2 = 2 * s * c / n;
}

// M (in the facet's s/p basis for the pair) into the frames of wi and wo.
template <typename U>
void to_direction_frames(MuellerT<U>& m, const Vec3& wo, const Vec3& wi) {
  // The facet's s: perpendicular to the plane of wo and wi (which holds the facet normal);
  // for wi ∥ wo (normal incidence on the facet) any axis ⊥ wo, where the matrix does not
  // depend on it.
  const Vec3 n = cross(wi, wo);
  const Float l2 = length_squared(n);
  const Vec3 sh = l2 > Float(1e-30) ? n * (1 / std::sqrt(l2)) : stokes_s_axis(wo);
  Float c2a, s2a, c2b, s2b;
  frame_turn(-wi, stokes_s_axis(wi), sh, c2a, s2a);
  frame_turn(wo, sh, stokes_s_axis(wo), c2b, s2b);
  m.rotate_frames(c2a, s2a, c2b, s2b);
}

template <typename U>
U as_colour(const U& v) { return v; }
template <typename U>
U as_colour(Float v)
  requires(!std::is_same_v<U, Float>)
{ return U(v); }

// `m` scaled per channel so that M00 = value exactly; a channel whose shape has M00 = 0
// (a value the shape cannot carry), or one so small (subnormal, at a grazing facet) that
// value / M00 overflows, becomes a depolarizer of that value.
template <typename U>
void scale_to(MuellerT<U>& m, const U& value) {
  U scale = map(value, m.m00(), [](Float v, Float m00) {
    const Float s = m00 != 0 ? v / m00 : Float(0);
    return std::isfinite(s) ? s : Float(0);
  });
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) *= scale;
  m(0, 0) = value;
}

}  // namespace polarization_detail

// The Fresnel factor of the scattering wi → wo as the colour type C (top of the file).
// `shape` is called only in polarized mode and returns MuellerT<Unpolarized<C>>; wo and wi
// are the actual directions of the pair (not mirrored).
template <typename C, typename V, typename Shape>
[[gnu::always_inline]] inline C fresnel_factor(const V& value, Shape&& shape, const Vec3& wo, const Vec3& wi) {
  if constexpr (!kPolarized<C>) {
    return C(value);
  } else {
    using U = Unpolarized<C>;
    C m = shape();
    polarization_detail::scale_to(m, polarization_detail::as_colour<U>(value));
    polarization_detail::to_direction_frames(m, wo, wi);
    return m;
  }
}

// A depolarizing reflector seen through a polarizing coat (the plastic's base): the light
// entering at wi is weighed by the coat's transmission of its polarization, the base
// depolarizes it, and it leaves at wo partially polarized by the coat again:
// M = value (1, τo, 0, 0)ᵀ (1, τi, 0, 0), with
// τ = (T_s − T_p)/(T_s + T_p) of the coat at each direction, in the frame of that direction
// (whose plane of incidence is the coat's); `taus()`, called in polarized mode only, gives (τo, τi). Unpolarized C: C(value).
template <typename C, typename U, typename Tau>
[[gnu::always_inline]] inline C depolarized_through(const U& value, Tau&& taus) {
  if constexpr (!kPolarized<C>) {
    return C(value);
  } else {
    const auto [tau_o, tau_i] = taus();
    C m(value);
    m(0, 1) = value * tau_i;
    m(1, 0) = value * tau_o;
    m(1, 1) = value * (tau_o * tau_i);
    return m;
  }
}

// MuellerT<U> from a matrix of numbers, the same in every channel.
template <typename U>
MuellerT<U> broadcast(const MuellerT<Float>& m) {
  MuellerT<U> r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r(i, j) = U(m(i, j));
  return r;
}

}  // namespace gonio
