// gonio subsurface (SPEC §3): a semi-infinite slab of a `subsurface` material under a
// collimated beam at normal incidence; issue 14. Prints Rd, its standard error and the
// radial profile, by the material's own method.

#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "commands.h"
#include "gonio/json_text.h"
#include "gonio/subsurface/diffusion.h"
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
  bool stats = false;
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

// --stats (an addition): what the run cost, appended to the line.
struct RunStats {
  double parse_seconds = 0, walk_seconds = 0, steps_per_path = 0;
};

std::string result_line(const SlabResult& r, const RunStats* stats) {
  std::string out = "{\"Rd\":" + json_color(r.Rd) + ",\"stderr\":" + json_color(r.stderr_) + ",\"profile\":[";
  for (size_t i = 0; i < r.profile.size(); ++i) {
    if (i) out += ",";
    out += "[" + json_number(r.profile[i].r) + "," + json_color(r.profile[i].value) + "]";
  }
  out += "]";
  if (stats)
    out += ",\"parse_seconds\":" + json_number(stats->parse_seconds) + ",\"walk_seconds\":" +
           json_number(stats->walk_seconds) + ",\"steps_per_path\":" + json_number(stats->steps_per_path);
  return out + "}\n";
}

void run_subsurface(const SubsurfaceArgs& a) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const Subsurface s = load_subsurface(a.bsdf);
  const auto t1 = Clock::now();
  SlabResult r;
  std::uint64_t steps = 0;
  if (s.method == SubsurfaceMethod::Diffusion) {
    r = slab_diffusion(s);  // the profile's closed form: stderr 0, no paths
  } else {
    SlabWalkOptions o;
    o.steps = &steps;
    r = slab_random_walk(s, std::uint64_t(a.samples), std::uint64_t(a.seed), o);
  }
  const auto t2 = Clock::now();
  RunStats st;
  st.parse_seconds = std::chrono::duration<double>(t1 - t0).count();
  st.walk_seconds = std::chrono::duration<double>(t2 - t1).count();
  st.steps_per_path = double(steps) / double(a.samples);
  std::cout << result_line(r, a.stats ? &st : nullptr);
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
  cmd->add_flag("--stats", args->stats,
                "also print parse_seconds (reading the material, with its albedo table), walk_seconds and "
                "steps_per_path (mean scattering events of a path; an addition to SPEC's output)");
  cmd->callback([args] { run_subsurface(*args); });
}

}  // namespace gonio::cli
