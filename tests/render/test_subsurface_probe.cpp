// Probe-ray exit sampling (King et al. 2013) against the profile it samples: the weighted
// exits are an estimate of Sp over the surface, so their histogram must reproduce the
// annulus means of Sp on a flat slab (two faces: chords that cross twice) and the
// integral of Sp over a sphere (all three axes, curved surface). Expected values come
// from quadrature of DiffusionProfile::Sp in the test.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "gonio/render/accel.h"
#include "gonio/render/subsurface_probe.h"
#include "../unit/test_scale.h"

namespace gonio::render {
namespace {

constexpr double kPiT = 3.14159265358979323846;

Medium probe_medium() {
  Medium m;
  m.sigma_s = Color(1.0f, 2.0f, 4.0f);
  m.sigma_a = Color(0.5f, 0.1f, 0.01f);  // probe spheres of quite different radii
  m.g = 0;
  return m;
}

const DiffusionProfile& probe_profile() {
  static const DiffusionProfile p(probe_medium(), 1.3f, 256);
  return p;
}

Float min_rmax(const DiffusionProfile& p) { return std::min({p.r_max(0), p.r_max(1), p.r_max(2)}); }
Float max_rmax(const DiffusionProfile& p) { return std::max({p.r_max(0), p.r_max(1), p.r_max(2)}); }

// ∫ f(r) 2π r dr over [a, b] by the trapezoid rule in ln r.
double annulus_integral(const std::function<double(double)>& f, double a, double b, int n = 4000) {
  const double la = std::log(a), h = (std::log(b) - la) / n;
  double s = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = std::exp(la + i * h);
    s += (i == 0 || i == n ? 0.5 : 1.0) * 2 * kPiT * r * r * f(r);
  }
  return s * h;
}

// A square of half-size w at height z, its normal +z (up) or −z.
Mesh square(Float w, Float z, bool up) {
  Mesh m;
  m.positions = {{-w, -w, z}, {w, -w, z}, {w, w, z}, {-w, w, z}};
  m.indices = up ? std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3} : std::vector<std::uint32_t>{0, 2, 1, 0, 3, 2};
  m.material = 0;
  return m;
}

struct Tally {
  double sum = 0, sum2 = 0;
  void add(double w) { sum += w, sum2 += w * w; }
  // (estimate − want) / its standard error, over n samples.
  double z(double want, std::uint64_t n) const {
    const double mean = sum / double(n), var = std::max(sum2 / double(n) - mean * mean, 0.0);
    const double se = std::sqrt(var / double(n));
    return se > 0 ? (mean - want) / se : (mean == want ? 0 : 1e9);
  }
};

TEST(SubsurfaceProbe, FlatSlabExitsReproduceTheProfile) {
  const DiffusionProfile& p = probe_profile();
  const Float reach = max_rmax(p), near = min_rmax(p);
  Scene scene;
  scene.materials.resize(1);
  // Top face at z = 0 (the entry's surface), bottom face below it: normal chords cross both.
  // Deep enough that bottom points within one channel's disc radius lie beyond its sphere.
  const Float depth = 0.6f * near;
  scene.meshes = {square(3 * reach, 0, true), square(3 * reach, -depth, false)};
  const Accel accel(scene);
  SurfaceHit entry;
  entry.p = {0, 0, 0};
  entry.ng = entry.ns = {0, 0, 1};
  entry.material = 0;
  const Frame frame = Frame::from_normal(entry.ng);

  constexpr int kBins = 10;
  std::vector<double> edge(kBins + 1);
  for (int k = 0; k <= kBins; ++k) edge[static_cast<size_t>(k)] = 0.01 * near * std::pow(90.0, double(k) / kBins);
  std::vector<std::array<Tally, 3>> tally(kBins), bottom(kBins);
  std::vector<double> bottom_edge(kBins + 1);
  for (int k = 0; k <= kBins; ++k) bottom_edge[static_cast<size_t>(k)] = 0.01 * reach * std::pow(100.0, double(k) / kBins);
  const std::uint64_t n = gonio::test::scaled(300000, 30000);
  Pcg32 rng(11);
  std::uint64_t found = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto exit = sample_probe_exit(accel, entry, frame, p, rng);
    if (!exit) continue;
    ++found;
    ASSERT_TRUE(exit->weight.is_finite());
    const double r = std::hypot(exit->hit.p.x, exit->hit.p.y);
    if (std::abs(exit->hit.p.z) > 1e-4f * reach) {  // the bottom face
      const int k = static_cast<int>(std::upper_bound(bottom_edge.begin(), bottom_edge.end(), r) - bottom_edge.begin()) - 1;
      if (k >= 0 && k < kBins)
        for (int c = 0; c < 3; ++c) bottom[static_cast<size_t>(k)][static_cast<size_t>(c)].add(exit->weight[c]);
      continue;
    }
    const int k = static_cast<int>(std::upper_bound(edge.begin(), edge.end(), r) - edge.begin()) - 1;
    if (k < 0 || k >= kBins) continue;
    for (int c = 0; c < 3; ++c) tally[static_cast<size_t>(k)][static_cast<size_t>(c)].add(exit->weight[c]);
  }
  // Normal probes always find the plane; tangent ones (half of them) never do.
  EXPECT_NEAR(double(found) / double(n), 0.5, 0.01);
  double worst = 0;
  for (int k = 0; k < kBins; ++k)
    for (int c = 0; c < 3; ++c) {
      const double want = annulus_integral([&](double r) { return double(p.Sp(Float(r))[c]); },
                                           edge[static_cast<size_t>(k)], edge[static_cast<size_t>(k) + 1]);
      const double z = tally[static_cast<size_t>(k)][static_cast<size_t>(c)].z(want, n);
      worst = std::max(worst, std::abs(z));
      EXPECT_LT(std::abs(z), 5) << "bin " << k << " channel " << c;
    }
  // The bottom face: Sp at the distance √(ρ² + depth²), where some channel's sphere reaches.
  for (int k = 0; k < kBins; ++k)
    for (int c = 0; c < 3; ++c) {
      const double want = annulus_integral(
          [&](double rho) {
            const double dist = std::hypot(rho, double(depth));
            return dist <= reach ? double(p.Sp(Float(dist))[c]) : 0.0;
          },
          bottom_edge[static_cast<size_t>(k)], bottom_edge[static_cast<size_t>(k) + 1], 20000);
      const double z = bottom[static_cast<size_t>(k)][static_cast<size_t>(c)].z(want, n);
      worst = std::max(worst, std::abs(z));
      EXPECT_LT(std::abs(z), 5) << "bottom bin " << k << " channel " << c;
    }
  std::printf("worst |z| %.2f (r_max %g %g %g)\n", worst, p.r_max(0), p.r_max(1), p.r_max(2));
}

TEST(SubsurfaceProbe, SphereExitsIntegrateTheProfile) {
  const DiffusionProfile& p = probe_profile();
  // The sphere lies inside the largest probe sphere, so every point of it can be found,
  // but its far side lies beyond the smaller ones (their strategies cannot reach it).
  const Float radius = 0.45f * max_rmax(p);
  ASSERT_GT(2 * radius, min_rmax(p));
  Scene scene;
  scene.materials.resize(1);
  scene.spheres.push_back({{0, 0, -radius}, radius, 0, -1});
  const Accel accel(scene);
  SurfaceHit entry;
  entry.p = {0, 0, 0};
  entry.ng = entry.ns = {0, 0, 1};
  entry.material = 0;
  const Frame frame = Frame::from_normal_tangent(entry.ng, {1, 0.3f, 0});

  // Four zones of polar angle about the entry (at the pole): ∫ Sp(2R sin(θ/2)) 2π R² sin θ dθ.
  constexpr int kZones = 4;
  std::vector<std::array<Tally, 3>> tally(kZones);
  const std::uint64_t n = gonio::test::scaled(300000, 30000);
  Pcg32 rng(5);
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto exit = sample_probe_exit(accel, entry, frame, p, rng);
    if (!exit) continue;
    ASSERT_TRUE(exit->weight.is_finite());
    const double cos_t = std::clamp(double(exit->hit.p.z + radius) / radius, -1.0, 1.0);
    const int k = std::min(static_cast<int>(std::acos(cos_t) / kPiT * kZones), kZones - 1);
    for (int c = 0; c < 3; ++c) tally[static_cast<size_t>(k)][static_cast<size_t>(c)].add(exit->weight[c]);
  }
  for (int k = 0; k < kZones; ++k)
    for (int c = 0; c < 3; ++c) {
      // Midpoint rule in θ, fine enough for the Sp ~ 1/r near the pole (integrable in area).
      const int m = 20000;
      const double t0 = kPiT * k / kZones, h = kPiT / kZones / m;
      double want = 0;
      for (int j = 0; j < m; ++j) {
        const double th = t0 + (j + 0.5) * h;
        want += p.Sp(Float(2 * radius * std::sin(th / 2)))[c] * 2 * kPiT * radius * radius * std::sin(th) * h;
      }
      const double z = tally[static_cast<size_t>(k)][static_cast<size_t>(c)].z(want, n);
      EXPECT_LT(std::abs(z), 5) << "zone " << k << " channel " << c << " want " << want;
    }
}

TEST(SubsurfaceProbe, NoExitWithoutTheMaterial) {
  const DiffusionProfile& p = probe_profile();
  Scene scene;
  scene.materials.resize(2);
  Mesh other = square(10 * max_rmax(p), 0, true);
  other.material = 1;
  scene.meshes = {other};
  const Accel accel(scene);
  SurfaceHit entry;
  entry.ng = entry.ns = {0, 0, 1};
  entry.material = 0;
  Pcg32 rng(2);
  for (int i = 0; i < 1000; ++i) EXPECT_FALSE(sample_probe_exit(accel, entry, Frame::from_normal(entry.ng), p, rng));
}

TEST(SubsurfaceProbe, AllHitsQueryListsEveryCrossing) {
  Scene scene;
  scene.materials.resize(1);
  scene.meshes = {square(1, 0, true), square(1, -0.5f, false), square(1, -1, true)};
  scene.spheres.push_back({{0, 0, -3}, 0.5f, 0, -1});
  const Accel accel(scene);
  std::vector<Float> t;
  const int n = accel.for_each_hit(Ray{{0.1f, 0.2f, 1}, {0, 0, -1}, 10}, [&](const SurfaceHit& h) {
    t.push_back(h.t);
    return true;
  });
  ASSERT_EQ(n, 5);
  const std::vector<Float> want = {1, 1.5f, 2, 4 - std::sqrt(0.2f), 4 + std::sqrt(0.2f)};
  for (int i = 0; i < n; ++i) EXPECT_NEAR(t[static_cast<size_t>(i)], want[static_cast<size_t>(i)], 1e-5f) << i;
  // Through a shared edge of two triangles (the diagonal x = y of the square): one crossing.
  EXPECT_EQ(accel.for_each_hit(Ray{{0.25f, 0.25f, 0.5f}, {0, 0, -1}, 1.25f}, [](const SurfaceHit&) { return true; }), 2);
}

}  // namespace
}  // namespace gonio::render
