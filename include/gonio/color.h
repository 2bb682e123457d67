#pragma once
// The one colour type of gonio, generic in how many channels it carries (after OSL's
// BSDL, one colour type for RGB and spectra): Color holds linear (r, g, b) in the default
// RGB mode; SampledSpectrum holds the radiometric values at the 4 wavelengths of one path
// in spectral mode (spectrum/wavelengths.h). Models are templates on the colour type and
// use only the channel-wise operations below, so each model is one piece of code for
// both modes.

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "gonio/math/constants.h"

namespace gonio {

template <int N>
class BasicColor {
  static_assert(N >= 1);

 public:
  constexpr BasicColor() : c_{} {}
  constexpr explicit BasicColor(Float v) { c_.fill(v); }
  // One value per channel: (r, g, b) for Color, the 4 wavelengths' for SampledSpectrum.
  template <typename... T>
    requires(N > 1 && sizeof...(T) == N && (std::is_arithmetic_v<T> && ...))
  constexpr BasicColor(T... v) : c_{static_cast<Float>(v)...} {}

  static constexpr int size() { return N; }
  constexpr Float operator[](int i) const { return c_[static_cast<size_t>(i)]; }
  constexpr Float& operator[](int i) { return c_[static_cast<size_t>(i)]; }

  constexpr BasicColor& operator+=(const BasicColor& o) { for (int i = 0; i < N; ++i) (*this)[i] += o[i]; return *this; }
  constexpr BasicColor& operator-=(const BasicColor& o) { for (int i = 0; i < N; ++i) (*this)[i] -= o[i]; return *this; }
  constexpr BasicColor& operator*=(const BasicColor& o) { for (int i = 0; i < N; ++i) (*this)[i] *= o[i]; return *this; }
  // Division where the divisor is 0 gives 0: a channel with no density (a wavelength
  // dropped by dispersion, pdf 0) carries no estimate, and no Inf or NaN is made.
  constexpr BasicColor& operator/=(const BasicColor& o) {
    for (int i = 0; i < N; ++i) (*this)[i] = o[i] != 0 ? (*this)[i] / o[i] : Float(0);
    return *this;
  }
  constexpr BasicColor& operator*=(Float s) { for (int i = 0; i < N; ++i) (*this)[i] *= s; return *this; }
  constexpr BasicColor& operator/=(Float s) { return *this *= (1 / s); }
  constexpr bool operator==(const BasicColor&) const = default;

  constexpr bool is_black() const {
    for (int i = 0; i < N; ++i) if ((*this)[i] != 0) return false;
    return true;
  }
  constexpr Float max_component() const {
    Float m = c_[0];
    for (int i = 1; i < N; ++i) m = std::max(m, (*this)[i]);
    return m;
  }
  constexpr Float min_component() const {
    Float m = c_[0];
    for (int i = 1; i < N; ++i) m = std::min(m, (*this)[i]);
    return m;
  }
  constexpr Float average() const {
    Float s = 0;
    for (int i = 0; i < N; ++i) s += (*this)[i];
    return s / N;
  }
  bool is_finite() const {
    for (int i = 0; i < N; ++i) if (!std::isfinite((*this)[i])) return false;
    return true;
  }

 private:
  std::array<Float, N> c_;
};

template <int N> constexpr BasicColor<N> operator+(BasicColor<N> a, const BasicColor<N>& b) { return a += b; }
template <int N> constexpr BasicColor<N> operator-(BasicColor<N> a, const BasicColor<N>& b) { return a -= b; }
template <int N> constexpr BasicColor<N> operator*(BasicColor<N> a, const BasicColor<N>& b) { return a *= b; }
template <int N> constexpr BasicColor<N> operator/(BasicColor<N> a, const BasicColor<N>& b) { return a /= b; }
template <int N> constexpr BasicColor<N> operator*(BasicColor<N> a, Float s) { return a *= s; }
template <int N> constexpr BasicColor<N> operator*(Float s, BasicColor<N> a) { return a *= s; }
template <int N> constexpr BasicColor<N> operator/(BasicColor<N> a, Float s) { return a /= s; }
template <int N> constexpr BasicColor<N> operator-(Float s, const BasicColor<N>& a) { return BasicColor<N>(s) - a; }

// Applies a scalar function to every channel; how models build channel-wise formulas
// (e.g. conductor Fresnel) without knowing how many channels there are.
template <int N, typename Fn>
constexpr BasicColor<N> map(const BasicColor<N>& a, Fn&& fn) {
  BasicColor<N> r;
  for (int i = 0; i < N; ++i) r[i] = fn(a[i]);
  return r;
}
template <int N, typename Fn>
constexpr BasicColor<N> map(const BasicColor<N>& a, const BasicColor<N>& b, Fn&& fn) {
  BasicColor<N> r;
  for (int i = 0; i < N; ++i) r[i] = fn(a[i], b[i]);
  return r;
}

// RGB mode's colour: linear (r, g, b).
using Color = BasicColor<3>;
inline constexpr int kColorChannels = Color::size();

// Wavelengths carried by one path in spectral mode: a hero and three rotations (Wilkie et
// al. 2014), and their values.
inline constexpr int kSpectrumSamples = 4;
using SampledSpectrum = BasicColor<kSpectrumSamples>;

// The visible range sampled and integrated over, in nm (SPEC §1).
inline constexpr Float kLambdaMin = 360, kLambdaMax = 830;

}  // namespace gonio
