// gonio measure: the virtual gonioreflectometer (SPEC §3, issue 13). A surface (JSON,
// include/gonio/measure/surface.h) is traced as a periodic microsurface; -o fills a MERL
// table, --gantry reads detectors at given directions, --preview draws the height field.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_io.h"
#include "cli_signals.h"
#include "commands.h"
#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/microsurface.h"
#include "gonio/measure/preview.h"
#include "gonio/measure/surface.h"
#include "gonio/measure/table.h"
#include "gonio/io/output_file.h"
#include "gonio/measured_data.h"
#include "gonio/merl.h"
#include "gonio/rgl/write.h"

namespace gonio::cli {

namespace {
struct MeasureArgs {
  std::string surface, output, gantry, json, preview, stderr_table, support_table, format = "merl";
  std::int64_t samples = 10'000'000;
  bool samples_given = false;
  int threads = 0;
  std::int64_t seed = 0;
  std::int64_t max_bounces = measure::Microsurface::kDefaultMaxBounces;
  std::int64_t min_rays = std::int64_t(measure::kTableMinExpectedRays);
  bool min_rays_given = false;
};

struct ArgText {
  std::string text, source, base_dir;
};

// OPTION's value: JSON text, or @path to a file holding it (a relative path inside the
// file is then relative to the file's directory).
ArgText read_json_arg(const std::string& arg, const std::string& option) {
  if (arg.empty() || arg[0] != '@') return {arg, option, ""};
  const std::string path = arg.substr(1);
  std::string text;
  try {
    text = read_text_file(path, kMaxJsonFileBytes, "a JSON file");
  } catch (const InputError& e) {
    throw InputError(option + ": " + e.what());
  }
  return {std::move(text), path, std::filesystem::path(path).parent_path().string()};
}

// An output file's directory must exist and be writable before hours of tracing.
void check_writable(const std::string& path, const std::string& option) {
  if (path.empty()) throw InputError(option + ": empty file name");
  std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(option + " " + path + ": no such directory");
  if (std::filesystem::is_directory(p, ec)) throw InputError(option + " " + path + ": is a directory");
  if (::access(dir.c_str(), W_OK) != 0) throw InputError(option + " " + path + ": directory not writable");
  try {
    check_output_target(path, "the output");  // a device or FIFO is never replaced
  } catch (const InputError& e) {
    throw InputError(option + " " + e.what());
  }
}

std::string duration(double s) {
  char buf[32];
  if (!(s >= 0) || !std::isfinite(s)) return "?";
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), int(s / 60) % 60);
  return buf;
}

// Progress on stderr with an estimate of the time left: a redrawn bar, only when stderr is a
// terminal (SPEC §3); otherwise none.
std::function<void(double)> progress_reporter(const char* what) {
  if (isatty(STDERR_FILENO) != 1) return {};
  const auto start = std::chrono::steady_clock::now();
  auto last = std::make_shared<int>(-1);
  return [=](double done) {
    const int step = static_cast<int>(done * 100);
    if (step == *last) return;
    *last = step;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double left = done > 0 ? elapsed * (1 - done) / done : -1;
    std::fprintf(stderr, "\r%s [%-40s] %3d%%  ETA %-8s", what, std::string(std::size_t(done * 40), '#').c_str(),
                 int(done * 100), duration(left).c_str());
    if (done >= 1) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

std::string quoted(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string counts_json(const measure::RayCounts& c) {
  return "{\"launched\":" + std::to_string(c.launched) + ",\"up\":" + std::to_string(c.up) +
         ",\"down\":" + std::to_string(c.down) + ",\"absorbed\":" + std::to_string(c.absorbed) +
         ",\"capped\":" + std::to_string(c.capped) + ",\"lost\":" + std::to_string(c.lost) +
         ",\"segments\":" + std::to_string(c.segments) + ",\"bounces\":" + std::to_string(c.bounces) + "}";
}

std::string gantry_json(const measure::GantryReading& g, const measure::Surface& s, std::uint64_t seed) {
  std::string o = "{\"mode\":\"gantry\",\"surface\":" + quoted(s.type) + ",\"material\":" + quoted(s.material.name()) +
                  ",\"seed\":" + std::to_string(seed) + ",\"aperture\":" + json_number(g.aperture) +
                  ",\"rays_per_incidence\":" + std::to_string(g.rays_per_incidence) + ",\"incidences\":[";
  for (std::size_t i = 0; i < g.incidences.size(); ++i) {
    const measure::IncidenceReading& r = g.incidences[i];
    o += (i ? "," : "");
    o += "{\"theta_i\":" + json_number(r.theta_i) + ",\"phi_i\":" + json_number(r.phi_i) +
         ",\"albedo\":" + json_color(r.albedo) + ",\"stderr_albedo\":" + json_color(r.stderr_albedo) +
         ",\"transmittance\":" + json_color(r.transmittance) +
         ",\"stderr_transmittance\":" + json_color(r.stderr_transmittance) + ",\"rays\":" + counts_json(r.counts) +
         ",\"detectors\":[";
    for (std::size_t d = 0; d < r.detectors.size(); ++d) {
      const measure::DetectorReading& x = r.detectors[d];
      o += (d ? "," : "");
      o += "{\"theta_o\":" + json_number(x.theta_o) + ",\"phi_o\":" + json_number(x.phi_o) + ",\"f\":" + json_color(x.f) +
           ",\"stderr\":" + json_color(x.stderr_f) + ",\"hits\":" + std::to_string(x.hits) +
           ",\"solid_angle\":" + json_number(x.solid_angle) + "}";
    }
    o += "]}";
  }
  return o + "]}";
}

// The keys of relative_stderr_above: measure::kTableErrorLevels as written in docs/cli.md.
constexpr const char* kErrorLevelNames[3] = {"0.01", "0.05", "0.2"};

std::string table_json(const measure::TableReading& t, const measure::Surface& s, const std::string& file,
                       std::uint64_t seed, std::int64_t min_rays, double seconds) {
  std::string o = "{\"mode\":\"table\",\"file\":" + quoted(file) + ",\"surface\":" + quoted(s.type) +
                  ",\"material\":" + quoted(s.material.name()) + ",\"seed\":" + std::to_string(seed) +
                  ",\"entries\":" + std::to_string(MerlTable::kEntries) + ",\"filled\":" + std::to_string(t.filled) +
                  ",\"missing\":" + std::to_string(t.missing) + ",\"zero\":" + std::to_string(t.zero) + ",\"pooled\":" + std::to_string(t.pooled) +
                  ",\"filled_by_pilot\":" + std::to_string(t.filled_by_pilot) +
                  ",\"min_expected_rays\":" + std::to_string(min_rays) +
                  ",\"relative_stderr_above\":{";
  for (int q = 0; q < 3; ++q)
    o += std::string(q ? "," : "") + "\"" + kErrorLevelNames[q] + "\":" + json_number(t.fraction_above[q]);
  o += "},\"rays\":" + counts_json(t.counts) + ",\"pilot_rays\":" + std::to_string(t.pilot_rays) +
       ",\"seconds\":" + json_number(seconds) + ",\"albedo\":[";
  for (std::size_t b = 0; b < t.bands.size(); ++b) {
    const measure::AlbedoBand& a = t.bands[b];
    o += (b ? "," : "");
    o += "{\"theta_i\":[" + json_number(a.theta_lo) + "," + json_number(a.theta_hi) + "],\"rays\":" +
         std::to_string(a.rays) + ",\"albedo\":" + json_color(a.albedo) + ",\"stderr\":" + json_color(a.stderr_albedo) +
         "}";
  }
  return o + "]}";
}

// Each entry's standard error in the table's layout (missing where the table is).
MerlTable stderr_table(const measure::TableReading& t) {
  MerlTable e;
  for (std::size_t q = 0; q < 3 * MerlTable::kEntries; ++q)
    e.rgb[q] = t.table.rgb[q] < 0 ? MerlTable::kMissing : t.stderr_f[q];
  return e;
}

// The bins each entry pooled (1: its own), in all three channels (missing where the
// table is).
MerlTable support_table(const measure::TableReading& t) {
  MerlTable e;
  for (std::size_t q = 0; q < MerlTable::kEntries; ++q)
    for (std::size_t c = 0; c < 3; ++c)
      e.rgb[3 * q + c] = t.table.rgb[3 * q] < 0 ? MerlTable::kMissing : float(t.support[q]);
  return e;
}

void emit(const std::string& object, const std::string& json_file) {
  if (json_file.empty()) {
    std::cout << object << "\n";
    return;
  }
  try {
    write_file_whole(json_file, object + "\n", "the JSON result");
  } catch (const InputError& e) {
    throw InputError(std::string("--json ") + e.what());
  }
  std::cout << "{\"json\":" << quoted(json_file) << "}\n";
}

void run_measure(const MeasureArgs& a) {
  if (a.output.empty() && a.gantry.empty() && a.preview.empty())
    throw InputError("measure: give -o OUT.binary (a MERL table), --gantry SPEC (detector readings) or --preview FILE");
  if (!a.output.empty() && !a.gantry.empty())
    throw InputError("measure: -o (a MERL table) and --gantry (detector readings) are separate runs; give one");
  if (!a.json.empty() && a.output.empty() && a.gantry.empty())
    throw InputError("--json: there is no measurement to write (give -o or --gantry)");
  // Every input is checked before the first ray.
  const ArgText st = read_json_arg(a.surface, "--surface");
  const measure::Surface surface = measure::parse_surface(st.text, st.source, st.base_dir);
  measure::GantrySpec spec;
  if (!a.gantry.empty()) {
    const ArgText gt = read_json_arg(a.gantry, "--gantry");
    spec = measure::parse_gantry(gt.text, gt.source);
  }
  if (!a.output.empty()) check_writable(a.output, "-o");
  if (!a.json.empty()) check_writable(a.json, "--json");
  if (a.min_rays_given && a.output.empty()) throw InputError("--min-rays: give it with -o (a MERL table)");
  if (!a.stderr_table.empty()) {
    if (a.output.empty()) throw InputError("--stderr-table: give it with -o (a MERL table)");
    if (a.stderr_table == a.output) throw InputError("--stderr-table " + a.stderr_table + ": the same file as -o");
    check_writable(a.stderr_table, "--stderr-table");
  }
  if (!a.support_table.empty()) {
    if (a.output.empty()) throw InputError("--support-table: give it with -o (a MERL table)");
    if (a.support_table == a.output || a.support_table == a.stderr_table)
      throw InputError("--support-table " + a.support_table + ": the same file as -o or --stderr-table");
    check_writable(a.support_table, "--support-table");
  }
  if (!a.preview.empty()) {
    const std::string ext = lower_extension(a.preview);
    if (ext != ".png" && ext != ".exr") throw InputError("--preview " + a.preview + ": must end in .png or .exr");
    check_writable(a.preview, "--preview");
    measure::write_surface_preview(surface.field, a.preview);
  }
  if (a.output.empty() && a.gantry.empty()) return;

  const measure::Microsurface micro(surface.field, surface.material, static_cast<std::uint32_t>(a.max_bounces));
  measure::RunOptions options;
  // A table's default is its own (table.h): its bins are far smaller than a detector.
  options.samples = a.samples_given || a.output.empty() ? static_cast<std::uint64_t>(a.samples)
                                                        : measure::kTableDefaultSamples;
  options.threads = a.threads;
  options.seed = static_cast<std::uint64_t>(a.seed);
  const auto start = std::chrono::steady_clock::now();
  if (!a.gantry.empty()) {
    options.progress = progress_reporter("measuring");
    const measure::GantryReading g = measure::run_gantry(micro, spec, options);
    emit(gantry_json(g, surface, options.seed), a.json);
    return;
  }
  options.progress = progress_reporter("measuring");
  measure::TableOptions table;
  table.min_expected_rays = double(a.min_rays);
  const measure::TableReading t = measure::measure_table(micro, options, table);
  // A signal during the 35 MB writes removes the temporaries (cli_signals.h).
  install_stop_signals();
  std::optional<OutputFile> out, err, sup;
  create_removable([&] { return out.emplace(a.output, "the table").temporary_path(); });
  if (!a.stderr_table.empty())
    create_removable([&] { return err.emplace(a.stderr_table, "the standard errors' table").temporary_path(); });
  if (!a.support_table.empty())
    create_removable([&] { return sup.emplace(a.support_table, "the support table").temporary_path(); });
  if (a.format == "rgl") {
    // SPEC §3 `--format rgl`: the measured table, as the `measured` model reads it,
    // acquired into an RGL .bsdf file by tabulate_rgl (its NDF by the power iteration from
    // the measured retro-reflection; include/gonio/rgl/write.h).
    RglWriteOptions opt;
    opt.description = "gonio measure";
    const BxDF measured = MeasuredBxDF::make(std::make_shared<const MeasuredData>(MerlTable(t.table), a.output));
    const std::vector<std::uint8_t> bytes = tabulate_rgl(measured, opt);
    out->commit(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  } else {
    write_merl(*out, t.table);
  }
  if (err) write_merl(*err, stderr_table(t));
  if (sup) write_merl(*sup, support_table(t));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  emit(table_json(t, surface, a.output, options.seed, a.min_rays, seconds), a.json);
}
}  // namespace

void register_measure(CLI::App& app) {
  auto args = std::make_shared<MeasureArgs>();
  auto* cmd = app.add_subcommand(
      "measure",
      "The virtual gonioreflectometer: traces a microsurface (docs/gonioreflectometer.md) and writes its "
      "isotropic BRDF as a MERL table (-o), or reads detectors at given directions (--gantry)");
  cmd->add_option("--surface", args->surface, "surface JSON (type flat|gaussian|vgroove|image, material), or @file")
      ->required();
  cmd->add_option("-o,--output", args->output, "the MERL table to write (.binary); prints a JSON summary");
  cmd->add_option("--gantry", args->gantry,
                  "detector readings instead of a table: JSON {theta_i, phi_i, theta_o, phi_o, aperture} or @file; "
                  "prints one JSON object");
  cmd->add_option("--stderr-table", args->stderr_table,
                  "with -o: also write each entry's standard error (1/sr) as a MERL table (.binary) of the same "
                  "layout, missing where the table is");
  cmd->add_option("--support-table", args->support_table,
                  "with -o: also write how many bins each entry's estimate pooled (1: its own bin; more: "
                  "filled from its neighbourhood) as a MERL table (.binary) of the same layout");
  CLI::Option* min_rays = cmd->add_option("--min-rays", args->min_rays,
                  "with -o: the rays an entry must expect (for a Lambertian sample, or from the pilot's rays) to be "
                  "estimated from its own bin, else from a region of bins around it, 0 to 1000000 (default 25; 0: "
                  "every bin from its own)")
      ->transform(decimal_in_range(0, 1'000'000));
  cmd->add_option("--format", args->format,
                  "with -o: merl (default, a MERL .binary table) or rgl (an RGL .bsdf file of the measured table, SPEC §3)")
      ->check(CLI::IsMember({"merl", "rgl"}));
  cmd->add_option("--json", args->json, "write the JSON result to FILE instead of stdout");
  cmd->add_option("--preview", args->preview, "write a shaded image of the height field (.png or .exr)");
  CLI::Option* samples = cmd->add_option("--samples", args->samples,
                  "total rays launched from the light, 1 to 10^12 (default 200000000 for -o, 10000000 split "
                  "evenly over the gantry's incidences)")
      ->transform(decimal_in_range(1, kMaxSamples));
  cmd->add_option("--threads", args->threads, "worker threads, 0 to 1024 (default 0: all cores)")
      ->transform(decimal_in_range(0, kMaxThreads));
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (default 0)")
      ->transform(decimal_in_range(0, kMaxSeed));
  cmd->add_option("--max-bounces", args->max_bounces,
                  "facet interactions allowed to a ray, 1 to 1000000 (default 1000; a ray that meets one more "
                  "facet is dropped and counted as capped; 1: single scattering alone)")
      ->transform(decimal_in_range(1, 1'000'000));
  cmd->callback([args, min_rays, samples] {
    args->min_rays_given = min_rays->count() > 0;
    args->samples_given = samples->count() > 0;
    run_measure(*args);
  });
}

}  // namespace gonio::cli
