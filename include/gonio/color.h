#pragma once
// The one colour type of gonio. In the default RGB mode it holds linear (r, g, b); a
// spectral mode will hold a handful of radiometric samples at a path's wavelengths by
// changing kColorChannels. Models use only the channel-wise operations below, so they
// do not change when the representation does.

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>

#include "gonio/math/constants.h"

namespace gonio {

#ifndef GONIO_COLOR_CHANNELS
#define GONIO_COLOR_CHANNELS 3
#endif
inline constexpr int kColorChannels = GONIO_COLOR_CHANNELS;

class Color {
 public:
  constexpr Color() : c_{} {}
  constexpr explicit Color(Float v) { c_.fill(v); }
  // Three channels (r, g, b). Only meaningful in RGB mode.
  template <int N = kColorChannels>
    requires(N == 3)
  constexpr Color(Float r, Float g, Float b) : c_{r, g, b} {}

  static constexpr int size() { return kColorChannels; }
  constexpr Float operator[](int i) const { return c_[static_cast<size_t>(i)]; }
  constexpr Float& operator[](int i) { return c_[static_cast<size_t>(i)]; }

  constexpr Color& operator+=(const Color& o) { for (int i = 0; i < size(); ++i) (*this)[i] += o[i]; return *this; }
  constexpr Color& operator-=(const Color& o) { for (int i = 0; i < size(); ++i) (*this)[i] -= o[i]; return *this; }
  constexpr Color& operator*=(const Color& o) { for (int i = 0; i < size(); ++i) (*this)[i] *= o[i]; return *this; }
  constexpr Color& operator/=(const Color& o) { for (int i = 0; i < size(); ++i) (*this)[i] /= o[i]; return *this; }
  constexpr Color& operator*=(Float s) { for (int i = 0; i < size(); ++i) (*this)[i] *= s; return *this; }
  constexpr Color& operator/=(Float s) { return *this *= (1 / s); }
  constexpr bool operator==(const Color&) const = default;

  constexpr bool is_black() const {
    for (int i = 0; i < size(); ++i) if ((*this)[i] != 0) return false;
    return true;
  }
  constexpr Float max_component() const {
    Float m = c_[0];
    for (int i = 1; i < size(); ++i) m = std::max(m, (*this)[i]);
    return m;
  }
  constexpr Float min_component() const {
    Float m = c_[0];
    for (int i = 1; i < size(); ++i) m = std::min(m, (*this)[i]);
    return m;
  }
  constexpr Float average() const {
    Float s = 0;
    for (int i = 0; i < size(); ++i) s += (*this)[i];
    return s / size();
  }
  bool is_finite() const {
    for (int i = 0; i < size(); ++i) if (!std::isfinite((*this)[i])) return false;
    return true;
  }

 private:
  std::array<Float, kColorChannels> c_;
};

constexpr Color operator+(Color a, const Color& b) { return a += b; }
constexpr Color operator-(Color a, const Color& b) { return a -= b; }
constexpr Color operator*(Color a, const Color& b) { return a *= b; }
constexpr Color operator/(Color a, const Color& b) { return a /= b; }
constexpr Color operator*(Color a, Float s) { return a *= s; }
constexpr Color operator*(Float s, Color a) { return a *= s; }
constexpr Color operator/(Color a, Float s) { return a /= s; }
constexpr Color operator-(Float s, const Color& a) { return Color(s) - a; }

// Applies a scalar function to every channel; how models build channel-wise formulas
// (e.g. conductor Fresnel) without knowing how many channels there are.
template <typename Fn>
constexpr Color map(const Color& a, Fn&& fn) {
  Color r;
  for (int i = 0; i < Color::size(); ++i) r[i] = fn(a[i]);
  return r;
}
template <typename Fn>
constexpr Color map(const Color& a, const Color& b, Fn&& fn) {
  Color r;
  for (int i = 0; i < Color::size(); ++i) r[i] = fn(a[i], b[i]);
  return r;
}

}  // namespace gonio
