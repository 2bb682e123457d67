#include "gonio/spectrum/spectrum_json.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gonio/error.h"
#include "gonio/spectrum/glasses.h"

namespace gonio {
namespace {

const char* use_name(SpectrumUse use) {
  switch (use) {
    case SpectrumUse::kReflectance: return "a reflectance";
    case SpectrumUse::kEmission: return "an emission";
    case SpectrumUse::kIndex: return "an index";
  }
  return "";
}

// The range of values `use` allows, checked on numbers, RGB components and tabulated values.
void check_value(double v, const std::string& f, SpectrumUse use) {
  const bool ok = use == SpectrumUse::kReflectance ? (v >= 0 && v <= 1)
                  : use == SpectrumUse::kEmission  ? (v >= 0 && v <= double(RgbIlluminantSpectrum::kMaxComponent))
                                                   : (v >= 1e-4 && v <= 1e4);
  if (!ok) {
    const char* range = use == SpectrumUse::kReflectance ? "[0, 1]" : use == SpectrumUse::kEmission ? "[0, 1e9]" : "[1e-4, 1e4]";
    throw InputError(f + ": " + use_name(use) + " must be in " + range + ", got " + format_number(v));
  }
}

double number(const nlohmann::json& v, const std::string& what) {
  if (!v.is_number()) throw InputError(what + " must be a number, got " + v.dump());
  return v.get<double>();
}

std::array<double, 3> three_numbers(const nlohmann::json& v, const std::string& what) {
  if (!v.is_array() || v.size() != 3) throw InputError(what + " must be an array of 3 numbers, got " + v.dump());
  return {number(v[0], what), number(v[1], what), number(v[2], what)};
}

Spectrum tabulated(const nlohmann::json& v, const std::string& f, SpectrumUse use, const std::string& base_dir) {
  PiecewiseLinearSpectrum s;
  if (v.is_string()) {
    std::filesystem::path p = v.get<std::string>();
    if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
    s = PiecewiseLinearSpectrum::from_csv_file(p.string());
  } else if (v.is_array()) {
    std::vector<std::pair<double, double>> points;
    for (const auto& row : v) {
      if (!row.is_array() || row.size() != 2 || !row[0].is_number() || !row[1].is_number())
        throw InputError(f + ": spectrum points are [nm, value] pairs, got " + row.dump());
      points.emplace_back(row[0].get<double>(), row[1].get<double>());
    }
    s = PiecewiseLinearSpectrum::from_points(points, f);
  } else {
    throw InputError(f + ": \"spectrum\" takes [[nm, value], ...] or a CSV file name, got " + v.dump());
  }
  check_value(s.min_value(), f, use);
  check_value(s.max_value(), f, use);
  return s;
}

}  // namespace

Spectrum parse_spectrum(const nlohmann::json& value, std::string_view field, SpectrumUse use,
                        const std::string& base_dir) {
  const std::string f(field);
  if (value.is_number()) {
    const double v = value.get<double>();
    check_value(v, f, use);
    if (use == SpectrumUse::kEmission) return D65Spectrum{Float(v)};  // grey light is white: v · D65
    return ConstantSpectrum{Float(v)};
  }
  if (value.is_array()) {
    if (use == SpectrumUse::kIndex)
      throw InputError(f + ": an index is a number, a spectrum, a glass name or {\"sellmeier\": ...}, not RGB");
    const auto c = three_numbers(value, f);
    for (double v : c) check_value(v, f, use);
    if (use == SpectrumUse::kEmission) return RgbIlluminantSpectrum(Float(c[0]), Float(c[1]), Float(c[2]));
    return RgbAlbedoSpectrum(Float(c[0]), Float(c[1]), Float(c[2]));
  }
  if (value.is_string()) {
    if (use != SpectrumUse::kIndex) throw InputError(f + ": a name is only accepted for an index (a glass)");
    const std::string name = value.get<std::string>();
    if (auto g = named_glass(name)) return *g;
    std::string names;
    for (auto n : named_glass_names()) names += (names.empty() ? "" : ", ") + std::string(n);
    throw InputError(f + ": unknown glass '" + name + "' (known: " + names + ")");
  }
  if (!value.is_object() || value.size() != 1)
    throw InputError(f + ": expected a number, [r, g, b] or one of {\"spectrum\"}, {\"blackbody\"}, "
                     "{\"illuminant\"}, {\"sellmeier\"}, got " + value.dump());
  const auto it = value.begin();
  const std::string key = it.key();
  const nlohmann::json& v = it.value();
  if (key == "spectrum") return tabulated(v, f, use, base_dir);
  if (key == "blackbody") {
    if (use != SpectrumUse::kEmission) throw InputError(f + ": \"blackbody\" is only accepted for emission");
    const double k = number(v, f + ": blackbody");
    if (!(k >= BlackbodySpectrum::kMinKelvin && k <= BlackbodySpectrum::kMaxKelvin))
      throw InputError(f + ": blackbody temperature must be in [" + format_number(BlackbodySpectrum::kMinKelvin) + ", " +
                       format_number(BlackbodySpectrum::kMaxKelvin) + "] K, got " + format_number(k));
    return BlackbodySpectrum(k);
  }
  if (key == "illuminant") {
    if (use != SpectrumUse::kEmission) throw InputError(f + ": \"illuminant\" is only accepted for emission");
    if (v != "D65") throw InputError(f + ": the only illuminant is \"D65\", got " + v.dump());
    return D65Spectrum{1};
  }
  if (key == "sellmeier") {
    if (use != SpectrumUse::kIndex) throw InputError(f + ": \"sellmeier\" is only accepted for an index");
    if (!v.is_object() || v.size() != 2 || !v.contains("B") || !v.contains("C"))
      throw InputError(f + ": sellmeier takes {\"B\": [b1, b2, b3], \"C\": [c1, c2, c3]}, got " + v.dump());
    return SellmeierSpectrum(three_numbers(v["B"], f + ": sellmeier B"), three_numbers(v["C"], f + ": sellmeier C"),
                             f + ": sellmeier");
  }
  throw InputError(f + ": unknown spectrum form \"" + key + "\" (known: spectrum, blackbody, illuminant, sellmeier)");
}

}  // namespace gonio
