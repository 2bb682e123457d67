#pragma once
// Snell's law through the plane a subsurface walk's next-event estimate proposes through
// (path_tracer.cpp, "Next-event estimation from inside a medium"): the map from a
// direction d inside the medium to the direction ω it leaves in, its inverse, and the
// Jacobian |dω/dd| that turns the light's solid-angle density of ω into the proposal's
// density of d. From the solid-angle form of Snell's law,
//   n_in² cos θ_in dω_in = n_out² cos θ_out dω_out  (Veach 1997, §5.2),
// with η = n_in/n_out: |dω/dd| = η² cos θ_d / cos θ_ω. Here, in a header, so that the
// tests can hold it to a finite-difference Jacobian of the map they compute themselves.

#include <algorithm>
#include <cmath>

#include "gonio/math/vec3.h"

namespace gonio::render {

// d inside (index eta relative to outside) to ω outside through a plane of unit normal n
// (pointing out of the medium), and |dω/dd|; false where d does not leave (it heads in,
// or total internal reflection).
inline bool walk_plane_out(const Vec3& d, const Vec3& n, Float eta, Vec3& omega, Float& jacobian) {
  const Float cos_d = dot(d, n);
  if (!(cos_d > 0)) return false;
  const Float sin2_o = eta * eta * std::max(Float(0), 1 - cos_d * cos_d);
  if (!(sin2_o < 1)) return false;
  const Float cos_o = std::sqrt(1 - sin2_o);
  if (!(cos_o > 0)) return false;
  omega = normalize((d - n * cos_d) * eta + n * cos_o);
  jacobian = eta * eta * cos_d / cos_o;
  return true;
}

// The inverse: the d inside that leaves as ω; false where none does.
inline bool walk_plane_in(const Vec3& omega, const Vec3& n, Float eta, Vec3& d) {
  const Float cos_o = dot(omega, n);
  if (!(cos_o > 0)) return false;
  const Float sin2_d = std::max(Float(0), 1 - cos_o * cos_o) / (eta * eta);
  if (!(sin2_d < 1)) return false;
  d = normalize((omega - n * cos_o) / eta + n * std::sqrt(1 - sin2_d));
  return true;
}

}  // namespace gonio::render
