// Speed and quality of `gonio fit` (docs/fitting.md): tables made from analytic materials
// (f at each bin's centre, as `gonio tabulate` writes), every model fitted to each.
//   gonio_bench_fit                       the table of docs/fitting.md (both metrics)
//   gonio_bench_fit write JSON OUT.binary  a table of material JSON, for `gonio fit --data`

#include <cstdio>
#include <string>
#include <vector>

#include "gonio/fit/fit.h"
#include "gonio/material.h"
#include "gonio/merl.h"

namespace {

gonio::MerlTable tabulate(const std::string& json) {
  const gonio::BxDF m = gonio::parse_material(json);
  gonio::MerlTable t;
  for (int i = 0; i < gonio::MerlTable::kThetaH; ++i)
    for (int j = 0; j < gonio::MerlTable::kThetaD; ++j)
      for (int k = 0; k < gonio::MerlTable::kPhiD; ++k) {
        const auto [wo, wi] = gonio::merl_directions(gonio::merl_theta_h(i), gonio::merl_theta_d(j), gonio::merl_phi_d(k));
        if (wo.z > 0 && wi.z > 0) t.set(i, j, k, m.f(wo, wi));
        else t.set_missing(i, j, k);  // below the horizon: no measurement
      }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "write") {
    gonio::write_merl(argv[3], tabulate(argv[2]));
    return 0;
  }
  const std::vector<std::pair<std::string, std::string>> tables = {
      {"GGX", R"({"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":[0.9,0.6,0.3]})"},
      {"blend", R"({"type":"blend","weight":0.3,"bsdfs":[{"type":"diffuse","reflectance":[0.5,0.2,0.1]},)"
                R"({"type":"roughconductor","alpha":0.1,"fresnel":"schlick","f0":0.9}]})"},
  };
  for (const auto& [name, json] : tables) {
    const gonio::MerlTable table = tabulate(json);
    for (const char* metric : {"log", "ngan"})
      for (const auto& model : gonio::fit_model_names()) {
        gonio::FitOptions o;
        o.model = model;
        o.metric = gonio::parse_fit_metric(metric);
        const gonio::FitResult r = gonio::fit_merl(table, o);
        std::printf("| %s | %s | %s | %.4g | %d | %lld | %.2f | `%s` |\n", name.c_str(), metric, model.c_str(), r.error,
                    r.starts, r.evaluations, r.seconds, r.material.dump().c_str());
        std::fflush(stdout);
      }
  }
}
