// gonio fresnel: exact (and Schlick) Fresnel reflectance for one incidence angle (SPEC §3).

#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "cli_io.h"
#include "commands.h"
#include "gonio/fresnel.h"

namespace gonio::cli {

namespace {
struct FresnelArgs {
  double eta = 1.5, k = 0, theta = 0;
  bool schlick = false;
};

void run_fresnel(const FresnelArgs& a) {
  const std::string index_range = "[" + show_number(kMinIndex) + ", " + show_number(kMaxIndex) + "]";
  if (!(a.eta >= kMinIndex && a.eta <= kMaxIndex))
    throw InputError("--eta must be in " + index_range + ", got " + show_number(a.eta));
  if (!(a.k >= 0 && a.k <= kMaxIndex))
    throw InputError("--k must be in [0, " + show_number(kMaxIndex) + "], got " + show_number(a.k));
  if (!(a.theta >= 0 && a.theta <= 90))
    throw InputError("--theta must be in [0, 90] degrees, got " + show_number(a.theta));
  const double cos_i = a.theta == 90 ? 0.0 : std::cos(a.theta * kPiD / 180);
  const bool conductor = a.k > 0;
  FresnelTerms<double> t;
  if (conductor) t = fresnel_conductor_terms(cos_i, a.eta, a.k);
  else t = fresnel_dielectric_terms(cos_i, a.eta);
  const double r = t.r();
  std::string out = "{\"Rs\":" + json_number(t.rs) + ",\"Rp\":" + json_number(t.rp) +
                    ",\"R\":" + json_number(r) + ",\"T\":" + json_number(1 - r) + ",\"cos_t\":" +
                    ((conductor || t.tir) ? std::string("null") : json_number(t.cos_t));
  if (a.schlick) {
    const double s = conductor ? fresnel_schlick(fresnel_f0(a.eta, a.k), cos_i)
                               : fresnel_schlick_dielectric(cos_i, a.eta);
    out += ",\"schlick\":" + json_number(s);
  }
  std::cout << out << "}\n";
}
}  // namespace

void register_fresnel(CLI::App& app) {
  auto args = std::make_shared<FresnelArgs>();
  auto* cmd = app.add_subcommand(
      "fresnel",
      "Fresnel reflectance at incidence --theta from the outside onto relative index --eta "
      "(+ i --k for a conductor); prints {\"Rs\",\"Rp\",\"R\",\"T\",\"cos_t\"}");
  cmd->add_option("--eta", args->eta, "relative index n_inside / n_outside (> 0)")->required();
  cmd->add_option("--k", args->k, "extinction coefficient (conductor); 0 or absent: dielectric");
  cmd->add_option("--theta", args->theta, "incidence angle in degrees, [0, 90]")->required();
  cmd->add_flag("--schlick", args->schlick, "also print Schlick's approximation");
  cmd->callback([args] { run_fresnel(*args); });
}

}  // namespace gonio::cli
