// The measured model's φd fold (SPEC §2: a MERL table holds φd in [0°, 180°), since
// swapping wi and wo adds 180° to φd, Rusinkiewicz 1998 §3) on a table that is not
// symmetric under φd → −φd. Measured isotropic materials are (mirror symmetry through the
// plane of incidence), so a fold by |φd| instead of φd + 180° reads the same value from
// them, and from the tests' cos 2φd patterns: this table has a sin 2φd term, which tells
// −φd (folded: 180° − φd) from φd.
//
// Independence: the table's bin centres are SPEC §2's, the directions come from
// Rusinkiewicz's frame, both written out below; the expected value is the analytic pattern
// at φd taken modulo 180°.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <utility>

#include "gonio/bxdf/measured.h"
#include "gonio/measured_data.h"
#include "gonio/merl.h"

namespace gonio {
namespace {

// Bin centres (SPEC §2), radians: θh = ((i + ½)/90)² π/2, θd = (j + ½)°, φd = (k + ½)°.
double fold_theta_h(int i) { return std::pow((i + 0.5) / 90, 2) * kPiD / 2; }
double fold_theta_d(int j) { return (j + 0.5) * kPiD / 180; }
double fold_phi_d(int k) { return (k + 0.5) * kPiD / 180; }

// The pattern, a function of the table's angles: positive, with both parities in φd, and a
// sum of one term per angle.
double fold_pattern(double th, double td, double pd) {
  return 0.5 + 0.2 * th + 0.1 * td + 0.15 * std::cos(2 * pd) + 0.2 * std::sin(2 * pd);
}

// wi = cos θd h + sin θd (cos φd t + sin φd b) in the frame h = (sin θh, 0, cos θh),
// t = (cos θh, 0, −sin θh), b = (0, 1, 0) (φh = 0); wo = 2 (wi·h) h − wi.
std::pair<Vec3, Vec3> fold_directions(double th, double td, double pd) {
  const double h[3] = {std::sin(th), 0, std::cos(th)}, t[3] = {std::cos(th), 0, -std::sin(th)}, b[3] = {0, 1, 0};
  double wi[3], wo[3];
  for (int a = 0; a < 3; ++a) wi[a] = std::cos(td) * h[a] + std::sin(td) * (std::cos(pd) * t[a] + std::sin(pd) * b[a]);
  const double hd = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
  for (int a = 0; a < 3; ++a) wo[a] = 2 * hd * h[a] - wi[a];
  return {Vec3{Float(wo[0]), Float(wo[1]), Float(wo[2])}, Vec3{Float(wi[0]), Float(wi[1]), Float(wi[2])}};
}

// At bin centres the lookup returns the entry itself; at φd, φd + 180° (wi and wo swapped)
// and −φd (the pair mirrored through the plane of incidence) it must return the pattern at
// φd, φd and 180° − φd respectively.
TEST(Measured, FoldsPhiDByReciprocityNotByMirrorSymmetry) {
  // The table in memory, as read_merl would make it (the MERL file format has tests of its
  // own): writing and reading 35 MB would be most of this test's time.
  MerlTable table;
  for (int i = 0; i < MerlTable::kThetaH; ++i)
    for (int j = 0; j < MerlTable::kThetaD; ++j)
      for (int k = 0; k < MerlTable::kPhiD; ++k)
        table.set(i, j, k, Color(Float(fold_pattern(fold_theta_h(i), fold_theta_d(j), fold_phi_d(k)))));
  const MeasuredBxDF m = MeasuredBxDF::make(std::make_shared<const MeasuredData>(std::move(table)));
  int checked = 0;
  for (int i = 5; i < 90; i += 7)
    for (int j = 3; j < 90; j += 11)
      for (int k = 2; k < 180; k += 13) {
        const double th = fold_theta_h(i), td = fold_theta_d(j), pd = fold_phi_d(k);
        const struct {
          double phi, expected_phi;
          const char* what;
        } cases[] = {{pd, pd, "phi_d"}, {pd + kPiD, pd, "phi_d + 180"}, {-pd, kPiD - pd, "-phi_d"}};
        for (const auto& c : cases) {
          const auto [wo, wi] = fold_directions(th, td, c.phi);
          if (wo.z < 0.05 || wi.z < 0.05) continue;
          const double want = fold_pattern(th, td, c.expected_phi);
          ASSERT_NEAR(m.f(wo, wi, TransportMode::Radiance)[0], want, 1e-3 * want) << c.what << ": i " << i << ", j " << j << ", k " << k;
          ++checked;
        }
      }
  EXPECT_GT(checked, 400);
}

}  // namespace
}  // namespace gonio
