// gonio table: the lecture's Fresnel reflectance table (lecture §5.4, Fig. 8): Rs, Rp and
// R against the angle of incidence for glass, water and gold, with the Brewster and
// critical angles. The main job until the renderer lands.

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "gonio/fresnel.h"
#include "gonio/metals.h"

namespace gonio::cli {

namespace {
constexpr double kDeg = kPiD / 180;

void dielectric_table(const char* name, double eta) {
  // Brewster: tan θB = η (Rp = 0); critical angle from the dense side: sin θc = 1/η.
  std::printf("\n%s, eta = %.4g\n", name, eta);
  std::printf("  Brewster angle (outside): %.4f deg   critical angle (inside): %.4f deg\n",
              std::atan(eta) / kDeg, std::asin(1 / eta) / kDeg);
  std::printf("  %5s | %9s %9s %9s %9s | %9s %9s %9s   (from inside)\n", "theta", "Rs", "Rp", "R",
              "Schlick", "Rs", "Rp", "R");
  for (int deg = 0; deg <= 90; deg += 5) {
    const double c = deg == 90 ? 0.0 : std::cos(deg * kDeg);
    const auto out = fresnel_dielectric_terms(c, eta);
    const auto in = fresnel_dielectric_terms(-c, eta);
    std::printf("  %5d | %9.6f %9.6f %9.6f %9.6f | %9.6f %9.6f %9.6f%s\n", deg, out.rs, out.rp,
                out.r(), fresnel_schlick_dielectric(c, eta), in.rs, in.rp, in.r(),
                in.tir ? "  TIR" : "");
  }
}

void conductor_table(const char* name, const ComplexIor& m) {
  std::printf("\n%s, RGB-mode n + ik: r %.4f+%.4fi, g %.4f+%.4fi, b %.4f+%.4fi\n",
              name, m.eta[0], m.k[0], m.eta[1], m.k[1], m.eta[2], m.k[2]);
  std::printf("  %5s | %9s %9s %9s | %9s %9s %9s\n", "theta", "R red", "R green", "R blue",
              "Rs green", "Rp green", "Schlick g");
  int min_deg = 0;
  double min_rp = 2;
  for (int deg = 0; deg <= 90; ++deg) {
    const auto t = fresnel_conductor_terms(std::cos(deg * kDeg), double(m.eta[1]), double(m.k[1]));
    if (t.rp < min_rp) min_rp = t.rp, min_deg = deg;
  }
  for (int deg = 0; deg <= 90; deg += 5) {
    const double c = deg == 90 ? 0.0 : std::cos(deg * kDeg);
    double r[3];
    for (int i = 0; i < 3; ++i) r[i] = fresnel_conductor(c, double(m.eta[i]), double(m.k[i]));
    const auto g = fresnel_conductor_terms(c, double(m.eta[1]), double(m.k[1]));
    std::printf("  %5d | %9.6f %9.6f %9.6f | %9.6f %9.6f %9.6f\n", deg, r[0], r[1], r[2], g.rs, g.rp,
                fresnel_schlick(fresnel_f0(double(m.eta[1]), double(m.k[1])), c));
  }
  std::printf("  principal angle (Rp minimum, green, 1 deg steps): %d deg, Rp = %.6f\n", min_deg, min_rp);
}

void run_table() {
  std::printf("Fresnel reflectance (lecture section 5.4): s, p and unpolarised R = (Rs + Rp) / 2\n");
  dielectric_table("glass", 1.5);
  dielectric_table("water", 1.333);
  conductor_table("gold (Au)", *named_metal("Au"));
}
}  // namespace

void register_table(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "table", "Print the lecture's Fresnel table: Rs, Rp, R for glass, water and gold, 0-90 deg, "
               "with the Brewster and critical angles");
  cmd->callback([] { run_table(); });
}

}  // namespace gonio::cli
