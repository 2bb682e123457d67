// gonio sample: importance-sample wi for lines 'wo u0 u1 u2' read from stdin (SPEC §3).

#include <iostream>
#include <memory>
#include <string>

#include "cli_io.h"
#include "commands.h"

namespace gonio::cli {

namespace {
struct SampleArgs {
  std::string bsdf;
  std::string mode = "radiance";
};

Float unit_interval(double u, size_t line, const char* name) {
  if (!(u >= 0 && u < 1))
    throw InputError("stdin line " + std::to_string(line) + ": " + name + " must be in [0, 1), got " +
                     json_number(u));
  // Rounding to float may reach 1; keep it inside [0, 1).
  return std::min(Float(u), kOneMinusEpsilon);
}

void run_sample(const SampleArgs& a) {
  const BxDF bxdf = load_bsdf(a.bsdf);
  const TransportMode mode = parse_mode(a.mode);
  const auto rows = read_six_numbers(std::cin);
  std::string out;
  out.reserve(rows.size() * 128);
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const Vec3 wo = unit_vector(r[0], r[1], r[2], i + 1, "wo");
    const Float u0 = unit_interval(r[3], i + 1, "u0");
    const Float u1 = unit_interval(r[4], i + 1, "u1");
    const Float u2 = unit_interval(r[5], i + 1, "u2");
    const auto s = bxdf.sample(wo, u0, u1, u2, mode);
    if (!s) {
      out += "{\"wi\":null}\n";
      continue;
    }
    out += "{\"wi\":[" + json_number(s->wi.x) + "," + json_number(s->wi.y) + "," +
           json_number(s->wi.z) + "],\"weight\":" + json_color(s->weight) +
           ",\"pdf\":" + (s->delta ? std::string("null") : json_number(s->pdf)) +
           ",\"delta\":" + (s->delta ? "true" : "false") + ",\"lobe\":\"" +
           (s->lobe == Lobe::Reflection ? "reflection" : "transmission") + "\"}\n";
  }
  std::cout << out;
}
}  // namespace

void register_sample(CLI::App& app) {
  auto args = std::make_shared<SampleArgs>();
  auto* cmd = app.add_subcommand(
      "sample",
      "Sample wi for lines 'wo_x wo_y wo_z u0 u1 u2' on stdin (u in [0,1); u0 picks the lobe); "
      "prints {\"wi\",\"weight\",\"pdf\",\"delta\",\"lobe\"} or {\"wi\":null}");
  cmd->add_option("--bsdf", args->bsdf, "material JSON text, or @path to a file holding it")->required();
  add_mode_option(*cmd, args->mode);
  cmd->callback([args] { run_sample(*args); });
}

}  // namespace gonio::cli
