// gonio fresnel: exact (and Schlick) Fresnel reflectance at one angle or a range of
// angles, for an index given as numbers or as a named metal or glass (SPEC §3).

#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_io.h"
#include "cli_number.h"
#include "cli_mueller.h"
#include "commands.h"
#include "gonio/fresnel.h"
#include "gonio/math/degrees.h"
#include "gonio/named_index.h"
#include "gonio/polarization/interface.h"

namespace gonio::cli {

namespace {
struct FresnelArgs {
  double eta = 1.5, k = 0, theta = 0;
  std::vector<double> theta_range;
  std::string material;
  bool schlick = false;
  bool mueller = false;  // --mueller
  std::string wavelength;
  bool spectral = false;  // --wavelength given
};

// One channel's results, formatted.
struct FresnelLine {
  std::string rs, rp, r, t, cos_t, schlick;
  std::string mueller_r, mueller_t;  // --mueller; mueller_t empty for a conductor
};

FresnelLine fresnel_at(double eta, double k, double theta_deg) {
  const double cos_i = cos_degrees(theta_deg);
  const bool conductor = k > 0;
  const FresnelTerms<double> t = fresnel_terms(cos_i, eta, k);
  const double r = t.r();
  FresnelLine l{json_number(t.rs), json_number(t.rp), json_number(r), json_number(1 - r),
                (conductor || t.tir) ? std::string("null") : json_number(t.cos_t),
                json_number(fresnel_schlick_terms(cos_i, eta, k)), "", ""};
  // The Mueller matrices of polarization/interface.h, their M00 the R and T printed.
  const auto amp = conductor ? fresnel_conductor_amplitudes(cos_i, eta, k) : fresnel_dielectric_amplitudes(cos_i, eta);
  Mueller mr = mueller_reflection(amp);
  mr(0, 0) = mr(1, 1) = r;
  l.mueller_r = json_mueller(mr);
  if (!conductor) {
    Mueller mt = mueller_transmission(amp);
    if (!t.tir) mt(0, 0) = mt(1, 1) = 1 - r;
    l.mueller_t = json_mueller(mt);
  }
  return l;
}

// `index`: with --wavelength, the "eta" and "k" used (SPEC §3), appended.
std::string object(const std::vector<FresnelLine>& channels, bool schlick, bool mueller, const std::string& index = "") {
  // One channel: numbers (SPEC §3); three (a named material in RGB mode): arrays.
  auto field = [&](std::string FresnelLine::*member) {
    if (channels.size() == 1) return channels[0].*member;
    std::string s = "[";
    for (size_t i = 0; i < channels.size(); ++i) s += (i ? "," : "") + channels[i].*member;
    return s + "]";
  };
  std::string out = "{\"Rs\":" + field(&FresnelLine::rs) + ",\"Rp\":" + field(&FresnelLine::rp) +
                    ",\"R\":" + field(&FresnelLine::r) + ",\"T\":" + field(&FresnelLine::t) +
                    ",\"cos_t\":" + field(&FresnelLine::cos_t);
  if (schlick) out += ",\"schlick\":" + field(&FresnelLine::schlick);
  if (mueller) {
    out += ",\"mueller_r\":" + field(&FresnelLine::mueller_r);
    if (!channels[0].mueller_t.empty()) out += ",\"mueller_t\":" + field(&FresnelLine::mueller_t);
  }
  return out + index + "}\n";
}

void run_fresnel(const FresnelArgs& a) {
  // (eta, k) per channel.
  std::vector<std::pair<double, double>> index;
  const std::optional<Float> nm = a.spectral ? std::optional<Float>(parse_wavelength(a.wavelength)) : std::nullopt;
  if (!a.material.empty()) {
    index = named_index(a.material, nm);
  } else {
    check_fresnel_index(a.eta, a.k);
    index.emplace_back(a.eta, a.k);
  }
  // With --wavelength: one channel, and the index used.
  // A named material's index is a float (the tables'), printed as one (SPEC §1: %.9g).
  auto index_number = [&](double v) { return a.material.empty() ? json_number(v) : json_number(Float(v)); };
  const std::string used =
      nm ? ",\"eta\":" + index_number(index[0].first) + ",\"k\":" + index_number(index[0].second) : std::string();
  std::vector<double> thetas;
  if (!a.theta_range.empty()) {
    thetas = angle_range(a.theta_range, "--theta-range", 0, 90);
  } else {
    if (!(a.theta >= 0 && a.theta <= 90))
      throw InputError("--theta must be in [0, 90] degrees, got " + format_number(a.theta));
    thetas.push_back(a.theta);
  }
  // Everything is computed before anything is written.
  std::string out;
  for (double theta : thetas) {
    std::vector<FresnelLine> channels;
    for (const auto& [eta, k] : index) channels.push_back(fresnel_at(eta, k, theta));
    out += object(channels, a.schlick, a.mueller, used);
  }
  std::cout << out;
}
}  // namespace

void register_fresnel(CLI::App& app) {
  auto args = std::make_shared<FresnelArgs>();
  auto* cmd = app.add_subcommand(
      "fresnel",
      "Fresnel reflectance at incidence --theta (or each angle of --theta-range) from the outside onto "
      "relative index --eta (+ i --k for a conductor) or a named --material; prints "
      "{\"Rs\",\"Rp\",\"R\",\"T\",\"cos_t\"} per angle");
  auto* eta = cmd->add_option("--eta", args->eta, "relative index n_inside / n_outside (> 0)")
                   ->check(decimal_number());
  auto* k = cmd->add_option("--k", args->k, "extinction coefficient (conductor); 0 or absent: dielectric")
                 ->check(decimal_number());
  auto* material = cmd->add_option(
      "--material", args->material,
      "a named metal (Au, Ag, Cu, Al, CuZn) or glass (BK7, ...) instead of --eta/--k: every field becomes "
      "[r, g, b], the RGB-mode index (a glass: at 650, 550, 450 nm; a metal: n there, k fitted to its colour)");
  material->excludes(eta)->excludes(k);
  auto* theta = cmd->add_option("--theta", args->theta, "incidence angle in degrees, [0, 90]")
                     ->check(decimal_number());
  auto* range = cmd->add_option("--theta-range", args->theta_range,
                                "FROM TO COUNT: COUNT angles from FROM to TO degrees, evenly spaced, one line each")
                    ->expected(3)
                    ->check(decimal_number());
  range->excludes(theta);
  cmd->add_flag("--schlick", args->schlick, "also print Schlick's approximation");
  cmd->add_flag("--mueller", args->mueller,
                "also print the Mueller matrices \"mueller_r\" (reflection) and, for a dielectric, \"mueller_t\" "
                "(transmitted power), 4x4 row-major in the s/p basis, Q = I_s - I_p (docs/polarization.md)");
  auto* wavelength = cmd->add_option(
      "--wavelength", args->wavelength,
      "NM: the index at this one wavelength in nm, [360, 830] (a named --material's measured n, k there); "
      "the fields stay numbers and \"eta\", \"k\" (the index used) are added");
  cmd->callback([args, eta, material, theta, range, wavelength] {
    args->spectral = wavelength->count() > 0;
    if (eta->count() == 0 && material->count() == 0) throw InputError("fresnel: give --eta N (or --material NAME)");
    if (theta->count() == 0 && range->count() == 0)
      throw InputError("fresnel: give --theta DEG (or --theta-range FROM TO COUNT)");
    run_fresnel(*args);
  });
}

}  // namespace gonio::cli
