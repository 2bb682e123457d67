// Colour noise of spectral against RGB rendering at equal time (issue 11, item 8): renders
// a scene in each mode at a high sample count (each mode's own reference: the two modes
// converge to slightly different images, the spectral one with measured spectra), then
// at budgets of equal wall time, and prints the RMSE of each against its reference.
//   gonio_colour_noise SCENE.json REFERENCE_SPP RGB_SPP [THREADS]
// The spectral budget is RGB_SPP scaled by the measured time ratio of the two modes.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"

using namespace gonio::render;

namespace {

Image render_at(Scene s, bool spectral, int spp, std::uint64_t seed, int threads, double* seconds) {
  s.settings.spectral = spectral;
  s.settings.spp = spp;
  s.settings.seed = seed;
  RenderOptions o;
  o.threads = threads;
  RenderStats st;
  Image img = render(s, o, &st);
  if (seconds) *seconds = st.seconds;
  return img;
}

// Root mean square over pixels and channels.
double rmse(const Image& a, const Image& b) {
  double sum = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.at(x, y)[c]) - double(b.at(x, y)[c]);
        sum += d * d;
      }
  return std::sqrt(sum / (3.0 * a.width() * a.height()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s SCENE.json REFERENCE_SPP RGB_SPP [THREADS]\n", argv[0]);
    return 2;
  }
  const Scene scene = load_scene_file(argv[1]);
  const int ref_spp = std::atoi(argv[2]), spp = std::atoi(argv[3]);
  const int threads = argc > 4 ? std::atoi(argv[4]) : 0;
  double t_rgb = 0, t_spec = 0;
  const Image ref_rgb = render_at(scene, false, ref_spp, 1000, threads, nullptr);
  const Image ref_spec = render_at(scene, true, ref_spp, 1000, threads, nullptr);
  const Image rgb = render_at(scene, false, spp, 7, threads, &t_rgb);
  // Time ratio from a same-spp spectral render, then the equal-time budget.
  const Image spec_same = render_at(scene, true, spp, 7, threads, &t_spec);
  const int spp_eq = std::max(1, int(std::lround(spp * t_rgb / t_spec)));
  double t_eq = 0;
  const Image spec_eq = render_at(scene, true, spp_eq, 7, threads, &t_eq);
  std::printf("reference %d spp each mode; RGB %d spp %.2f s: RMSE %.5f\n", ref_spp, spp, t_rgb, rmse(rgb, ref_rgb));
  std::printf("spectral %d spp %.2f s: RMSE %.5f (same spp); spectral %d spp %.2f s: RMSE %.5f (equal time)\n", spp,
              t_spec, rmse(spec_same, ref_spec), spp_eq, t_eq, rmse(spec_eq, ref_spec));
  std::printf("RMSE between the two references: %.5f\n", rmse(ref_rgb, ref_spec));
  return 0;
}
