// gonio render: the reflection equation on a scene (SPEC §3). Writes linear OpenEXR or
// tone-mapped sRGB PNG, by the output's extension.

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "commands.h"
#include "gonio/error.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"

namespace gonio::cli {

namespace {
struct RenderArgs {
  std::string scene;
  std::string output = "gonio.png";
  int spp = -1;      // -1: not given
  int threads = -1;
  std::int64_t seed = -1;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// "1.23 M" style figures for the closing line.
std::string si(double v) {
  char buf[32];
  if (v >= 1e9) std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
  else if (v >= 1e6) std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
  else if (v >= 1e3) std::snprintf(buf, sizeof buf, "%.1f k", v / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f ", v);
  return buf;
}

void run_render(const RenderArgs& a) {
  const std::string ext = lower_extension(a.output);
  if (ext != ".exr" && ext != ".png")
    throw InputError("-o " + a.output + ": the output must end in .exr (linear) or .png (sRGB)");
  const std::filesystem::path dir = std::filesystem::path(a.output).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw InputError("-o " + a.output + ": directory " + dir.string() + " does not exist");
  if (a.spp != -1 && a.spp < 1) throw InputError("--spp must be >= 1, got " + std::to_string(a.spp));
  if (a.threads != -1 && a.threads < 1) throw InputError("--threads must be >= 1, got " + std::to_string(a.threads));
  if (a.seed < -1) throw InputError("--seed must be >= 0, got " + std::to_string(a.seed));

  render::Scene scene = a.scene.empty() ? render::parse_scene(render::default_scene_json(), "default scene", "")
                                        : render::load_scene_file(a.scene);
  if (a.spp > 0) scene.settings.spp = a.spp;
  if (a.seed >= 0) scene.settings.seed = static_cast<std::uint64_t>(a.seed);

  const bool tty = isatty(STDERR_FILENO) == 1;
  render::RenderOptions options;
  options.threads = std::max(0, a.threads);
  int last_step = -1;
  options.progress = [&](double done) {
    if (tty) {
      const int step = static_cast<int>(done * 40);
      if (step == last_step) return;
      last_step = step;
      std::fprintf(stderr, "\rrendering [%-40s] %3d%%", std::string(static_cast<size_t>(step), '#').c_str(),
                   static_cast<int>(done * 100));
    } else {
      const int step = static_cast<int>(done * 10);
      if (step == last_step) return;
      last_step = step;
      std::fprintf(stderr, "rendering: %d%%\n", step * 10);
    }
    std::fflush(stderr);
  };
  render::RenderStats stats;
  const render::Image image = render::render(scene, options, &stats);
  if (tty) std::fprintf(stderr, "\n");
  if (ext == ".exr") {
    render::write_exr(image, a.output);
  } else {
    render::PngOptions png;
    png.exposure_stops = scene.settings.exposure;
    png.tonemap = scene.settings.filmic ? render::ToneMap::Filmic : render::ToneMap::Clamp;
    render::write_png(image, a.output, png);
  }
  const unsigned threads = a.threads > 0 ? static_cast<unsigned>(a.threads) : std::max(1u, std::thread::hardware_concurrency());
  std::fprintf(stderr, "rendered %dx%d at %d spp on %u threads in %.2f s (+%.2f s setup): %ssamples/s, %srays/s\n",
               scene.camera.width, scene.camera.height, scene.settings.spp, threads, stats.seconds,
               stats.setup_seconds, si(double(stats.samples) / stats.seconds).c_str(),
               si(double(stats.rays) / stats.seconds).c_str());
  std::cout << a.output << "\n";
}
}  // namespace

void register_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a scene (JSON, docs/scene-format.md); without one, the built-in default scene");
  cmd->add_option("scene", args->scene, "scene file (JSON)");
  cmd->add_option("-o,--output", args->output, "output image: .exr (linear) or .png (tone-mapped sRGB); default gonio.png");
  cmd->add_option("--spp", args->spp, "samples per pixel (overrides the scene's)");
  cmd->add_option("--threads", args->threads, "worker threads (default: all cores)");
  cmd->add_option("--seed", args->seed, "random seed (overrides the scene's; default 0)");
  cmd->callback([args] { run_render(*args); });
}

}  // namespace gonio::cli
