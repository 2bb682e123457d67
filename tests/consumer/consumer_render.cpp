// Renders a 16×16 image through gonio::render: a diffuse sphere under a constant sky, so
// every pixel is finite and the sphere's centre is lit.

#include <cmath>
#include <cstdio>

#include <gonio/render/renderer.h>
#include <gonio/render/scene_loader.h>

int main() {
  const char* scene_json = R"({
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30, "width": 16, "height": 16},
    "render": {"spp": 16, "max_depth": 4},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                "material": {"type": "diffuse", "reflectance": 0.5}}],
    "environment": {"radiance": 1}
  })";
  const gonio::render::Scene scene = gonio::render::parse_scene(scene_json, "consumer scene", ".");
  gonio::render::RenderStats stats;
  const gonio::render::Image img = gonio::render::render(scene, {.threads = 1}, &stats);
  if (img.width() != 16 || img.height() != 16) {
    std::fprintf(stderr, "consumer_render: image is %dx%d, expected 16x16\n", img.width(), img.height());
    return 1;
  }
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(img.at(x, y)[c]) || img.at(x, y)[c] < 0) {
          std::fprintf(stderr, "consumer_render: pixel (%d, %d) is not a finite radiance\n", x, y);
          return 1;
        }
  // A white sky of radiance 1 over a Lambertian of albedo 0.5 gives about 0.5 (plus
  // interreflection: none on a convex sphere).
  const double centre = img.at(8, 8)[1];
  if (!(centre > 0.3 && centre < 0.7)) {
    std::fprintf(stderr, "consumer_render: centre pixel %.6g, expected about 0.5\n", centre);
    return 1;
  }
  std::printf("consumer_render: 16x16 at %d spp, centre %.4g\n", stats.spp, centre);
  return 0;
}
