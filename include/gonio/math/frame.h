#pragma once
// The local shading frame (S, T, N) of a surface point: the lecture's DifferentialGeometry
// frame (lecture §3.2). Directions in the local frame have z along N, x along S (the
// direction of anisotropy) and y along T = N × S (SPEC §1).

#include <cmath>

#include "gonio/math/vec3.h"

namespace gonio {

struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  // Any orthonormal frame around a unit normal. Branchless construction of
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), listing 3.
  static Frame from_normal(const Vec3& n) {
    const Float sign = std::copysign(Float(1), n.z);
    const Float a = -1 / (sign + n.z);
    const Float b = n.x * n.y * a;
    Frame f;
    f.n = n;
    f.s = {1 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    return f;
  }

  // Frame whose S follows a tangent (e.g. a brushing direction or dP/du), projected into
  // the tangent plane by Gram–Schmidt. A tangent parallel to N, or zero, falls back to
  // from_normal. Inputs need not be unit length; a zero normal gives the canonical frame.
  static Frame from_normal_tangent(Vec3 n, const Vec3& tangent) {
    n = normalize(n);
    if (length_squared(n) == 0) return Frame{};
    const Vec3 s = tangent - n * dot(n, tangent);
    const Float l2 = length_squared(s);
    if (!(l2 > Float(1e-12) * length_squared(tangent)) || !(l2 > 0)) return from_normal(n);
    Frame f;
    f.n = n;
    f.s = s * (1 / std::sqrt(l2));
    f.t = cross(f.n, f.s);
    return f;
  }

  Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace gonio
