// gonio spectrum: an RGB colour upsampled to a spectrum (Jakob & Hanika 2019) and its round
// trip back to linear sRGB (SPEC §3; docs/spectral.md).

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_io.h"
#include "cli_number.h"
#include "commands.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/rgb_to_spectrum.h"

namespace gonio::cli {

namespace {
struct SpectrumArgs {
  std::vector<double> rgb;
  bool emission = false;
};

template <typename S>
void print_spectrum(const S& s, bool emission) {
  std::string lambda, values;
  for (int nm = 360; nm <= 830; nm += 5) {
    if (nm != 360) lambda += ',', values += ',';
    lambda.append(std::to_string(nm));
    values.append(json_number(s.eval(Float(nm))));
  }
  // Reflectance: XYZ under D65 (luminance 1); emission: its own XYZ (cie.h).
  const XYZ xyz = emission ? integrate_xyz([&](double nm) { return s.eval(Float(nm)); })
                           : integrate_xyz([&](double nm) { return s.eval(Float(nm)) * d65(Float(nm)); });
  std::cout << "{\"lambda\":[" << lambda << "],\"values\":[" << values << "],\"rgb\":"
            << json_color(xyz_to_linear_srgb(xyz)) << "}\n";
}

void run_spectrum(const SpectrumArgs& a) {
  if (a.rgb.size() != 3) throw InputError("--rgb takes three numbers R G B");
  const double hi = a.emission ? double(RgbIlluminantSpectrum::kMaxComponent) : 1.0;
  const char* names[3] = {"R", "G", "B"};
  for (int i = 0; i < 3; ++i) {
    const double v = a.rgb[size_t(i)];
    if (!(v >= 0 && v <= hi))
      throw InputError(std::string("--rgb: ") + names[i] + " must be in [0, " + format_number(hi) + "]" +
                       (a.emission ? "" : " for a reflectance (--emission for light)") + ", got " + format_number(v));
  }
  const Float r = Float(a.rgb[0]), g = Float(a.rgb[1]), b = Float(a.rgb[2]);
  if (a.emission) print_spectrum(RgbIlluminantSpectrum(r, g, b), true);
  else print_spectrum(RgbAlbedoSpectrum(r, g, b), false);
}
}  // namespace

void register_spectrum(CLI::App& app) {
  auto args = std::make_shared<SpectrumArgs>();
  auto* cmd = app.add_subcommand(
      "spectrum",
      "An RGB reflectance (or, with --emission, light) upsampled to a spectrum; prints "
      "{\"lambda\":[360,365,..,830],\"values\":[..],\"rgb\":[..]}, rgb being the round trip to linear sRGB");
  cmd->add_option("--rgb", args->rgb, "linear sRGB: R G B, each in [0, 1] for a reflectance, >= 0 for light")
      ->expected(3)
      ->check(decimal_number())
      ->required();
  cmd->add_flag("--emission", args->emission,
                "light: m S(rgb/m) D65 with m = 2 max(rgb), D65 of luminance 1 (white stays white)");
  cmd->callback([args] { run_spectrum(*args); });
}

}  // namespace gonio::cli
