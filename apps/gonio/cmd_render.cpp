// gonio render: the reflection equation on a scene (SPEC §3). Writes linear OpenEXR or
// tone-mapped sRGB PNG, by the output's extension.
//
// The output file is created (under a temporary name) before the scene is rendered, so an
// output that cannot be written costs no rendering time. SIGINT and SIGTERM stop the
// render between tiles; the passes completed so far are written as an image with fewer
// samples per pixel, and the exit status is 128 + the signal number (130, 143). Before
// the render starts, or at a second signal, gonio ends at once and writes nothing
// (cli_signals.h).

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cli_io.h"
#include "cli_number.h"
#include "cli_signals.h"
#include "commands.h"
#include "gonio/error.h"
#include "gonio/render/gltf_loader.h"
#include "gonio/render/image_output.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"
#include "gonio/render/stokes_image.h"

namespace gonio::cli {

namespace {
struct RenderArgs {
  std::string scene;
  std::string output = "gonio.png";
  int spp = 0;         // 0: the scene's
  int threads = 0;     // 0: all cores
  bool spectral = false;  // overrides the scene's "render": {"spectral": false}
  bool polarized = false;  // overrides the scene's "render": {"polarized": false}
  std::string dop;         // --dop: the false-colour DoLP/AoLP image (PNG)
  std::optional<double> polarizer;  // --polarizer DEG: overrides the scene's /camera/polarizer
  std::int64_t seed = -1;  // -1: the scene's
  // Unset: the scene's. An option given empty (--sampler '') is a bad value, not "unset".
  std::optional<std::string> sampler, light_sampler;
  // --sample-range A B: only the per-pixel sample indices [A, B), written as their sums
  // (docs/distributed.md); empty: the whole render.
  std::vector<std::int64_t> sample_range;
  // SPEC §3 (glTF scenes, and every scene): image size, a glTF camera by name, exposure.
  int width = 0, height = 0;  // 0: the scene's
  std::string camera;
  std::optional<double> exposure;
};

// "1.23 M" style figures for the closing line.
std::string si(double v) {
  char buf[32];
  if (!(v >= 0) || !std::isfinite(v)) v = 0;
  if (v >= 1e9) std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
  else if (v >= 1e6) std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
  else if (v >= 1e3) std::snprintf(buf, sizeof buf, "%.1f k", v / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f ", v);
  return buf;
}

// Whether anything in the scene emits: a light, an emitting material, a non-black
// environment. Without one every path carries zero radiance (SPEC §3 asks for a warning).
bool has_light(const render::Scene& scene) {
  if (!scene.point_lights.empty() || !scene.area_lights.empty() || !scene.environment.is_black()) return true;
  return std::any_of(scene.materials.begin(), scene.materials.end(), [](const render::Material& m) { return m.emits; });
}

void run_render(const RenderArgs& a) {
  const std::string ext = lower_extension(a.output);
  if (ext != ".exr" && ext != ".png")
    throw InputError("-o " + a.output + ": the output must end in .exr (linear) or .png (sRGB)");

  const bool ranged = !a.sample_range.empty();
  if (ranged) {
    if (a.sample_range.size() != 2 || a.sample_range[0] >= a.sample_range[1])
      throw InputError("--sample-range A B: needs A < B (the sample indices [A, B)), got " +
                       std::to_string(a.sample_range.at(0)) + " " + std::to_string(a.sample_range.at(1)));
    if (a.spp > 0 && a.sample_range[1] > a.spp)
      throw InputError("--sample-range " + std::to_string(a.sample_range[0]) + " " + std::to_string(a.sample_range[1]) +
                       ": beyond --spp " + std::to_string(a.spp) + " (the indices run from 0 to spp - 1)");
    if (ext != ".exr")
      throw InputError("-o " + a.output + ": --sample-range writes the samples' sums, which need a linear .exr output");
    if (!a.dop.empty()) throw InputError("--dop " + a.dop + ": not with --sample-range (it writes sums, not an image)");
  }
  if (!a.dop.empty() && lower_extension(a.dop) != ".png")
    throw InputError("--dop " + a.dop + ": the polarization image must end in .png");
  // Until the render starts, a signal ends gonio at once (reading a scene from a FIFO
  // without a writer waits in open()), removing the temporaries (cli_signals.h).
  install_stop_signals();
  std::optional<render::ImageOutput> out, dop_out;
  // An unwritable location fails here, before any work.
  create_removable([&] { return out.emplace(a.output).temporary_path(); });
  if (!a.dop.empty()) create_removable([&] { return dop_out.emplace(a.dop).temporary_path(); });
  if (a.exposure && !(std::isfinite(*a.exposure) && std::abs(*a.exposure) <= 64))
    throw InputError("--exposure must be a number of stops in [-64, 64], got " + format_number(*a.exposure));
  const bool gltf = !a.scene.empty() && render::is_gltf_path(a.scene);
  if (!a.camera.empty() && !gltf)
    throw InputError("--camera " + a.camera + ": only a glTF scene (.gltf, .glb) has named cameras");
  render::Scene scene = a.scene.empty() ? render::parse_scene(render::default_scene_json(), "default scene", "")
                        : gltf          ? render::load_gltf_scene(a.scene, {a.camera})
                                        : render::load_scene_file(a.scene);
  if (a.width > 0 || a.height > 0) {
    // One of the two given: the other keeps the camera's aspect ratio.
    const double aspect = double(scene.camera.width) / double(scene.camera.height);
    const int w = a.width > 0 ? a.width : std::max(1, int(std::lround(a.height * aspect)));
    const int h = a.height > 0 ? a.height : std::max(1, int(std::lround(a.width / aspect)));
    if (std::int64_t(w) * h > render::kMaxFilmPixels)
      throw InputError("--width/--height: " + std::to_string(w) + " x " + std::to_string(h) + " is more than " +
                       std::to_string(render::kMaxFilmPixels) + " pixels");
    scene.camera.width = w;
    scene.camera.height = h;
  }
  if (a.spp > 0) scene.settings.spp = a.spp;
  if (a.seed >= 0) scene.settings.seed = static_cast<std::uint64_t>(a.seed);
  if (a.sampler) {
    const auto type = render::sampler_type_from_name(*a.sampler);
    if (!type) throw InputError("--sampler must be zsobol, sobol or independent, got \"" + *a.sampler + "\"");
    scene.settings.sampler = *type;
  }
  if (a.light_sampler) {
    const auto type = render::light_sampler_type_from_name(*a.light_sampler);
    if (!type) throw InputError("--light-sampler must be bvh, power or uniform, got \"" + *a.light_sampler + "\"");
    scene.settings.light_sampler = *type;
  }
  if (a.spectral) scene.settings.spectral = true;
  if (a.polarized) scene.settings.polarized = true;
  if (a.polarizer) {
    if (!(*a.polarizer >= -360 && *a.polarizer <= 360))
      throw InputError("--polarizer must be in [-360, 360] degrees, got " + format_number(*a.polarizer));
    scene.camera.polarizer_deg = static_cast<Float>(*a.polarizer);
  }
  if (!a.dop.empty() && !scene.settings.polarized)
    throw InputError("--dop " + a.dop + ": needs a polarized render (--polarized or \"render\": {\"polarized\": true})");
  if (scene.camera.polarizer_deg && !scene.settings.polarized)
    throw InputError((a.scene.empty() ? std::string("default scene") : a.scene) +
                     ": /camera/polarizer needs a polarized render (--polarized or \"render\": {\"polarized\": true})");
  // A full disk fails here; a polarized EXR holds four layers (S0..S3).
  out->reserve(scene.camera.width, scene.camera.height, scene.settings.polarized ? 4 : 1);
  if (dop_out) dop_out->reserve(scene.camera.width, scene.camera.height);

  // Printed once the image is written (SPEC §3: a refusal's error line is alone on stderr,
  // and the renderer and the write may still refuse).
  const bool no_lights = !has_light(scene);
  const bool tty = isatty(STDERR_FILENO) == 1;
  render::RenderOptions options;
  options.threads = a.threads;
  options.stop = &stop_requested();
  if (ranged) {
    options.sample_begin = static_cast<int>(a.sample_range[0]);
    options.sample_end = static_cast<int>(a.sample_range[1]);
    options.sums = true;
  }
  int last_step = -1;
  // Progress only on a terminal (SPEC §3): a log or a pipe gets the closing line alone.
  if (tty)
    options.progress = [&](double done) {
      const int step = static_cast<int>(done * 40);
      if (step == last_step) return;
      last_step = step;
      std::fprintf(stderr, "\rrendering [%-40s] %3d%%", std::string(static_cast<size_t>(step), '#').c_str(),
                   static_cast<int>(done * 100));
      std::fflush(stderr);
    };
  render::RenderStats stats;
  render::StokesImages stokes;
  // From here on the first signal stops the render between tiles, and the passes done
  // are written; a second one ends gonio at once.
  set_interruptible(true);
  render::Image image = render::render(scene, options, &stats, &stokes);
  if (a.exposure && *a.exposure != 0) {
    // --exposure EV multiplies the image by 2^EV (SPEC §3), in every output format.
    const Float k = Float(std::exp2(*a.exposure));
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) image.at(x, y) *= k;
    for (render::Image& s : stokes)
      for (int y = 0; y < s.height(); ++y)
        for (int x = 0; x < s.width(); ++x) s.at(x, y) *= k;
  }
  if (tty && last_step >= 0) std::fprintf(stderr, "\n");
  const int sig = stop_signal() == SIGTERM ? SIGTERM : SIGINT;
  const char* sig_name = sig == SIGTERM ? "SIGTERM" : "SIGINT";
  if (stats.stopped) exit_status() = 128 + sig;
  if (ranged && stats.stopped) {
    // A part of a range has fewer samples in its sums than its indices say: write nothing.
    std::fprintf(stderr, "gonio: interrupted by %s before the sample range was complete: no sums written\n", sig_name);
    return;
  }
  if (stats.spp == 0) {
    // Not one pass completed: there is no image to write (the temporary goes away).
    std::fprintf(stderr, "gonio: interrupted by %s before any pass was complete: no image written\n", sig_name);
    return;
  }
  render::PngOptions png;
  png.exposure_stops = scene.settings.exposure;
  png.tonemap = scene.settings.filmic ? render::ToneMap::Filmic : render::ToneMap::Clamp;
  if (scene.settings.polarized && ext == ".exr")
    out->write_exr_layers({{"S0", &stokes[0]}, {"S1", &stokes[1]}, {"S2", &stokes[2]}, {"S3", &stokes[3]}});
  else
    out->write(image, png);  // a polarized PNG shows S0, the intensity through the polarizer
  if (dop_out) dop_out->write_png(render::dop_image(stokes), {0, render::ToneMap::Clamp});
  const unsigned threads = a.threads > 0 ? static_cast<unsigned>(a.threads) : std::max(1u, std::thread::hardware_concurrency());
  if (no_lights) std::fprintf(stderr, "warning: the scene has no lights; the image is black\n");
  if (stats.stopped)
    std::fprintf(stderr, "interrupted by %s: ", sig_name);
  const char* mode = scene.settings.spectral && scene.settings.polarized ? " (spectral, polarized)"
                     : scene.settings.spectral                           ? " (spectral)"
                     : scene.settings.polarized                          ? " (polarized)"
                                                                         : "";
  if (ranged)
    std::fprintf(stderr, "rendered the sums of samples [%d, %d) of %dx%d%s", options.sample_begin, options.sample_end,
                 scene.camera.width, scene.camera.height, mode);
  else
    std::fprintf(stderr, "rendered %dx%d at %d spp%s", scene.camera.width, scene.camera.height, stats.spp, mode);
  if (stats.stopped) std::fprintf(stderr, " (of %d)", scene.settings.spp);
  std::fprintf(stderr, " on %u threads in %.2f s (+%.2f s setup): %ssamples/s, %srays/s\n", threads, stats.seconds,
               stats.setup_seconds, si(double(stats.samples) / stats.seconds).c_str(),
               si(double(stats.rays) / stats.seconds).c_str());
  std::cout << a.output << "\n";
  if (dop_out) std::cout << a.dop << "\n";
}

}  // namespace

void register_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a scene (JSON, docs/scene-format.md, or glTF 2.0, docs/gltf.md); without one, the built-in default scene");
  cmd->add_option("scene", args->scene, "scene file (JSON, .gltf or .glb)");
  cmd->add_option("--width", args->width, "image width in pixels, 1 to 65536 (overrides the scene's camera)")
      ->transform(decimal_in_range(1, 65536));
  cmd->add_option("--height", args->height, "image height in pixels, 1 to 65536 (overrides the scene's camera)")
      ->transform(decimal_in_range(1, 65536));
  cmd->add_option("--camera", args->camera, "NAME: the glTF camera to render through (default: the first)");
  cmd->add_option("--exposure", args->exposure, "EV: multiply the image by 2^EV (default 0)")->check(decimal_number());
  cmd->add_option("-o,--output", args->output, "output image: .exr (linear) or .png (tone-mapped sRGB); default gonio.png");
  cmd->add_option("--spp", args->spp, "samples per pixel, 1 to 1048576 (overrides the scene's)")
      ->transform(decimal_in_range(1, kMaxSpp));
  cmd->add_option("--threads", args->threads, "worker threads, 0 to 1024 (default 0: all cores)")
      ->transform(decimal_in_range(0, kMaxThreads));
  cmd->add_option("--seed", args->seed, "random seed, 0 to 2147483647 (overrides the scene's; default 0)")
      ->transform(decimal_in_range(0, kMaxSeed));
  cmd->add_option("--sampler", args->sampler,
                  "zsobol (default), sobol or independent: where the samples' random numbers come from (overrides "
                  "the scene's \"render\": {\"sampler\"}; docs/scene-format.md)");
  cmd->add_option("--light-sampler", args->light_sampler,
                  "bvh (default), power or uniform: how next-event estimation picks the light it samples (overrides "
                  "the scene's \"render\": {\"light_sampler\"}; docs/scene-format.md)");
  cmd->add_option("--sample-range", args->sample_range,
                  "A B: render only the per-pixel sample indices [A, B) of the render's sequences, 0 <= A < B <= "
                  "1048576, and write their per-pixel SUMS (not the mean) as linear .exr: passes of a distributed "
                  "render (docs/distributed.md)")
      ->expected(2)
      ->transform(decimal_in_range(0, kMaxSpp));
  cmd->add_flag("--spectral", args->spectral,
                "spectral transport: 4 sampled wavelengths per path (also \"render\": {\"spectral\": true})");
  cmd->add_flag("--polarized", args->polarized,
                "polarized transport: Stokes vectors along paths; an .exr output holds layers S0..S3 (also \"render\": "
                "{\"polarized\": true})");
  cmd->add_option("--polarizer", args->polarizer,
                  "DEG: a linear polarizer before the film, its axis DEG counter-clockwise from the image's +x, "
                  "-360 to 360 (needs a polarized render; overrides the scene's camera \"polarizer\")")
      ->check(decimal_number());
  cmd->add_option("--dop", args->dop,
                  "with a polarized render, also write PNG: hue the angle, brightness the degree of linear polarization");
  cmd->callback([args] { run_render(*args); });
}

}  // namespace gonio::cli
