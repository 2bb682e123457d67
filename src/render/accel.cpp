// Embree scene construction and the hit record. Triangles use Embree's triangle
// geometry, spheres its analytic sphere primitive (RTC_GEOMETRY_TYPE_SPHERE_POINT).

#include "gonio/render/accel.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
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

}  // namespace

struct Accel::Impl {
  const Scene& scene;
  RTCDevice device = nullptr;
  RTCScene rtc = nullptr;
  // geomID → shape: meshes first, then spheres.
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
  for (const Sphere& s : scene.spheres) {
    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), 1));
    v[0] = s.center.x;
    v[1] = s.center.y;
    v[2] = s.center.z;
    v[3] = s.radius;
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(im.rtc, g, id++);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(im.rtc);
  if (!im.error.empty()) throw std::runtime_error(im.error);
}

Accel::~Accel() = default;

bool Accel::intersect(const Ray& ray, SurfaceHit& hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x;
  rh.ray.org_y = ray.o.y;
  rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x;
  rh.ray.dir_y = ray.d.y;
  rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = 0;
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
  if (rh.hit.geomID >= impl_->sphere_base) {
    const Sphere& s = scene.spheres[rh.hit.geomID - impl_->sphere_base];
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
