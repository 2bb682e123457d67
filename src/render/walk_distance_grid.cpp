// The random walk's distance bound (walk_distance_grid.h).

#include "gonio/render/walk_distance_grid.h"

#include <algorithm>
#include <cmath>

namespace gonio::render {

WalkDistanceGrid::WalkDistanceGrid(const Accel& accel, const Vec3& lo, const Vec3& hi, Float voxel) : accel_(accel), lo_(lo) {
  const Vec3 extent = hi - lo;
  const Float longest = std::max({extent.x, extent.y, extent.z, Float(0)});
  h_ = std::max(voxel, longest / Float(kMaxVoxelsPerAxis));
  if (!(h_ > 0) || !std::isfinite(h_)) h_ = 1;
  inv_h_ = 1 / h_;
  const Float e[3] = {extent.x, extent.y, extent.z};
  std::size_t count = 1;
  for (int a = 0; a < 3; ++a) {
    n_[a] = std::clamp(int(std::ceil(std::max(e[a], Float(0)) * inv_h_)), 1, kMaxVoxelsPerAxis);
    count *= std::size_t(n_[a]);
  }
  cap_ = 16 * h_;
  const Float scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y),
                                std::abs(hi.z), Float(1)});
  margin_ = Float(1e-5) * scale;
  distance_ = std::make_unique<std::atomic<float>[]>(count);
  for (std::size_t i = 0; i < count; ++i) distance_[i].store(-1, std::memory_order_relaxed);
}

Float WalkDistanceGrid::lower_bound(const Vec3& p) const {
  const Vec3 q = (p - lo_) * inv_h_;
  if (!(q.x >= 0 && q.y >= 0 && q.z >= 0)) return 0;  // also NaN
  const int ix = int(q.x), iy = int(q.y), iz = int(q.z);
  if (ix >= n_[0] || iy >= n_[1] || iz >= n_[2]) return 0;
  std::atomic<float>& slot = distance_[(std::size_t(iz) * std::size_t(n_[1]) + std::size_t(iy)) * std::size_t(n_[0]) + std::size_t(ix)];
  const Vec3 c = lo_ + Vec3{Float(ix) + Float(0.5), Float(iy) + Float(0.5), Float(iz) + Float(0.5)} * h_;
  float d = slot.load(std::memory_order_relaxed);
  if (d < 0) {
    d = float(accel_.distance_to_surface(c, cap_));
    slot.store(d, std::memory_order_relaxed);
  }
  // Relative rounding of the query's own distance, then the absolute margin.
  return d * Float(1 - 1e-4) - length(p - c) - margin_;
}

}  // namespace gonio::render
