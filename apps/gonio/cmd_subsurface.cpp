// gonio subsurface (SPEC §3): a semi-infinite slab of a `subsurface` material under a
// collimated beam at normal incidence; issue 14. Prints Rd, its standard error and the
// radial profile, by the material's own method.

#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "commands.h"
#include "gonio/json_text.h"
#include "gonio/subsurface/slab_walk.h"
#include "gonio/subsurface/subsurface.h"

namespace gonio::cli {

namespace {

// Paths of the random walk by default: about a second for marble (ϖ ≈ 0.999, ~130
// scattering events a path) on two cores; Rd's standard error is then ~0.001.
constexpr std::int64_t kDefaultSubsurfaceSamples = 1 << 17;

struct SubsurfaceArgs {
  std::string bsdf;
  std::int64_t samples = kDefaultSubsurfaceSamples;
  std::int64_t seed = 1;
};

Subsurface load_subsurface(const std::string& arg) {
  // load_bsdf reads and checks --bsdf as every command does (file errors, JSON syntax,
  // the material's fields), so the messages are the same; the JSON is then read again
  // for the medium, which a BxDF does not carry.
  const BxDF boundary = load_bsdf(arg);
  const bool file = !arg.empty() && arg[0] == '@';
  const std::string source = file ? arg.substr(1) : "--bsdf";
  const std::string text = file ? read_text_file(source, kMaxJsonFileBytes, "a material file") : arg;
  const nlohmann::json j = parse_json_text(text, source);
  const auto type = j.find("type");
  if (type == j.end() || *type != "subsurface")
    throw InputError(source + ": subsurface needs a material of type \"subsurface\", got " +
                     (type == j.end() ? std::string("none") : json_excerpt(*type)));
  (void)boundary;
  return subsurface_from_json(j, source);
}

std::string result_line(const SlabResult& r) {
  std::string out = "{\"Rd\":" + json_color(r.Rd) + ",\"stderr\":" + json_color(r.stderr_) + ",\"profile\":[";
  for (size_t i = 0; i < r.profile.size(); ++i) {
    if (i) out += ",";
    out += "[" + json_number(r.profile[i].r) + "," + json_color(r.profile[i].value) + "]";
  }
  return out + "]}\n";
}

void run_subsurface(const SubsurfaceArgs& a) {
  const Subsurface s = load_subsurface(a.bsdf);
  SlabResult r;
  if (s.method == SubsurfaceMethod::Diffusion) {
    // TODO(issue 14, ssdiffusion): r = slab_diffusion(s) from gonio/subsurface/diffusion.h
    // once that branch is merged.
    throw InputError("diffusion: not built yet");
  } else {
    r = slab_random_walk(s, std::uint64_t(a.samples), std::uint64_t(a.seed));
  }
  std::cout << result_line(r);
}

}  // namespace

void register_subsurface(CLI::App& app) {
  auto args = std::make_shared<SubsurfaceArgs>();
  auto* cmd = app.add_subcommand(
      "subsurface",
      "Diffuse reflectance Rd and its radial profile of a semi-infinite slab of a subsurface material (surface z = 0, "
      "medium below) under a collimated beam at normal incidence, by the material's method");
  cmd->add_option("--bsdf", args->bsdf, "material JSON text of type subsurface, or @path to a file holding it")
      ->required();
  cmd->add_option("--samples", args->samples,
                  "random-walk paths, 1 to 10^12 (default " + std::to_string(kDefaultSubsurfaceSamples) + ")")
      ->transform(decimal_in_range(1, kMaxSamples));
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (default 1)")->transform(decimal_in_range(0, kMaxSeed));
  cmd->callback([args] { run_subsurface(*args); });
}

}  // namespace gonio::cli
