// Tracing of the periodic microsurface of include/gonio/measure/microsurface.h.
#include "gonio/measure/microsurface.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "gonio/error.h"
#include "gonio/math/frame.h"

namespace gonio::measure {
namespace {

void embree_error(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  if (last->empty())
    *last = "embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

struct Microsurface::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string error;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

Microsurface::Microsurface(const HeightField& field, const BxDF& material, std::uint32_t max_bounces, Mesh mesh,
                           Tracer tracer)
    : impl_(std::make_unique<Impl>()),
      material_(material),
      max_bounces_(max_bounces),
      transmissive_(is_transmissive(material.flags())) {
  const int n = field.n;
  if (max_bounces < 1) throw InputError("surface: the bounce cap must be at least 1");
  if (n < 1 || n > 32766 || field.z.size() != std::size_t(n) * std::size_t(n))
    throw InputError("surface: the height field must be n x n with 1 <= n <= 32766, got n = " + std::to_string(n));
  if (!(field.size > 0) || !std::isfinite(field.size))
    throw InputError("surface: the patch size must be a positive number, got " + format_number(field.size));
  z_min_ = kInf, z_max_ = -kInf;
  for (const float z : field.z) {
    if (!std::isfinite(z)) throw InputError("surface: the height field holds a non-finite height");
    z_min_ = std::min(z_min_, double(z));
    z_max_ = std::max(z_max_, double(z));
  }
  size_ = field.size;
  // The steepest facet's slope |∇z| (the forward differences of heightfield.h's two
  // triangles per cell), with a margin for the float vertices.
  {
    const double h = field.spacing();
    double g2 = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double z00 = field.at(i, j), z10 = field.at(i + 1, j), z01 = field.at(i, j + 1),
                     z11 = field.at(i + 1, j + 1);
        g2 = std::max(g2, ((z10 - z00) * (z10 - z00) + (z01 - z00) * (z01 - z00)) / (h * h));
        g2 = std::max(g2, ((z11 - z01) * (z11 - z01) + (z11 - z10) * (z11 - z10)) / (h * h));
      }
    max_slope_ = std::sqrt(g2) * (1 + 1e-3) + 1e-6;
  }
  // The offset that lifts a scattered ray off its facet: a few float ulps of the largest
  // coordinate (Embree works in float), and never below a millionth of a cell.
  const double extent = std::max({size_, std::abs(z_min_), std::abs(z_max_)});
  eps_ = std::max(8 * extent * double(std::numeric_limits<float>::epsilon()), 1e-6 * field.spacing());

  if (tracer == Tracer::HeightField) {
    hf_ = std::make_unique<HeightFieldTracer>(field);
    return;
  }
  Impl& im = *impl_;
  im.device = rtcNewDevice("verbose=0");
  if (!im.device) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(im.device, embree_error, &im.error);
  im.scene = rtcNewScene(im.device);
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
  // Quads are faster, a grid smaller (the header); beyond kMaxQuadResolution the grid keeps
  // the memory bounded.
  const bool quad = mesh == Mesh::Quads || (mesh == Mesh::Auto && n <= kMaxQuadResolution);
  RTCGeometry g = rtcNewGeometry(im.device, quad ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_GRID);
  const int m = n + 1;  // vertices per side: the last repeats the first (periodic closure)
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), std::size_t(m) * std::size_t(m)));
  const double h = field.spacing();
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      float* p = v + 3 * (std::size_t(i) + std::size_t(m) * std::size_t(j));
      // The far edge at exactly `size`, so the tile's border meets the wrap exactly.
      p[0] = i == n ? float(size_) : float(i * h);
      p[1] = j == n ? float(size_) : float(j * h);
      p[2] = field.at(i, j);
    }
  if (quad) {
    // Quad (v0, v1, v2, v3) is split by Embree into (v0, v1, v3) and (v2, v3, v1), as the grid.
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4,
                                                               4 * sizeof(unsigned), std::size_t(n) * std::size_t(n)));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        unsigned* q4 = idx + 4 * (std::size_t(i) + std::size_t(n) * std::size_t(j));
        const unsigned v0 = unsigned(i + m * j);
        q4[0] = v0, q4[1] = v0 + 1, q4[2] = v0 + 1 + unsigned(m), q4[3] = v0 + unsigned(m);
      }
  } else {
    auto* grid = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID,
                                                             sizeof(RTCGrid), 1));
    grid->startVertexID = 0;
    grid->stride = static_cast<unsigned>(m);
    grid->width = static_cast<unsigned short>(m);
    grid->height = static_cast<unsigned short>(m);
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(im.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(im.scene);
  if (!im.error.empty()) throw std::runtime_error(im.error);
}

Microsurface::~Microsurface() = default;

namespace {

// One Embree query from o along d in [0, tfar]; returns the hit distance (or +inf) and
// the unnormalised geometric normal.
double intersect(RTCScene scene, const double o[3], const Vec3& d, double tfar, Vec3& ng) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = float(o[0]);
  rh.ray.org_y = float(o[1]);
  rh.ray.org_z = float(o[2]);
  rh.ray.dir_x = d.x;
  rh.ray.dir_y = d.y;
  rh.ray.dir_z = d.z;
  rh.ray.tnear = 0;
  rh.ray.tfar = std::isfinite(tfar) ? float(tfar) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return kInf;
  ng = Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
  return rh.ray.tfar;
}

// x wrapped into the tile [0, size] (both borders belong to it: a ray on a border moving
// out of the tile leaves it with a zero-length segment and re-enters at the other).
double wrap(double x, double size) {
  if (x >= 0 && x <= size) return x;
  x -= size * std::floor(x / size);
  return x >= size || x < 0 ? 0 : x;
}

// Where the segment from p along d ends: at the tile's border (texit) or at the slab
// [z_min, z_max] (tz); tend = min of both, +inf for a direction that is not one.
struct SegmentEnd {
  double tx, ty, tz, texit, tend;
};
SegmentEnd segment_end(const double p[3], const Vec3& d, double size, double z_min, double z_max) {
  SegmentEnd e;
  e.tx = d.x > 0 ? (size - p[0]) / d.x : d.x < 0 ? -p[0] / d.x : kInf;
  e.ty = d.y > 0 ? (size - p[1]) / d.y : d.y < 0 ? -p[1] / d.y : kInf;
  e.tz = d.z > 0 ? (z_max - p[2]) / d.z : d.z < 0 ? (z_min - p[2]) / d.z : kInf;
  e.texit = std::max(0.0, std::min(e.tx, e.ty));
  e.tend = std::min(e.texit, e.tz);
  return e;
}

// The far end handed to Embree: a little past the segment's end, because the lowest and
// highest facets lie on the slab's faces, where a float hit distance may come out a hair
// beyond tz.
float query_tfar(double tend, double eps) { return float(tend * (1 + 1e-6) + eps); }

}  // namespace

Vec3 Microsurface::normal_below(double x, double y) const {
  const double o[3] = {wrap(x, size_), wrap(y, size_), z_max_ + 1 + (z_max_ - z_min_)};
  Vec3 ng;
  if (hf_) {
    const double down[3] = {0, 0, -1};
    const HeightFieldTracer::Hit hit = hf_->intersect(o, down, kInf, 0);
    if (!std::isfinite(hit.t)) return {};
    ng = hit.ng;
  } else if (!std::isfinite(intersect(impl_->scene, o, Vec3{0, 0, -1}, kInf, ng))) {
    return {};
  }
  const Vec3 n = normalize(ng);
  return n.z < 0 ? -n : n;
}

TraceResult Microsurface::trace(double u, double v, const Vec3& direction, Pcg32& rng) const {
  // Position in double: the wraps and the offsets are exact to far below a float ulp.
  double p[3] = {wrap(u * size_, size_), wrap(v * size_, size_), z_max_ + eps_};
  return walk(p, direction, rng, nullptr);
}

void Microsurface::trace_packet(const double* u, const double* v, int count, const Vec3& direction, Pcg32& rng,
                                TraceResult* out) const {
  if (count < 1) return;
  if (count > kPacketSize) throw std::invalid_argument("Microsurface::trace_packet: more than 16 rays");
  if (hf_) {  // no packets: the height-field tracer takes one ray at a time
    for (int k = 0; k < count; ++k) out[k] = trace(u[k], v[k], direction, rng);
    return;
  }
  double p[kPacketSize][3];
  alignas(64) int valid[kPacketSize] = {};
  alignas(64) RTCRayHit16 rh;
  for (int k = 0; k < kPacketSize; ++k) {
    rh.ray.tnear[k] = 0, rh.ray.tfar[k] = 0, rh.ray.time[k] = 0;
    rh.ray.mask[k] = 0xFFFFFFFFu, rh.ray.id[k] = unsigned(k), rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    rh.ray.org_x[k] = rh.ray.org_y[k] = rh.ray.org_z[k] = 0;
    rh.ray.dir_x[k] = direction.x, rh.ray.dir_y[k] = direction.y, rh.ray.dir_z[k] = direction.z;
  }
  // The rays whose first step walk() would take with a query go into the packet, with
  // the very query walk() would make (same origin, direction and far end).
  const bool queries = direction.z < 0;
  for (int k = 0; k < count; ++k) {
    p[k][0] = wrap(u[k] * size_, size_), p[k][1] = wrap(v[k] * size_, size_), p[k][2] = z_max_ + eps_;
    const SegmentEnd e = segment_end(p[k], direction, size_, z_min_, z_max_);
    if (!queries || !(p[k][2] > z_min_) || !std::isfinite(e.tend)) continue;
    valid[k] = -1;
    rh.ray.org_x[k] = float(p[k][0]), rh.ray.org_y[k] = float(p[k][1]), rh.ray.org_z[k] = float(p[k][2]);
    rh.ray.tfar[k] = query_tfar(e.tend, eps_);
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(valid, impl_->scene, &ctx, &rh);
  // Then each ray in turn, in order, so that each draws from rng as trace() would.
  for (int k = 0; k < count; ++k) {
    if (!valid[k]) {
      out[k] = walk(p[k], direction, rng, nullptr);
      continue;
    }
    FirstQuery q;
    q.t = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? kInf : double(rh.ray.tfar[k]);
    q.ng = Vec3{rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]};
    out[k] = walk(p[k], direction, rng, &q);
  }
}

Microsurface::Step Microsurface::advance(double p[3], const Vec3& d, Vec3& ng, std::uint32_t& wraps,
                                         std::uint32_t& segments, const FirstQuery*& first, double* distance,
                                         bool from_facet) const {
  const double tz = d.z > 0 ? (z_max_ - p[2]) / d.z : d.z < 0 ? (z_min_ - p[2]) / d.z : kInf;
  if (hf_) {
    // One query across as many tiles as the ray crosses, up to a little past the slab's
    // face (the lowest and highest facets lie on it), as Embree's far end below.
    ++segments;
    const double o[3] = {p[0], p[1], p[2]}, dir[3] = {d.x, d.y, d.z};
    const double tfar = tz * (1 + 1e-6) + eps_;
    const HeightFieldTracer::Hit hit =
        hf_->intersect(o, dir, tfar, kMaxWraps - std::min(wraps, kMaxWraps), nullptr, from_facet ? 0 : -1);
    wraps += hit.wraps;
    segments += hit.wraps;
    if (hit.overflow || !(std::isfinite(hit.t) || std::isfinite(tz))) return Step::Lost;
    const double t = std::isfinite(hit.t) ? hit.t : tz;
    if (distance) *distance = t;
    for (int k = 0; k < 3; ++k) p[k] += double(d[k]) * t;
    p[0] = wrap(p[0], size_);
    p[1] = wrap(p[1], size_);
    if (!std::isfinite(hit.t)) {
      p[2] = d.z > 0 ? z_max_ : z_min_;
      return Step::Slab;
    }
    ng = hit.ng;
    return Step::Facet;
  }
  double travelled = 0;
  for (;;) {
    // The segment ends at the tile's border or at the slab [z_min, z_max].
    const auto [tx, ty, tz_seg, texit, tend] = segment_end(p, d, size_, z_min_, z_max_);
    if (!std::isfinite(tend)) return Step::Lost;  // horizontal and vertical at once: not a direction
    ++segments;
    double t;
    if (first) {  // this query was made in trace_packet's packet
      t = first->t, ng = first->ng;
      first = nullptr;
    } else {
      t = intersect(impl_->scene, p, d, query_tfar(tend, eps_), ng);
    }
    if (std::isfinite(t)) {
      for (int k = 0; k < 3; ++k) p[k] += double(d[k]) * t;
      if (distance) *distance = travelled + t;
      return Step::Facet;
    }
    if (tz_seg <= texit) {  // reached the slab's face: the next test ends the ray
      p[0] = wrap(p[0] + double(d.x) * tz_seg, size_);
      p[1] = wrap(p[1] + double(d.y) * tz_seg, size_);
      p[2] = d.z > 0 ? z_max_ : z_min_;
      if (distance) *distance = travelled + tz_seg;
      return Step::Slab;
    }
    // Left the tile's square: re-enter at the opposite side.
    if (++wraps > kMaxWraps) return Step::Lost;
    for (int k = 0; k < 3; ++k) p[k] += double(d[k]) * texit;
    travelled += texit;
    if (tx <= ty) p[0] = d.x > 0 ? 0 : size_;
    if (ty <= tx) p[1] = d.y > 0 ? 0 : size_;
    p[0] = wrap(p[0], size_);
    p[1] = wrap(p[1], size_);
  }
}

Microsurface::Probe Microsurface::probe(const double p[3], const Vec3& d) const {
  Probe r;
  double q[3] = {p[0], p[1], p[2]};
  const FirstQuery* none = nullptr;
  std::uint32_t segments = 0;
  const Step s = advance(q, d, r.ng, r.wraps, segments, none, &r.distance, false);
  r.facet = s == Step::Facet;
  r.lost = s == Step::Lost;
  if (r.facet) q[0] = wrap(q[0], size_), q[1] = wrap(q[1], size_);
  for (int k = 0; k < 3; ++k) r.point[k] = q[k];
  return r;
}

TraceResult Microsurface::walk(double p[3], const Vec3& direction, Pcg32& rng, const FirstQuery* first) const {
  TraceResult r;
  Vec3 d = direction;
  Color w(1);
  std::uint32_t wraps = 0;
  bool above = true;  // on the upper side of the surface (it enters from above)
  for (;;) {
    // Done: above every facet going up, or below every facet going down.
    if (d.z > 0 && p[2] >= z_max_) {
      r.fate = Fate::Up;
      break;
    }
    if (d.z < 0 && p[2] <= z_min_) {
      r.fate = Fate::Down;
      break;
    }
    // Also done, without a query: a ray above the surface climbing more steeply than any
    // facet (the piecewise-linear field is Lipschitz with constant max_slope_, so along the
    // ray's horizontal path the surface rises more slowly than the ray and never reaches
    // it), or one below it falling more steeply.
    const double rise = above ? d.z : -d.z;
    if (rise > 0 && rise > max_slope_ * std::sqrt(double(d.x) * d.x + double(d.y) * d.y)) {
      r.fate = above ? Fate::Up : Fate::Down;
      break;
    }
    Vec3 ng;
    const Step step = advance(p, d, ng, wraps, r.segments, first, nullptr, r.bounces > 0);
    if (step == Step::Lost) {
      r.fate = Fate::Lost;
      break;
    }
    if (step == Step::Slab) continue;  // at the slab's face: the next test ends the ray
    Vec3 n = normalize(ng);
    if (n.z < 0) n = -n;
    if (!(n.z > 0)) {  // a degenerate facet
      r.fate = Fate::Lost;
      break;
    }
    if (r.bounces >= max_bounces_) {  // one facet more than the cap allows
      r.fate = Fate::Capped;
      break;
    }
    const Frame frame = Frame::from_normal_tangent(n, Vec3{1, 0, 0});
    const Vec3 wo = frame.to_local(-d);
    const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    const auto s = material_.sample(wo, u0, u1, u2, TransportMode::Importance);
    ++r.bounces;
    if (!s || s->weight.is_black()) {
      r.fate = Fate::Absorbed;
      break;
    }
    w *= s->weight;
    d = normalize(frame.to_world(s->wi));
    // Lift the origin off the facet's plane, on the side the new direction leaves to.
    above = dot(d, n) > 0;
    const double side = above ? eps_ : -eps_;
    p[0] = wrap(p[0] + n.x * side, size_);
    p[1] = wrap(p[1] + n.y * side, size_);
    p[2] += n.z * side;
  }
  // Below an opaque material nothing can arrive: a ray that got there slipped between
  // facets (a float-precision crack at a sharp crease, about 1 ray in 10^5 on a 60°
  // V-groove) and is counted lost, not transmitted.
  if (r.fate == Fate::Down && !transmissive_) r.fate = Fate::Lost;
  if (r.fate == Fate::Up || r.fate == Fate::Down) {
    bool finite = is_finite(d);
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(w[c]);
    if (!finite) {
      r.fate = Fate::Lost;
      return r;
    }
    r.direction = d;
    r.weight = w;
  }
  return r;
}

}  // namespace gonio::measure
