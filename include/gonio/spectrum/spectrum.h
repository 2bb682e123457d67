#pragma once
// Spectrum: any of gonio's spectral inputs as one value type. Evaluation dispatches on a
// std::variant (no virtual call, no allocation); construction validates and may allocate.

#include <type_traits>
#include <utility>
#include <variant>

#include "gonio/spectrum/blackbody.h"
#include "gonio/spectrum/d65.h"
#include "gonio/spectrum/piecewise_linear.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/sellmeier.h"

namespace gonio {

struct ConstantSpectrum {
  Float value = 0;
  Float eval(Float) const { return value; }
  SampledSpectrum eval(const SampledWavelengths&) const { return SampledSpectrum(value); }
};

// The normalised D65 illuminant (d65.h) times a scale.
struct D65Spectrum {
  Float scale = 1;
  Float eval(Float lambda) const { return scale * d65(lambda); }
  SampledSpectrum eval(const SampledWavelengths& w) const { return scale * d65(w); }
};

class Spectrum {
 public:
  using Variant = std::variant<ConstantSpectrum, PiecewiseLinearSpectrum, BlackbodySpectrum, D65Spectrum,
                               SellmeierSpectrum, RgbAlbedoSpectrum, RgbIlluminantSpectrum>;

  Spectrum() : v_(ConstantSpectrum{0}) {}
  template <typename T>
    requires std::is_constructible_v<Variant, T&&>
  Spectrum(T&& s) : v_(std::forward<T>(s)) {}

  Float eval(Float lambda) const {
    return std::visit([lambda](const auto& s) { return s.eval(lambda); }, v_);
  }
  SampledSpectrum eval(const SampledWavelengths& w) const {
    return std::visit([&w](const auto& s) { return s.eval(w); }, v_);
  }
  const Variant& variant() const { return v_; }

 private:
  Variant v_;
};

}  // namespace gonio
