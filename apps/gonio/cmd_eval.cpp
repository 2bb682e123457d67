// gonio eval: f and pdf for direction pairs read from stdin (SPEC §3).

#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_io.h"
#include "cli_mueller.h"
#include "gonio/polarization/polarized_bxdf.h"
#include "commands.h"
#include "gonio/batch.h"

namespace gonio::cli {

namespace {
struct EvalArgs {
  std::string bsdf;
  std::string mode = "radiance";
  std::string wavelength;
  bool spectral = false;  // --wavelength given
  bool polarized = false;  // --polarized: add "mueller"
};

// The output lines for an RGB model or a spectral one at a single wavelength.
template <typename C>
std::string eval_lines(const BxDFT<C>& bxdf, TransportMode mode, const std::vector<std::array<double, 6>>& rows,
                       bool polarized = false) {
  std::vector<Vec3> wo(rows.size()), wi(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    wo[i] = unit_vector(r[0], r[1], r[2], i + 1, "wo");
    wi[i] = unit_vector(r[3], r[4], r[5], i + 1, "wi");
  }
  std::vector<C> f(rows.size());
  std::vector<Float> pdf(rows.size());
  eval_batch<C>(bxdf, wo, wi, mode, f, pdf);  // batch.h: the loop the Python module runs too
  std::string out;
  out.reserve(rows.size() * 64);
  const std::optional<PolarizedBxDFT<C>> pol = polarized ? std::optional<PolarizedBxDFT<C>>(bxdf) : std::nullopt;
  for (size_t i = 0; i < rows.size(); ++i) {
    out += "{\"f\":" + json_color(f[i]) + ",\"pdf\":" + json_number(pdf[i]);
    if (pol) out += ",\"mueller\":" + json_mueller_channels(pol->eval(wo[i], wi[i], mode).f);  // SPEC §3
    out += "}\n";
  }
  return out;
}

void run_eval(const EvalArgs& a) {
  const TransportMode mode = parse_mode(a.mode);
  if (a.spectral) {
    const Float nm = parse_wavelength(a.wavelength);
    const auto m = load_bsdf_at_wavelength(a.bsdf, nm);
    std::cout << eval_lines(m->bxdf, mode, read_six_numbers(std::cin), a.polarized);
    return;
  }
  const BxDF bxdf = load_bsdf(a.bsdf);
  std::cout << eval_lines(bxdf, mode, read_six_numbers(std::cin), a.polarized);
}
}  // namespace

void register_eval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* cmd = app.add_subcommand(
      "eval",
      "Evaluate f (1/sr, no cosine) and pdf for lines 'wo_x wo_y wo_z wi_x wi_y wi_z' on stdin; "
      "prints {\"f\":[r,g,b],\"pdf\":p} per line");
  cmd->add_option("--bsdf", args->bsdf, "material JSON text, or @path to a file holding it")->required();
  add_point_options(*cmd);
  add_mode_option(*cmd, args->mode);
  auto* wavelength = add_wavelength_option(*cmd, args->wavelength);
  cmd->add_flag("--polarized", args->polarized,
                "also print \"mueller\": one 4x4 Mueller matrix per colour channel, M00 = f (docs/polarization.md)");
  cmd->callback([args, wavelength] {
    args->spectral = wavelength->count() > 0;
    run_eval(*args);
  });
}

}  // namespace gonio::cli
