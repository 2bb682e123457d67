#pragma once
// The material registry: every material type of SPEC §2 with its parameters — name,
// kind, default, accepted range, meaning — declared once. The parser (material.h) reads
// its defaults, ranges and choices from here and rejects any key not listed; `gonio
// materials` and docs/materials.md are printed from the same table, so the reference
// cannot drift from what the parser accepts.

#include <span>
#include <string>
#include <string_view>

namespace gonio {

enum class ParamKind {
  Number,     // a JSON number
  Colour,     // a number (grey), [r, g, b] or a spectrum
  Roughness,  // a number (isotropic) or [alpha_x, alpha_y]
  Choice,     // one of the strings in `choices`
  Boolean,    // true or false
  Metal,      // the name of a measured metal (named_metal_names())
  Materials,  // an array of 2 material descriptions
  Material,   // one material description (layered's top and bottom)
  File,       // a path (a string), relative to the scene file or the working directory
  Film,       // a thin film: an object {"thickness": nm, "eta": index} (issue 34)
  Lobes,      // a number (every lobe of a fibre) or [R, TT, TRT] (hair, issue 60)
  Pair,       // [a, b] (MaterialX's vector2)
};

// An interval of accepted values; `present` false means any (finite) value.
struct ParamRange {
  double lo = 0, hi = 0;
  bool lo_open = false, hi_open = false;
  bool present = false;
  constexpr bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
};
constexpr ParamRange closed(double lo, double hi) { return {lo, hi, false, false, true}; }
constexpr ParamRange open_closed(double lo, double hi) { return {lo, hi, true, false, true}; }
constexpr ParamRange closed_open(double lo, double hi) { return {lo, hi, false, true, true}; }

struct ParamSpec {
  std::string_view name;
  ParamKind kind;
  // The default as JSON text ("0.5", "\"ggx\"", "false"); empty: none (the parameter is
  // required, or optional with the meaning given in `meaning`).
  std::string_view default_json;
  ParamRange range;          // per channel for colours, per entry for a roughness
  std::string_view unit;     // appended to the range ("degrees"), may be empty
  std::string_view choices;  // Choice: the accepted strings, separated by '|'
  bool required;             // no default, and the type cannot do without it
  std::string_view meaning;  // one sentence
};

struct MaterialTypeSpec {
  std::string_view name;
  std::string_view summary;  // one line
  std::string_view source;   // the papers (and equations) it follows
  std::span<const ParamSpec> params;
  std::string_view notes;    // constraints between parameters; may be empty
};

// Every material type, in SPEC §2's order.
std::span<const MaterialTypeSpec> material_types();
// The type named `name`, or nullptr.
const MaterialTypeSpec* find_material_type(std::string_view name);
// The parameter `name` of `type`, or nullptr.
const ParamSpec* find_param(const MaterialTypeSpec& type, std::string_view name);

// "[0, 1]", "(0, 10]", "[0, 90) degrees"; empty when the range is absent.
std::string range_text(const ParamRange& range, std::string_view unit = {});
// What an error says a value must be: "in [0, 1]", "> 0 and <= 10", "in [0, 90) degrees".
std::string range_requirement(const ParamRange& range, std::string_view unit = {});
// The same for a value the range does not contain, naming the bound it breaks where the
// range is open below: "> 0" for alpha = -0.1 (SPEC §2's example, "alpha must be > 0, got
// -0.1"), "<= 10" for alpha = 11; a closed range is named whole ("in [0, 1]").
std::string range_requirement(const ParamRange& range, std::string_view unit, double value);
// "alpha, distribution, fresnel, ..." in the table's order.
std::string param_names(const MaterialTypeSpec& type);

}  // namespace gonio
