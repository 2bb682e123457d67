// The gantry of include/gonio/measure/gantry.h.
#include "gonio/measure/gantry.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/math/constants.h"
#include "waves.h"

namespace gonio::measure {
namespace {

constexpr double kDegree = kPiD / 180;

std::vector<double> parse_angles(const nlohmann::json& v, const std::string& where, double lo, double hi) {
  std::vector<double> out;
  auto number = [&](const nlohmann::json& x, const std::string& name) {
    if (!x.is_number()) throw InputError(name + " must be a number, got " + x.dump());
    const double d = x.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi)
      throw InputError(name + " must be in [" + format_number(lo) + ", " + format_number(hi) + "], got " +
                       format_number(d));
    return d;
  };
  if (v.is_number()) {
    out.push_back(number(v, where));
  } else if (v.is_array()) {
    if (v.empty()) throw InputError(where + " must not be empty");
    for (std::size_t k = 0; k < v.size(); ++k) out.push_back(number(v[k], where + "[" + std::to_string(k) + "]"));
  } else if (v.is_object()) {
    for (const auto& [key, _] : v.items())
      if (key != "from" && key != "to" && key != "count")
        throw InputError(where + ": unknown field \"" + key + "\" (a range has from, to, count)");
    if (!v.contains("from") || !v.contains("to") || !v.contains("count"))
      throw InputError(where + ": a range needs from, to and count");
    const double a = number(v["from"], where + ".from"), b = number(v["to"], where + ".to");
    const auto& c = v["count"];
    if (!c.is_number_integer() || c.get<std::int64_t>() < 1 || c.get<std::int64_t>() > 100000)
      throw InputError(where + ".count must be an integer in [1, 100000], got " + c.dump());
    const auto count = c.get<std::int64_t>();
    for (std::int64_t k = 0; k < count; ++k) out.push_back(count == 1 ? a : a + (b - a) * double(k) / double(count - 1));
  } else {
    throw InputError(where + " must be a number, a list of numbers or {\"from\",\"to\",\"count\"}, got " + v.dump());
  }
  if (out.size() > 100000) throw InputError(where + ": at most 100000 angles");
  return out;
}

// Running sums of one estimate per channel: Σx and Σx².
struct Moments {
  double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
  void add(const Color& x) {
    for (int c = 0; c < 3; ++c) s[c] += x[c], s2[c] += double(x[c]) * x[c];
  }
  void add(const Moments& o) {
    for (int c = 0; c < 3; ++c) s[c] += o.s[c], s2[c] += o.s2[c];
  }
  // The mean of N draws (zeros included) divided by `scale`, and its standard error.
  void mean(std::uint64_t n, double scale, Color& m, Color& se) const {
    for (int c = 0; c < 3; ++c) {
      const double mu = s[c] / double(n);
      const double var = n > 1 ? std::max(0.0, s2[c] / double(n) - mu * mu) / double(n - 1) : 0.0;
      m[c] = Float(mu / scale);
      se[c] = Float(std::sqrt(var) / scale);
    }
  }
};

struct BlockResult {
  RayCounts counts;
  Moments up, down;
  std::vector<Moments> det;
  std::vector<std::uint64_t> hits;
};

// The rings of detectors (one per θo) a direction with a given cos θ may fall in.
class DetectorRings {
 public:
  DetectorRings(const GantrySpec& spec, double cos_beta) {
    const double beta = std::acos(cos_beta), slack = 1e-4;
    std::vector<std::vector<std::uint32_t>> lists(kBuckets);
    for (std::size_t a = 0; a < spec.theta_o.size(); ++a) {
      const double theta = spec.theta_o[a] * kDegree;
      const double z_hi = std::cos(std::max(0.0, theta - beta)) + slack;
      const double z_lo = std::cos(std::min(kPiD, theta + beta)) - slack;
      for (int k = bucket(z_lo), last = bucket(z_hi); k <= last; ++k) lists[std::size_t(k)].push_back(std::uint32_t(a));
    }
    start_.push_back(0);
    for (const auto& l : lists) {
      rings_.insert(rings_.end(), l.begin(), l.end());
      start_.push_back(rings_.size());
    }
  }
  std::span<const std::uint32_t> near(double z) const {
    const std::size_t k = std::size_t(bucket(z));
    return {rings_.data() + start_[k], rings_.data() + start_[k + 1]};
  }

 private:
  static constexpr int kBuckets = 512;
  static int bucket(double z) {  // z in [−1, 1] (a unit vector's); NaN: bucket 0
    const double x = (std::clamp(z, -1.0, 1.0) + 1) * (kBuckets / 2);
    return x > 0 ? std::min(int(x), kBuckets - 1) : 0;
  }
  std::vector<std::uint32_t> rings_;
  std::vector<std::size_t> start_;
};

}  // namespace

GantrySpec parse_gantry(std::string_view json_text, std::string_view source) {
  const nlohmann::json j = parse_json_text(json_text, source);
  const std::string src(source);
  if (!j.is_object()) throw InputError(src + ": the gantry must be a JSON object");
  GantrySpec g;
  for (const auto& [key, _] : j.items())
    if (key != "theta_i" && key != "phi_i" && key != "theta_o" && key != "phi_o" && key != "aperture")
      throw InputError(src + ": unknown field \"" + key + "\" (expected theta_i, phi_i, theta_o, phi_o, aperture)");
  if (!j.contains("theta_o")) throw InputError(src + ": theta_o (the detectors' polar angles) is required");
  if (j.contains("theta_i")) g.theta_i = parse_angles(j["theta_i"], src + ": theta_i", 0, 89.999);
  if (j.contains("phi_i")) g.phi_i = parse_angles(j["phi_i"], src + ": phi_i", -360, 360);
  g.theta_o = parse_angles(j["theta_o"], src + ": theta_o", 0, 180);
  if (j.contains("phi_o")) g.phi_o = parse_angles(j["phi_o"], src + ": phi_o", -360, 360);
  for (const double t : g.theta_o)
    if (t == 90) throw InputError(src + ": theta_o = 90 lies in the horizon (below 90: reflection, above: transmission)");
  if (j.contains("aperture")) {
    const auto& a = j["aperture"];
    // Bounded below: the reading divides by the cone's projected solid angle, π sin²β cos θc,
    // which a vanishing β would make 0.
    if (!a.is_number() || !(a.get<double>() >= 0.01 && a.get<double>() <= 30))
      throw InputError(src + ": aperture must be a half-angle in [0.01, 30] degrees, got " + a.dump());
    g.aperture = a.get<double>();
  }
  const std::size_t incidences = g.theta_i.size() * g.phi_i.size(), detectors = g.theta_o.size() * g.phi_o.size();
  if (incidences > kMaxGantryIncidences || detectors > kMaxGantryDetectors)
    throw InputError(src + ": at most " + std::to_string(kMaxGantryIncidences) + " incidences and " +
                     std::to_string(kMaxGantryDetectors) + " detectors");
  if (incidences * detectors > kMaxGantryReadings)
    throw InputError(src + ": " + std::to_string(incidences) + " incidences x " + std::to_string(detectors) +
                     " detectors = " + std::to_string(incidences * detectors) + " readings, more than the " +
                     std::to_string(kMaxGantryReadings) + " one run may take");
  return g;
}

double cone_projected_solid_angle(double theta_c, double beta) {
  const double c = std::cos(theta_c), s = std::abs(std::sin(theta_c));
  const double sign = c >= 0 ? 1 : -1;
  if (std::abs(theta_c - (sign > 0 ? 0 : kPiD)) + beta <= kPiD / 2 + 1e-15)
    return kPiD * std::sin(beta) * std::sin(beta) * std::abs(c);  // the cone is on one side
  // A direction at angle α from the axis and azimuth ψ around it has
  // cos θ = cos α cos θc + sin α sin θc cos ψ; the ψ integral of max(0, A + B cos ψ) is in
  // closed form, the α integral by the midpoint rule.
  const int steps = 4096;
  double sum = 0;
  for (int k = 0; k < steps; ++k) {
    const double a = (k + 0.5) * beta / steps;
    const double A = sign * std::cos(a) * c, B = std::sin(a) * s;
    double inner;
    if (A >= B) inner = 2 * kPiD * A;
    else if (A <= -B) inner = 0;
    else {
      const double psi0 = std::acos(-A / B);
      inner = 2 * (A * psi0 + B * std::sin(psi0));
    }
    sum += inner * std::sin(a);
  }
  return sum * beta / steps;
}

GantryReading run_gantry(const Microsurface& surface, const GantrySpec& spec, const RunOptions& options) {
  GantryReading out;
  out.aperture = spec.aperture;
  const std::size_t n_inc = spec.theta_i.size() * spec.phi_i.size();
  const std::size_t n_det = spec.theta_o.size() * spec.phi_o.size();
  const std::uint64_t per = std::max<std::uint64_t>(1, options.samples / std::max<std::size_t>(1, n_inc));
  out.rays_per_incidence = per;
  const std::uint64_t blocks_per = (per + kBlockRays - 1) / kBlockRays;

  // Detector axes and their projected solid angles.
  const double cos_beta = std::cos(spec.aperture * kDegree);
  std::vector<Vec3> axis(n_det);
  std::vector<double> omega(n_det);
  std::vector<char> below(spec.theta_o.size());  // per θo: a transmission detector
  for (std::size_t a = 0; a < spec.theta_o.size(); ++a) {
    below[a] = spec.theta_o[a] > 90;
    for (std::size_t b = 0; b < spec.phi_o.size(); ++b) {
      const std::size_t d = a * spec.phi_o.size() + b;
      axis[d] = spherical_direction(spec.theta_o[a] * kDegree, spec.phi_o[b] * kDegree);
      omega[d] = cone_projected_solid_angle(spec.theta_o[a] * kDegree, spec.aperture * kDegree);
    }
  }

  std::vector<Vec3> light(n_inc);
  out.incidences.resize(n_inc);
  for (std::size_t a = 0; a < spec.theta_i.size(); ++a)
    for (std::size_t b = 0; b < spec.phi_i.size(); ++b) {
      const std::size_t i = a * spec.phi_i.size() + b;
      light[i] = -spherical_direction(spec.theta_i[a] * kDegree, spec.phi_i[b] * kDegree);
      out.incidences[i].theta_i = spec.theta_i[a];
      out.incidences[i].phi_i = spec.phi_i[b];
    }

  // Which detectors a leaving ray can be in, by its cos θ: a cone of half-angle β about θc
  // holds only polar angles in [θc − β, θc + β], so each ring of detectors (one θo) covers
  // a band of cos θ. The band's buckets list the rings that overlap them (widened by far
  // more than the float dot product's rounding), and the cone test itself decides, as for
  // every detector: a ray checks the few detectors near its polar angle, not all of them.
  const DetectorRings rings(spec, cos_beta);

  // Per incidence: the sums, merged block by block in order.
  std::vector<BlockResult> total(n_inc);
  for (auto& t : total) t.det.assign(n_det, {}), t.hits.assign(n_det, 0);

  detail::run_blocks<BlockResult>(
      blocks_per * n_inc, options.threads, options.progress,
      [&](BlockResult& r) {
        r.counts = {};
        r.up = r.down = {};
        r.det.assign(n_det, {});
        r.hits.assign(n_det, 0);
      },
      [&](std::uint64_t block, BlockResult& r) {
        const std::uint64_t inc = block / blocks_per, b = block % blocks_per;
        Pcg32 rng(options.seed, block_stream(inc, b));
        const std::uint64_t first = b * kBlockRays, last = std::min(per, first + kBlockRays);
        const Vec3 dir = light[inc];
        for (std::uint64_t k = first; k < last; ++k) {
          double u, v;
          entry_point(k - first, last - first == kBlockRays, rng, u, v);
          const TraceResult t = surface.trace(u, v, dir, rng);
          r.counts.add(t);
          if (t.fate != Fate::Up && t.fate != Fate::Down) continue;
          const bool up = t.fate == Fate::Up;
          (up ? r.up : r.down).add(t.weight);
          for (const std::uint32_t a : rings.near(t.direction.z)) {
            if (below[a] == up) continue;  // a reflection detector sees only rays going up
            for (std::size_t d = a * spec.phi_o.size(), e = d + spec.phi_o.size(); d < e; ++d)
              if (dot(t.direction, axis[d]) >= cos_beta) {
                r.det[d].add(t.weight);
                ++r.hits[d];
              }
          }
        }
      },
      [&](std::uint64_t block, const BlockResult& r) {
        BlockResult& t = total[block / blocks_per];
        t.counts += r.counts;
        t.up.add(r.up);
        t.down.add(r.down);
        for (std::size_t d = 0; d < n_det; ++d) t.det[d].add(r.det[d]), t.hits[d] += r.hits[d];
      });

  for (std::size_t i = 0; i < n_inc; ++i) {
    IncidenceReading& inc = out.incidences[i];
    const BlockResult& t = total[i];
    inc.counts = t.counts;
    t.up.mean(per, 1, inc.albedo, inc.stderr_albedo);
    t.down.mean(per, 1, inc.transmittance, inc.stderr_transmittance);
    inc.detectors.resize(n_det);
    for (std::size_t a = 0; a < spec.theta_o.size(); ++a)
      for (std::size_t b = 0; b < spec.phi_o.size(); ++b) {
        const std::size_t d = a * spec.phi_o.size() + b;
        DetectorReading& r = inc.detectors[d];
        r.theta_o = spec.theta_o[a];
        r.phi_o = spec.phi_o[b];
        r.solid_angle = omega[d];
        r.hits = t.hits[d];
        t.det[d].mean(per, omega[d], r.f, r.stderr_f);
      }
  }
  return out;
}

}  // namespace gonio::measure
