// Speed of subsurface scattering in the renderer (issue 14, item 6): not a test, a
// measurement, disabled by default; scripts/subsurface_speed.sh runs it. It renders the
// marble scenes at a reduced size and prints samples/s, and the random walk's mean number
// of steps per walk.

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"

namespace gonio::render {
namespace {

TEST(SubsurfaceRenderSpeed, DISABLED_MarbleScenes) {
  const int spp = std::getenv("GONIO_SPEED_SPP") ? std::atoi(std::getenv("GONIO_SPEED_SPP")) : 8;
  for (const char* name : {"marble-opaque", "marble", "marble-diffusion"}) {
    Scene scene = load_scene_file(std::string(GONIO_SOURCE_DIR) + "/scenes/" + name + ".json");
    scene.camera.width = 200;
    scene.camera.height = 150;
    scene.settings.spp = spp;
    RenderStats st;
    render(scene, {}, &st);
    std::printf("%-17s %dx%d at %d spp: %.2f s, %.1f ksamples/s, %.2f Mrays/s", name, scene.camera.width,
                scene.camera.height, st.spp, st.seconds, double(st.samples) / st.seconds / 1e3,
                double(st.rays) / st.seconds / 1e6);
    if (st.walks > 0)
      std::printf(", %llu walks, %.1f steps per walk, %.2f walks per sample", (unsigned long long)st.walks,
                  double(st.walk_steps) / double(st.walks), double(st.walks) / double(st.samples));
    if (st.probe_exits > 0) std::printf(", %.2f diffusion exits per sample", double(st.probe_exits) / double(st.samples));
    std::printf("\n");
    for (const Material& m : scene.materials)
      if (m.subsurface) {
        const Color w = m.subsurface->medium.single_scattering_albedo();
        std::printf("  %s: sigma_s = [%g, %g, %g], sigma_a = [%g, %g, %g] per unit, albedo = [%.5f, %.5f, %.5f]\n",
                    m.name.c_str(), m.subsurface->medium.sigma_s[0], m.subsurface->medium.sigma_s[1],
                    m.subsurface->medium.sigma_s[2], m.subsurface->medium.sigma_a[0], m.subsurface->medium.sigma_a[1],
                    m.subsurface->medium.sigma_a[2], w[0], w[1], w[2]);
      }
  }
}

}  // namespace
}  // namespace gonio::render
