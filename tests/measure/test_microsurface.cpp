// The microsurface tracer: triangulation, periodic wrapping and energy conservation.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "../unit/test_scale.h"
#include "gonio/material.h"
#include "gonio/measure/instrument.h"
#include "gonio/measure/microsurface.h"
#include "gonio/rng.h"
#include "surfaces_for_tests.h"

namespace gonio::measure {
namespace {

// Embree's quads and grid, and the height-field tracer, must all split each cell along the
// (i+1, j)–(i, j+1) diagonal (heightfield.h): the normal under every point is the
// forward-difference normal of its triangle, computed here from the heights alone.
class MicrosurfaceMesh : public ::testing::TestWithParam<std::pair<Microsurface::Mesh, Microsurface::Tracer>> {};

TEST_P(MicrosurfaceMesh, FacetNormalsAreTheForwardDifferencesOfTheField) {
  HeightField f;
  f.n = 8;
  f.size = 4;  // spacing 0.5
  Pcg32 rng(7);
  for (int k = 0; k < 64; ++k) f.z.push_back(float(rng.next_double() - 0.5));
  const Microsurface s(f, parse_material(R"({"type":"diffuse"})"), Microsurface::kDefaultMaxBounces, GetParam().first,
                       GetParam().second);
  ASSERT_EQ(int(s.tracer()), int(GetParam().second));
  const double h = f.spacing();
  for (int k = 0; k < 400; ++k) {
    const double x = rng.next_double() * f.size, y = rng.next_double() * f.size;
    const int i = int(x / h), j = int(y / h);
    const double fx = x / h - i, fy = y / h - j;
    if (std::abs(fx + fy - 1) < 1e-3) continue;  // on the diagonal itself
    double sx, sy;
    if (fx + fy < 1) {  // lower-left triangle (i, j), (i+1, j), (i, j+1)
      sx = (f.at(i + 1, j) - f.at(i, j)) / h;
      sy = (f.at(i, j + 1) - f.at(i, j)) / h;
    } else {  // upper-right (i+1, j), (i+1, j+1), (i, j+1)
      sx = (f.at(i + 1, j + 1) - f.at(i, j + 1)) / h;
      sy = (f.at(i + 1, j + 1) - f.at(i + 1, j)) / h;
    }
    const Vec3 expect = normalize(Vec3{Float(-sx), Float(-sy), 1});
    const Vec3 got = s.normal_below(x, y);
    EXPECT_NEAR(got.x, expect.x, 1e-4) << x << " " << y;
    EXPECT_NEAR(got.y, expect.y, 1e-4) << x << " " << y;
    EXPECT_NEAR(got.z, expect.z, 1e-4) << x << " " << y;
  }
}
INSTANTIATE_TEST_SUITE_P(Microsurface, MicrosurfaceMesh,
                         ::testing::Values(std::pair{Microsurface::Mesh::Quads, Microsurface::Tracer::Embree},
                                           std::pair{Microsurface::Mesh::Grid, Microsurface::Tracer::Embree},
                                           std::pair{Microsurface::Mesh::Auto, Microsurface::Tracer::HeightField}));

// trace_packet makes the same first queries as trace() (in one Embree packet) and then
// draws from the rng in the same order: the rays must end alike, ray for ray.
TEST(Microsurface, PacketTracesAsSingleRays) {
  const Microsurface s(testsurf::eggcrate_field(32, 4), parse_material(R"({"type":"diffuse"})"),
                       Microsurface::kDefaultMaxBounces, Microsurface::Mesh::Auto, Microsurface::Tracer::Embree);
  for (const double theta : {0.0, 40.0, 75.0, 100.0}) {  // 100°: moving up, no query
    const Vec3 d = -spherical_direction(theta * kPiD / 180, 0.7);
    for (const int count : {1, 7, 16}) {
      double u[16], v[16];
      Pcg32 pick(3, std::uint64_t(count));
      for (int k = 0; k < count; ++k) u[k] = pick.next_double(), v[k] = pick.next_double();
      Pcg32 rng_single(5, std::uint64_t(theta)), rng_packet(5, std::uint64_t(theta));
      TraceResult packet[16];
      s.trace_packet(u, v, count, d, rng_packet, packet);
      for (int k = 0; k < count; ++k) {
        const TraceResult one = s.trace(u[k], v[k], d, rng_single);
        EXPECT_EQ(int(packet[k].fate), int(one.fate)) << theta << " " << count << " " << k;
        EXPECT_EQ(packet[k].bounces, one.bounces) << theta << " " << count << " " << k;
        EXPECT_EQ(packet[k].segments, one.segments) << theta << " " << count << " " << k;
        EXPECT_NEAR(packet[k].direction.x, one.direction.x, 1e-4);
        EXPECT_NEAR(packet[k].direction.y, one.direction.y, 1e-4);
        EXPECT_NEAR(packet[k].direction.z, one.direction.z, 1e-4);
      }
    }
  }
}

// A vertical ray into a mirror V-groove of facet slope s = tan θf leaves the first facet
// at elevation e above the horizon, tan e = t = cot 2θf = (1 − s²) / 2s; it meets the
// opposite facet iff it passes below the ridge, which happens for the entry points
// nearer the groove's bottom: a fraction (s − t) / (s + t) of them (for a uniformly
// drawn entry, from the two lines' heights). With s = 0.65 the rays climb at t = 0.444,
// below the facets' slope but above half of it: a tracer that stopped rays climbing
// more steeply than a too small slope bound would let them all escape after one bounce.
TEST(Microsurface, VGrooveSecondBounceFraction) {
  const double s = 0.65, t = (1 - s * s) / (2 * s);
  const Microsurface surf(testsurf::vgroove_field(16, s), parse_material(R"({"type":"mirror","reflectance":1})"));
  const std::uint64_t n = gonio::test::scaled(4000, 1000);
  Pcg32 rng(17);
  std::uint64_t twice = 0;
  for (std::uint64_t k = 0; k < n; ++k) {
    const double u = rng.next_double(), v = rng.next_double();
    const TraceResult r = surf.trace(u, v, Vec3{0, 0, -1}, rng);
    ASSERT_EQ(int(r.fate), int(Fate::Up));
    if (r.bounces >= 2) ++twice;
  }
  const double expect = (s - t) / (s + t), se = std::sqrt(expect * (1 - expect) / double(n));
  EXPECT_NEAR(double(twice) / double(n), expect, 5 * se);
}

// A white conductor (F = 1) absorbs nothing: every ray leaves upwards with its whole
// power, after however many bounces and wraps (a ray that slipped through the tile's
// border or a facet would leave downwards or be lost).
void expect_no_loss(const HeightField& field, const char* name) {
  const Microsurface s(field, parse_material(R"({"type":"mirror","reflectance":1})"));
  const std::uint64_t n = gonio::test::scaled(20000, 4000);
  for (const double theta : {0.0, 30.0, 60.0, 80.0, 88.0}) {
    Pcg32 rng(11, std::uint64_t(theta));
    const Vec3 d = -spherical_direction(theta * kPiD / 180, 0.3);
    double power = 0;
    RayCounts counts;
    std::uint64_t multi = 0;
    for (std::uint64_t k = 0; k < n; ++k) {
      const TraceResult t = s.trace(rng.next_double(), rng.next_double(), d, rng);
      counts.add(t);
      multi += t.bounces > 1;
      if (t.fate == Fate::Up) power += t.weight[0];
    }
    const double albedo = power / double(n);
    EXPECT_LE(std::abs(1 - albedo), 1e-3) << name << " theta_i " << theta;
    EXPECT_EQ(counts.down + counts.lost + counts.capped + counts.absorbed, 0u) << name << " theta_i " << theta;
    if (theta == 60.0) {
      EXPECT_GT(multi, n / 50) << name << ": the surface should scatter multiply";
    }
  }
}

TEST(Microsurface, WhiteConductorEggCrateLosesNoRay) { expect_no_loss(testsurf::eggcrate_field(32, 4), "egg-crate"); }
TEST(Microsurface, WhiteConductorVGrooveLosesNoRay) { expect_no_loss(testsurf::vgroove_field(16, 2.0), "v-groove"); }

// The bounce cap: in a 90° V-groove a vertical ray needs exactly two bounces (it is sent
// across the groove horizontally, then back up), so a cap of 1 drops every ray and a
// cap of 2 keeps them all.
TEST(Microsurface, BounceCapDropsTheRaysThatNeedMore) {
  const HeightField f = testsurf::vgroove_field(8, 1.0);
  const BxDF white = parse_material(R"({"type":"mirror","reflectance":1})");
  const Microsurface one(f, white, 1), two(f, white, 2);
  Pcg32 rng(5);
  for (int k = 0; k < 200; ++k) {
    const double u = rng.next_double() * 0.98 + 0.01, v = rng.next_double();
    if (std::abs(u - 0.5) < 0.01) continue;  // the ridge itself
    const TraceResult a = one.trace(u, v, Vec3{0, 0, -1}, rng), b = two.trace(u, v, Vec3{0, 0, -1}, rng);
    EXPECT_EQ(int(a.fate), int(Fate::Capped)) << u;
    EXPECT_EQ(int(b.fate), int(Fate::Up)) << u;
    EXPECT_EQ(b.bounces, 2u);
    EXPECT_NEAR(b.direction.z, 1, 1e-5);
  }
}

// A ray that runs nearly parallel to the patch wraps around it many times and is then
// stopped, not traced forever.
TEST(Microsurface, HorizontalRaysEnd) {
  const Microsurface s(testsurf::flat_field(), parse_material(R"({"type":"diffuse"})"));
  Pcg32 rng(3);
  const TraceResult t = s.trace(0.5, 0.5, normalize(Vec3{1, 0.3f, -1e-9f}), rng);
  EXPECT_TRUE(t.fate == Fate::Lost || t.fate == Fate::Up || t.fate == Fate::Down);
  EXPECT_LE(t.segments, Microsurface::kMaxWraps + 2);
}

TEST(Microsurface, BadFieldIsInputError) {
  HeightField f;
  f.n = 2;
  f.z = {0, 1, 2};
  EXPECT_THROW(Microsurface(f, parse_material(R"({"type":"diffuse"})")), InputError);
  f.z = {0, 1, 2, std::nanf("")};
  EXPECT_THROW(Microsurface(f, parse_material(R"({"type":"diffuse"})")), InputError);
}

}  // namespace
}  // namespace gonio::measure
