// The models of `gonio fit`: slots, starts, and parameter vector ↔ material description
// (fit_models.h). Only isotropic parameters: MERL tables are isotropic.

#include "fit_models.h"

#include <algorithm>
#include <cmath>

#include "gonio/error.h"
#include "gonio/material.h"

namespace gonio::fit_detail {
namespace {

using json = nlohmann::json;

// Starting values shared by the models: roughness and lobe exponents spanning glossy to
// broad lobes, the multi-start of docs/fitting.md.
const std::vector<double> kAlphaStarts = {0.05, 0.2, 0.5};
const std::vector<double> kExponentStarts = {10, 100, 1000};
const std::vector<double> kSigmaStarts = {5, 20, 40};  // degrees

Slot colour_unit(const char* name, double start) { return {name, true, Map::Logit, 0, 1, {start}}; }
Slot alpha_slot() { return {"alpha", false, Map::Log, 1e-3, 0.99, kAlphaStarts}; }

ojson rgb(const std::vector<double>& v, size_t at) { return ojson::array({v[at], v[at + 1], v[at + 2]}); }

// kd and ks of the two-lobe models from the total albedo s and the specular share t, so
// that kd + ks = s ≤ 1 per channel whatever the variables (SPEC §2's bound).
ojson kd_of(const std::vector<double>& v, size_t s) {
  return ojson::array({v[s] * (1 - v[s + 3]), v[s + 1] * (1 - v[s + 4]), v[s + 2] * (1 - v[s + 5])});
}
ojson ks_of(const std::vector<double>& v, size_t s) {
  return ojson::array({v[s] * v[s + 3], v[s + 1] * v[s + 4], v[s + 2] * v[s + 5]});
}

// The conductor's multiple-scattering lobe (Kulla & Conty 2017) is a fixed choice of the
// --init, not a fitted parameter: written out only when asked for.
ojson with_multiscatter(ojson m, const ojson& fx) {
  if (fx.contains("multiscatter") && fx["multiscatter"].get<bool>()) m["multiscatter"] = true;
  return m;
}
ojson describe_roughconductor_schlick(const std::vector<double>& v, const ojson& fx) {
  return with_multiscatter({{"type", "roughconductor"}, {"distribution", fx["distribution"]}, {"fresnel", "schlick"},
                            {"f0", rgb(v, 0)}, {"alpha", v[3]}},
                           fx);
}
ojson describe_roughconductor_exact(const std::vector<double>& v, const ojson& fx) {
  return with_multiscatter({{"type", "roughconductor"}, {"distribution", fx["distribution"]}, {"fresnel", "exact"},
                            {"eta", rgb(v, 0)}, {"k", rgb(v, 3)}, {"alpha", v[6]}},
                           fx);
}
ojson describe_plastic(const std::vector<double>& v, const ojson& fx) {
  return {{"type", "plastic"}, {"eta", fx["eta"]}, {"reflectance", rgb(v, 0)}, {"alpha", v[3]},
          {"distribution", fx["distribution"]}};
}
ojson describe_phong(const std::vector<double>& v, const ojson&) {
  return {{"type", "phong"}, {"kd", kd_of(v, 0)}, {"ks", ks_of(v, 0)}, {"exponent", v[6]}};
}
ojson describe_blinnphong(const std::vector<double>& v, const ojson&) {
  return {{"type", "blinnphong"}, {"kd", kd_of(v, 0)}, {"ks", ks_of(v, 0)}, {"exponent", v[6]}};
}
ojson describe_ward(const std::vector<double>& v, const ojson&) {
  return {{"type", "ward"}, {"kd", kd_of(v, 0)}, {"ks", ks_of(v, 0)}, {"alpha", v[6]}};
}
ojson describe_ashikhminshirley(const std::vector<double>& v, const ojson&) {
  return {{"type", "ashikhminshirley"}, {"rd", rgb(v, 0)}, {"rs", rgb(v, 3)}, {"nu", v[6]}, {"nv", v[6]}};
}
ojson describe_orennayar(const std::vector<double>& v, const ojson& fx) {
  return {{"type", "orennayar"}, {"model", fx["model"]}, {"reflectance", rgb(v, 0)}, {"sigma", v[3]}};
}
ojson describe_blend(const std::vector<double>& v, const ojson& fx) {
  return {{"type", "blend"},
          {"weight", v[0]},
          {"bsdfs", ojson::array({ojson{{"type", "diffuse"}, {"reflectance", rgb(v, 1)}},
                                  ojson{{"type", "roughconductor"}, {"distribution", fx["distribution"]},
                                        {"fresnel", "schlick"}, {"f0", rgb(v, 4)}, {"alpha", v[7]}}})}};
}

// OpenPBR Surface (issue 35): the base and its specular layer, the parameters a measured
// opaque material decides; the coat, fuzz, film, transmission and subsurface stay at
// their defaults (off). specular_ior and base_diffuse_roughness are fixed choices.
ojson describe_openpbr(const std::vector<double>& v, const ojson& fx) {
  return {{"type", "openpbr"},
          {"base_color", rgb(v, 0)},
          {"base_metalness", v[3]},
          {"specular_color", rgb(v, 4)},
          {"specular_roughness", v[7]},
          {"specular_ior", fx["specular_ior"]},
          {"base_diffuse_roughness", fx["base_diffuse_roughness"]}};
}

[[noreturn]] void bad_init(const std::string& what) { throw InputError("--init: " + what); }

std::vector<double> init_colour(const json& j, const char* key) {
  const json& v = j.at(key);
  if (v.is_number()) return {v.get<double>(), v.get<double>(), v.get<double>()};
  if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number())
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  bad_init(std::string(key) + " must be a number or [r, g, b], got " + v.dump());
}
double init_number(const json& j, const char* key) {
  const json& v = j.at(key);
  if (v.is_number()) return v.get<double>();
  if (std::string(key) == "alpha" && v.is_array())
    bad_init("alpha must be a number (fit is isotropic: MERL tables are), got " + v.dump());
  bad_init(std::string(key) + " must be a number, got " + v.dump());
}
bool init_flag(const json& j, const char* key) {
  const json& v = j.at(key);
  if (!v.is_boolean()) bad_init(std::string(key) + " must be true or false, got " + v.dump());
  return v.get<bool>();
}
std::string init_choice(const json& j, const char* key) {
  const json& v = j.at(key);
  if (!v.is_string()) bad_init(std::string(key) + " must be a string, got " + v.dump());
  return v.get<std::string>();
}

// Rejects keys of `j` outside `allowed`, and a type other than `type`.
void check_keys(const json& j, const std::string& type, std::initializer_list<const char*> allowed,
                const std::string& where) {
  if (!j.is_object()) bad_init(where + "must be a JSON object, got " + j.dump());
  if (j.contains("type") && !(j["type"].is_string() && j["type"].get<std::string>() == type))
    bad_init(where + "type must be \"" + type + "\" (the fitted model), got " + j["type"].dump());
  for (const auto& [key, value] : j.items()) {
    if (key == "type") continue;
    if (std::find_if(allowed.begin(), allowed.end(), [&name = key](const char* a) { return name == a; }) == allowed.end()) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      bad_init(where + "unknown or unfitted field '" + key + "' for " + type + " (allowed: " + list + ")");
    }
  }
}

bool microfacet(const std::string& name) { return name == "roughconductor" || name == "plastic" || name == "blend"; }

}  // namespace

const std::vector<std::string>& fit_model_list() {
  static const std::vector<std::string> names = {"roughconductor", "plastic",   "blinnphong", "phong",  "ward",
                                                 "ashikhminshirley", "orennayar", "blend",    "openpbr"};
  return names;
}

double to_value(const Slot& s, double u) {
  if (s.map == Map::Log) return std::exp(u);
  return s.lo + (s.hi - s.lo) / (1 + std::exp(-u));
}
double variable_lower(const Slot& s) { return s.map == Map::Log ? std::log(s.lo) : -kLogitBound; }
double variable_upper(const Slot& s) { return s.map == Map::Log ? std::log(s.hi) : kLogitBound; }
double to_variable(const Slot& s, double v) {
  double u;
  if (s.map == Map::Log) {
    u = std::log(std::clamp(v, s.lo, s.hi));
  } else {
    const double p = std::clamp((v - s.lo) / (s.hi - s.lo), 1e-12, 1 - 1e-12);
    u = std::log(p / (1 - p));
  }
  return std::clamp(u, variable_lower(s), variable_upper(s));
}

FitModel make_fit_model(const std::string& name, const std::string& distribution, const json& init_in) {
  const auto& names = fit_model_list();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError("--model: unknown model '" + name + "' (known: " + list + ")");
  }
  if (!distribution.empty() && distribution != "ggx" && distribution != "beckmann")
    throw InputError("--distribution must be ggx or beckmann, got '" + distribution + "'");
  if (!distribution.empty() && !microfacet(name))
    throw InputError("--distribution applies to roughconductor, plastic and blend, not " + name);
  const json init = init_in.is_null() ? json::object() : init_in;
  if (!init.is_object()) bad_init("must be a JSON object (a material of type " + name + "), got " + init.dump());

  FitModel m;
  auto given = [&](const char* slot, std::vector<double> v) { m.given.emplace_back(slot, std::move(v)); };
  // The distribution: --distribution, else the init's (the coat's, the conductor's), else ggx.
  auto choose_distribution = [&](const json& j) {
    std::string d = j.contains("distribution") ? init_choice(j, "distribution") : "";
    if (!d.empty() && !distribution.empty() && d != distribution)
      bad_init("distribution \"" + d + "\" contradicts --distribution " + distribution);
    if (d.empty()) d = distribution.empty() ? "ggx" : distribution;
    m.fixed["distribution"] = d;
  };

  if (name == "roughconductor") {
    check_keys(init, name, {"alpha", "distribution", "fresnel", "f0", "eta", "k", "multiscatter"}, "");
    choose_distribution(init);
    m.fixed["multiscatter"] = init.contains("multiscatter") && init_flag(init, "multiscatter");
    const std::string fresnel = init.contains("fresnel") ? init_choice(init, "fresnel") : "";
    const bool exact = fresnel == "exact" || (fresnel.empty() && (init.contains("eta") || init.contains("k")));
    if (exact) {
      if (init.contains("f0")) bad_init("f0 goes with fresnel \"schlick\"; the exact Fresnel fit takes eta and k");
      m.slots = {{"eta", true, Map::Log, 0.02, 50, {1.0}}, {"k", true, Map::Log, 1e-3, 100, {3.0}}, alpha_slot()};
      m.describe = describe_roughconductor_exact;
      if (init.contains("eta")) given("eta", init_colour(init, "eta"));
      if (init.contains("k")) given("k", init_colour(init, "k"));
    } else {
      if (!fresnel.empty() && fresnel != "schlick") bad_init("fresnel must be \"exact\" or \"schlick\", got \"" + fresnel + "\"");
      m.slots = {colour_unit("f0", 0.5), alpha_slot()};
      m.describe = describe_roughconductor_schlick;
      if (init.contains("f0")) given("f0", init_colour(init, "f0"));
    }
    if (init.contains("alpha")) given("alpha", {init_number(init, "alpha")});
  } else if (name == "plastic") {
    check_keys(init, name, {"alpha", "distribution", "eta", "reflectance"}, "");
    choose_distribution(init);
    m.fixed["eta"] = init.contains("eta") ? init_number(init, "eta") : 1.5;
    m.slots = {colour_unit("reflectance", 0.5), alpha_slot()};
    m.describe = describe_plastic;
    if (init.contains("reflectance")) given("reflectance", init_colour(init, "reflectance"));
    if (init.contains("alpha")) given("alpha", {init_number(init, "alpha")});
  } else if (name == "phong" || name == "blinnphong" || name == "ward") {
    const bool ward = name == "ward";
    const char* shape = ward ? "alpha" : "exponent";
    check_keys(init, name, {"kd", "ks", shape}, "");
    m.slots = {colour_unit("albedo", 0.6), colour_unit("share", 0.5),
               ward ? alpha_slot() : Slot{"exponent", false, Map::Log, 0.5, 1e5, kExponentStarts}};
    m.describe = ward ? describe_ward : name == "phong" ? describe_phong : describe_blinnphong;
    if (init.contains("kd") != init.contains("ks")) bad_init("give both kd and ks, or neither");
    if (init.contains("kd")) {
      const auto kd = init_colour(init, "kd"), ks = init_colour(init, "ks");
      std::vector<double> s(3), t(3);
      for (int c = 0; c < 3; ++c) {
        s[c] = kd[c] + ks[c];
        t[c] = s[c] > 0 ? ks[c] / s[c] : 0.5;
      }
      given("albedo", s);
      given("share", t);
    }
    if (init.contains(shape)) given(shape, {init_number(init, shape)});
  } else if (name == "ashikhminshirley") {
    check_keys(init, name, {"rd", "rs", "nu", "nv"}, "");
    m.slots = {colour_unit("rd", 0.5), colour_unit("rs", 0.5), {"n", false, Map::Log, 0.5, 1e5, kExponentStarts}};
    m.describe = describe_ashikhminshirley;
    if (init.contains("rd")) given("rd", init_colour(init, "rd"));
    if (init.contains("rs")) given("rs", init_colour(init, "rs"));
    if (init.contains("nu") && init.contains("nv") && init_number(init, "nu") != init_number(init, "nv"))
      bad_init("nu and nv must be equal (fit is isotropic: MERL tables are)");
    if (init.contains("nu")) given("n", {init_number(init, "nu")});
    else if (init.contains("nv")) given("n", {init_number(init, "nv")});
  } else if (name == "orennayar") {
    check_keys(init, name, {"reflectance", "sigma", "model"}, "");
    m.fixed["model"] = init.contains("model") ? init_choice(init, "model") : "qualitative";
    m.slots = {colour_unit("reflectance", 0.5), {"sigma", false, Map::Logit, 0, 89, kSigmaStarts}};
    m.describe = describe_orennayar;
    if (init.contains("reflectance")) given("reflectance", init_colour(init, "reflectance"));
    if (init.contains("sigma")) given("sigma", {init_number(init, "sigma")});
  } else if (name == "openpbr") {
    check_keys(init, name,
               {"base_color", "base_metalness", "specular_color", "specular_roughness", "specular_ior",
                "base_diffuse_roughness"},
               "");
    m.fixed["specular_ior"] = init.contains("specular_ior") ? init_number(init, "specular_ior") : 1.5;
    m.fixed["base_diffuse_roughness"] =
        init.contains("base_diffuse_roughness") ? init_number(init, "base_diffuse_roughness") : 0.0;
    // Roughness r is α = r² (SPEC-OPB): the starts are the other models' α starts' roots.
    m.slots = {colour_unit("base_color", 0.5), {"base_metalness", false, Map::Logit, 0, 1, {0.5}},
               colour_unit("specular_color", 0.9), {"specular_roughness", false, Map::Log, 1e-3, 1, {0.22, 0.45, 0.7}}};
    m.describe = describe_openpbr;
    for (const char* c : {"base_color", "specular_color"})
      if (init.contains(c)) given(c, init_colour(init, c));
    for (const char* x : {"base_metalness", "specular_roughness"})
      if (init.contains(x)) given(x, {init_number(init, x)});
  } else {  // blend of diffuse + roughconductor (Schlick)
    check_keys(init, name, {"weight", "bsdfs"}, "");
    json diffuse = json::object(), conductor = json::object();
    if (init.contains("bsdfs")) {
      const json& b = init["bsdfs"];
      if (!b.is_array() || b.size() != 2)
        bad_init("bsdfs must be [a diffuse, a roughconductor] for the blend fit, got " + b.dump());
      diffuse = b[0], conductor = b[1];
    }
    check_keys(diffuse, "diffuse", {"reflectance"}, "bsdfs[0]: ");
    check_keys(conductor, "roughconductor", {"alpha", "distribution", "fresnel", "f0"}, "bsdfs[1]: ");
    if (conductor.contains("fresnel") && init_choice(conductor, "fresnel") != "schlick")
      bad_init("bsdfs[1]: the blend fit uses fresnel \"schlick\" (f0)");
    choose_distribution(conductor);
    m.slots = {{"weight", false, Map::Logit, 0, 1, {0.5}}, colour_unit("reflectance", 0.5), colour_unit("f0", 0.5),
               alpha_slot()};
    m.describe = describe_blend;
    if (init.contains("weight")) given("weight", {init_number(init, "weight")});
    if (diffuse.contains("reflectance")) given("reflectance", init_colour(diffuse, "reflectance"));
    if (conductor.contains("f0")) given("f0", init_colour(conductor, "f0"));
    if (conductor.contains("alpha")) given("alpha", {init_number(conductor, "alpha")});
  }

  // The init's values must make a valid material: checked by the parser, which names the
  // field and the range (e.g. "roughconductor: alpha must be in (0, ...], got -0.1").
  std::vector<double> v;
  for (const Slot& s : m.slots) {
    std::vector<double> value(s.colour ? 3 : 1, s.starts[0]);
    for (const auto& [key, g] : m.given)
      if (key == s.name) value = g;
    v.insert(v.end(), value.begin(), value.end());
  }
  try {
    (void)material_from_json(json::parse(m.describe(v, m.fixed).dump()));
  } catch (const InputError& e) {
    bad_init(e.what());
  }
  return m;
}

}  // namespace gonio::fit_detail
