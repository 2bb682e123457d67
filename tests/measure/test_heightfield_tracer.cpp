// The height-field tracer (heightfield_tracer.h) against Embree, the reference: the same
// first facet for random, grazing, edge-aligned, vertex-aimed and many-times-wrapping rays
// over several fields; no ray slips between facets; the mipmap's bounds hold every height.
//
// Bugs put into heightfield_tracer.cpp that these tests caught (each reverted): a DDA step
// that skips a column going −x, or a +x border one cell short (every comparison with
// Embree, NoRaySlips, ReportsTheFacetItHit, PathsAreEmbrees); the upper levels' bounds, or
// a cell's own bound, without the (i+1, j+1) corner (the comparisons, NoRaySlips; the
// former also MipmapBoundsHoldTheirCells); the cell's far corners read without the wrap
// (all of the above); tile crossings not counted (FirstHitIsEmbreesOnRandomRays and
// AfterManyWraps); the two side cells at a node's corner not tested (NoRaySlips alone:
// rays aimed at vertices then slipped through, 10–40 of 4000 per field).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../unit/test_scale.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/measure/gaussian_surface.h"
#include "gonio/measure/heightfield_tracer.h"
#include "gonio/measure/microsurface.h"
#include "gonio/rng.h"
#include "surfaces_for_tests.h"

namespace gonio::measure {
namespace {

using Tracer = Microsurface::Tracer;

// Test fields, all with cell side h = 1 (size = n), so that Embree's float vertices are the
// exact grid positions and both tracers see the same facets.
struct Case {
  std::string name;
  HeightField field;
};

HeightField gaussian(int n, double alpha, std::uint64_t seed) {
  GaussianSurfaceParams p;
  p.resolution = n;
  p.alpha_x = p.alpha_y = alpha;
  p.size = n;
  p.seed = seed;
  if (n <= 32) p.correlation = 3.0 / n;
  return gaussian_height_field(p);
}

HeightField noise(int n, double amplitude, std::uint64_t seed) {  // independent heights: steep
  HeightField f;
  f.n = n;
  f.size = n;
  Pcg32 rng(seed);
  for (int k = 0; k < n * n; ++k) f.z.push_back(float(amplitude * (2 * rng.next_double() - 1)));
  return f;
}

std::vector<Case> cases() {
  return {
      {"gaussian 16, alpha 1", gaussian(16, 1.0, 3)},
      {"gaussian 64, alpha 0.3", gaussian(64, 0.3, 5)},
      {"gaussian 128, alpha 2 (steep)", gaussian(128, 2.0, 7)},
      {"noise 16, +-3", noise(16, 3.0, 11)},
      {"noise 24 (three levels)", noise(24, 0.7, 13)},
      {"eggcrate 13 (cells only)", testsurf::eggcrate_field(13, 2)},
      {"vgroove 16, 80 deg", testsurf::vgroove_field(16, std::tan(80 * kPiD / 180))},
  };
}

// The facet under a point of the plane, from heightfield.h's triangulation (h = 1): cell
// (i, j) and triangle 0 (fx + fy < 1) or 1, and how far the point is from the facet's
// border in cells (a point closer than float precision can belong to either facet).
struct Facet {
  int i, j, triangle;
  double border;
};
Facet facet_at(double x, double y, int n) {
  const double fi = std::floor(x), fj = std::floor(y), fx = x - fi, fy = y - fj;
  Facet f;
  f.i = ((int(fi) % n) + n) % n;
  f.j = ((int(fj) % n) + n) % n;
  f.triangle = fx + fy < 1 ? 0 : 1;
  f.border = std::min({fx, fy, 1 - fx, 1 - fy, std::abs(fx + fy - 1) / std::sqrt(2.0)});
  return f;
}

double modulo(double x, int n) {  // x in [0, n)
  const double m = x - n * std::floor(x / n);
  return m >= n ? 0 : m;
}

double wrapped_distance(double a, double b, double size) {
  const double d = std::abs(a - b);
  return std::min(d, size - d);
}

// One ray through both tracers. Both must meet a facet or both not; when they do, the same
// path length (relative 1e-4), the same end point and the same facet (cell and triangle,
// unless the point is within float precision of the facet's border) and normal.
struct Compare {
  const Microsurface& embree;
  const Microsurface& hf;
  int n;
  int mismatches = 0, hits = 0, rays = 0;
  int embree_nearer_at_border = 0, hf_nearer_at_border = 0;
  std::string first_failure = {};

  void ray(const double p_in[3], const Vec3& d, const char* kind, bool compare_wraps = true) {
    // Origins in float, as Embree takes them, so that both start at the same point.
    const double p[3] = {double(float(p_in[0])), double(float(p_in[1])), double(float(p_in[2]))};
    const Microsurface::Probe a = embree.probe(p, d), b = hf.probe(p, d);
    ++rays;
    std::string why;
    // Where the two disagree about whether or where a facet was met, the nearer answer may
    // lie on a facet's border (an edge or a vertex) within float precision: Embree, in
    // float and not watertight, may slip through an edge that the ray crosses (then the
    // height-field tracer is the nearer), or touch a peak or ridge that the ray passes by
    // in double precision (then Embree is). Those are counted apart.
    const bool differ = a.facet != b.facet || std::abs(a.distance - b.distance) > 1e-4 * std::max(a.distance, 1.0);
    if (a.lost == b.lost && differ) {
      const bool a_nearer = a.facet && (!b.facet || a.distance < b.distance);
      const Microsurface::Probe& near = a_nearer ? a : b;
      if (near.facet && facet_at(near.point[0], near.point[1], n).border < 1e-3) {
        ++(a_nearer ? embree_nearer_at_border : hf_nearer_at_border);
        return;
      }
    }
    if (a.facet != b.facet || a.lost != b.lost) {
      why = "embree facet " + std::to_string(a.facet) + " lost " + std::to_string(a.lost) + ", height field facet " +
            std::to_string(b.facet) + " lost " + std::to_string(b.lost);
    } else if (a.facet) {
      ++hits;
      const Facet fa = facet_at(a.point[0], a.point[1], n), fb = facet_at(b.point[0], b.point[1], n);
      const double tol = 1e-4 * std::max(a.distance, 1.0);
      const Vec3 na = normalize(a.ng.z < 0 ? -a.ng : a.ng), nb = normalize(b.ng);
      if (std::abs(a.distance - b.distance) > tol) {
        why = "distance " + std::to_string(a.distance) + " vs " + std::to_string(b.distance);
      } else if (wrapped_distance(a.point[0], b.point[0], n) > tol ||
                 wrapped_distance(a.point[1], b.point[1], n) > tol || std::abs(a.point[2] - b.point[2]) > tol) {
        why = "end point differs";
      } else if (fa.border > 1e-3 && (fa.i != fb.i || fa.j != fb.j || fa.triangle != fb.triangle)) {
        why = "facet (" + std::to_string(fa.i) + "," + std::to_string(fa.j) + "," + std::to_string(fa.triangle) +
              ") vs (" + std::to_string(fb.i) + "," + std::to_string(fb.j) + "," + std::to_string(fb.triangle) + ")";
      } else if (fa.border > 1e-3 && length(na - nb) > 1e-4) {
        why = "normal differs";
      }
    }
    if (why.empty() && compare_wraps && a.wraps != b.wraps)
      why = "wraps " + std::to_string(a.wraps) + " vs " + std::to_string(b.wraps);
    if (!why.empty()) {
      if (mismatches++ == 0)
        first_failure = std::string(kind) + ": " + why + " (origin " + std::to_string(p[0]) + " " +
                        std::to_string(p[1]) + " " + std::to_string(p[2]) + ", direction " + std::to_string(d.x) +
                        " " + std::to_string(d.y) + " " + std::to_string(d.z) + ")";
    }
  }
};

Vec3 uniform_direction(Pcg32& rng) {
  const double z = 2 * rng.next_double() - 1, phi = 2 * kPiD * rng.next_double(), s = std::sqrt(1 - z * z);
  return normalize(Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(z)});
}

TEST(HeightFieldTracer, FirstHitIsEmbreesOnRandomRays) {
  const BxDF mirror = parse_material(R"({"type":"mirror"})");
  const std::uint64_t per_kind = gonio::test::scaled(1500, 300);
  for (const Case& c : cases()) {
    const Microsurface embree(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::Embree);
    const Microsurface hf(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::HeightField);
    ASSERT_EQ(int(hf.tracer()), int(Tracer::HeightField));
    const double n = c.field.n, lo = hf.z_min(), hi = hf.z_max(), range = std::max(hi - lo, 1e-3);
    Compare cmp{embree, hf, c.field.n};
    Pcg32 rng(29, std::uint64_t(c.field.n));
    for (std::uint64_t k = 0; k < per_kind; ++k) {
      // Anywhere in the slab and a little around it, in any direction (from below too).
      const double p[3] = {rng.next_double() * n, rng.next_double() * n,
                           lo - 0.1 * range + 1.3 * range * rng.next_double()};
      cmp.ray(p, uniform_direction(rng), "random");
      // Grazing: within 3° of the horizon, so long paths over many cells.
      const double phi = 2 * kPiD * rng.next_double(), e = (rng.next_double() * 3 + 0.01) * kPiD / 180;
      const Vec3 g = normalize(Vec3{Float(std::cos(phi) * std::cos(e)), Float(std::sin(phi) * std::cos(e)),
                                    Float(rng.next_double() < 0.5 ? -std::sin(e) : std::sin(e))});
      cmp.ray(p, g, "grazing");
      // From above the highest point, downwards: the light's first segment.
      const double top[3] = {p[0], p[1], hi + 1e-3 * range};
      const Vec3 down = uniform_direction(rng);
      cmp.ray(top, Vec3{down.x, down.y, -std::abs(down.z)}, "from above");
    }
    EXPECT_EQ(cmp.mismatches, 0) << c.name << ": " << cmp.mismatches << " of " << cmp.rays
                                 << "; first: " << cmp.first_failure;
    EXPECT_GT(cmp.hits, cmp.rays / 3) << c.name;
  }
}

// Rays exactly along the grid's lines — in the plane of a column of cell borders (x = i),
// of a row (y = j), or of a row of diagonals (x + y = k) — and rays aimed at vertices, where
// three or six facets meet: the answers there depend on how the tracer settles ties.
TEST(HeightFieldTracer, FirstHitIsEmbreesAlongEdgesAndThroughVertices) {
  const BxDF mirror = parse_material(R"({"type":"mirror"})");
  const std::uint64_t per_kind = gonio::test::scaled(600, 200);
  for (const Case& c : cases()) {
    const Microsurface embree(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::Embree);
    const Microsurface hf(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::HeightField);
    const int n = c.field.n;
    const double lo = hf.z_min(), hi = hf.z_max(), range = std::max(hi - lo, 1e-3);
    Compare cmp{embree, hf, n};
    Pcg32 rng(31, std::uint64_t(n));
    for (std::uint64_t k = 0; k < per_kind; ++k) {
      const double z = lo + range * rng.next_double(), s = rng.next_double() * n;
      const double dz = (2 * rng.next_double() - 1) * 0.8;
      const double line = double((rng.next_u32() % std::uint32_t(n)));
      const Float side = rng.next_double() < 0.5 ? -1 : 1;
      const double along_x[3] = {s, line, z}, along_y[3] = {line, s, z};
      // Wraps are not compared: a ray along a border line crosses the tile at corners,
      // which Embree counts once and the height-field tracer twice.
      cmp.ray(along_x, normalize(Vec3{side, 0, Float(dz)}), "along a row of borders", false);
      cmp.ray(along_y, normalize(Vec3{0, side, Float(dz)}), "along a column of borders", false);
      const double diag[3] = {s, modulo(line - s, n), z};  // x + y = line (mod n)
      cmp.ray(diag, normalize(Vec3{side, -side, Float(dz)}), "along a row of diagonals", false);
      // At a vertex from above.
      const int vi = int((rng.next_u32() % std::uint32_t(n))), vj = int((rng.next_u32() % std::uint32_t(n)));
      const double vz = c.field.at(vi, vj);
      const Vec3 dir = uniform_direction(rng);
      const Vec3 down{dir.x, dir.y, -std::max(std::abs(dir.z), Float(0.05))};
      const double reach = (hi + 0.01 * range - vz) / -double(down.z);
      const double from[3] = {modulo(vi - double(down.x) * reach, n), modulo(vj - double(down.y) * reach, n),
                              hi + 0.01 * range};
      cmp.ray(from, down, "at a vertex", false);
    }
    EXPECT_EQ(cmp.mismatches, 0) << c.name << ": " << cmp.mismatches << " of " << cmp.rays
                                 << "; first: " << cmp.first_failure;
    std::printf("%s: %d rays, %d hits; at a border, Embree nearer %d, height field nearer %d\n", c.name.c_str(),
                cmp.rays, cmp.hits, cmp.embree_nearer_at_border, cmp.hf_nearer_at_border);
  }
}

// Nearly horizontal rays inside the slab wrap around the patch many times before they meet
// a facet (or give up after Microsurface::kMaxWraps): the crossings must be counted alike
// and the facet found the same.
TEST(HeightFieldTracer, FirstHitIsEmbreesAfterManyWraps) {
  const BxDF mirror = parse_material(R"({"type":"mirror"})");
  const std::uint64_t rays = gonio::test::scaled(150, 60);
  std::uint64_t wraps = 0, total = 0;
  for (const Case& c : cases()) {
    const Microsurface embree(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::Embree);
    const Microsurface hf(c.field, mirror, 1000, Microsurface::Mesh::Auto, Tracer::HeightField);
    const int n = c.field.n;
    const double lo = hf.z_min(), hi = hf.z_max(), range = std::max(hi - lo, 1e-3);
    Compare cmp{embree, hf, n};
    Pcg32 rng(37, std::uint64_t(n));
    for (std::uint64_t k = 0; k < rays; ++k) {
      // Just above the highest point or just below the lowest, descending (or rising) by a
      // fraction 1e-3 to 1e-5 of the slab per cell.
      const bool above = rng.next_double() < 0.5;
      const double p[3] = {rng.next_double() * n, rng.next_double() * n,
                           above ? hi - 1e-4 * range : lo + 1e-4 * range};
      const double phi = 2 * kPiD * rng.next_double(), slope = range * std::pow(10.0, -3 - 2 * rng.next_double());
      const Vec3 d = normalize(Vec3{Float(std::cos(phi)), Float(std::sin(phi)), Float(above ? -slope : slope)});
      cmp.ray(p, d, "many wraps");
      wraps += hf.probe(p, d).wraps;
      ++total;
    }
    EXPECT_EQ(cmp.mismatches, 0) << c.name << ": " << cmp.mismatches << " of " << cmp.rays
                                 << "; first: " << cmp.first_failure;
  }
  EXPECT_GT(double(wraps) / double(total), 10.0) << "the rays should wrap many times";
}

// Watertightness: a closed surface stops every ray that crosses it. Rays from above the
// highest point to below the lowest one aimed at vertices (where six facets meet) and at
// points of edges (where two do) must all meet a facet, on every field.
TEST(HeightFieldTracer, NoRaySlipsThroughAnEdgeOrVertex) {
  const std::uint64_t rays = gonio::test::scaled(4000, 1000);
  for (const Case& c : cases()) {
    const HeightFieldTracer tracer(c.field);
    const int n = c.field.n;
    float lo = c.field.z[0], hi = lo;
    for (const float z : c.field.z) lo = std::min(lo, z), hi = std::max(hi, z);
    Pcg32 rng(41, std::uint64_t(n));
    int slipped = 0;
    for (std::uint64_t k = 0; k < rays; ++k) {
      const int i = int((rng.next_u32() % std::uint32_t(n))), j = int((rng.next_u32() % std::uint32_t(n)));
      // The target: a vertex, a point of the bottom or left border, or of the diagonal.
      double tx = i, ty = j;
      const double f = rng.next_double();
      switch (k % 4) {
        case 1: tx += f; break;
        case 2: ty += f; break;
        case 3: tx += f, ty += 1 - f; break;
        default: break;
      }
      const double z00 = c.field.at(i, j), z10 = c.field.at(i + 1, j), z01 = c.field.at(i, j + 1);
      double tz = z00;
      if (k % 4 == 1) tz = z00 + f * (z10 - z00);
      if (k % 4 == 2) tz = z00 + f * (z01 - z00);
      if (k % 4 == 3) tz = z10 + (1 - f) * (z01 - z10);
      // In double, from 1 to 3 units above the highest point, any azimuth, up to 80° off
      // the vertical; the target lies exactly on the ray's line up to the rounding of o.
      const double theta = 80 * kPiD / 180 * rng.next_double(), phi = 2 * kPiD * rng.next_double();
      const double d[3] = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)};
      const double reach = (hi + 1 + 2 * rng.next_double() - tz) / std::cos(theta);
      const double o[3] = {tx - d[0] * reach, ty - d[1] * reach, tz - d[2] * reach};
      const double tmax = (o[2] - lo + 1) / std::cos(theta);
      const HeightFieldTracer::Hit hit = tracer.intersect(o, d, tmax, 1000000);
      if (!std::isfinite(hit.t)) ++slipped;
    }
    EXPECT_EQ(slipped, 0) << c.name << ": rays through edges and vertices that met no facet";
  }
}

// The tracer's own account of the facet (cell, triangle, normal) agrees with the point it
// returns, and its normal is the forward-difference normal of that triangle (heightfield.h).
TEST(HeightFieldTracer, ReportsTheFacetItHit) {
  const HeightField f = noise(16, 2.0, 43);
  const HeightFieldTracer tracer(f);
  Pcg32 rng(47);
  int checked = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 dir = uniform_direction(rng);
    const double d[3] = {dir.x, dir.y, -std::abs(double(dir.z)) - 0.05};
    const double o[3] = {rng.next_double() * 16, rng.next_double() * 16, 3};
    const HeightFieldTracer::Hit hit = tracer.intersect(o, d, 1e3, 100000);
    ASSERT_TRUE(std::isfinite(hit.t));
    const Facet at = facet_at(o[0] + d[0] * hit.t, o[1] + d[1] * hit.t, 16);
    if (at.border < 1e-9) continue;
    ++checked;
    EXPECT_EQ(at.i, hit.i);
    EXPECT_EQ(at.j, hit.j);
    EXPECT_EQ(at.triangle, hit.triangle);
    double sx, sy;
    if (at.triangle == 0) {
      sx = f.at(at.i + 1, at.j) - f.at(at.i, at.j), sy = f.at(at.i, at.j + 1) - f.at(at.i, at.j);
    } else {
      sx = f.at(at.i + 1, at.j + 1) - f.at(at.i, at.j + 1), sy = f.at(at.i + 1, at.j + 1) - f.at(at.i + 1, at.j);
    }
    const Vec3 expect = normalize(Vec3{Float(-sx), Float(-sy), 1}), got = normalize(hit.ng);
    EXPECT_LT(length(expect - got), 1e-5);
  }
  EXPECT_GT(checked, 1900);
}

// The maximum mipmap: each node's [min, max] holds every height of its footprint's cells
// (the corners (a·2^L … (a+1)·2^L, same in y), modulo n), and is tight to the 16-bit code
// grid. The levels stop where 2^L no longer divides n.
TEST(HeightFieldTracer, MipmapBoundsHoldTheirCells) {
  for (const Case& c : cases()) {
    const HeightFieldTracer tracer(c.field);
    const int n = c.field.n;
    int expect_levels = 1;
    while (n % (1 << expect_levels) == 0) ++expect_levels;
    EXPECT_EQ(tracer.levels(), expect_levels) << c.name;
    float lo = c.field.z[0], hi = lo;
    for (const float z : c.field.z) lo = std::min(lo, z), hi = std::max(hi, z);
    const double step = (double(hi) - lo) / 65535;
    for (int level = 0; level < tracer.levels(); ++level) {
      const int m = n >> level, s = 1 << level;
      for (int b = 0; b < m; ++b)
        for (int a = 0; a < m; ++a) {
          float mn = c.field.at(a * s, b * s), mx = mn;
          for (int y = b * s; y <= b * s + s; ++y)
            for (int x = a * s; x <= a * s + s; ++x)
              mn = std::min(mn, c.field.at(x, y)), mx = std::max(mx, c.field.at(x, y));
          const double slack = level == 0 ? 0 : 1.01 * step + 1e-6 * std::abs(mx);
          ASSERT_LE(tracer.node_min(level, a, b), mn) << c.name << " level " << level << " node " << a << "," << b;
          ASSERT_GE(tracer.node_max(level, a, b), mx) << c.name << " level " << level << " node " << a << "," << b;
          ASSERT_GE(tracer.node_min(level, a, b), mn - slack) << c.name << " level " << level;
          ASSERT_LE(tracer.node_max(level, a, b), mx + slack) << c.name << " level " << level;
        }
    }
  }
}

// Whole paths: on a white mirror surface (no random choices) rays scattered many times
// end alike with either tracer, ray for ray, but for the few whose path passes within float
// precision of an edge and then diverges.
TEST(HeightFieldTracer, PathsAreEmbreesOnAGaussianMirror) {
  const HeightField f = gaussian(64, 0.6, 53);
  const BxDF mirror = parse_material(R"({"type":"mirror","reflectance":1})");
  const Microsurface embree(f, mirror, 1000, Microsurface::Mesh::Auto, Tracer::Embree);
  const Microsurface hf(f, mirror);
  const std::uint64_t rays = gonio::test::scaled(4000, 1000);
  std::uint64_t same = 0, multiple = 0;
  for (const double theta : {0.0, 45.0, 80.0}) {
    const Vec3 d = -normalize(Vec3{Float(std::sin(theta * kPiD / 180)), 0.2f, Float(std::cos(theta * kPiD / 180))});
    Pcg32 pick(59, std::uint64_t(theta)), ra(1), rb(1);
    for (std::uint64_t k = 0; k < rays; ++k) {
      const double u = pick.next_double(), v = pick.next_double();
      const TraceResult a = embree.trace(u, v, d, ra), b = hf.trace(u, v, d, rb);
      multiple += a.bounces > 1;
      same += a.fate == b.fate && a.bounces == b.bounces && length(a.direction - b.direction) < 1e-3;
    }
  }
  EXPECT_GT(multiple, 3 * rays / 20) << "the surface should scatter multiply";
  EXPECT_GE(double(same), 0.995 * double(3 * rays));
}

TEST(HeightFieldTracer, BadFieldIsInputError) {
  HeightField f;
  f.n = 2;
  f.z = {0, 1, 2};
  EXPECT_THROW(HeightFieldTracer{f}, InputError);
  f.z = {0, 1, 2, std::nanf("")};
  EXPECT_THROW(HeightFieldTracer{f}, InputError);
}

}  // namespace
}  // namespace gonio::measure
