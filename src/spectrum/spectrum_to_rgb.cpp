#include "gonio/spectrum/spectrum_to_rgb.h"

#include <algorithm>

#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/color_space.h"
#include "gonio/spectrum/d65.h"

namespace gonio {

Color spectrum_to_rgb(const Spectrum& s, SpectrumUse use) {
  Color c;
  switch (use) {
    case SpectrumUse::kIndex:
      for (int i = 0; i < 3; ++i) c[i] = s.eval(kRgbIndexWavelengths[i]);
      return c;
    case SpectrumUse::kReflectance: {
      static const Float white_y = integrate_xyz([](double l) { return d65(Float(l)); }).y;
      const XYZ xyz = integrate_xyz([&](double l) { return s.eval(Float(l)) * d65(Float(l)); });
      c = xyz_to_linear_srgb({xyz.x / white_y, xyz.y / white_y, xyz.z / white_y});
      for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], Float(0), Float(1));
      return c;
    }
    case SpectrumUse::kEmission: {
      c = xyz_to_linear_srgb(integrate_xyz([&](double l) { return s.eval(Float(l)); }));
      for (int i = 0; i < 3; ++i) c[i] = std::max(c[i], Float(0));
      return c;
    }
  }
  return c;
}

}  // namespace gonio
