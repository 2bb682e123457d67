#pragma once
// SampledSpectrum: the values of a spectral quantity at the kSpectrumSamples wavelengths
// of one path (SampledWavelengths), with the channel-wise arithmetic of gonio::Color.
// A later templating of the models on the colour type uses it as the spectral colour.

#include <algorithm>
#include <array>
#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

// Wavelengths carried by one path: a hero and three rotations (Wilkie et al. 2014).
inline constexpr int kSpectrumSamples = 4;
// The visible range sampled and integrated over, in nm (SPEC §1).
inline constexpr Float kLambdaMin = 360, kLambdaMax = 830;

class SampledSpectrum {
 public:
  constexpr SampledSpectrum() : v_{} {}
  constexpr explicit SampledSpectrum(Float c) : v_{c, c, c, c} {}
  constexpr SampledSpectrum(Float a, Float b, Float c, Float d) : v_{a, b, c, d} {}

  static constexpr int size() { return kSpectrumSamples; }
  constexpr Float operator[](int i) const { return v_[static_cast<size_t>(i)]; }
  constexpr Float& operator[](int i) { return v_[static_cast<size_t>(i)]; }

  constexpr SampledSpectrum& operator+=(const SampledSpectrum& o) { for (int i = 0; i < size(); ++i) (*this)[i] += o[i]; return *this; }
  constexpr SampledSpectrum& operator-=(const SampledSpectrum& o) { for (int i = 0; i < size(); ++i) (*this)[i] -= o[i]; return *this; }
  constexpr SampledSpectrum& operator*=(const SampledSpectrum& o) { for (int i = 0; i < size(); ++i) (*this)[i] *= o[i]; return *this; }
  // Division where the divisor is 0 gives 0 (a dropped wavelength has pdf 0 and value 0).
  constexpr SampledSpectrum& operator/=(const SampledSpectrum& o) {
    for (int i = 0; i < size(); ++i) (*this)[i] = o[i] != 0 ? (*this)[i] / o[i] : Float(0);
    return *this;
  }
  constexpr SampledSpectrum& operator*=(Float s) { for (int i = 0; i < size(); ++i) (*this)[i] *= s; return *this; }
  constexpr SampledSpectrum& operator/=(Float s) { return *this *= (1 / s); }
  constexpr bool operator==(const SampledSpectrum&) const = default;

  constexpr bool is_black() const {
    for (int i = 0; i < size(); ++i) if ((*this)[i] != 0) return false;
    return true;
  }
  constexpr Float max_component() const { return std::max(std::max(v_[0], v_[1]), std::max(v_[2], v_[3])); }
  constexpr Float min_component() const { return std::min(std::min(v_[0], v_[1]), std::min(v_[2], v_[3])); }
  constexpr Float average() const { return (v_[0] + v_[1] + v_[2] + v_[3]) / size(); }
  bool is_finite() const {
    for (int i = 0; i < size(); ++i) if (!std::isfinite((*this)[i])) return false;
    return true;
  }

 private:
  std::array<Float, kSpectrumSamples> v_;
};

constexpr SampledSpectrum operator+(SampledSpectrum a, const SampledSpectrum& b) { return a += b; }
constexpr SampledSpectrum operator-(SampledSpectrum a, const SampledSpectrum& b) { return a -= b; }
constexpr SampledSpectrum operator*(SampledSpectrum a, const SampledSpectrum& b) { return a *= b; }
constexpr SampledSpectrum operator/(SampledSpectrum a, const SampledSpectrum& b) { return a /= b; }
constexpr SampledSpectrum operator*(SampledSpectrum a, Float s) { return a *= s; }
constexpr SampledSpectrum operator*(Float s, SampledSpectrum a) { return a *= s; }
constexpr SampledSpectrum operator/(SampledSpectrum a, Float s) { return a /= s; }
constexpr SampledSpectrum operator-(Float s, const SampledSpectrum& a) { return SampledSpectrum(s) - a; }

template <typename Fn>
constexpr SampledSpectrum map(const SampledSpectrum& a, Fn&& fn) {
  SampledSpectrum r;
  for (int i = 0; i < SampledSpectrum::size(); ++i) r[i] = fn(a[i]);
  return r;
}
template <typename Fn>
constexpr SampledSpectrum map(const SampledSpectrum& a, const SampledSpectrum& b, Fn&& fn) {
  SampledSpectrum r;
  for (int i = 0; i < SampledSpectrum::size(); ++i) r[i] = fn(a[i], b[i]);
  return r;
}

}  // namespace gonio
