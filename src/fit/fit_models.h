#pragma once
// Each model `gonio fit` knows: its free parameters (slots), how each maps to an
// unconstrained optimisation variable, its starting values, and the conversion of a
// parameter vector to a material description (and of an --init description to starting
// values). The one place where a model's parameter vector meets its JSON (fit_models.cpp).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gonio::fit_detail {

using ojson = nlohmann::ordered_json;

// How a slot's value v relates to its optimisation variable u.
enum class Map {
  Logit,  // v = lo + (hi − lo) / (1 + e^−u), u in [−kLogitBound, kLogitBound]
  Log,    // v = e^u, u in [ln lo, ln hi] (Ceres bounds)
};
inline constexpr double kLogitBound = 12;

struct Slot {
  std::string name;
  bool colour;  // three variables (r, g, b), else one
  Map map;
  double lo, hi;
  std::vector<double> starts;  // starting values (several: the multi-start)
};

struct FitModel {
  std::vector<Slot> slots;
  // Values given by --init, per slot name (1 or 3 numbers); they replace the starts.
  std::vector<std::pair<std::string, std::vector<double>>> given;
  // The material description of slot values v (slot order, a colour's three in a row).
  ojson (*describe)(const std::vector<double>& v, const ojson& fixed) = nullptr;
  ojson fixed;  // the discrete choices (distribution, fresnel, plastic's eta, ...)
};

// The model `name` with the choices of `distribution` ("" = from init or ggx) and `init`
// (null or an object of that type). Throws InputError for an unknown model, a bad
// distribution or a bad init (which is also checked by parsing it as a material).
FitModel make_fit_model(const std::string& name, const std::string& distribution, const nlohmann::json& init);

const std::vector<std::string>& fit_model_list();

// Variables ↔ values.
double to_value(const Slot& s, double u);
double to_variable(const Slot& s, double v);  // clamped into the variable's bounds
double variable_lower(const Slot& s);
double variable_upper(const Slot& s);

}  // namespace gonio::fit_detail
