// Evaluates a material through the public API of SPEC §5 and checks the results against
// closed forms: a Lambertian f = ρ/π, and its hemispherical–hemispherical reflectance ρ.

#include <cmath>
#include <cstdio>
#include <cstring>

#include <gonio/material.h>
#include <gonio/reflectance.h>
#include <gonio/version.h>

int main() {
  const gonio::BxDF m = gonio::parse_material(R"({"type":"diffuse","reflectance":[0.2,0.4,0.6]})");
  const auto f = m.f(gonio::Vec3{0, 0, 1}, gonio::Vec3{0.6f, 0, 0.8f});
  const double pi = 3.14159265358979323846;
  const double expected[3] = {0.2 / pi, 0.4 / pi, 0.6 / pi};
  for (int c = 0; c < 3; ++c) {
    if (std::fabs(f[c] - expected[c]) > 1e-6) {
      std::fprintf(stderr, "consumer_core: f[%d] = %.9g, expected %.9g\n", c, double(f[c]), expected[c]);
      return 1;
    }
  }
  const auto rho = gonio::reflectance(m, gonio::HemisphereDomain{}, gonio::HemisphereDomain{});
  if (std::fabs(rho.value[1] - 0.4) > 1e-3) {
    std::fprintf(stderr, "consumer_core: rho_hh[1] = %.9g, expected 0.4\n", double(rho.value[1]));
    return 1;
  }
  if (std::strcmp(gonio::version_string, GONIO_VERSION_STRING) != 0 || GONIO_VERSION_MAJOR != 0 ||
      GONIO_VERSION_MINOR != 2) {
    std::fprintf(stderr, "consumer_core: unexpected version %s\n", gonio::version_string);
    return 1;
  }
  std::printf("consumer_core: gonio %s, f = %.6g %.6g %.6g, rho_hh = %.6g\n", gonio::version_string,
              double(f[0]), double(f[1]), double(f[2]), double(rho.value[1]));
  return 0;
}
