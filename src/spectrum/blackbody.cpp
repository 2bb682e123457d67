#include "gonio/spectrum/blackbody.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "gonio/error.h"
#include "gonio/spectrum/cie.h"

namespace gonio {
namespace {
// CODATA 2018 exact values (SI): Planck, speed of light, Boltzmann.
constexpr double kH = 6.62607015e-34, kC = 299792458.0, kKb = 1.380649e-23;
}  // namespace

double planck(double lambda_nm, double kelvin) {
  if (!(lambda_nm > 0 && lambda_nm < 1e12) || !(kelvin > 0)) return 0;  // B -> 0 at both ends (and for NaN)
  const double l = lambda_nm * 1e-9;
  const double x = kH * kC / (l * kKb * kelvin);
  if (x > 700) return 0;  // exp overflows double; B underflows long before
  const double l5 = (l * l) * (l * l) * l;
  return 2 * kH * kC * kC / (l5 * std::expm1(x));
}

BlackbodySpectrum::BlackbodySpectrum(double kelvin) : kelvin_(kelvin), scale_(0) {
  if (!(kelvin >= kMinKelvin && kelvin <= kMaxKelvin)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "blackbody temperature must be in [%g, %g] K, got %.9g", kMinKelvin, kMaxKelvin,
                  kelvin);
    throw InputError(buf);
  }
  // Y in double (cie.h's normalisation, trapezoid rule on the 1 nm CMF table): at 100 K
  // B is ~1e-61 in the visible, far below float's range but normal in double.
  using namespace spectral_data;
  double y = 0;
  for (int i = 0; i < kCieSamples; ++i)
    y += ((i == 0 || i == kCieSamples - 1) ? 0.5 : 1.0) * planck(kCieFirstNm + i, kelvin) * kCieY[i];
  scale_ = cie_y_integral() / y;
}

Float BlackbodySpectrum::eval(Float lambda) const {
  return Float(scale_ * planck(double(lambda), kelvin_));
}

}  // namespace gonio
