// Probe-ray sampling of the exit point (King et al. 2013; pbrt-v3 §15.4.1).

#include "gonio/render/subsurface_probe.h"

#include <array>
#include <cmath>

namespace gonio::render {
namespace {

// The axis probability of King et al.: the normal half the time (on flat surfaces it finds
// the exit alone), each tangent a quarter (for the exits on surfaces at an angle).
constexpr std::array<Float, 3> kAxisProb = {0.25f, 0.25f, 0.5f};  // s, t, n

// Channels with a profile to sample; each is chosen with probability 1 / count.
int active_channels(const DiffusionProfile& profile, std::array<int, 3>& which) {
  int m = 0;
  for (int c = 0; c < Color::size(); ++c)
    if (profile.r_max(c) > 0) which[static_cast<size_t>(m++)] = c;
  return m;
}

}  // namespace

Float probe_exit_pdf(const SurfaceHit& entry, const Frame& frame, const DiffusionProfile& profile,
                     const SurfaceHit& exit) {
  std::array<int, 3> which{};
  const int m = active_channels(profile, which);
  if (m == 0) return 0;
  const Vec3 d = frame.to_local(exit.p - entry.p);
  const Vec3 n = frame.to_local(exit.ng);
  // Distance from the entry point within the disc of each axis (the plane it is normal to)
  // and the cosine that turns a density over that disc into one over the surface.
  const std::array<Float, 3> r_proj = {std::sqrt(d.y * d.y + d.z * d.z), std::sqrt(d.x * d.x + d.z * d.z),
                                       std::sqrt(d.x * d.x + d.y * d.y)};
  const std::array<Float, 3> cosine = {std::abs(n.x), std::abs(n.y), std::abs(n.z)};
  // A channel's probes are chords of its own sphere of radius r_max: a point farther than
  // that from the entry is on none of them, whatever its distance within a disc.
  const Float dist2 = length_squared(d);
  Float pdf = 0;
  for (int j = 0; j < m; ++j) {
    const int c = which[static_cast<size_t>(j)];
    if (dist2 > profile.r_max(c) * profile.r_max(c)) continue;
    for (int a = 0; a < 3; ++a)
      pdf += kAxisProb[static_cast<size_t>(a)] * profile.pdf_r(c, r_proj[static_cast<size_t>(a)]) * cosine[static_cast<size_t>(a)];
  }
  return pdf / static_cast<Float>(m);
}

std::optional<ProbeExit<Color>> sample_probe_exit(const Accel& accel, const SurfaceHit& entry, const Frame& frame,
                                                  const DiffusionProfile& profile, Pcg32& rng) {
  std::array<int, 3> which{};
  const int m = active_channels(profile, which);
  if (m == 0) return std::nullopt;
  // The probe axis and the disc's two directions.
  const Float ua = rng.next_float();
  Vec3 axis = frame.n, b1 = frame.s, b2 = frame.t;
  if (ua >= kAxisProb[2]) {
    if (ua < kAxisProb[2] + kAxisProb[0]) {
      axis = frame.s, b1 = frame.t, b2 = frame.n;
    } else {
      axis = frame.t, b1 = frame.n, b2 = frame.s;
    }
  }
  const int ch = which[static_cast<size_t>(std::min(static_cast<int>(rng.next_float() * static_cast<Float>(m)), m - 1))];
  const Float r = profile.sample_r(ch, rng.next_float());
  const Float r_max = profile.r_max(ch);
  const Float half = std::sqrt(std::max(Float(0), r_max * r_max - r * r));
  if (!(half > 0)) return std::nullopt;
  const Float phi = 2 * kPi * rng.next_float();
  const Vec3 on_disc = entry.p + (b1 * std::cos(phi) + b2 * std::sin(phi)) * r;
  // The chord of the sphere of radius r_max through the disc point, along the axis.
  const Ray probe{on_disc + axis * half, -axis, 2 * half};
  // One crossing of the same material, uniformly, by reservoir sampling: no list is kept.
  SurfaceHit chosen;
  int count = 0;
  accel.for_each_hit(probe, [&](const SurfaceHit& h) {
    if (h.material != entry.material) return true;
    ++count;
    if (rng.next_float() * static_cast<Float>(count) < 1) chosen = h;
    return true;
  });
  if (count == 0) return std::nullopt;
  const Float pdf = probe_exit_pdf(entry, frame, profile, chosen);
  if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  const Color weight = profile.Sp(length(chosen.p - entry.p)) * (static_cast<Float>(count) / pdf);
  if (!weight.is_finite()) return std::nullopt;
  return ProbeExit<Color>{chosen, weight};
}

}  // namespace gonio::render
