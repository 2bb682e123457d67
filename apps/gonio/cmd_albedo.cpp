// gonio albedo: directional–hemispherical (or hemispherical–hemispherical) reflectance
// and transmittance (SPEC §3; lecture §4).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_io.h"
#include "cli_number.h"
#include "commands.h"
#include "cli_work.h"
#include "gonio/hemispherical_average.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/reflectance.h"
#include "gonio/rng.h"

namespace gonio::cli {

namespace {
struct AlbedoArgs {
  std::string bsdf;
  double theta = 0, phi = 0;
  std::vector<double> theta_range;
  bool hemispherical = false, inside = false;
  std::int64_t samples = 1 << 20;
  std::int64_t seed = 1;
  std::string wavelength;
  bool spectral = false;  // --wavelength given
  bool polarized = false;  // --polarized: accepted, no effect (below)
};

double checked_degrees(double v, double lo, double hi, const char* name) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(std::string(name) + " must be in [" + format_number(lo) + ", " + format_number(hi) +
                     "] degrees, got " + format_number(v));
  return v * kPiD / 180;
}

// --- Output -------------------------------------------------------------------------
// The view's figures (SPEC §3), then, for a model that is not reciprocal, the light's.
template <typename Estimate>
std::string albedo_line(const Estimate& e, const std::string& theta) {
  std::string line = "{\"theta\":" + theta + ",\"reflectance\":" + json_color(e.reflectance) +
                     ",\"transmittance\":" + json_color(e.transmittance) + ",\"albedo\":" + json_color(e.albedo) +
                     ",\"stderr\":" + json_color(e.se_albedo) + ",\"stderr_reflectance\":" +
                     json_color(e.se_reflectance) + ",\"stderr_transmittance\":" + json_color(e.se_transmittance);
  if (e.light)
    line += ",\"reflectance_light\":" + json_color(e.light->reflectance) + ",\"transmittance_light\":" +
            json_color(e.light->transmittance) + ",\"stderr_reflectance_light\":" +
            json_color(e.light->se_reflectance) + ",\"stderr_transmittance_light\":" +
            json_color(e.light->se_transmittance);
  return line + ",\"exact\":" + (e.exact ? "true" : "false") + "}\n";
}

// An RGB model or a spectral one at a single wavelength (reflectance.h takes both).
template <typename Model>
void run_albedo_with(const AlbedoArgs& a, const Model& bxdf) {
  const ReflectanceOptions opt{std::uint64_t(a.samples), std::uint64_t(a.seed)};
  if (a.hemispherical) {
    check_cli_work(bxdf, double(a.samples), "albedo");
    std::cout << albedo_line(hemispherical_albedo(bxdf, a.inside, opt), "null");
    return;
  }
  const double p = checked_degrees(a.phi, -360, 360, "--phi");
  std::vector<double> thetas;
  if (!a.theta_range.empty()) {
    thetas = angle_range(a.theta_range, "--theta-range", 0, 90);
  } else {
    checked_degrees(a.theta, 0, 90, "--theta");
    thetas.push_back(a.theta);
  }
  check_cli_work(bxdf, double(a.samples) * double(thetas.size()), "albedo");
  // Each angle with the same seed, so a line equals the --theta run at its angle; every
  // line is formatted before anything is written.
  std::string out;
  for (double theta : thetas) {
    const double t = theta * kPiD / 180;
    const double z = std::cos(t);
    const Vec3 wo{Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)), Float(a.inside ? -z : z)};
    out += albedo_line(directional_albedo(bxdf, wo, opt), json_number(theta));
  }
  std::cout << out;
}

void run_albedo(const AlbedoArgs& a) {
  if (a.spectral) {
    const Float nm = parse_wavelength(a.wavelength);
    const auto m = load_bsdf_at_wavelength(a.bsdf, nm);
    run_albedo_with(a, m->bxdf);
    return;
  }
  run_albedo_with(a, load_bsdf(a.bsdf));
}
}  // namespace

void register_albedo(CLI::App& app) {
  auto args = std::make_shared<AlbedoArgs>();
  auto* cmd = app.add_subcommand(
      "albedo",
      "The view's directional-hemispherical reflectance, transmittance (refraction scaling removed) and "
      "albedo for wo at --theta (and --phi; 90 reports the limit), or their cosine-weighted average with "
      "--hemispherical; a model that is not reciprocal adds the light's (reflectance_light, transmittance_light)");
  cmd->add_option("--bsdf", args->bsdf, "material JSON text, or @path to a file holding it")->required();
  add_point_options(*cmd);
  auto* theta = cmd->add_option("--theta", args->theta, "polar angle of wo in degrees, [0, 90]")
                     ->check(decimal_number());
  auto* range = cmd->add_option("--theta-range", args->theta_range,
                                "FROM TO COUNT: COUNT polar angles from FROM to TO degrees, evenly spaced, one line each")
                    ->expected(3)
                    ->check(decimal_number());
  range->excludes(theta);
  auto* phi = cmd->add_option("--phi", args->phi, "azimuth of wo in degrees (default 0)")
                   ->check(decimal_number());
  auto* hemi = cmd->add_flag("--hemispherical", args->hemispherical,
                             "rho_hh: average over all wo on one side, cosine-weighted (theta ignored)");
  theta->excludes(hemi);
  range->excludes(hemi);
  phi->excludes(hemi);
  cmd->add_flag("--inside", args->inside, "put wo on the z < 0 side");
  cmd->add_option("--samples", args->samples, "Monte Carlo samples, 1 to 10^12 (default 1048576)")
      ->transform(decimal_in_range(1, kMaxSamples));
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (default 1)")->transform(decimal_in_range(0, kMaxSeed));
  auto* wavelength = add_wavelength_option(*cmd, args->wavelength);
  // SPEC §3 lists it for albedo too: the albedo of unpolarized light is M00's, the same.
  cmd->add_flag("--polarized", args->polarized,
                "accepted as for eval and sample; the albedo of unpolarized light is that of M00, so the output is unchanged");
  cmd->callback([args, theta, range, hemi, wavelength] {
    args->spectral = wavelength->count() > 0;
    if (theta->count() == 0 && range->count() == 0 && hemi->count() == 0)
      throw InputError("albedo: give --theta DEG, --theta-range FROM TO COUNT or --hemispherical");
    run_albedo(*args);
  });
}

}  // namespace gonio::cli
