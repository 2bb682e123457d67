#pragma once
// Fitting an analytic model to a measured isotropic BRDF (a MERL table) with Ceres:
// `gonio fit` (SPEC §3, docs/fitting.md). The model's continuous parameters are optimised
// in an unconstrained space (logit for values in [0, 1], log with bounds for scales) by
// Levenberg–Marquardt on a stratified subsample of the table, from a few starting points;
// the best fit's error is then computed on the full table.
//
// Built as the separate library gonio_fit (Ceres is its private dependency; the core
// library `gonio` does not depend on Ceres).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/fit/metric.h"
#include "gonio/merl.h"

namespace gonio {

struct FitOptions {
  // roughconductor, plastic, blinnphong, phong, ward, ashikhminshirley, orennayar, blend
  // (fit_model_names()).
  std::string model;
  // "ggx" or "beckmann" for the microfacet models; empty: the --init's, else ggx.
  std::string distribution;
  FitMetric metric = FitMetric::Log;
  // A starting material of type `model` (may be partial): its values start the
  // optimisation, its discrete choices (fresnel, distribution, plastic's eta) are kept.
  // Null: none.
  nlohmann::json init;
  // The subsample: every θh bin, every `stride`-th θd bin and every 2·`stride`-th φd bin.
  int stride = 3;
  // Iteration limit of each start.
  int max_iterations = 100;
};

struct FitResult {
  nlohmann::ordered_json material;  // valid input to material_from_json / `--bsdf`
  double error = 0;         // the metric of `material` against the full table
  long long evaluations = 0;  // model evaluations f(wo, wi), fit and final error together
  double seconds = 0;         // wall-clock time of the whole fit
  int starts = 0;             // starting points tried
};

// The models `fit_merl` knows, in the order of docs/fitting.md.
const std::vector<std::string>& fit_model_names();

// Checks the options alone (model, distribution, init, stride) as fit_merl does, without a
// table: a command line can report them before it reads a 35 MB file.
void check_fit_options(const FitOptions& options);

// Fits `options.model` to `table`. Throws InputError (one line) for an unknown model, a bad
// distribution, a bad or mismatched init, or a table with no usable entry.
FitResult fit_merl(const MerlTable& table, const FitOptions& options);

// Silences the solver's own log (Ceres's glog messages on stderr, e.g. "Terminating: ..."
// when a start fails) for the whole process, so that a failed fit is reported by the one
// line of its InputError. A program that wants glog's messages does not call it.
void quiet_solver_log();

}  // namespace gonio
