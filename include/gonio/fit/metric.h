#pragma once
// The two error metrics `gonio fit` minimises and reports (docs/fitting.md gives their
// formulas, sources and the derivation of the weights). Both compare a model with a MERL
// table over the table's entries whose two directions (at the bin centre) are above the
// horizon and which were measured, each entry weighted by the solid-angle measure of its
// bin in (ωi, ωo):
//   ngan: E = sqrt( Σ_e w_e Σ_c (g_c cos θi − f_c cos θi)² / (3 Σ_e w_e) )   (Ngan et al. 2005)
//   log:  E = sqrt( Σ_e w_e Σ_c (ln(1 + g_c cos θi) − ln(1 + f_c cos θi))² / (3 Σ_e w_e) )
//         (Löw et al. 2012)
// with f the table, g the model, c the three channels.

#include <cmath>
#include <string>
#include <string_view>

#include "gonio/bxdf.h"
#include "gonio/merl.h"

namespace gonio {

enum class FitMetric { Ngan, Log };

// "ngan" or "log"; InputError naming the value otherwise.
FitMetric parse_fit_metric(std::string_view name);
std::string_view fit_metric_name(FitMetric m);

// The compressed value the metric compares: f cos θi (ngan) or ln(1 + f cos θi) (log).
inline double fit_transform(FitMetric m, double f, double cos_theta_i) {
  const double v = f * cos_theta_i;
  return m == FitMetric::Ngan ? v : std::log1p(v);
}

// An entry counts as measured when no channel is negative (MERL's "not measured") or NaN;
// read_merl marks all three, a table made in memory may not.
inline bool merl_entry_measured(const Color& f) { return f[0] >= 0 && f[1] >= 0 && f[2] >= 0; }

// The weight of entry (i, j, ·) up to a constant factor: the solid-angle measure of its bin,
// dωi dωo = 4 cos θd sin θd sin θh dθh dφh dθd dφd (docs/fitting.md), at the bin centre,
// with the θh bin's width (π/2)(2i + 1)/90² (its axis is quadratic in the index).
double merl_entry_weight(int i, int j);

// The metric of `model` against every counted entry of `table` (above). Throws
// InputError when no entry counts (an empty table). `evaluations`, when given, is
// increased by the number of model evaluations.
double fit_error(const MerlTable& table, const BxDF& model, FitMetric metric, long long* evaluations = nullptr);

}  // namespace gonio
