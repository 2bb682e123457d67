// The random walk's distance bound (walk_distance_grid.h) and the closest-point query under
// it (Accel::distance_to_surface, Accel::closest_point), against the closed-form distance
// to a cube and a sphere;
// and the walk's boundary with the bound against the same boundary without it (the bound
// may only spare rays, never change an answer).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gonio/render/accel.h"
#include "gonio/render/subsurface_walk.h"
#include "gonio/render/walk_distance_grid.h"
#include "gonio/rng.h"
#include "gonio/subsurface/random_walk.h"

namespace gonio::render {
namespace {

// The cube [−1, 1]³ as 12 outward-wound triangles, and a sphere of radius 0.5 at (3, 0, 0).
Scene cube_and_sphere() {
  Scene s;
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1 ? 1.f : -1.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.f : -1.f});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  m.material = 0;
  s.meshes.push_back(m);
  Sphere sp;
  sp.center = {3, 0, 0};
  sp.radius = 0.5f;
  sp.material = 0;
  s.spheres.push_back(sp);
  return s;
}

double cube_distance(const Vec3& p) {
  const double ax = std::abs(double(p.x)), ay = std::abs(double(p.y)), az = std::abs(double(p.z));
  if (ax <= 1 && ay <= 1 && az <= 1) return std::min({1 - ax, 1 - ay, 1 - az});
  const double dx = std::max(ax - 1, 0.0), dy = std::max(ay - 1, 0.0), dz = std::max(az - 1, 0.0);
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double exact_distance(const Vec3& p) {
  const double dx = double(p.x) - 3, dy = double(p.y), dz = double(p.z);
  return std::min(cube_distance(p), std::abs(std::sqrt(dx * dx + dy * dy + dz * dz) - 0.5));
}

Vec3 uniform_point(Pcg32& rng, const Vec3& lo, const Vec3& hi) {
  return {lo.x + (hi.x - lo.x) * rng.next_float(), lo.y + (hi.y - lo.y) * rng.next_float(),
          lo.z + (hi.z - lo.z) * rng.next_float()};
}

// The distance, and the nearest point itself (the random walk's next-event planes,
// path_tracer.cpp): on the surface (the cube's max-norm 1 or the sphere's radius) at the
// closed-form distance from p; for p inside the cube, the direction to it is the nearest
// face's outward normal.
TEST(WalkDistanceGrid, ClosestPointQueryIsTheClosedFormDistance) {
  const Scene scene = cube_and_sphere();
  const Accel accel(scene);
  Pcg32 rng(3, 5);
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p = uniform_point(rng, {-2, -2, -2}, {4.5f, 2, 2});
    const double expected = exact_distance(p);
    ASSERT_NEAR(double(accel.distance_to_surface(p, 100)), expected, 2e-6) << p.x << " " << p.y << " " << p.z;
    // A nearer cap is returned as it is.
    ASSERT_NEAR(double(accel.distance_to_surface(p, 0.05f)), std::min(expected, 0.05), 2e-6);

    Vec3 q{1e9f, 1e9f, 1e9f};
    const Float d = accel.closest_point(p, 100, q);
    ASSERT_NEAR(double(length(p - q)), expected, 2e-6) << p.x << " " << p.y << " " << p.z;
    const double on_cube = std::max({std::abs(double(q.x)), std::abs(double(q.y)), std::abs(double(q.z))});
    const double dx = double(q.x) - 3, on_sphere = std::sqrt(dx * dx + double(q.y) * q.y + double(q.z) * q.z);
    ASSERT_LT(std::min(std::abs(on_cube - 1), std::abs(on_sphere - 0.5)), 2e-6) << q.x << " " << q.y << " " << q.z;
    // Inside the cube, away from where two faces are equally near: the nearest face's normal.
    double a[3] = {std::abs(double(p.x)), std::abs(double(p.y)), std::abs(double(p.z))};
    const int axis = a[0] >= a[1] && a[0] >= a[2] ? 0 : a[1] >= a[2] ? 1 : 2;
    const double sign = (axis == 0 ? p.x : axis == 1 ? p.y : p.z) > 0 ? 1 : -1;
    std::sort(a, a + 3);
    if (a[2] < 0.99 && a[2] - a[1] > 0.01) {
      const Vec3 n = (q - p) / d;
      ASSERT_NEAR(double(axis == 0 ? n.x : axis == 1 ? n.y : n.z), sign, 1e-5) << p.x << " " << p.y << " " << p.z;
    }
  }
  // Nothing within the radius: the radius, and the point left as it was.
  Vec3 q{7, 8, 9};
  EXPECT_FLOAT_EQ(accel.closest_point({0, 0, 0}, 0.5f, q), 0.5f);
  EXPECT_EQ(q.x, 7);
}

TEST(WalkDistanceGrid, ClosestPointQueryOnATriangleFromEverySide) {
  // One triangle, points around it in every Voronoi region (its face, edges and corners),
  // against the nearest of 400² points spread over the triangle (within 3e-3).
  Scene scene;
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0.2f, 0}, {0.3f, 1, 0.1f}};
  m.indices = {0, 1, 2};
  m.material = 0;
  scene.meshes.push_back(m);
  const Accel accel(scene);
  std::vector<Vec3> samples;
  const int k = 400;
  for (int i = 0; i <= k; ++i)
    for (int j = 0; i + j <= k; ++j) {
      const Float a = Float(i) / k, b = Float(j) / k;
      samples.push_back(m.positions[0] * (1 - a - b) + m.positions[1] * a + m.positions[2] * b);
    }
  Pcg32 rng(5, 1);
  for (int n = 0; n < 200; ++n) {
    const Vec3 p = uniform_point(rng, {-1, -1, -0.5f}, {2, 2, 0.5f});
    double best = 1e30;
    for (const Vec3& q : samples) best = std::min(best, double(length(p - q)));
    ASSERT_NEAR(double(accel.distance_to_surface(p, 100)), best, 3e-3) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(WalkDistanceGrid, BoundIsBelowTheDistanceByLessThanAVoxelDiagonal) {
  const Scene scene = cube_and_sphere();
  const Accel accel(scene);
  const Float h = 0.1f;
  const WalkDistanceGrid grid(accel, {-1, -1, -1}, {1, 1, 1}, h);
  Pcg32 rng(11, 2);
  int useful = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p = uniform_point(rng, {-1, -1, -1}, {1, 1, 1});
    const double d = exact_distance(p), b = double(grid.lower_bound(p));
    ASSERT_LE(b, d) << p.x << " " << p.y << " " << p.z;
    // D(c) − |p − c| ≥ D(p) − 2|p − c|, and |p − c| is at most half the voxel's diagonal.
    ASSERT_GE(b, d - std::sqrt(3.0) * h - 1e-3) << p.x << " " << p.y << " " << p.z;
    useful += b > 0.2;
  }
  EXPECT_GT(useful, 20000 / 4);
  // Outside the box: nothing is known.
  EXPECT_EQ(grid.lower_bound({1.5f, 0, 0}), 0);
  EXPECT_EQ(grid.lower_bound({0, -1.01f, 0}), 0);
  EXPECT_EQ(grid.lower_bound({std::nanf(""), 0, 0}), 0);
}

TEST(WalkDistanceGrid, WalkStepsMeetTheBoundaryAsTheirRaysDo) {
  const Scene scene = cube_and_sphere();
  const Accel accel(scene);
  const WalkDistanceGrid grid(accel, {-1, -1, -1}, {1, 1, 1}, 0.08f);
  std::uint64_t rays_plain = 0, rays_grid = 0;
  const SceneBoundary plain(accel, rays_plain), bounded(accel, rays_grid, &grid);
  Pcg32 rng(7, 9);
  int crossings = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = uniform_point(rng, {-0.999f, -0.999f, -0.999f}, {0.999f, 0.999f, 0.999f});
    const Float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
    const Float r = std::sqrt(std::max(Float(0), 1 - z * z));
    const Vec3 d{r * std::cos(phi), r * std::sin(phi), z};
    const double t = -std::log1p(-double(rng.next_float())) * 0.1;  // a step of mean 0.1
    SceneBoundary::Hit a, b;
    const bool meets = gonio::boundary_within(plain, p, d, t, a);
    ASSERT_EQ(gonio::boundary_within(bounded, p, d, t, b), meets) << i;
    if (meets) {
      ++crossings;
      ASSERT_EQ(a.t, b.t);
    }
  }
  EXPECT_GT(crossings, n / 20);
  // Most steps of mean 0.1 in a cube of half-size 1 are answered without a ray.
  EXPECT_EQ(rays_plain, std::uint64_t(n));
  EXPECT_LT(rays_grid, rays_plain / 2);
}

}  // namespace
}  // namespace gonio::render
