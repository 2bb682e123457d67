// Embree scene construction and the hit record. Triangles use Embree's triangle
// geometry; spheres are one Embree user geometry whose callbacks intersect them
// analytically (cheaper per ray than Embree's ray-oriented point primitives, and exact).

#include "gonio/render/accel.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace gonio::render {
namespace {

// Embree reports errors through a C callback, which must not throw; the message is kept
// and turned into an exception once control is back in C++.
void embree_error(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  if (last->empty())
    *last = "embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

// Nearest root in (tnear, tfar) of |o + t·d − c|² = r², d unit length, in the stable form
// of Haines et al., "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing
// Gems, 2019, ch. 7): the discriminant from the distance of c to the ray's line, and the
// small root from the product of the roots, both without cancellation.
bool hit_sphere(const Sphere& s, const Vec3& o, const Vec3& d, float tnear, float tfar, float& t) {
  const Vec3 f = o - s.center;
  const Float b = -dot(f, d);
  const Vec3 perp = f + d * b;
  const Float r2 = s.radius * s.radius;
  const Float disc = r2 - length_squared(perp);
  if (!(disc >= 0)) return false;
  const Float c = length_squared(f) - r2;
  const Float q = b + std::copysign(std::sqrt(disc), b);
  const Float t0 = q != 0 ? c / q : Float(0), t1 = q;
  const Float lo = std::min(t0, t1), hi = std::max(t0, t1);
  t = lo > tnear ? lo : hi;
  return t > tnear && t < tfar;
}

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  args->bounds_o->lower_x = s.center.x - s.radius;
  args->bounds_o->lower_y = s.center.y - s.radius;
  args->bounds_o->lower_z = s.center.z - s.radius;
  args->bounds_o->upper_x = s.center.x + s.radius;
  args->bounds_o->upper_y = s.center.y + s.radius;
  args->bounds_o->upper_z = s.center.z + s.radius;
}

// Single rays only (rtcIntersect1 / rtcOccluded1): N is 1.
void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  float t;
  if (!hit_sphere(s, {rh->ray.org_x, rh->ray.org_y, rh->ray.org_z}, {rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z},
                  rh->ray.tnear, rh->ray.tfar, t))
    return;
  rh->ray.tfar = t;
  rh->hit.u = rh->hit.v = 0;
  rh->hit.Ng_x = rh->hit.Ng_y = rh->hit.Ng_z = 0;  // computed by Accel::intersect
  rh->hit.primID = args->primID;
  rh->hit.geomID = args->geomID;
  rh->hit.instID[0] = args->context->instID[0];
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  auto* r = reinterpret_cast<RTCRay*>(args->ray);
  float t;
  if (hit_sphere(s, {r->org_x, r->org_y, r->org_z}, {r->dir_x, r->dir_y, r->dir_z}, r->tnear, r->tfar, t))
    r->tfar = -std::numeric_limits<float>::infinity();
}

// The point of the segment [a, b] nearest to p.
Vec3 segment_closest_point(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Float len2 = length_squared(ab);
  const Float t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, Float(0), Float(1)) : Float(0);
  return a + ab * t;
}

// The point of the triangle abc nearest to p: p's projection on its plane when that falls
// inside it (on the inner side of all three edges), else the nearest point of its edges
// (the nearest point of a convex polygon to a point projecting outside it lies on its
// boundary; Ericson 2005, "Real-Time Collision Detection", §5.1.5).
Vec3 triangle_closest_point(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(b - a, c - a);
  const Float n2 = length_squared(n);
  if (n2 > 0 && dot(cross(b - a, p - a), n) >= 0 && dot(cross(c - b, p - b), n) >= 0 && dot(cross(a - c, p - c), n) >= 0)
    return p - n * (dot(p - a, n) / n2);
  const Vec3 e[3] = {segment_closest_point(p, a, b), segment_closest_point(p, b, c), segment_closest_point(p, c, a)};
  const Float d2[3] = {length_squared(p - e[0]), length_squared(p - e[1]), length_squared(p - e[2])};
  return e[d2[1] < d2[0] ? (d2[2] < d2[1] ? 2 : 1) : (d2[2] < d2[0] ? 2 : 0)];
}

}  // namespace

struct Accel::Impl {
  const Scene& scene;
  RTCDevice device = nullptr;
  RTCScene rtc = nullptr;
  // geomID → shape: one per mesh, then one user geometry holding every sphere.
  unsigned sphere_base = 0;
  std::string error;

  explicit Impl(const Scene& s) : scene(s) {}
  ~Impl() {
    if (rtc) rtcReleaseScene(rtc);
    if (device) rtcReleaseDevice(device);
  }
};

Accel::Accel(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {
  Impl& im = *impl_;
  im.device = rtcNewDevice("verbose=0");
  if (!im.device) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(im.device, embree_error, &im.error);
  im.rtc = rtcNewScene(im.device);
  rtcSetSceneBuildQuality(im.rtc, RTC_BUILD_QUALITY_HIGH);
  unsigned id = 0;
  for (const Mesh& m : scene.meshes) {
    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree-allocated buffers carry the padding its SIMD loads need.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.positions.size()));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      v[3 * i] = m.positions[i].x;
      v[3 * i + 1] = m.positions[i].y;
      v[3 * i + 2] = m.positions[i].z;
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.indices.size() / 3));
    std::memcpy(idx, m.indices.data(), m.indices.size() * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(im.rtc, g, id++);
    rtcReleaseGeometry(g);
  }
  im.sphere_base = id;
  if (!scene.spheres.empty()) {
    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(scene.spheres.size()));
    rtcSetGeometryUserData(g, const_cast<Sphere*>(scene.spheres.data()));
    rtcSetGeometryBoundsFunction(g, sphere_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, sphere_intersect);
    rtcSetGeometryOccludedFunction(g, sphere_occluded);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(im.rtc, g, id++);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(im.rtc);
  if (!im.error.empty()) throw std::runtime_error(im.error);
}

Accel::~Accel() = default;

bool Accel::intersect(const Ray& ray, SurfaceHit& hit) const { return intersect_after(ray, 0, hit); }

bool Accel::intersect_after(const Ray& ray, Float tnear, SurfaceHit& hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x;
  rh.ray.org_y = ray.o.y;
  rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x;
  rh.ray.dir_y = ray.d.y;
  rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = tnear;
  rh.ray.tfar = ray.tmax;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->rtc, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

  const Scene& scene = impl_->scene;
  hit.t = rh.ray.tfar;
  if (rh.hit.geomID == impl_->sphere_base) {
    const Sphere& s = scene.spheres[rh.hit.primID];
    // Re-project onto the sphere: o + t·d carries the float error of t.
    const Vec3 r = normalize(ray.o + ray.d * hit.t - s.center);
    hit.p = s.center + r * s.radius;
    hit.ng = hit.ns = r;
    // Spheres are parameterised around +y: u follows the latitude circles, so the
    // tangent (dP/du) is horizontal and anisotropic materials look brushed around y.
    hit.tangent = Vec3{-r.z, 0, r.x};
    hit.uv = {std::atan2(r.x, r.z) * kInv2Pi + Float(0.5), std::acos(std::clamp(r.y, Float(-1), Float(1))) * kInvPi};
    hit.material = s.material;
    hit.area_light = s.area_light;
    return true;
  }
  const Mesh& m = scene.meshes[rh.hit.geomID];
  const unsigned* tri = &m.indices[3 * static_cast<size_t>(rh.hit.primID)];
  const Float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
  const Vec3 &p0 = m.positions[tri[0]], &p1 = m.positions[tri[1]], &p2 = m.positions[tri[2]];
  hit.p = p0 * b0 + p1 * b1 + p2 * b2;
  hit.ng = normalize(cross(p1 - p0, p2 - p0));
  if (!m.normals.empty()) {
    hit.ns = normalize(m.normals[tri[0]] * b0 + m.normals[tri[1]] * b1 + m.normals[tri[2]] * b2);
    if (!(length_squared(hit.ns) > 0)) hit.ns = hit.ng;
    // Vertex normals say which side is outside; the geometric normal follows them.
    if (dot(hit.ns, hit.ng) < 0) hit.ng = -hit.ng;
  } else {
    hit.ns = hit.ng;
  }
  if (!m.uvs.empty()) {
    const Vec2 &t0 = m.uvs[tri[0]], &t1 = m.uvs[tri[1]], &t2 = m.uvs[tri[2]];
    hit.uv = {t0.x * b0 + t1.x * b1 + t2.x * b2, t0.y * b0 + t1.y * b1 + t2.y * b2};
  } else {
    hit.uv = {b1, b2};
  }
  hit.tangent = m.tangents.empty() ? Vec3{}
                                   : m.tangents[tri[0]] * b0 + m.tangents[tri[1]] * b1 + m.tangents[tri[2]] * b2;
  hit.material = m.material;
  hit.area_light = m.area_light;
  return true;
}

namespace {

struct ClosestPointQuery {
  const Scene* scene;
  unsigned sphere_base;
  Vec3 point;
  bool found = false;
};

// Embree's point-query callback: where the primitive's nearest point is nearer than the
// query's radius, keeps it and shrinks the radius to its distance.
bool closest_point_visit(RTCPointQueryFunctionArguments* args) {
  auto& q = *static_cast<ClosestPointQuery*>(args->userPtr);
  const Vec3 p{args->query->x, args->query->y, args->query->z};
  Vec3 nearest;
  if (args->geomID == q.sphere_base) {
    const Sphere& s = q.scene->spheres[args->primID];
    const Vec3 r = p - s.center;
    const Float len = length(r);
    nearest = s.center + (len > 0 ? r * (s.radius / len) : Vec3{s.radius, 0, 0});
  } else {
    const Mesh& m = q.scene->meshes[args->geomID];
    const unsigned* tri = &m.indices[3 * static_cast<size_t>(args->primID)];
    const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
    // No point of the triangle is nearer than its plane: most of the triangles whose boxes
    // the query's sphere meets are rejected by that alone (a degenerate one, without a
    // plane, by its edges below).
    const Vec3 n = cross(b - a, c - a);
    const Float h = dot(p - a, n), r = args->query->radius, n2 = length_squared(n);
    if (n2 > 0 && !(h * h < r * r * n2)) return false;
    nearest = triangle_closest_point(p, a, b, c);
  }
  const Float d = length(p - nearest);
  if (!(d < args->query->radius)) return false;
  args->query->radius = float(d);
  q.point = nearest;
  q.found = true;
  return true;
}

}  // namespace

Float Accel::distance_to_surface(const Vec3& p, Float max_distance) const {
  Vec3 nearest;
  return closest_point(p, max_distance, nearest);
}

Float Accel::closest_point(const Vec3& p, Float max_distance, Vec3& nearest) const {
  RTCPointQuery query;
  query.x = p.x;
  query.y = p.y;
  query.z = p.z;
  query.time = 0;
  query.radius = max_distance;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  ClosestPointQuery user{&impl_->scene, impl_->sphere_base, {}};
  rtcPointQuery(impl_->rtc, &query, &ctx, closest_point_visit, &user);
  if (user.found) nearest = user.point;
  return query.radius;
}

bool Accel::occluded(const Vec3& o, const Vec3& d, Float tmax) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.tnear = 0;
  r.tfar = tmax;
  r.time = 0;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(impl_->rtc, &ctx, &r);
  return r.tfar < 0;
}

}  // namespace gonio::render
