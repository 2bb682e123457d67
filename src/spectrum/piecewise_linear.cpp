#include "gonio/spectrum/piecewise_linear.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/spectrum/csv.h"

namespace gonio {
namespace {

// Checks one point against its predecessor; `at` names it ("file.csv:7: " or "what: point 3: ").
void check_point(double nm, double value, const double* previous_nm, const std::string& at) {
  if (!std::isfinite(nm) || !(nm > 0))
    throw InputError(at + "wavelength must be a positive number of nm, got " + format_number(nm));
  if (nm > 1e6) throw InputError(at + "wavelength must be at most 1e6 nm, got " + format_number(nm));
  if (previous_nm && !(nm > *previous_nm))
    throw InputError(at + "wavelengths must increase, got " + format_number(nm) + " nm after " + format_number(*previous_nm) + " nm");
  if (!std::isfinite(value) || std::abs(value) > 1e30)
    throw InputError(at + "value must be a finite number, got " + format_number(value));
}

}  // namespace

PiecewiseLinearSpectrum PiecewiseLinearSpectrum::from_points(const std::vector<std::pair<double, double>>& points,
                                                             std::string_view what) {
  if (points.empty()) throw InputError(std::string(what) + ": a spectrum needs at least one [nm, value] point");
  PiecewiseLinearSpectrum s;
  for (size_t i = 0; i < points.size(); ++i) {
    const double* prev = i > 0 ? &points[i - 1].first : nullptr;
    check_point(points[i].first, points[i].second, prev, std::string(what) + ": point " + std::to_string(i + 1) + ": ");
    s.lambda_.push_back(Float(points[i].first));
    s.value_.push_back(Float(points[i].second));
  }
  // Strictly increasing in double may tie in float (e.g. 500 and 500.00001).
  for (size_t i = 1; i < s.lambda_.size(); ++i)
    if (!(s.lambda_[i] > s.lambda_[i - 1]))
      throw InputError(std::string(what) + ": point " + std::to_string(i + 1) + ": wavelengths " +
                       format_number(points[i - 1].first) + " and " + format_number(points[i].first) + " nm are too close");
  return s;
}

PiecewiseLinearSpectrum PiecewiseLinearSpectrum::from_csv_text(std::string_view text, std::string_view source) {
  const auto rows = parse_csv(text, source, 2);
  std::vector<std::pair<double, double>> points;
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::string at = std::string(source) + ":" + std::to_string(rows[i].line) + ": ";
    check_point(rows[i].values[0], rows[i].values[1], i > 0 ? &rows[i - 1].values[0] : nullptr, at);
    if (i > 0 && !(Float(rows[i].values[0]) > Float(rows[i - 1].values[0])))
      throw InputError(at + "wavelength too close to the previous row's");
    points.emplace_back(rows[i].values[0], rows[i].values[1]);
  }
  return from_points(points, source);
}

PiecewiseLinearSpectrum PiecewiseLinearSpectrum::from_csv_file(const std::string& path) {
  return from_csv_text(read_text_file(path, kMaxSpectrumFileBytes, "a spectrum file"), path);
}

Float PiecewiseLinearSpectrum::eval(Float lambda) const {
  const size_t n = lambda_.size();
  if (n == 0) return 0;
  if (!(lambda > lambda_[0])) return value_[0];  // NaN too
  if (!(lambda < lambda_[n - 1])) return value_[n - 1];
  // First node > lambda: 1 ≤ i ≤ n − 1.
  const size_t i = size_t(std::upper_bound(lambda_.begin(), lambda_.end(), lambda) - lambda_.begin());
  const Float t = (lambda - lambda_[i - 1]) / (lambda_[i] - lambda_[i - 1]);
  return value_[i - 1] + t * (value_[i] - value_[i - 1]);
}

PiecewiseLinearSpectrum PiecewiseLinearSpectrum::scaled(Float s) const {
  PiecewiseLinearSpectrum r = *this;
  for (auto& v : r.value_) v *= s;
  return r;
}

Float PiecewiseLinearSpectrum::min_value() const {
  return value_.empty() ? 0 : *std::min_element(value_.begin(), value_.end());
}
Float PiecewiseLinearSpectrum::max_value() const {
  return value_.empty() ? 0 : *std::max_element(value_.begin(), value_.end());
}

}  // namespace gonio
