// Compiled with nothing but `pkg-config --cflags --libs gonio` (tests/consumer/run.sh).

#include <cmath>
#include <cstdio>

#include <gonio/material.h>

int main() {
  const gonio::BxDF m = gonio::parse_material(R"({"type":"mirror","reflectance":0.25})");
  const auto f = m.f(gonio::Vec3{0, 0, 1}, gonio::Vec3{0, 0, 1});  // a delta lobe: f = 0
  if (!(f[0] == 0 && f[1] == 0 && f[2] == 0)) {
    std::fprintf(stderr, "pkgconfig_core: a mirror's f should be 0 off its delta\n");
    return 1;
  }
  const gonio::BxDF d = gonio::parse_material(R"({"type":"diffuse","reflectance":0.5})");
  const double v = d.f(gonio::Vec3{0, 0, 1}, gonio::Vec3{0, 0, 1})[0];
  if (std::fabs(v - 0.5 / 3.14159265358979323846) > 1e-6) {
    std::fprintf(stderr, "pkgconfig_core: diffuse f = %.9g, expected 0.5/pi\n", v);
    return 1;
  }
  std::printf("pkgconfig_core: ok\n");
  return 0;
}
