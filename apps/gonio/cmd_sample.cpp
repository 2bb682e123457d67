// gonio sample: importance-sample wi for lines 'wo u0 u1 u2' read from stdin (SPEC §3), or,
// with --count N, N samples per line 'wo' from gonio's own random numbers.

#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "gonio/rng.h"

#include "cli_io.h"
#include "cli_mueller.h"
#include "gonio/polarization/polarized_bxdf.h"
#include "commands.h"

namespace gonio::cli {

namespace {
struct SampleArgs {
  std::string bsdf;
  std::string mode = "radiance";
  std::int64_t count = 0;  // 0: the u's come from stdin
  std::int64_t seed = 1;
  std::string wavelength;
  bool spectral = false;  // --wavelength given
  bool polarized = false;  // --polarized: add "mueller" (of the weight)
};

// Largest --count: samples drawn per input line.
constexpr std::int64_t kMaxCount = 100'000'000;

Float unit_interval(double u, size_t line, const char* name) {
  if (!(u >= 0 && u < 1))
    throw InputError("stdin line " + std::to_string(line) + ": " + name + " must be in [0, 1), got " +
                     json_number(u));
  // Rounding to float may reach 1; keep it inside [0, 1).
  return std::min(Float(u), kOneMinusEpsilon);
}

template <typename C>
void append_sample(std::string& out, const BxDFT<C>& bxdf, const Vec3& wo, Float u0, Float u1, Float u2,
                   TransportMode mode, const PolarizedBxDFT<C>* pol = nullptr) {
  const auto s = bxdf.sample(wo, u0, u1, u2, mode);
  if (!s) {
    out += "{\"wi\":null}\n";
    return;
  }
  out += "{\"wi\":[" + json_number(s->wi.x) + "," + json_number(s->wi.y) + "," + json_number(s->wi.z) +
         "],\"weight\":" + json_color(s->weight) +
         ",\"pdf\":" + (s->delta ? std::string("null") : json_number(s->pdf)) +
         ",\"delta\":" + (s->delta ? "true" : "false") + ",\"lobe\":\"" +
         (s->lobe == Lobe::Reflection ? "reflection" : "transmission") + "\"";
  // The same sample in polarized mode (the same wi; M00 = weight).
  if (pol)
    if (const auto p = pol->sample(wo, u0, u1, u2, mode)) out += ",\"mueller\":" + json_mueller_channels(p->weight);
  out += "}\n";
}

// The samples of an RGB model or of a spectral one at a single wavelength.
template <typename C>
void run_sample_with(const SampleArgs& a, const BxDFT<C>& bxdf) {
  const TransportMode mode = parse_mode(a.mode);
  const std::optional<PolarizedBxDFT<C>> polarized =
      a.polarized ? std::optional<PolarizedBxDFT<C>>(bxdf) : std::nullopt;
  const PolarizedBxDFT<C>* pol = polarized ? &*polarized : nullptr;
  if (a.count > 0) {
    // Lines 'wo' only; line i draws its u's from PCG32 stream i of the seed, so a line's
    // samples do not depend on the lines before it. All input is checked first.
    const auto rows = read_numbers(std::cin, 3, " (wo only: --count draws the u's)");
    std::vector<Vec3> wos;
    for (size_t i = 0; i < rows.size(); ++i) wos.push_back(unit_vector(rows[i][0], rows[i][1], rows[i][2], i + 1, "wo"));
    std::string out;
    for (size_t i = 0; i < wos.size(); ++i) {
      Pcg32 rng(std::uint64_t(a.seed), std::uint64_t(i));
      for (std::int64_t n = 0; n < a.count; ++n) {
        const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
        append_sample(out, bxdf, wos[i], u0, u1, u2, mode, pol);
        if (out.size() > (1 << 20)) {
          std::cout << out;
          out.clear();
        }
      }
    }
    std::cout << out;
    return;
  }
  const auto rows = read_six_numbers(std::cin);
  std::string out;
  out.reserve(rows.size() * 128);
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const Vec3 wo = unit_vector(r[0], r[1], r[2], i + 1, "wo");
    const Float u0 = unit_interval(r[3], i + 1, "u0");
    const Float u1 = unit_interval(r[4], i + 1, "u1");
    const Float u2 = unit_interval(r[5], i + 1, "u2");
    append_sample(out, bxdf, wo, u0, u1, u2, mode, pol);
  }
  std::cout << out;
}
void run_sample(const SampleArgs& a) {
  if (a.spectral) {
    const Float nm = parse_wavelength(a.wavelength);
    const auto m = load_bsdf_at_wavelength(a.bsdf, nm);
    run_sample_with(a, m->bxdf);
    return;
  }
  run_sample_with(a, load_bsdf(a.bsdf));
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
  auto* count = cmd->add_option("--count", args->count,
                                "N samples per stdin line 'wo_x wo_y wo_z', with gonio's own random u's "
                                "(1 to 100000000)")
                    ->transform(decimal_in_range(1, kMaxCount));
  cmd->add_option("--seed", args->seed, "random seed for --count, 0 to 2147483647 (default 1)")
      ->transform(decimal_in_range(0, kMaxSeed))
      ->needs(count);
  auto* wavelength = add_wavelength_option(*cmd, args->wavelength);
  cmd->add_flag("--polarized", args->polarized,
                "also print \"mueller\": the weight as one 4x4 Mueller matrix per colour channel (docs/polarization.md)");
  cmd->callback([args, wavelength] {
    args->spectral = wavelength->count() > 0;
    run_sample(*args);
  });
}

}  // namespace gonio::cli
