#pragma once
// The gantry of the virtual gonioreflectometer: incidences (θi, φi) of a distant light
// and detectors (θo, φo), each a cone of half-angle `aperture` around its direction.
//
// For each incidence N rays enter at uniform points of the patch above its highest point
// (on a periodic patch, uniform irradiance E) moving along −ωi. A detector measures
//   f = dL/dE = Σ w / (N · Ω),   Ω = ∫_cone |cos θ| dω,
// the power Σw/N reaching it per unit incident power, spread over the patch and the
// cone's projected solid angle (radiance L = dΦ / (dA cos θ dω), irradiance E = Φ/A).
// While the cone stays on one side of the horizon Ω = π sin²β |cos θc| (β the aperture);
// a cone that crosses the horizon counts only its part on its axis's side (quadrature).
// θo > 90° addresses transmission detectors below the patch (they see rays that left
// downwards). Standard errors come from the per-ray variance of each estimate, per RGB
// channel. Albedo = all power that left upwards, transmittance = all that left downwards.

#include <cstdint>
#include <string_view>
#include <vector>

#include "gonio/color.h"
#include "gonio/measure/instrument.h"
#include "gonio/measure/microsurface.h"

namespace gonio::measure {

struct GantrySpec {
  // Angles in degrees: θi in [0, 90), θo in [0, 180] except 90, φ any finite value.
  std::vector<double> theta_i{0}, phi_i{0}, theta_o, phi_o{0};
  double aperture = 2.0;  // detector half-angle β in degrees, (0, 30]
};

// Most incidences, detectors, and readings (incidences × detectors) of one run: every
// reading holds its sums per block batch and in the result, some 200 bytes of memory and
// of JSON output each, so a million readings take a few hundred MB, and 10^4 × 10^4
// (tens of GB) is refused before the first ray instead of failing for memory after it.
inline constexpr std::size_t kMaxGantryIncidences = 100'000;
inline constexpr std::size_t kMaxGantryDetectors = 100'000;
inline constexpr std::size_t kMaxGantryReadings = 1'000'000;

// JSON: {"theta_i": A, "phi_i": A, "theta_o": A, "phi_o": A, "aperture": deg}, each A a
// number, a list of numbers, or a range {"from": a, "to": b, "count": n} (both ends
// included). theta_o is required; theta_i, phi_i, phi_o default to 0 and aperture to 2.
// Throws InputError naming `source` and the field, or the bound exceeded (above).
GantrySpec parse_gantry(std::string_view json_text, std::string_view source = "--gantry");

// ∫ |cos θ| dω over the part of the cone (axis at polar angle theta_c, half-angle beta,
// radians) on its axis's side of the horizon.
double cone_projected_solid_angle(double theta_c, double beta);

struct DetectorReading {
  double theta_o = 0, phi_o = 0;  // degrees
  Color f, stderr_f;              // 1/sr
  std::uint64_t hits = 0;         // rays that reached it
  double solid_angle = 0;         // Ω, the cone's projected solid angle (sr)
};

struct IncidenceReading {
  double theta_i = 0, phi_i = 0;  // degrees
  RayCounts counts;
  Color albedo, stderr_albedo, transmittance, stderr_transmittance;
  std::vector<DetectorReading> detectors;  // theta_o-major, then phi_o
};

struct GantryReading {
  double aperture = 0;        // degrees
  std::uint64_t rays_per_incidence = 0;
  std::vector<IncidenceReading> incidences;  // theta_i-major, then phi_i
};

// options.samples rays in all, split evenly over the incidences (at least 1 each).
GantryReading run_gantry(const Microsurface& surface, const GantrySpec& spec, const RunOptions& options);

}  // namespace gonio::measure
