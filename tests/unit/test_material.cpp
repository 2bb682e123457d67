// Material descriptions (SPEC §2): every type with its defaults and colour forms, and an
// error naming the field for every kind of bad input. Named metals are checked against
// the measured tables shipped in data/metals/.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gonio/material.h"
#include "gonio/metals.h"

namespace gonio {
namespace {

TEST(Material, EachTypeWithDefaults) {
  EXPECT_EQ(parse_material(R"({"type":"diffuse"})").name(), "diffuse");
  const BxDF d = parse_material(R"({"type":"diffuse","reflectance":[0.1,0.2,0.3]})");
  EXPECT_FLOAT_EQ(d.f({0, 0, 1}, {0, 0, 1})[2], 0.3f / float(kPiD));
  const BxDF grey = parse_material(R"({"type":"diffuse","reflectance":0.25})");
  EXPECT_FLOAT_EQ(grey.f({0, 0, 1}, {0, 0, 1})[0], 0.25f / float(kPiD));
  // Default reflectance 0.5.
  EXPECT_FLOAT_EQ(parse_material(R"({"type":"diffuse"})").f({0, 0, 1}, {0, 0, 1})[1], 0.5f / float(kPiD));

  const auto mirror = parse_material(R"({"type":"mirror"})").sample({0, 0, 1}, 0.5f, 0.5f, 0.5f);
  EXPECT_EQ(mirror->weight, Color(1.f));

  EXPECT_FLOAT_EQ(parse_material(R"({"type":"dielectric"})").relative_eta(), 1.5f);
  EXPECT_FLOAT_EQ(parse_material(R"({"type":"dielectric","eta":1.33})").relative_eta(), 1.33f);
  EXPECT_FLOAT_EQ(parse_material(R"({"type":"dielectric","eta":1})").relative_eta(), 1.f);
}

TEST(Material, ConductorForms) {
  const Vec3 n{0, 0, 1};
  auto weight = [&](const char* json) { return parse_material(json).sample(n, 0.5f, 0.5f, 0.5f)->weight; };
  // Gold at normal incidence, green: ((n−1)² + k²)/((n+1)² + k²) with (0.3504, 2.7141).
  const double f0g = ((0.3504 - 1) * (0.3504 - 1) + 2.7141 * 2.7141) / ((1.3504 * 1.3504) + 2.7141 * 2.7141);
  EXPECT_NEAR(weight(R"({"type":"conductor","material":"Au"})")[1], f0g, 1e-5);
  EXPECT_NEAR(weight(R"({"type":"conductor","eta":0.3504,"k":2.7141})")[1], f0g, 1e-5);
  EXPECT_NEAR(weight(R"({"type":"conductor","fresnel":"schlick","material":"Au"})")[1], f0g, 1e-5);
  EXPECT_NEAR(weight(R"({"type":"conductor","fresnel":"schlick","f0":[0.9,0.5,0.1]})")[2], 0.1, 1e-6);
  // With Schlick and the index, F0 is computed from the index; at 60° the formula applies.
  const Vec3 w60{std::sin(1.0471976f), 0, 0.5f};
  const Color s = parse_material(R"({"type":"conductor","fresnel":"schlick","eta":1.5,"k":0})")
                      .sample(w60, 0.5f, 0.5f, 0.5f)->weight;
  EXPECT_NEAR(s[0], 0.04 + 0.96 * std::pow(0.5, 5), 1e-6);
}

// Parses `json` expecting an InputError whose message contains every one of `parts`.
void expect_error(const std::string& json, std::vector<std::string> parts) {
  try {
    parse_material(json);
    ADD_FAILURE() << "no error for " << json;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
  }
}

TEST(Material, ErrorsNameTheField) {
  expect_error(R"({"type":"diffuse",})", {"malformed JSON", "line 1"});
  expect_error("{\n\"type\": \"diffuse\"\n\"reflectance\": 1}", {"malformed JSON", "line 3"});
  expect_error(R"([1,2])", {"JSON object"});
  expect_error(R"({"reflectance":0.5})", {"type"});
  expect_error(R"({"type":5})", {"type"});
  expect_error(R"({"type":"velvet"})", {"unknown type", "velvet"});
  expect_error(R"({"type":"diffuse","colour":0.5})", {"diffuse", "unknown parameter", "colour"});
  expect_error(R"({"type":"diffuse","reflectance":1.5})", {"diffuse", "reflectance", "1.5"});
  expect_error(R"({"type":"diffuse","reflectance":-0.1})", {"reflectance", "-0.1"});
  expect_error(R"({"type":"diffuse","reflectance":[0.1,0.2]})", {"reflectance", "[r, g, b]"});
  expect_error(R"({"type":"diffuse","reflectance":"red"})", {"reflectance"});
  expect_error(R"({"type":"diffuse","reflectance":1e999})", {"1e999"});
  expect_error(R"({"type":"mirror","reflectance":[0.1,2,0.3]})", {"mirror", "reflectance", "2"});
  expect_error(R"({"type":"dielectric","eta":-1})", {"dielectric", "eta", "-1"});
  expect_error(R"({"type":"dielectric","eta":0})", {"eta", "0.0001"});
  expect_error(R"({"type":"dielectric","eta":1e50})", {"eta", "1e+50"});
  expect_error(R"({"type":"conductor","eta":1,"k":1e50})", {"k", "1e+50"});
  expect_error(R"({"type":"dielectric","eta":[1.5,1.5,1.5]})", {"eta", "number"});
  expect_error(R"({"type":"conductor"})", {"conductor", "missing"});
  expect_error(R"({"type":"conductor","material":"Unobtainium"})", {"Unobtainium", "Au"});
  expect_error(R"({"type":"conductor","eta":-0.2,"k":3})", {"eta", "-0.2"});
  expect_error(R"({"type":"conductor","eta":0.2,"k":-3})", {"k", "-3"});
  expect_error(R"({"type":"conductor","k":3})", {"k needs eta"});
  expect_error(R"({"type":"conductor","f0":0.9})", {"f0", "schlick"});
  expect_error(R"({"type":"conductor","fresnel":"fast","material":"Au"})", {"fresnel", "fast"});
  expect_error(R"({"type":"conductor","material":"Au","eta":1})", {"material", "eta"});
  expect_error(R"({"type":"conductor","fresnel":"schlick","f0":1.2})", {"f0", "1.2"});
}

// Linear interpolation of a data/metals CSV at one wavelength.
std::pair<double, double> interpolate_nk(const std::string& metal, double lambda) {
  std::ifstream f(std::string(GONIO_SOURCE_DIR) + "/data/metals/" + metal + ".csv");
  EXPECT_TRUE(f) << metal;
  std::string line;
  double pl = 0, pn = 0, pk = 0;
  bool have_prev = false;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'l') continue;
    std::stringstream ss(line);
    double l, n, k;
    char c;
    ss >> l >> c >> n >> c >> k;
    if (have_prev && pl <= lambda && lambda <= l) {
      const double t = (lambda - pl) / (l - pl);
      return {pn + t * (n - pn), pk + t * (k - pk)};
    }
    pl = l, pn = n, pk = k, have_prev = true;
  }
  ADD_FAILURE() << lambda << " nm not in " << metal;
  return {0, 0};
}

TEST(Material, NamedMetalsAreTheMeasuredIndexAt650_550_450nm) {
  for (auto name : named_metal_names()) {
    const auto m = named_metal(name);
    ASSERT_TRUE(m);
    const double lambdas[3] = {650, 550, 450};
    for (int c = 0; c < 3; ++c) {
      const auto [n, k] = interpolate_nk(std::string(name), lambdas[c]);
      EXPECT_NEAR(m->eta[c], n, 1e-3) << name << " " << lambdas[c];
      EXPECT_NEAR(m->k[c], k, 1e-3) << name << " " << lambdas[c];
    }
  }
  // REFERENCES.md's table: gold at 550 nm 0.350 / 2.714.
  EXPECT_NEAR(named_metal("Au")->eta[1], 0.350, 1e-3);
  EXPECT_NEAR(named_metal("Au")->k[1], 2.714, 1e-3);
  EXPECT_FALSE(named_metal("Pt"));
}

}  // namespace
}  // namespace gonio
