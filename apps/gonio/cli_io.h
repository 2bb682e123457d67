#pragma once
// Input and output helpers shared by the gonio subcommands: loading --bsdf, reading
// numeric lines from stdin with line-numbered errors, and JSON number formatting with
// round-trip precision (SPEC §1: %.9g for float, %.17g for double).

#include <array>
#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_number.h"  // decimal_number, decimal_in_range: every number option

#include "gonio/bxdf.h"
#include "gonio/error.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio::cli {

// --bsdf value: the JSON text itself, or @path to a file holding it (read through the
// bounded reader: at most kMaxJsonFileBytes, devices and pipes included).
BxDF load_bsdf(const std::string& arg);
// The same material with its spectra recorded (spectral mode: --wavelength).
MaterialWithSpectra load_bsdf_with_spectra(const std::string& arg);

// --uv U V and --position X Y Z (SPEC §2): where a MaterialX material's node graphs are
// evaluated. Given, they are added to a --bsdf of the form {"mtlx": ...} as its "uv" and
// "position" before load_bsdf* parse it; other materials do not vary and ignore them.
void add_point_options(CLI::App& cmd);

// --wavelength NM (SPEC §1 "Spectral mode"): evaluate at one wavelength in nanometres.
// The option is read as text so that the error names it and the value as typed.
CLI::Option* add_wavelength_option(CLI::App& cmd, std::string& text);
// NM as a finite number in [kLambdaMin, kLambdaMax] (360 to 830 nm); InputError otherwise.
Float parse_wavelength(const std::string& text);

// A material evaluated at one wavelength: the spectra, the scratch its blend parts live
// in and the spectral model, kept together (the model points into the scratch).
struct MaterialAtWavelength {
  MaterialWithSpectra material;
  SpectralScratch scratch;
  SampledWavelengths wavelengths;
  SpectralBxDF bxdf;
};
// load_bsdf_with_spectra(arg), made spectral at `nm` (to_spectral). Heap-allocated so
// that the model's pointers into the scratch stay valid.
std::unique_ptr<MaterialAtWavelength> load_bsdf_at_wavelength(const std::string& arg, Float nm);

// SPEC §3's ranges of the integer options, shared by every command that has them.
inline constexpr std::int64_t kMaxSamples = 1'000'000'000'000;  // --samples 1 to 10^12
inline constexpr std::int64_t kMaxSeed = 2'147'483'647;         // --seed 0 to 2^31 - 1
inline constexpr std::int64_t kMaxSpp = 1'048'576;              // --spp 1 to 2^20
inline constexpr std::int64_t kMaxThreads = 1024;               // --threads 0 to 1024

// --mode radiance|importance (validated by CLI11's check; this only maps the name).
TransportMode parse_mode(const std::string& name);
void add_mode_option(CLI::App& cmd, std::string& mode);

// Range of relative indices the CLI accepts (as the material descriptions do).
inline constexpr double kMinIndex = 1e-4, kMaxIndex = 1e4;

// Reads every non-blank line of `in` as exactly N finite numbers. Throws InputError
// naming the line on anything else. All input is validated before anything is printed,
// so a bad line never leaves partial output behind.
std::vector<std::array<double, 6>> read_six_numbers(std::istream& in);
// The same for lines of `n` <= 6 numbers (the rest of each array is 0); `what` follows
// "expected n numbers" in the error ("" or e.g. " (wo only: --count draws the u's)").
std::vector<std::array<double, 6>> read_numbers(std::istream& in, size_t n, const char* what = "");

// Direction read from stdin line `line`, normalised in double; a zero vector is bad input.
Vec3 unit_vector(double x, double y, double z, size_t line, const char* name);

// The angles of an option FROM TO COUNT (`--theta-range`): COUNT (an integer, 1 to
// kMaxRangeCount) evenly spaced angles from FROM to TO degrees, both ends included (COUNT 1:
// FROM alone); FROM and TO in [lo, hi]. Throws InputError naming `option` otherwise.
inline constexpr double kMaxRangeCount = 100000;
std::vector<double> angle_range(const std::vector<double>& from_to_count, const char* option, double lo, double hi);

// The extension of `path`, lower-cased, with its dot (".png"); empty without one.
std::string lower_extension(const std::string& path);

std::string json_number(float v);
std::string json_number(double v);
std::string json_color(const Color& c);
// Spectral mode at one wavelength (SampledWavelengths::single): the one-element array [v] (SPEC §1),
// v the value at the wavelength (slot 0; every slot holds the same wavelength).
std::string json_color(const SampledSpectrum& s);

}  // namespace gonio::cli
