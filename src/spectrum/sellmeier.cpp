#include "gonio/spectrum/sellmeier.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "gonio/error.h"

namespace gonio {
namespace {
constexpr double kLoUm = kLambdaMin / 1000.0, kHiUm = kLambdaMax / 1000.0;
}  // namespace

SellmeierSpectrum::SellmeierSpectrum(const std::array<double, 3>& b, const std::array<double, 3>& c,
                                     std::string_view what)
    : b_(b), c_(c) {
  const std::string w(what);
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(b[size_t(i)]) || std::abs(b[size_t(i)]) > 1e6)
      throw InputError(w + ": B[" + std::to_string(i) + "] must be a finite number, got " + format_number(b[size_t(i)]));
    if (!std::isfinite(c[size_t(i)]) || c[size_t(i)] < 0 || c[size_t(i)] > 1e12)
      throw InputError(w + ": C[" + std::to_string(i) + "] must be a number ≥ 0 (µm²), got " + format_number(c[size_t(i)]));
    // A pole λ² = C_i inside the visible range (with a margin of 1 nm).
    const double pole = std::sqrt(c[size_t(i)]);
    if (b[size_t(i)] != 0 && pole >= kLoUm - 1e-3 && pole <= kHiUm + 1e-3)
      throw InputError(w + ": C[" + std::to_string(i) + "] = " + format_number(c[size_t(i)]) + " µm² puts a pole at " +
                       format_number(pole * 1000) + " nm, inside the visible range 360-830 nm");
  }
  // n within [1e-4, 1e4] over the visible range (n² is monotone between poles, so a
  // dense check finds where it leaves the range).
  for (int k = 0; k <= 470; ++k) {
    const double nm = kLambdaMin + k;
    double s = 1;
    const double l2 = (nm / 1000) * (nm / 1000);
    for (int i = 0; i < 3; ++i) s += b[size_t(i)] * l2 / (l2 - c[size_t(i)]);
    if (!(s >= 1e-8 && s <= 1e8))
      throw InputError(w + ": the index must be within [1e-4, 1e4] over 360-830 nm, but n² = " + format_number(s) + " at " +
                       format_number(nm) + " nm");
  }
}

double SellmeierSpectrum::index(double lambda_nm) const {
  const double l = lambda_nm / 1000;  // µm
  const double l2 = l * l;
  double n2 = 1;
  for (int i = 0; i < 3; ++i) n2 += b_[size_t(i)] * l2 / (l2 - c_[size_t(i)]);
  return n2 > 0 ? std::sqrt(n2) : 0;
}

Float SellmeierSpectrum::eval(Float lambda) const {
  // Outside the validated visible range the index is held at its end values.
  const double l = std::clamp(double(lambda), double(kLambdaMin), double(kLambdaMax));
  return Float(index(std::isnan(l) ? double(kLambdaMin) : l));
}

}  // namespace gonio
