// The MERL bin measures of include/gonio/measure/merl_bins.h.
#include "gonio/measure/merl_bins.h"

#include <algorithm>
#include <cmath>

#include "gonio/math/constants.h"
#include "gonio/math/fast_atan.h"
#include "gonio/merl.h"

namespace gonio::measure {
namespace {

constexpr double kHalfPi = kPiD / 2;

// θh edges: index = 90 √(θh / (π/2)) (merl.h), so edge i is (i/90)² π/2.
double theta_h_edge(int i) {
  const double x = double(i) / MerlTable::kThetaH;
  return x * x * kHalfPi;
}
double theta_d_edge(int j) { return double(j) / MerlTable::kThetaD * kHalfPi; }
double phi_d_edge(int k) { return double(k) / MerlTable::kPhiD * kPiD; }

std::vector<double> compute() {
  constexpr int H = MerlTable::kThetaH, D = MerlTable::kThetaD, P = MerlTable::kPhiD;
  constexpr int Q = 16;  // midpoint rule per axis in a cut bin
  const double dphi = kPiD / P;
  std::vector<double> m(MerlTable::kEntries, 0.0);
  std::vector<double> len(P), whole(P + 1);
  for (int i = 0; i < H; ++i) {
    const double h0 = theta_h_edge(i), h1 = theta_h_edge(i + 1);
    for (int j = 0; j < D; ++j) {
      const double d0 = theta_d_edge(j), d1 = theta_d_edge(j + 1);
      // tan θh tan θd grows with both: the bin's largest product is at its far corner.
      if (std::tan(h1) * std::tan(d1) < 1) {
        const double full = 16 * kPiD * (std::cos(h0) - std::cos(h1)) *
                             (std::sin(d1) * std::sin(d1) - std::sin(d0) * std::sin(d0)) / 2 * dphi;
        for (int k = 0; k < P; ++k) m[MerlTable::index(i, j, k)] = full;
        continue;
      }
      // len[k]: ∫∫ weight × (valid length of φd bin k); whole bins inside (α, π − α) are
      // added through a difference array, the two bins its ends cut directly.
      std::fill(len.begin(), len.end(), 0.0);
      std::fill(whole.begin(), whole.end(), 0.0);
      const double wh = (h1 - h0) / Q, wd = (d1 - d0) / Q;
      for (int a = 0; a < Q; ++a) {
        const double th = h0 + (a + 0.5) * wh;
        for (int b = 0; b < Q; ++b) {
          const double td = d0 + (b + 0.5) * wd;
          const double weight = std::sin(th) * std::cos(td) * std::sin(td) * wh * wd;
          // Valid φd: |cos φd| < 1 / (tan θh tan θd), i.e. φd in (α, π − α).
          const double c = std::tan(th) * std::tan(td);
          const double alpha = c <= 1 ? 0.0 : std::acos(1 / c);
          const double lo = alpha, hi = kPiD - alpha;
          if (!(hi > lo)) continue;
          const int klo = std::min(P - 1, int(lo / dphi)), khi = std::min(P - 1, int(hi / dphi));
          if (klo == khi) {
            len[klo] += weight * (hi - lo);
            continue;
          }
          len[klo] += weight * (phi_d_edge(klo + 1) - lo);
          len[khi] += weight * (hi - phi_d_edge(khi));
          whole[klo + 1] += weight * dphi;  // bins klo+1 .. khi-1 whole
          whole[khi] -= weight * dphi;
        }
      }
      double run = 0;
      for (int k = 0; k < P; ++k) {
        run += whole[k];
        len[k] += run;
        if (len[k] < 1e-18) len[k] = 0;  // the running sum's rounding where nothing is valid
      }
      for (int k = 0; k < P; ++k) m[MerlTable::index(i, j, k)] = 16 * kPiD * len[k];
    }
  }
  return m;
}

}  // namespace

const std::vector<double>& merl_bin_measures() {
  static const std::vector<double> m = compute();
  return m;
}

MerlBin merl_bin(double theta_h, double theta_d, double phi_d) {
  const int i = std::clamp(int(std::sqrt(std::max(0.0, theta_h) / kHalfPi) * MerlTable::kThetaH), 0, MerlTable::kThetaH - 1);
  const int j = std::clamp(int(theta_d / kHalfPi * MerlTable::kThetaD), 0, MerlTable::kThetaD - 1);
  const int k = std::clamp(int(phi_d / kPiD * MerlTable::kPhiD), 0, MerlTable::kPhiD - 1);
  return {i, j, k};
}

}  // namespace gonio::measure

namespace gonio::measure {

MerlBin merl_bin_of(const Vec3& wo, const Vec3& wi) {
  Float th, td, pd;
  half_diff_angles<Float>(wo, wi, [](Float y, Float x) { return fast_atan2(y, x); }, th, td, pd);
  // Indices as merl_bin (merl.h's index formulas), φd folded by reciprocity into [0, π).
  constexpr Float kToH = Float(1 / (kPiD / 2)), kToD = Float(MerlTable::kThetaD / (kPiD / 2)),
                  kToP = Float(MerlTable::kPhiD / kPiD);
  if (pd < 0) pd += kPi;
  const int i = std::clamp(int(std::sqrt(std::max(Float(0), th) * kToH) * MerlTable::kThetaH), 0, MerlTable::kThetaH - 1);
  const int j = std::clamp(int(td * kToD), 0, MerlTable::kThetaD - 1);
  const int k = std::clamp(int(pd * kToP), 0, MerlTable::kPhiD - 1);
  return {i, j, k};
}

}  // namespace gonio::measure
