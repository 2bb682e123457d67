#pragma once
// Input and output helpers shared by the gonio subcommands: loading --bsdf, reading
// numeric lines from stdin with line-numbered errors, and JSON number formatting with
// round-trip precision (SPEC §1: %.9g for float, %.17g for double).

#include <array>
#include <istream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gonio/bxdf.h"
#include "gonio/error.h"

namespace gonio::cli {

// --bsdf value: the JSON text itself, or @path to a file holding it.
BxDF load_bsdf(const std::string& arg);

// --mode radiance|importance (validated by CLI11's check; this only maps the name).
TransportMode parse_mode(const std::string& name);
void add_mode_option(CLI::App& cmd, std::string& mode);

// Range of relative indices the CLI accepts (as the material descriptions do).
inline constexpr double kMinIndex = 1e-4, kMaxIndex = 1e4;

// Reads every non-blank line of `in` as exactly N finite numbers. Throws InputError
// naming the line on anything else. All input is validated before anything is printed,
// so a bad line never leaves partial output behind.
std::vector<std::array<double, 6>> read_six_numbers(std::istream& in);

// Direction read from stdin line `line`, normalised in double; a zero vector is bad input.
Vec3 unit_vector(double x, double y, double z, size_t line, const char* name);

// A number for an error message: like json_number, but nan and inf print as words.
std::string show_number(double v);

std::string json_number(float v);
std::string json_number(double v);
std::string json_color(const Color& c);

}  // namespace gonio::cli
