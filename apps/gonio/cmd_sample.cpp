// gonio sample: importance-sample wi for lines 'wo u0 u1 u2' read from stdin (SPEC §3), or,
// with --count N, N samples per line 'wo' from gonio's own random numbers.

#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <algorithm>
#include <span>
#include <vector>

#include "gonio/batch.h"
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

// Samples drawn per batch call (batch.h), the buffers reused from one call to the next.
constexpr size_t kChunk = 4096;

template <typename C>
struct SampleBuffers {
  std::vector<Vec3> wi = std::vector<Vec3>(kChunk);
  std::vector<C> weight = std::vector<C>(kChunk);
  std::vector<Float> pdf = std::vector<Float>(kChunk);
  std::vector<std::uint8_t> delta = std::vector<std::uint8_t>(kChunk);
  std::vector<BatchLobe> lobe = std::vector<BatchLobe>(kChunk);
};

// Samples wo[i] with u[i] for every i (at most kChunk) and appends their lines.
template <typename C>
void append_samples(std::string& out, const BxDFT<C>& bxdf, std::span<const Vec3> wo,
                    std::span<const SampleUniforms> u, TransportMode mode, SampleBuffers<C>& b,
                    const PolarizedBxDFT<C>* pol) {
  const size_t n = wo.size();
  sample_batch<C>(bxdf, wo, u, mode,
                  {std::span(b.wi).first(n), std::span(b.weight).first(n), std::span(b.pdf).first(n),
                   std::span(b.delta).first(n), std::span(b.lobe).first(n)});
  for (size_t i = 0; i < n; ++i) {
    if (b.lobe[i] == BatchLobe::None) {
      out += "{\"wi\":null}\n";
      continue;
    }
    const bool delta = b.delta[i] != 0;
    out += "{\"wi\":[" + json_number(b.wi[i].x) + "," + json_number(b.wi[i].y) + "," + json_number(b.wi[i].z) +
           "],\"weight\":" + json_color(b.weight[i]) +
           ",\"pdf\":" + (delta ? std::string("null") : json_number(b.pdf[i])) +
           ",\"delta\":" + (delta ? "true" : "false") + ",\"lobe\":\"" +
           (b.lobe[i] == BatchLobe::Reflection ? "reflection" : "transmission") + "\"";
    // The same sample in polarized mode (the same wi; M00 = weight).
    if (pol)
      if (const auto p = pol->sample(wo[i], u[i].lobe, u[i].u1, u[i].u2, mode))
        out += ",\"mueller\":" + json_mueller_channels(p->weight);
    out += "}\n";
  }
}

// The samples of an RGB model or of a spectral one at a single wavelength.
template <typename C>
void run_sample_with(const SampleArgs& a, const BxDFT<C>& bxdf) {
  const TransportMode mode = parse_mode(a.mode);
  SampleBuffers<C> buffers;
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
    std::vector<Vec3> wo_chunk(kChunk);
    std::vector<SampleUniforms> u_chunk(kChunk);
    for (size_t i = 0; i < wos.size(); ++i) {
      Pcg32 rng(std::uint64_t(a.seed), std::uint64_t(i));
      std::fill(wo_chunk.begin(), wo_chunk.end(), wos[i]);
      for (std::int64_t done = 0; done < a.count;) {
        const size_t n = size_t(std::min<std::int64_t>(a.count - done, std::int64_t(kChunk)));
        for (size_t j = 0; j < n; ++j) {
          const Float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
          u_chunk[j] = {u0, u1, u2};
        }
        append_samples(out, bxdf, std::span<const Vec3>(wo_chunk).first(n), std::span<const SampleUniforms>(u_chunk).first(n),
                       mode, buffers, pol);
        done += std::int64_t(n);
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
  std::vector<Vec3> wos(rows.size());
  std::vector<SampleUniforms> us(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    wos[i] = unit_vector(r[0], r[1], r[2], i + 1, "wo");
    us[i] = {unit_interval(r[3], i + 1, "u0"), unit_interval(r[4], i + 1, "u1"), unit_interval(r[5], i + 1, "u2")};
  }
  std::string out;
  out.reserve(rows.size() * 128);
  for (size_t i = 0; i < rows.size(); i += kChunk) {
    const size_t n = std::min(kChunk, rows.size() - i);
    append_samples(out, bxdf, std::span<const Vec3>(wos).subspan(i, n), std::span<const SampleUniforms>(us).subspan(i, n),
                   mode, buffers, pol);
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
  add_point_options(*cmd);
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
