#include "cli_io.h"

#include <algorithm>
#include <type_traits>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <unistd.h>
#include <stdexcept>

#include "cli_number.h"
#include "gonio/batch.h"
#include "gonio/json_text.h"
#include "gonio/material.h"

#include <nlohmann/json.hpp>

namespace gonio::cli {

namespace {
// --bsdf's text and the name its errors use: the JSON itself ("--bsdf") or a file's.
struct BsdfText {
  std::string text, source;
};

BsdfText read_bsdf_arg(const std::string& arg) {
  if (!arg.empty() && arg[0] == '@') {
    const std::string path = arg.substr(1);
    // Say why a file cannot be used, in words, before the reader's own checks.
    if (!path.empty() && path.find('\0') == std::string::npos) {
      std::error_code ec;
      const auto st = std::filesystem::status(path, ec);
      if (st.type() == std::filesystem::file_type::not_found)
        throw InputError("--bsdf: " + path + ": file not found");
      if (st.type() == std::filesystem::file_type::directory)
        throw InputError("--bsdf: " + path + ": is a directory, not a material file");
      if (ec || ::access(path.c_str(), R_OK) != 0)
        throw InputError("--bsdf: " + path + ": not readable (" +
                         std::strerror(ec ? ec.value() : errno) + ")");
    }
    std::string text;
    try {
      text = read_text_file(path, kMaxJsonFileBytes, "a material file");
    } catch (const InputError& e) {
      throw InputError(std::string("--bsdf: ") + e.what());
    }
    return {std::move(text), path};
  }
  return {arg, "--bsdf"};
}

// The values of --uv and --position, when given (one command runs per process).
std::vector<double> g_uv, g_position;

// A {"mtlx": ...} material's text with the point options added; any other text as it is
// (the parser then reports its own errors).
BsdfText with_point(BsdfText b) {
  if (g_uv.empty() && g_position.empty()) return b;
  nlohmann::json j = nlohmann::json::parse(b.text, nullptr, false);
  if (!j.is_object() || !j.contains("mtlx")) return b;
  if (!g_uv.empty()) j["uv"] = g_uv;
  if (!g_position.empty()) j["position"] = g_position;
  b.text = j.dump();
  return b;
}
}  // namespace

void add_point_options(CLI::App& cmd) {
  cmd.add_option("--uv", g_uv, "U V: texture coordinates where a MaterialX material's graph is evaluated (default 0.5 0.5)")
      ->expected(2)
      ->check(decimal_number());
  cmd.add_option("--position", g_position,
                 "X Y Z: the position where a MaterialX material's graph is evaluated (default 0 0 0)")
      ->expected(3)
      ->check(decimal_number());
}

BxDF load_bsdf(const std::string& arg) {
  const BsdfText b = with_point(read_bsdf_arg(arg));
  return parse_material(b.text, b.source);
}

MaterialWithSpectra load_bsdf_with_spectra(const std::string& arg) {
  const BsdfText b = with_point(read_bsdf_arg(arg));
  return parse_material_with_spectra(b.text, b.source);
}

CLI::Option* add_wavelength_option(CLI::App& cmd, std::string& text) {
  return cmd.add_option("--wavelength", text,
                        "NM: evaluate the material at this one wavelength in nm, [360, 830] (spectral "
                        "mode); every colour is then printed as a one-element array [v]");
}

Float parse_wavelength(const std::string& text) {
  const double nm = parse_decimal(text).value_or(NAN);
  if (!std::isfinite(nm) || nm < double(kLambdaMin) || nm > double(kLambdaMax))
    throw InputError("--wavelength must be a number of nanometres in [" + format_number(double(kLambdaMin)) + ", " +
                     format_number(double(kLambdaMax)) + "], got '" + text + "'");
  return Float(nm);
}

std::unique_ptr<MaterialAtWavelength> load_bsdf_at_wavelength(const std::string& arg, Float nm) {
  auto m = std::make_unique<MaterialAtWavelength>();
  m->material = load_bsdf_with_spectra(arg);
  m->wavelengths = SampledWavelengths::single(nm);
  // A dispersive dielectric terminates the secondary slots; they hold the same
  // wavelength as the hero, which is the only one printed.
  m->bxdf = to_spectral(m->material.bxdf, m->material.spectra, m->wavelengths, m->scratch);
  return m;
}

TransportMode parse_mode(const std::string& name) {
  return name == "importance" ? TransportMode::Importance : TransportMode::Radiance;
}

void add_mode_option(CLI::App& cmd, std::string& mode) {
  cmd.add_option("--mode", mode, "transport mode: radiance (default) or importance")
      ->check(CLI::IsMember({"radiance", "importance"}));
}

std::vector<std::array<double, 6>> read_six_numbers(std::istream& in) { return read_numbers(in, 6); }

std::vector<std::array<double, 6>> read_numbers(std::istream& in, size_t n, const char* what) {
  std::vector<std::array<double, 6>> rows;
  std::string line;
  size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = "stdin line " + std::to_string(line_no) + ": ";
    std::array<double, 6> row{};
    size_t count = 0;
    const char* p = line.data();
    const char* end = p + line.size();
    while (true) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == ',')) ++p;
      if (p >= end) break;
      const char* tok = p;
      while (p < end && !(*p == ' ' || *p == '\t' || *p == '\r' || *p == ',')) ++p;
      const std::string token(tok, p);
      if (count == n) throw InputError(where + "expected " + std::to_string(n) + " numbers" + what + ", got more");
      const std::optional<double> v = parse_decimal(token);
      if (!v) throw InputError(where + "'" + token + "' is not a number");
      if (!std::isfinite(*v)) throw InputError(where + "'" + token + "' is not a finite number");
      row[count++] = *v;
    }
    if (count == 0) continue;  // blank line
    if (count != n)
      throw InputError(where + "expected " + std::to_string(n) + " numbers" + what + ", got " + std::to_string(count));
    rows.push_back(row);
  }
  if (in.bad()) throw InputError("stdin: read error");
  return rows;
}

Vec3 unit_vector(double x, double y, double z, size_t line, const char* name) {
  // batch.h's normalisation, shared with the Python module; the input is finite here.
  const std::optional<Vec3> w = unit_direction(x, y, z);
  if (!w) throw InputError("stdin line " + std::to_string(line) + ": " + name + " is a zero vector");
  return *w;
}

std::vector<double> angle_range(const std::vector<double>& v, const char* option, double lo, double hi) {
  const std::string name(option);
  if (v.size() != 3) throw InputError(name + " needs FROM TO COUNT");
  for (int i = 0; i < 2; ++i)
    if (!(v[size_t(i)] >= lo && v[size_t(i)] <= hi))
      throw InputError(name + ": " + (i == 0 ? "FROM" : "TO") + " must be in [" + format_number(lo) + ", " +
                       format_number(hi) + "] degrees, got " + format_number(v[size_t(i)]));
  const double count = v[2];
  if (!(count >= 1 && count <= kMaxRangeCount && count == std::floor(count)))
    throw InputError(name + ": COUNT must be an integer from 1 to " + format_number(kMaxRangeCount) + ", got " +
                     format_number(count));
  const auto n = static_cast<size_t>(count);
  std::vector<double> angles(n);
  for (size_t i = 0; i < n; ++i)
    angles[i] = i + 1 == n && n > 1 ? v[1] : v[0] + (v[1] - v[0]) * double(i) / double(n > 1 ? n - 1 : 1);
  return angles;
}

namespace {
std::string format(const char* fmt, double v) {
  if (!std::isfinite(v)) throw std::logic_error("a non-finite value reached the output");
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v + 0.0);  // + 0.0 turns -0 into 0
  return buf;
}
}  // namespace

std::string json_number(float v) { return format("%.9g", double(v)); }
std::string json_number(double v) { return format("%.17g", v); }

std::string json_color(const Color& c) {
  std::string s = "[";
  for (int i = 0; i < Color::size(); ++i) {
    if (i) s += ",";
    s += json_number(c[i]);
  }
  return s + "]";
}

std::string json_color(const SampledSpectrum& s) { return "[" + json_number(s[0]) + "]"; }

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace gonio::cli
