#pragma once
// A spectrum tabulated at increasing wavelengths and interpolated linearly between them
// ({"spectrum": [[nm, value], ...]} or a two-column CSV file, SPEC §2; the D65 table; the
// named glasses). Outside the tabulated range it keeps its end values.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gonio/spectrum/wavelengths.h"

namespace gonio {

class PiecewiseLinearSpectrum {
 public:
  // Points (nm, value). Throws InputError naming `what` unless there is at least one
  // point, every wavelength is finite and > 0 and they increase strictly, and every value
  // is finite.
  static PiecewiseLinearSpectrum from_points(const std::vector<std::pair<double, double>>& points,
                                             std::string_view what);
  // A two-column CSV file (csv.h); errors name file:line.
  static PiecewiseLinearSpectrum from_csv_file(const std::string& path);
  // From the rows of a parsed two-column table whose rows carry line numbers; errors
  // name `source`:line.
  static PiecewiseLinearSpectrum from_csv_text(std::string_view text, std::string_view source);

  Float eval(Float lambda) const;
  SampledSpectrum eval(const SampledWavelengths& w) const {
    return {eval(w[0]), eval(w[1]), eval(w[2]), eval(w[3])};
  }
  PiecewiseLinearSpectrum scaled(Float s) const;

  const std::vector<Float>& wavelengths() const { return lambda_; }
  const std::vector<Float>& values() const { return value_; }
  Float min_value() const;
  Float max_value() const;

 private:
  std::vector<Float> lambda_, value_;
};

}  // namespace gonio
