// gonio fit: Levenberg–Marquardt (Ceres) on a stratified subsample of a MERL table, from a
// few starting points; the best fit's error on the full table (gonio/fit/fit.h,
// docs/fitting.md).

#include "gonio/fit/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include <ceres/ceres.h>

#include "fit_models.h"
#include "gonio/error.h"
#include "gonio/material.h"

namespace gonio {
namespace {

using fit_detail::FitModel;
using fit_detail::ojson;
using fit_detail::Slot;

// One entry of the subsample: its directions, √(its share of the weight), and the
// table's value through the metric's compression, per channel.
struct Sample {
  Vec3 wo, wi;
  double sqrt_weight;
  double target[3];
};

// Values rounded to 7 significant digits (the models compute in float), so that the
// printed material is short and is exactly the material whose error is reported.
double round7(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return std::strtod(buf, nullptr);
}
void round_numbers(ojson& j) {
  if (j.is_number_float()) j = round7(j.get<double>());
  else if (j.is_array() || j.is_object())
    for (auto& e : j) round_numbers(e);
}

// The parameter vector's layout: its variables' slots, and the groups of variables that a
// central difference perturbs together. A colour slot is one group of three: channel c of
// every model here depends on channel c of its colour parameters only, so one pair of
// evaluations gives the three partial derivatives (the Jacobian is diagonal in the channels).
struct Layout {
  std::vector<const Slot*> slot_of;  // per variable
  struct Group {
    int first;
    bool colour;
  };
  std::vector<Group> groups;
  explicit Layout(const FitModel& m) {
    for (const Slot& s : m.slots) {
      groups.push_back({int(slot_of.size()), s.colour});
      for (int c = 0; c < (s.colour ? 3 : 1); ++c) slot_of.push_back(&s);
    }
  }
  int size() const { return int(slot_of.size()); }
};

// The models at the current variables and at the central-difference perturbations, shared
// by every residual block: Ceres evaluates the blocks one after another at the same point,
// so each material is parsed once per point, not once per block.
class ModelCache {
 public:
  ModelCache(const FitModel& m, const Layout& l) : model_(m), layout_(l) {}
  static constexpr double kStep = 1e-3;  // in the variables: relative 10⁻³ of a log-mapped value

  // nullopt when a material cannot be built (never expected: the variables are bounded).
  const std::optional<BxDF>& base(const double* u) {
    refresh(u);
    if (!base_) base_ = build(u, -1, 0);
    return *base_;
  }
  const std::optional<BxDF>& perturbed(const double* u, size_t group, int sign) {
    refresh(u);
    auto& slot = shifted_[2 * group + (sign > 0 ? 1 : 0)];
    if (!slot) slot = build(u, int(group), sign * kStep);
    return *slot;
  }
  std::vector<double> values(const double* u) const {
    std::vector<double> v(size_t(layout_.size()));
    for (int p = 0; p < layout_.size(); ++p) v[size_t(p)] = fit_detail::to_value(*layout_.slot_of[size_t(p)], u[p]);
    return v;
  }
  ojson describe(const double* u) const { return model_.describe(values(u), model_.fixed); }

 private:
  void refresh(const double* u) {
    if (key_.size() == size_t(layout_.size()) && std::equal(key_.begin(), key_.end(), u)) return;
    key_.assign(u, u + layout_.size());
    base_.reset();
    shifted_.assign(2 * layout_.groups.size(), std::nullopt);
  }
  std::optional<BxDF> build(const double* u, int group, double step) const {
    std::vector<double> x(u, u + layout_.size());
    if (group >= 0) {
      const auto& g = layout_.groups[size_t(group)];
      for (int c = 0; c < (g.colour ? 3 : 1); ++c) x[size_t(g.first + c)] += step;
    }
    try {
      return material_from_json(nlohmann::json::parse(describe(x.data()).dump()));
    } catch (const InputError&) {
      return std::nullopt;
    }
  }
  const FitModel& model_;
  const Layout& layout_;
  std::vector<double> key_;
  std::optional<std::optional<BxDF>> base_;
  std::vector<std::optional<std::optional<BxDF>>> shifted_;
};

// The residuals of a run of entries: r = √w (T(model) − T(table)) per channel, T the
// metric's compression; the Jacobian by central differences.
class BlockCost final : public ceres::CostFunction {
 public:
  BlockCost(std::vector<Sample> samples, FitMetric metric, const Layout& layout, ModelCache& cache,
            long long& evaluations)
      : s_(std::move(samples)), metric_(metric), layout_(layout), cache_(cache), evaluations_(evaluations) {
    set_num_residuals(int(3 * s_.size()));
    mutable_parameter_block_sizes()->push_back(layout.size());
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* u = parameters[0];
    const auto& base = cache_.base(u);
    if (!base || !residuals_of(*base, residuals)) return false;
    if (!jacobians || !jacobians[0]) return true;
    const int n = layout_.size();
    double* J = jacobians[0];
    std::fill(J, J + size_t(num_residuals()) * size_t(n), 0.0);
    const size_t nr = size_t(num_residuals());
    std::vector<double> plus(nr), minus(nr);
    for (size_t g = 0; g < layout_.groups.size(); ++g) {
      const auto& mp = cache_.perturbed(u, g, +1);
      const auto& mm = cache_.perturbed(u, g, -1);
      if (!mp || !mm || !residuals_of(*mp, plus.data()) || !residuals_of(*mm, minus.data())) return false;
      const auto& group = layout_.groups[g];
      for (int r = 0; r < num_residuals(); ++r) {
        const int p = group.first + (group.colour ? r % 3 : 0);
        J[size_t(r) * size_t(n) + size_t(p)] = (plus[size_t(r)] - minus[size_t(r)]) / (2 * ModelCache::kStep);
      }
    }
    return true;
  }

 private:
  bool residuals_of(const BxDF& m, double* r) const {
    evaluations_ += (long long)s_.size();
    for (size_t e = 0; e < s_.size(); ++e) {
      const Sample& s = s_[e];
      const Color g = m.f(s.wo, s.wi);
      for (int c = 0; c < 3; ++c) {
        const double v = s.sqrt_weight * (fit_transform(metric_, g[c], s.wi.z) - s.target[c]);
        if (!std::isfinite(v)) return false;
        r[3 * e + size_t(c)] = v;
      }
    }
    return true;
  }
  std::vector<Sample> s_;
  FitMetric metric_;
  const Layout& layout_;
  ModelCache& cache_;
  long long& evaluations_;
};

// The subsample: every θh bin; θd and φd bins at strides `stride` and 2·`stride`, offset
// to the middle of each stride. Entries measured and with both directions above the
// horizon only (the metric's entries).
std::vector<Sample> subsample(const MerlTable& table, FitMetric metric, int stride) {
  const int sd = stride, sp = 2 * stride;
  std::vector<Sample> out;
  double total = 0;
  for (int i = 0; i < MerlTable::kThetaH; ++i)
    for (int j = sd / 2; j < MerlTable::kThetaD; j += sd) {
      const double w = merl_entry_weight(i, j);
      for (int k = sp / 2; k < MerlTable::kPhiD; k += sp) {
        if (!merl_entry_measured(table.at(i, j, k))) continue;
        const auto [wo, wi] = merl_directions(merl_theta_h(i), merl_theta_d(j), merl_phi_d(k));
        if (!(wo.z > 0 && wi.z > 0)) continue;
        const Color f = table.at(i, j, k);
        Sample s{wo, wi, w, {}};
        for (int c = 0; c < 3; ++c) s.target[c] = fit_transform(metric, f[c], wi.z);
        out.push_back(s);
        total += w;
      }
    }
  // Normalised as the metric: Σ r² = 3 E² on the subsample.
  for (Sample& s : out) s.sqrt_weight = std::sqrt(s.sqrt_weight / total);
  return out;
}

}  // namespace

const std::vector<std::string>& fit_model_names() { return fit_detail::fit_model_list(); }

void check_fit_options(const FitOptions& options) {
  (void)fit_detail::make_fit_model(options.model, options.distribution, options.init);
  if (options.stride < 1 || options.stride > 45)
    throw InputError("--stride must be in [1, 45], got " + std::to_string(options.stride));
}

FitResult fit_merl(const MerlTable& table, const FitOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  check_fit_options(options);
  const FitModel model = fit_detail::make_fit_model(options.model, options.distribution, options.init);
  const Layout layout(model);
  FitResult result;

  std::vector<Sample> samples = subsample(table, options.metric, options.stride);
  if (samples.size() < size_t(layout.size()))
    throw InputError("the MERL table has " + std::to_string(samples.size()) +
                     " usable entries in the fit's subsample (measured, both directions above the horizon); "
                     "too few for " + std::to_string(layout.size()) + " parameters");

  // The multi-start: the starting values of the one slot with several (the roughness or
  // exponent), unless --init gave that slot.
  size_t multi = 0, starts = 1;
  for (size_t s = 0; s < model.slots.size(); ++s) {
    bool given = false;
    for (const auto& g : model.given) given |= g.first == model.slots[s].name;
    if (!given && model.slots[s].starts.size() > starts) multi = s, starts = model.slots[s].starts.size();
  }

  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<double> best;
  for (size_t start = 0; start < starts; ++start) {
    std::vector<double> u;
    for (size_t s = 0; s < model.slots.size(); ++s) {
      const Slot& slot = model.slots[s];
      std::vector<double> v(slot.colour ? 3 : 1, slot.starts[s == multi ? start : 0]);
      for (const auto& g : model.given)
        if (g.first == slot.name) v = g.second;
      for (double x : v) u.push_back(fit_detail::to_variable(slot, x));
    }
    ModelCache cache(model, layout);
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    // Residual blocks of many entries each: contiguous runs of the subsample (which is in
    // θh order), kBlocks of them.
    constexpr size_t kBlocks = 16;
    const size_t per_block = (samples.size() + kBlocks - 1) / kBlocks;
    for (size_t at = 0; at < samples.size(); at += per_block) {
      std::vector<Sample> block(samples.begin() + long(at), samples.begin() + long(std::min(samples.size(), at + per_block)));
      problem.AddResidualBlock(new BlockCost(std::move(block), options.metric, layout, cache, result.evaluations),
                               nullptr, u.data());
    }
    for (int p = 0; p < layout.size(); ++p) {
      problem.SetParameterLowerBound(u.data(), p, fit_detail::variable_lower(*layout.slot_of[size_t(p)]));
      problem.SetParameterUpperBound(u.data(), p, fit_detail::variable_upper(*layout.slot_of[size_t(p)]));
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    so.max_num_iterations = options.max_iterations;
    so.function_tolerance = 1e-10;
    so.parameter_tolerance = 1e-9;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (summary.final_cost < best_cost) {
      best_cost = summary.final_cost;
      best = u;
    }
    ++result.starts;
  }
  if (best.empty()) throw InputError("the fit found no finite error from any starting point");

  ModelCache cache(model, layout);
  ojson material = cache.describe(best.data());
  round_numbers(material);
  const BxDF fitted = material_from_json(nlohmann::json::parse(material.dump()));
  result.error = fit_error(table, fitted, options.metric, &result.evaluations);
  result.material = material;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace gonio
