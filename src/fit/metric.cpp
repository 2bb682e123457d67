// The error metrics of `gonio fit` (gonio/fit/metric.h, docs/fitting.md).

#include "gonio/fit/metric.h"

#include <cmath>

#include "gonio/error.h"
#include "gonio/math/constants.h"

namespace gonio {

FitMetric parse_fit_metric(std::string_view name) {
  if (name == "ngan") return FitMetric::Ngan;
  if (name == "log") return FitMetric::Log;
  throw InputError("--metric must be ngan or log, got '" + std::string(name) + "'");
}

std::string_view fit_metric_name(FitMetric m) { return m == FitMetric::Ngan ? "ngan" : "log"; }

double merl_entry_weight(int i, int j) {
  // dωi dωo = 4 cos θd dωh dωd: the half vector's Jacobian |∂ωo/∂ωh| = 4 (ωi·ωh) = 4 cos θd
  // (Walter et al. 2007, eq. 14, inverted), and ωi is ωd rotated by the frame of ωh, which
  // keeps solid angle (Rusinkiewicz 1998, §3). With dωh = sin θh dθh dφh, dωd = sin θd dθd dφd,
  // and the constant 4 · 2π (φh) · Δθd · Δφd dropped. θh = (π/2) x², x = (i + ½)/90 at the
  // centre, so the bin spans Δθh = (π/2)((i + 1)² − i²)/90².
  const double dtheta_h = (kPiD / 2) * (2 * i + 1) / double(MerlTable::kThetaH * MerlTable::kThetaH);
  const double td = merl_theta_d(j);
  return std::sin(merl_theta_h(i)) * dtheta_h * std::sin(td) * std::cos(td);
}

double fit_error(const MerlTable& table, const BxDF& model, FitMetric metric, long long* evaluations) {
  double sum = 0, weights = 0;
  long long count = 0;
  for (int i = 0; i < MerlTable::kThetaH; ++i)
    for (int j = 0; j < MerlTable::kThetaD; ++j) {
      const double w = merl_entry_weight(i, j);
      for (int k = 0; k < MerlTable::kPhiD; ++k) {
        if (!merl_entry_measured(table.at(i, j, k))) continue;
        const auto [wo, wi] = merl_directions(merl_theta_h(i), merl_theta_d(j), merl_phi_d(k));
        if (!(wo.z > 0 && wi.z > 0)) continue;
        const Color f = table.at(i, j, k), g = model.f(wo, wi);
        ++count;
        double e = 0;
        for (int c = 0; c < 3; ++c) {
          const double d = fit_transform(metric, g[c], wi.z) - fit_transform(metric, f[c], wi.z);
          e += d * d;
        }
        sum += w * e;
        weights += w;
      }
    }
  if (evaluations) *evaluations += count;
  if (!(weights > 0)) throw InputError("the MERL table has no measured entry with both directions above the horizon");
  const double e = std::sqrt(sum / (3 * weights));
  // A model that returns Inf or NaN somewhere has no finite error: report it as bad input
  // rather than letting a NaN out.
  if (!std::isfinite(e)) throw InputError("the model's error against the table is not finite");
  return e;
}

}  // namespace gonio
