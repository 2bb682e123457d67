#pragma once
// Stokes vectors and Mueller matrices (issue 15). The conventions, in one place (derived
// in docs/polarization.md):
//   * A beam travelling along d carries a reference frame (s, p) with s ⊥ d and p = d × s,
//     so that (s, p, d) is right-handed. Its Jones vector is (E_s, E_p), time dependence
//     e^{−iωt} (Born & Wolf, Principles of Optics, §1.4.2).
//   * Stokes vector S = (I, Q, U, V): I = |E_s|² + |E_p|², Q = |E_s|² − |E_p|² (SPEC §1),
//     U = 2 Re(E_s E_p*) (U > 0: linear at +45°, from s towards p), V = 2 Im(E_s E_p*)
//     (V > 0: right-handed in Born & Wolf's sense, the field turning clockwise to an
//     observer who looks towards the source; Born & Wolf §1.4.2 eq. 43 with δ = δ_p − δ_s).
//   * At an interface s is perpendicular to the plane of incidence (fresnel_amplitudes.h).
//   * Turning a frame by α about d (s' = cos α s + sin α p) changes the Stokes vector by
//     rotation(α): Q' = cos 2α Q + sin 2α U, U' = −sin 2α Q + cos 2α U.
// A Mueller matrix M maps the Stokes vector of the incident beam to that of the outgoing
// one: S_out = M S_in. MuellerT<C> holds one per colour channel: 16 entries, each a colour
// C (or a number), row-major; it is the colour type of a model instantiated for polarized
// mode (polarization/fresnel_factor.h), and M00 is the unpolarized quantity.

#include <array>
#include <cmath>
#include <complex>
#include <type_traits>

#include "gonio/color.h"

namespace gonio {

template <typename C>
class MuellerT {
 public:
  using entry_type = C;
  constexpr MuellerT() : m_{} {}
  // An ideal depolarizer scaled by v: v · diag(1, 0, 0, 0). How an unpolarized value (a
  // model's depolarizing part) is carried in polarized mode.
  constexpr explicit MuellerT(const C& v) : m_{} { m_[0] = v; }
  constexpr explicit MuellerT(Float v)
    requires(!std::is_same_v<C, Float>)
      : m_{} {
    m_[0] = C(v);
  }

  constexpr C& operator()(int r, int c) { return m_[size_t(4 * r + c)]; }
  constexpr const C& operator()(int r, int c) const { return m_[size_t(4 * r + c)]; }

  constexpr MuellerT& operator+=(const MuellerT& o) {
    for (size_t i = 0; i < 16; ++i) m_[i] += o.m_[i];
    return *this;
  }
  // Adding an unpolarized value: a depolarizing contribution.
  constexpr MuellerT& operator+=(const C& v) {
    m_[0] += v;
    return *this;
  }
  constexpr MuellerT& operator*=(Float s) {
    for (auto& e : m_) e *= s;
    return *this;
  }
  friend constexpr MuellerT operator*(MuellerT a, Float s) { return a *= s; }
  friend constexpr MuellerT operator*(Float s, MuellerT a) { return a *= s; }
  friend constexpr MuellerT operator+(MuellerT a, const MuellerT& b) { return a += b; }
  friend constexpr MuellerT operator*(const MuellerT& a, const MuellerT& b) {
    MuellerT r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        C s = a(i, 0) * b(0, j);
        for (int k = 1; k < 4; ++k) s += a(i, k) * b(k, j);
        r(i, j) = s;
      }
    return r;
  }
  // M ← M N: what a path's throughput does at a vertex (the camera's side on the left,
  // the new interaction on the right).
  constexpr MuellerT& operator*=(const MuellerT& n) { return *this = *this * n; }
  constexpr MuellerT& operator/=(Float s) {
    for (auto& e : m_) e /= s;
    return *this;
  }
  // Each channel's matrix scaled by that channel of a colour (a light's emission, a
  // medium's transmittance): the colour acts as a depolarization-free attenuator.
  friend constexpr MuellerT operator*(MuellerT a, const C& v)
    requires(!std::is_same_v<C, Float>)
  {
    for (auto& e : a.m_) e *= v;
    return a;
  }
  constexpr bool operator==(const MuellerT&) const = default;
  // Black when the unpolarized quantity is: a realizable matrix has |Mij| ≤ M00.
  constexpr bool is_black() const {
    if constexpr (std::is_same_v<C, Float>) return m_[0] == 0;
    else return m_[0].is_black();
  }
  constexpr bool is_finite() const {
    for (const auto& e : m_) {
      if constexpr (std::is_same_v<C, Float>) {
        if (!std::isfinite(e)) return false;
      } else if (!e.is_finite()) {
        return false;
      }
    }
    return true;
  }
  // The unpolarized quantity.
  constexpr const C& m00() const { return m_[0]; }

  // S_out = M S_in for a C-valued Stokes vector.
  constexpr std::array<C, 4> apply(const std::array<C, 4>& s) const {
    std::array<C, 4> r;
    for (int i = 0; i < 4; ++i) {
      C v = (*this)(i, 0) * s[0];
      for (int k = 1; k < 4; ++k) v += (*this)(i, k) * s[size_t(k)];
      r[size_t(i)] = v;
    }
    return r;
  }

  // M ← M R(a): the frame of the incident beam turned by a (given as cos 2a, sin 2a);
  // columns 1 and 2 change.
  constexpr void rotate_incident(Float c2a, Float s2a) {
    for (int r = 0; r < 4; ++r) {
      const C m1 = (*this)(r, 1), m2 = (*this)(r, 2);
      (*this)(r, 1) = m1 * c2a - m2 * s2a;
      (*this)(r, 2) = m1 * s2a + m2 * c2a;
    }
  }

  // M ← R(b) M R(a): the frame of the incident beam turned by a (angle a given as cos 2a,
  // sin 2a), the outgoing one by b. Row 0 and column 0 are untouched (rotations leave I
  // alone), so M00 stays bit for bit what it was.
  constexpr void rotate_frames(Float c2a, Float s2a, Float c2b, Float s2b) {
    rotate_incident(c2a, s2a);
    for (int c = 0; c < 4; ++c) {  // R(b) M: rows 1, 2
      const C m1 = (*this)(1, c), m2 = (*this)(2, c);
      (*this)(1, c) = m1 * c2b + m2 * s2b;
      (*this)(2, c) = m2 * c2b - m1 * s2b;
    }
  }

 private:
  std::array<C, 16> m_;
};

using Mueller = MuellerT<double>;

// What a model's colour type C carries: Unpolarized<C> is the colour of its parameters,
// kPolarized<C> whether its values are Mueller matrices.
template <typename C>
struct PolarizationTraits {
  using unpolarized = C;
  static constexpr bool polarized = false;
};
template <typename C>
struct PolarizationTraits<MuellerT<C>> {
  using unpolarized = C;
  static constexpr bool polarized = true;
};
template <typename C>
using Unpolarized = typename PolarizationTraits<C>::unpolarized;
template <typename C>
inline constexpr bool kPolarized = PolarizationTraits<C>::polarized;

// --- Elementary Mueller matrices (numbers) --------------------------------------------

// Rotation of the reference frame by alpha (radians) about the direction of propagation.
template <typename T>
MuellerT<T> mueller_rotation(T alpha) {
  const T c = std::cos(2 * alpha), s = std::sin(2 * alpha);
  MuellerT<T> m;
  m(0, 0) = m(3, 3) = 1;
  m(1, 1) = m(2, 2) = c;
  m(1, 2) = s;
  m(2, 1) = -s;
  return m;
}

// The Mueller matrix of the Jones matrix diag(a, b) in the s/p basis: for Jones vector
// (a E_s, b E_p), with z = a b*,
//   [[A, B, 0, 0], [B, A, 0, 0], [0, 0, Re z, −Im z], [0, 0, Im z, Re z]],
//   A = (|a|² + |b|²)/2, B = (|a|² − |b|²)/2.
template <typename T>
MuellerT<T> mueller_diagonal_jones(std::complex<T> a, std::complex<T> b) {
  const T na = std::norm(a), nb = std::norm(b);
  const std::complex<T> z = a * std::conj(b);
  MuellerT<T> m;
  m(0, 0) = m(1, 1) = (na + nb) / 2;
  m(0, 1) = m(1, 0) = (na - nb) / 2;
  m(2, 2) = m(3, 3) = z.real();
  m(2, 3) = -z.imag();
  m(3, 2) = z.imag();
  return m;
}

// Ideal linear polarizer whose transmission axis makes angle theta (radians) with s,
// towards p: the frame turned to the axis, diag-projector ½[[1,1],[1,1]] ⊕ 0, turned back.
template <typename T>
MuellerT<T> mueller_linear_polarizer(T theta) {
  const T c = std::cos(2 * theta), s = std::sin(2 * theta);
  MuellerT<T> m;
  m(0, 0) = T(0.5);
  m(0, 1) = m(1, 0) = c / 2;
  m(0, 2) = m(2, 0) = s / 2;
  m(1, 1) = c * c / 2;
  m(2, 2) = s * s / 2;
  m(1, 2) = m(2, 1) = c * s / 2;
  return m;
}

// Linear retarder: fast axis at theta (radians, from s towards p), the slow component
// delayed by delta (Jones diag(1, e^{iδ}) in the (fast, slow) frame, e^{−iωt}):
// R(−θ) M0 R(θ) with M0 = mueller_diagonal_jones(1, e^{iδ}).
template <typename T>
MuellerT<T> mueller_retarder(T theta, T delta) {
  const MuellerT<T> m0 = mueller_diagonal_jones(std::complex<T>(1), std::polar(T(1), delta));
  return mueller_rotation(-theta) * m0 * mueller_rotation(theta);
}

}  // namespace gonio
