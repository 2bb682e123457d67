// Light selection for next-event estimation (light_sampler.h): uniform, by power, and by
// a light BVH (Conty Estevez & Kulla 2018, "Importance sampling of many lights with
// adaptive tree splitting").

#include "gonio/render/light_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "gonio/math/cdf_guide.h"
#include "gonio/math/constants.h"

namespace gonio::render {
namespace {

Vec3 vmin(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
Vec3 vmax(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

Float surface_area(const LightBounds& b) {
  const Vec3 e = b.hi - b.lo;
  return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

Float axis_of(const Vec3& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

// Conty Estevez & Kulla 2018, §4.4 (the orientation measure of the SAOH): the solid
// angle the cone (θo, θe) emits into, weighted by cos θ,
//   M_Ω = 2π (1 − cos θo) + π/2 (2 θw sin θo − cos(θo − 2θw) − 2 θo sin θo + cos θo),
// θw = min(θo + θe, π).
Float orientation_measure(const LightBounds& b) {
  const Float theta_o = std::acos(std::clamp(b.cos_o, Float(-1), Float(1)));
  const Float theta_e = std::acos(std::clamp(b.cos_e, Float(-1), Float(1)));
  const Float theta_w = std::min(theta_o + theta_e, kPi);
  const Float sin_o = std::sqrt(std::max(Float(0), 1 - b.cos_o * b.cos_o));
  return 2 * kPi * (1 - b.cos_o) +
         kPi / 2 * (2 * theta_w * sin_o - std::cos(theta_o - 2 * theta_w) - 2 * theta_o * sin_o + b.cos_o);
}

// The SAOH cost of a node (Conty Estevez & Kulla 2018, eq. 4 without the constant
// denominator): power × orientation measure × surface area.
Float node_cost(const LightBounds& b) { return b.phi * orientation_measure(b) * surface_area(b); }

}  // namespace

std::optional<LightSamplerType> light_sampler_type_from_name(std::string_view name) {
  if (name == "bvh") return LightSamplerType::Bvh;
  if (name == "power") return LightSamplerType::Power;
  if (name == "uniform") return LightSamplerType::Uniform;
  return std::nullopt;
}

const char* light_sampler_type_name(LightSamplerType type) {
  switch (type) {
    case LightSamplerType::Bvh: return "bvh";
    case LightSamplerType::Power: return "power";
    case LightSamplerType::Uniform: return "uniform";
  }
  return "bvh";
}

Float light_power(const PointLight& light) { return 4 * kPi * light.intensity.average(); }

Float light_power(const AreaLight& light) {
  if (const auto* q = std::get_if<QuadLight>(&light))
    return kPi * q->radiance.average() * q->area() * (q->two_sided ? 2 : 1);
  const auto& s = std::get<SphereLight>(light);
  return kPi * s.radiance.average() * 4 * kPi * s.radius * s.radius;
}

Float light_power(const Environment& environment, Float scene_radius) {
  return kPi * environment.mean_radiance() * 4 * kPi * scene_radius * scene_radius;
}

LightBounds light_bounds(const AreaLight& light) {
  LightBounds b;
  b.phi = light_power(light);
  b.cos_e = 0;  // Lambertian emitters: up to 90° from the normal
  if (const auto* q = std::get_if<QuadLight>(&light)) {
    const std::array<Vec3, 4> corners = {q->corner, q->corner + q->edge1, q->corner + q->edge2,
                                         q->corner + q->edge1 + q->edge2};
    b.lo = b.hi = corners[0];
    for (const Vec3& c : corners) b.lo = vmin(b.lo, c), b.hi = vmax(b.hi, c);
    b.w = q->normal();
    b.cos_o = q->two_sided ? Float(-1) : Float(1);  // both sides: every direction
  } else {
    const auto& s = std::get<SphereLight>(light);
    const Vec3 r{s.radius, s.radius, s.radius};
    b.lo = s.center - r;
    b.hi = s.center + r;
    b.w = {0, 0, 1};
    b.cos_o = -1;  // normals in every direction
  }
  return b;
}

LightBounds merge(const LightBounds& a, const LightBounds& b) {
  if (!(a.phi > 0)) return b;
  if (!(b.phi > 0)) return a;
  LightBounds m;
  m.lo = vmin(a.lo, b.lo);
  m.hi = vmax(a.hi, b.hi);
  m.phi = a.phi + b.phi;
  m.cos_e = std::min(a.cos_e, b.cos_e);
  // The smallest cone holding both normal cones (Conty Estevez & Kulla 2018, Algorithm 1):
  // the wider cone grown by the half of what the narrower one sticks out beyond it.
  const LightBounds& wide = a.cos_o <= b.cos_o ? a : b;
  const LightBounds& narrow = a.cos_o <= b.cos_o ? b : a;
  const Float theta_a = std::acos(std::clamp(wide.cos_o, Float(-1), Float(1)));
  const Float theta_b = std::acos(std::clamp(narrow.cos_o, Float(-1), Float(1)));
  const Float cos_d = std::clamp(dot(wide.w, narrow.w), Float(-1), Float(1));
  const Float theta_d = std::acos(cos_d);
  m.w = wide.w;
  m.cos_o = wide.cos_o;
  if (std::min(theta_d + theta_b, kPi) <= theta_a) return m;
  const Float theta_o = (theta_a + theta_d + theta_b) / 2;
  const Vec3 ortho = narrow.w - wide.w * cos_d;
  const Float len = length(ortho);
  if (theta_o >= kPi || !(len > Float(1e-6))) {
    m.cos_o = -1;
    return m;
  }
  const Float theta_r = theta_o - theta_a;  // turn the axis towards the narrow cone's by this
  m.w = normalize(wide.w * std::cos(theta_r) + ortho * (std::sin(theta_r) / len));
  m.cos_o = std::cos(theta_o);
  return m;
}

Float LightBounds::importance(const Vec3& p, const Vec3& n) const {
  if (!(phi > 0)) return 0;
  const Vec3 to_p = p - (lo + hi) * Float(0.5);
  const Float d2 = length_squared(to_p);
  const Float r2 = length_squared(hi - lo) * Float(0.25);  // the bounding sphere's radius²
  // Inside the bounding sphere every direction may reach p: no angle bounds.
  if (!(d2 > r2)) return phi / std::max(r2, Float(1e-30));
  const Float sin2_b = r2 / d2;
  const Float sin_b = std::sqrt(sin2_b), cos_b = std::sqrt(std::max(Float(0), 1 - sin2_b));
  const Vec3 wp = to_p / std::sqrt(d2);
  // cos θ' for θ' = max(0, θw − θo − θb), by the angle-difference identities (no acos).
  Float cos_t = 1;
  const Float cos_w = std::clamp(dot(w, wp), Float(-1), Float(1));
  if (cos_w < cos_o) {  // θw > θo
    const Float sin_w = std::sqrt(std::max(Float(0), 1 - cos_w * cos_w));
    const Float sin_o = std::sqrt(std::max(Float(0), 1 - cos_o * cos_o));
    const Float cos_wo = cos_w * cos_o + sin_w * sin_o;  // cos(θw − θo)
    const Float sin_wo = sin_w * cos_o - cos_w * sin_o;  // sin(θw − θo) ≥ 0
    if (cos_wo < cos_b) cos_t = cos_wo * cos_b + sin_wo * sin_b;  // cos(θw − θo − θb)
  }
  if (cos_t <= cos_e) return 0;  // p is outside every emitter's emission cone
  // The receiver's cosine, bounded over the box: cos(max(0, θi − θb)), either side of n.
  Float cos_ti = 1;
  if (length_squared(n) > 0) {
    const Float cos_i = std::min(std::abs(dot(n, wp)) / length(n), Float(1));
    if (cos_i < cos_b) cos_ti = cos_i * cos_b + std::sqrt(std::max(Float(0), 1 - cos_i * cos_i)) * sin_b;
  }
  return phi * cos_t * cos_ti / d2;
}

LightSampler::LightSampler(const std::vector<AreaLight>& lights, const Environment* environment, Float scene_radius,
                           LightSamplerType type)
    : type_(type), area_count_(static_cast<int>(lights.size())), has_environment_(environment != nullptr) {
  if (type_ == LightSamplerType::Power) {
    // A CDF in double, stored as float with cdf_[n] = 1: light i's probability is the
    // length of its interval, exactly what cdf_interval's choice gives it.
    std::vector<double> power;
    for (const AreaLight& l : lights) power.push_back(std::max(0.0, double(light_power(l))));
    if (environment) power.push_back(std::max(0.0, double(light_power(*environment, scene_radius))));
    double total = 0;
    for (double p : power) total += p;
    const bool all_dark = !(total > 0) || !std::isfinite(total);
    if (all_dark) {  // nothing to weight by: every light alike
      std::fill(power.begin(), power.end(), 1.0);
      total = double(power.size());
    }
    cdf_.assign(power.size() + 1, 0.f);
    double run = 0;
    for (size_t i = 0; i < power.size(); ++i) {
      run += power[i];
      cdf_[i + 1] = float(run / total);
    }
    if (!power.empty()) cdf_.back() = 1.f;
  } else if (type_ == LightSamplerType::Bvh && area_count_ > 0) {
    std::vector<LightBounds> bounds;
    bounds.reserve(lights.size());
    for (const AreaLight& l : lights) bounds.push_back(light_bounds(l));
    std::vector<int> order(lights.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    trail_.assign(lights.size(), 0);
    nodes_.reserve(2 * lights.size());
    build(order, 0, area_count_, bounds, 0);
  }
}

// Splits [begin, end) of `order` by the SAOH (Conty Estevez & Kulla 2018, §4.4): over the
// three axes and 12 buckets of the lights' centres, the split of least
//   K_r (Φ_l M_Ω,l A_l + Φ_r M_Ω,r A_r),
// K_r = the node's longest extent / its extent along the axis (against thin slabs).
// Deeper than 32 levels (or with every centre equal) the split is at the median, so that
// a light's path fits the 64 bits of its trail.
int LightSampler::build(std::vector<int>& order, int begin, int end, const std::vector<LightBounds>& bounds,
                        int depth) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin == 1) {
    nodes_[size_t(index)].bounds = bounds[size_t(order[size_t(begin)])];
    nodes_[size_t(index)].leaf = true;
    nodes_[size_t(index)].second = order[size_t(begin)];
    return index;
  }
  LightBounds all = bounds[size_t(order[size_t(begin)])];
  Vec3 clo = (all.lo + all.hi) * Float(0.5), chi = clo;
  for (int i = begin + 1; i < end; ++i) {
    const LightBounds& b = bounds[size_t(order[size_t(i)])];
    all = merge(all, b);
    // A dark light's bounds do not enter `all` (merge): its box is kept apart.
    all.lo = vmin(all.lo, b.lo);
    all.hi = vmax(all.hi, b.hi);
    const Vec3 c = (b.lo + b.hi) * Float(0.5);
    clo = vmin(clo, c);
    chi = vmax(chi, c);
  }
  nodes_[size_t(index)].bounds = all;
  auto centre = [&](int light, int axis) {
    const LightBounds& b = bounds[size_t(light)];
    return axis_of((b.lo + b.hi) * Float(0.5), axis);
  };
  constexpr int kBuckets = 12;
  int best_axis = -1, best_bucket = -1;
  Float best_cost = std::numeric_limits<Float>::infinity();
  const Vec3 extent = all.hi - all.lo;
  const Float longest = std::max({extent.x, extent.y, extent.z});
  if (depth < 32) {
    for (int axis = 0; axis < 3; ++axis) {
      const Float c0 = axis_of(clo, axis), c1 = axis_of(chi, axis);
      if (!(c1 > c0)) continue;
      std::array<LightBounds, kBuckets> bucket{};
      std::array<int, kBuckets> count{};
      for (int i = begin; i < end; ++i) {
        const int light = order[size_t(i)];
        const int k = std::min(kBuckets - 1, static_cast<int>(Float(kBuckets) * (centre(light, axis) - c0) / (c1 - c0)));
        const LightBounds& b = bounds[size_t(light)];
        if (count[size_t(k)]++ == 0) bucket[size_t(k)] = b;
        else {
          bucket[size_t(k)] = merge(bucket[size_t(k)], b);
          bucket[size_t(k)].lo = vmin(bucket[size_t(k)].lo, b.lo);
          bucket[size_t(k)].hi = vmax(bucket[size_t(k)].hi, b.hi);
        }
      }
      const Float kr = axis_of(extent, axis) > 0 ? longest / axis_of(extent, axis) : Float(1);
      for (int split = 0; split + 1 < kBuckets; ++split) {
        LightBounds left, right;
        int nl = 0, nr = 0;
        for (int k = 0; k < kBuckets; ++k) {
          if (count[size_t(k)] == 0) continue;
          LightBounds& side = k <= split ? left : right;
          int& n = k <= split ? nl : nr;
          if (n == 0) side = bucket[size_t(k)];
          else {
            const LightBounds joined = merge(side, bucket[size_t(k)]);
            const Vec3 lo = vmin(side.lo, bucket[size_t(k)].lo), hi = vmax(side.hi, bucket[size_t(k)].hi);
            side = joined;
            side.lo = lo;
            side.hi = hi;
          }
          n += count[size_t(k)];
        }
        if (nl == 0 || nr == 0) continue;
        const Float cost = kr * (node_cost(left) + node_cost(right));
        if (cost < best_cost) best_cost = cost, best_axis = axis, best_bucket = split;
      }
    }
  }
  int mid;
  if (best_axis >= 0) {
    const Float c0 = axis_of(clo, best_axis), c1 = axis_of(chi, best_axis);
    const auto it = std::partition(order.begin() + begin, order.begin() + end, [&](int light) {
      const int k = std::min(kBuckets - 1, static_cast<int>(Float(kBuckets) * (centre(light, best_axis) - c0) / (c1 - c0)));
      return k <= best_bucket;
    });
    mid = static_cast<int>(it - order.begin());
  } else {
    mid = (begin + end) / 2;
  }
  if (mid <= begin || mid >= end) {
    // No bucket boundary separates the lights (or none was tried): halve by count along
    // the widest spread of centres.
    const Vec3 spread = chi - clo;
    const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
    mid = (begin + end) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](int a, int b) { return centre(a, axis) < centre(b, axis); });
  }
  // Children: the first right after this node, the second where it ends.
  const std::uint64_t bit = std::uint64_t(1) << depth;
  build(order, begin, mid, bounds, depth + 1);
  const int second = build(order, mid, end, bounds, depth + 1);
  nodes_[size_t(index)].second = second;
  // Each leaf below the second child gets this level's bit.
  for (int i = mid; i < end; ++i) trail_[size_t(order[size_t(i)])] |= bit;
  return index;
}

// The probability of the first child at an interior node: its share of the two children's
// importance at (p, n). A node's bounds are looser than its children's, so both children
// may bound p out while the node did not: then the children share by power instead, so
// that no choice is lost and the pmf over all lights sums to 1.
Float LightSampler::first_child_probability(int node, const Vec3& p, const Vec3& n) const {
  const Node& a = nodes_[size_t(node) + 1];
  const Node& b = nodes_[size_t(nodes_[size_t(node)].second)];
  Float ia = a.bounds.importance(p, n), ib = b.bounds.importance(p, n);
  if (!(ia + ib > 0) || !std::isfinite(ia + ib)) ia = a.bounds.phi, ib = b.bounds.phi;
  return ia + ib > 0 ? ia / (ia + ib) : Float(0.5);
}

Float LightSampler::area_share() const {
  if (area_count_ == 0) return 0;
  return has_environment_ ? 1 - kEnvironmentShare : Float(1);
}

LightSampler::Choice LightSampler::sample(const Vec3& p, const Vec3& n, Float u) const {
  const int total = count();
  if (total == 0) return {};
  switch (type_) {
    case LightSamplerType::Uniform: {
      const int i = std::min(static_cast<int>(u * Float(total)), total - 1);
      return {i, 1 / Float(total)};
    }
    case LightSamplerType::Power: {
      const int i = cdf_interval(cdf_.data(), total, u);
      const Float pmf = cdf_[size_t(i) + 1] - cdf_[size_t(i)];
      if (!(pmf > 0)) return {};
      return {i, pmf};
    }
    case LightSamplerType::Bvh: break;
  }
  if (has_environment_) {
    if (area_count_ == 0) return {environment_index(), 1};
    if (u < kEnvironmentShare) return {environment_index(), kEnvironmentShare};
    u = std::min((u - kEnvironmentShare) / (1 - kEnvironmentShare), kOneMinusEpsilon);
  }
  Float prob = area_share();
  int node = 0;
  while (!nodes_[size_t(node)].leaf) {
    const int a = node + 1, b = nodes_[size_t(node)].second;
    const Float pa = first_child_probability(node, p, n);
    if (u < pa) {
      u = std::min(u / pa, kOneMinusEpsilon);
      prob *= pa;
      node = a;
    } else {
      u = std::min((u - pa) / (1 - pa), kOneMinusEpsilon);
      prob *= 1 - pa;
      node = b;
    }
  }
  return {nodes_[size_t(node)].second, prob};
}

Float LightSampler::pmf(const Vec3& p, const Vec3& n, int light) const {
  if (light < 0 || light >= count()) return 0;
  switch (type_) {
    case LightSamplerType::Uniform: return 1 / Float(count());
    case LightSamplerType::Power: return cdf_[size_t(light) + 1] - cdf_[size_t(light)];
    case LightSamplerType::Bvh: break;
  }
  if (light == environment_index()) return area_count_ == 0 ? Float(1) : kEnvironmentShare;
  Float prob = area_share();
  std::uint64_t trail = trail_[size_t(light)];
  int node = 0;
  while (!nodes_[size_t(node)].leaf) {
    const int a = node + 1, b = nodes_[size_t(node)].second;
    const Float pa = first_child_probability(node, p, n);
    if (trail & 1) {
      prob *= 1 - pa;
      node = b;
    } else {
      prob *= pa;
      node = a;
    }
    trail >>= 1;
  }
  return prob;
}

}  // namespace gonio::render
