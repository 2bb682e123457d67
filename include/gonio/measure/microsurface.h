#pragma once
// A height field traced as a periodic microsurface (issue 13): rays scattered by the
// facets' material until they leave above the highest point (reflected) or below the
// lowest (transmitted).
//
// Two tracers find the facets, with the same facets and the same walk around them:
// Tracer::HeightField (the default), heightfield_tracer.h's maximum-mipmap walk over the
// grid, which needs no BVH and wraps by taking cell indices modulo n; and Tracer::Embree,
// one Embree scene per surface, kept as the reference the tests compare with.
//
// Embree geometry: the field's n × n samples become (n+1) × (n+1) vertices (the last row and
// column repeat the first, so the tile closes periodically) and one Embree quad per cell,
// or for fields above kMaxQuadResolution one Embree grid. Embree splits each quad
// (v0 = (i, j), v1 = (i+1, j), v2 = (i+1, j+1), v3 = (i, j+1)), in both forms, into the
// triangles (v0, v1, v3) and (v2, v3, v1): exactly heightfield.h's triangulation, so
// every facet normal is the forward-difference slope of the field. Quads trace faster
// (their BVH leaves hold vertex copies; a quarter less time at 2048², docs/benchmarks.md)
// but a 2048² field takes about 0.6 GB as quads against 0.16 GB as a grid.
//
// Periodic wrapping: with Embree a ray is traced only across the tile [0, size)²; when it
// leaves the tile's square without a hit it re-enters at the opposite side with the same
// height and direction (the height-field tracer crosses the border in one query, counting
// the crossings alike). It is done when it is above the highest point going up, or below the lowest
// going down; a nearly horizontal ray that wraps endlessly is stopped and counted lost.
// A ray above the surface that climbs more steeply than the steepest facet is done at
// once (no facet can reach it: the field is Lipschitz), and so is one below it falling
// more steeply; that saves the exit query of most rays leaving near the normal.
//
// Transport: rays come from the light and carry power, so each facet's BSDF is sampled
// in TransportMode::Importance (SPEC §1; Veach 1997 §5.2): a smooth glass facet then
// transmits the power fraction 1 − F. The facet frame: z = the facet's geometric normal
// turned to +z, x = the patch's +x projected onto the facet (Frame::from_normal_tangent).
// No Russian roulette: a white conductor must conserve every ray's power exactly.

#include <cstdint>
#include <memory>

#include "gonio/bxdf.h"
#include "gonio/color.h"
#include "gonio/math/vec3.h"
#include "gonio/measure/heightfield.h"
#include "gonio/measure/heightfield_tracer.h"
#include "gonio/rng.h"

namespace gonio::measure {

// How a traced ray ended.
enum class Fate : std::uint8_t {
  Up,        // left above the microsurface (reflection)
  Down,      // left below it (transmission)
  Absorbed,  // the facet's sample produced no direction or a zero weight
  Capped,    // hit a facet after the cap's last bounce (its power is dropped; counted)
  Lost,      // wrapped endlessly, left numerically invalid, or slipped below an opaque
             // material through a float-precision crack (counted)
};

struct TraceResult {
  Fate fate = Fate::Lost;
  Vec3 direction;            // unit, the direction it left in (Up / Down)
  Color weight{0};           // the power it carries out, per unit power in
  std::uint32_t bounces = 0;   // facet interactions
  std::uint32_t segments = 0;  // traced segments (facet queries, wraps included)
};

class Microsurface {
 public:
  // Default bounce cap: far beyond what a rough conductor or glass needs (a white
  // conductor's multiple scattering decays geometrically); rays that reach it are counted.
  // A ray that meets a facet after max_bounces bounces is dropped as Capped, so a cap of 1
  // measures the single-scattering component alone (what microfacet theory without
  // multiple scattering describes).
  static constexpr std::uint32_t kDefaultMaxBounces = 1000;
  // Wraps allowed to one ray (every wrap is one segment).
  static constexpr std::uint32_t kMaxWraps = 100000;
  // The largest field traced as quads by default (memory: see above).
  static constexpr int kMaxQuadResolution = 2048;
  // How the facets are handed to Embree; both give the same facets.
  enum class Mesh : std::uint8_t { Auto, Quads, Grid };
  // Which tracer finds the facets (above); `mesh` applies to Embree only.
  enum class Tracer : std::uint8_t { HeightField, Embree };

  // Throws InputError for an empty or non-finite field.
  Microsurface(const HeightField& field, const BxDF& material, std::uint32_t max_bounces = kDefaultMaxBounces,
               Mesh mesh = Mesh::Auto, Tracer tracer = Tracer::HeightField);
  ~Microsurface();
  Microsurface(const Microsurface&) = delete;
  Microsurface& operator=(const Microsurface&) = delete;

  // A ray from the distant light: it enters the patch at (u, v) · size (u, v in [0, 1))
  // above the highest point and moves along `direction` (unit, z < 0). The rng draws the
  // facets' lobe and direction samples.
  TraceResult trace(double u, double v, const Vec3& direction, Pcg32& rng) const;

  // trace() for up to kPacketSize rays of one direction entering at (u[k], v[k]): their
  // first segments go to Embree as one packet (faster when the entry points are close
  // together, as in a stratum of a block), the rest of each ray as in trace(), ray after
  // ray, drawing from rng as count calls of trace() would. Results in out[0, count).
  static constexpr int kPacketSize = 16;
  void trace_packet(const double* u, const double* v, int count, const Vec3& direction, Pcg32& rng,
                    TraceResult* out) const;

  // The facet normal (z > 0) of the first facet a vertical ray at (x, y) hits, for tests
  // of the triangulation; (0, 0, 0) if it hits nothing.
  Vec3 normal_below(double x, double y) const;

  // One query as trace() makes it, for comparing the tracers: from p (x, y in [0, size])
  // along d to the first facet, or else to the slab [z_min, z_max]'s face ahead.
  struct Probe {
    bool facet = false;      // met a facet (else reached the slab's face, or lost)
    bool lost = false;       // wrapped more than kMaxWraps times, or not a direction
    double point[3] = {};    // where it ended, x and y wrapped into the tile
    double distance = 0;     // the path length there
    Vec3 ng;                 // the facet's normal, unnormalised
    std::uint32_t wraps = 0;  // tile borders crossed
  };
  Probe probe(const double p[3], const Vec3& d) const;

  Tracer tracer() const { return hf_ ? Tracer::HeightField : Tracer::Embree; }

  double size() const { return size_; }
  double z_min() const { return z_min_; }
  double z_max() const { return z_max_; }
  const BxDF& material() const { return material_; }

 private:
  struct FirstQuery {  // the first query's answer, when it was made in a packet
    double t;
    Vec3 ng;
  };
  TraceResult walk(double p[3], const Vec3& direction, Pcg32& rng, const FirstQuery* first) const;
  // Moves p along d to the first facet (Step::Facet, ng its normal) or to the slab's face
  // ahead (Step::Slab), with either tracer; wraps and segments are counted on.
  enum class Step : std::uint8_t { Facet, Slab, Lost };
  Step advance(double p[3], const Vec3& d, Vec3& ng, std::uint32_t& wraps, std::uint32_t& segments,
               const FirstQuery*& first, double* distance, bool from_facet) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;                   // Embree (Tracer::Embree)
  std::unique_ptr<HeightFieldTracer> hf_;        // the height-field tracer (Tracer::HeightField)
  BxDF material_;
  std::uint32_t max_bounces_;
  bool transmissive_;
  double size_ = 1, z_min_ = 0, z_max_ = 0, eps_ = 0;
  double max_slope_ = 0;  // the steepest facet's |∇z|, a little enlarged
};

}  // namespace gonio::measure
