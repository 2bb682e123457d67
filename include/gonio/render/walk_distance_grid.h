#pragma once
// A lower bound of the distance from a point to the scene's nearest surface, over the box
// of the shapes that hold a random-walk medium (issue 38). A walk's step shorter than the
// bound at its start cannot meet a surface, so it needs no ray: deep inside a dense medium
// (marble: a mean free path of 0.4 mm in a 10 cm bunny) that is almost every step.
//
// The box is cut into voxels; the distance D(c) from each voxel's centre c is Embree's
// closest-point query (Accel::distance_to_surface), made the first time a walk asks for the
// voxel (a walk visits few of them) and kept. The distance to a set is 1-Lipschitz, so
// D(p) ≥ D(c) − |p − c| for every p of the voxel. The walks' answers are the rays' own: the
// grid only decides which steps need a ray (test: WalkDistanceGrid.*).

#include <atomic>
#include <cstddef>
#include <memory>

#include "gonio/math/vec3.h"
#include "gonio/render/accel.h"

namespace gonio::render {

class WalkDistanceGrid {
 public:
  // The box [lo, hi] in voxels of edge about `voxel` (at most kMaxVoxelsPerAxis per axis).
  WalkDistanceGrid(const Accel& accel, const Vec3& lo, const Vec3& hi, Float voxel);

  // A distance from p within which no surface lies (0 outside the box). Safe to call from
  // several threads: two threads filling the same voxel store the same value.
  Float lower_bound(const Vec3& p) const;

  static constexpr int kMaxVoxelsPerAxis = 128;

 private:
  const Accel& accel_;
  Vec3 lo_;
  Float h_ = 1, inv_h_ = 1;
  int n_[3] = {1, 1, 1};
  // Query radius: a voxel's D is kept up to this (farther surfaces do not matter to a step
  // of a few mean free paths, and a smaller radius makes the query cheaper).
  Float cap_ = 1;
  // Float rounding of the query, the points and the ray's own test, taken off every bound.
  Float margin_ = 0;
  std::unique_ptr<std::atomic<float>[]> distance_;  // per voxel, < 0 until computed
};

}  // namespace gonio::render
