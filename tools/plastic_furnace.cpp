// gonio_plastic_furnace: the white furnace sweep of rough plastic (docs/microfacet.md).
// A white base (ρ = 1) under a coat that absorbs nothing returns all the light, so the
// directional albedo must be 1 at every angle (issue 9: within [0.99, 1.005]). For each
// (distribution, α, η) it prints the lowest and highest albedo over the angles, with the
// angle, and FAIL outside the bounds. Exit 0 when none failed, 1 otherwise.
//
//   build/bin/gonio_plastic_furnace [--samples N] [--seed S]
// N samples per angle (default 200000); the estimate's standard error is ~0.0003 there.

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/math/spherical.h"
#include "gonio/reflectance.h"

int main(int argc, char** argv) {
  using namespace gonio;
  ReflectanceOptions opt{200000, 11};
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--samples") && has_value) opt.samples = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--seed") && has_value) opt.seed = std::strtoull(argv[++i], nullptr, 10);
    else {
      std::fprintf(stderr, "usage: gonio_plastic_furnace [--samples N] [--seed S]\n");
      return 2;
    }
  }
  if (opt.samples < 1) {
    std::fprintf(stderr, "gonio_plastic_furnace: --samples must be at least 1\n");
    return 2;
  }
  // η from the float next to 1 to the largest plastic accepts; α from the smallest rough
  // coat (below 1e-3 it is smooth) to the largest; angles up to 0.01° from grazing.
  const double etas[] = {1 + 1.2e-7, 1 + 1e-6, 1.00003, 1.0003, 1.002, 1.007, 1.03, 1.07, 1.2, 1.33,
                         1.5,        1.7,      2.4,     4,      6,     10,    30,   100,  1000, 1e4};
  const double alphas[] = {1e-3, 0.002, 0.005, 0.02, 0.1, 0.5, 2, 10};
  const double thetas[] = {0, 60, 80, 85, 88, 89, 89.5, 89.8, 89.9, 89.94, 89.97, 89.99};
  int failed = 0;
  for (const char* dist : {"ggx", "beckmann"})
    for (double eta : etas)
      for (double alpha : alphas) {
        char json[256];
        std::snprintf(json, sizeof json,
                      R"({"type":"plastic","reflectance":1,"distribution":"%s","alpha":%.9g,"eta":%.9g})", dist,
                      alpha, eta);
        const BxDF m = parse_material(json);
        double lo = 2, hi = 0, th_lo = 0, th_hi = 0;
        for (double th : thetas) {
          const double a = directional_albedo(m, direction_from_angles(Float(th * kPiD / 180), 0.4f), opt).albedo[0];
          if (a < lo) lo = a, th_lo = th;
          if (a > hi) hi = a, th_hi = th;
        }
        const bool fail = lo < 0.99 || hi > 1.005;
        failed += fail;
        std::printf("%-8s alpha %-6g eta %-10.9g min %.4f at %g deg, max %.4f at %g deg%s\n", dist, alpha, eta, lo,
                    th_lo, hi, th_hi, fail ? "  FAIL" : "");
      }
  std::printf("%d of %zu (distribution, alpha, eta) outside [0.99, 1.005]\n", failed,
              2 * std::size(etas) * std::size(alphas));
  return failed ? 1 : 0;
}
