// SPEC §3 output formats: one JSON object per line with exactly the documented fields
// (further fields are allowed as extensions), 3-component colours, null where SPEC says
// null, and numbers printed with round-trip precision.

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

const std::string kFormatDiffuse = R"({"type":"diffuse","reflectance":[0.2,0.4,0.6]})";
const std::string kFormatDielectric = R"({"type":"dielectric","eta":1.5})";

void expect_keys(const json& j, std::initializer_list<const char*> keys) {
  for (const char* k : keys) EXPECT_TRUE(j.contains(k)) << "missing '" << k << "' in " << j.dump();
}

TEST(CliFormat, EvalOneObjectPerLine) {
  const std::string in = "0 0 1 0 0.6 0.8\n0.3 0.4 0.5 -0.1 0.2 0.9\n0 0 1 0 0 -1\n";
  const auto objs = run_lines({"eval", "--bsdf", kFormatDiffuse}, in, 3);
  for (const auto& j : objs) {
    expect_keys(j, {"f", "pdf"});
    color3(j["f"]);
    EXPECT_TRUE(j["pdf"].is_number()) << j.dump();
  }
}

TEST(CliFormat, EvalAcceptsTabsSignsAndExponents) {
  const auto objs = run_lines({"eval", "--bsdf", kFormatDiffuse},
                              "0\t0\t1\t0\t0.6\t0.8\n+0 -0 1e0 0.0e+0 6e-1 +8E-1\n", 2);
  ASSERT_EQ(objs.size(), 2u);
  EXPECT_EQ(objs[0], objs[1]);
}

TEST(CliFormat, EvalEmptyInputGivesEmptyOutput) {
  const RunResult r = run_gonio({"eval", "--bsdf", kFormatDiffuse}, "");
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.out, "") << describe(r);
  EXPECT_EQ(r.err, "") << describe(r);
}

TEST(CliFormat, EvalLastLineWithoutNewline) {
  run_lines({"eval", "--bsdf", kFormatDiffuse}, "0 0 1 0 0.6 0.8\n0 0 1 0 0.6 0.8", 2);
}

TEST(CliFormat, EvalBsdfFromFile) {
  TempFile f(kFormatDiffuse, "gonio_cli_bsdf");
  const auto a = run_lines({"eval", "--bsdf", "@" + f.path()}, "0 0 1 0 0.6 0.8\n", 1);
  const auto b = run_lines({"eval", "--bsdf", kFormatDiffuse}, "0 0 1 0 0.6 0.8\n", 1);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(a[0], b[0]);
}

TEST(CliFormat, BsdfFileMayHoldWhitespaceAndNewlines) {
  TempFile f("{\n  \"type\": \"diffuse\",\n  \"reflectance\": [0.2, 0.4, 0.6]\n}\n", "gonio_cli_bsdf");
  run_lines({"eval", "--bsdf", "@" + f.path()}, "0 0 1 0 0.6 0.8\n", 1);
}

TEST(CliFormat, SampleNonDeltaFields) {
  const auto objs = run_lines({"sample", "--bsdf", kFormatDiffuse}, "0 0 1 0.5 0.3 0.7\n", 1);
  ASSERT_EQ(objs.size(), 1u);
  const json& j = objs[0];
  expect_keys(j, {"wi", "weight", "pdf", "delta", "lobe"});
  color3(j["wi"]);
  color3(j["weight"]);
  EXPECT_TRUE(j["pdf"].is_number()) << j.dump();
  EXPECT_EQ(j["delta"], false) << j.dump();
  EXPECT_EQ(j["lobe"], "reflection") << j.dump();
}

TEST(CliFormat, SampleDeltaFields) {
  const auto objs = run_lines({"sample", "--bsdf", kFormatDielectric},
                              "0.6 0 0.8 0.01 0.3 0.7\n0.6 0 0.8 0.99 0.3 0.7\n", 2);
  ASSERT_EQ(objs.size(), 2u);
  for (const auto& j : objs) {
    expect_keys(j, {"wi", "weight", "pdf", "delta", "lobe"});
    EXPECT_TRUE(j["pdf"].is_null()) << "pdf of a delta sample must be null: " << j.dump();
    EXPECT_EQ(j["delta"], true) << j.dump();
    EXPECT_TRUE(j["delta"].is_boolean());
  }
  EXPECT_EQ(objs[0]["lobe"], "reflection");
  EXPECT_EQ(objs[1]["lobe"], "transmission");
}

// When no direction is produced the object is exactly {"wi":null}.
TEST(CliFormat, SampleNoDirectionIsWiNull) {
  const RunResult r = run_gonio({"sample", "--bsdf", R"({"type":"mirror"})"}, "1 0 0 0.5 0.5 0.5\n");
  EXPECT_EQ(r.status, 0) << describe(r);
  const auto objs = parse_json_lines(r);
  ASSERT_EQ(objs.size(), 1u);
  if (objs[0]["wi"].is_null()) {
    EXPECT_EQ(objs[0], json::parse(R"({"wi":null})")) << r.out;
  } else {
    // A tool may also produce a direction at grazing; then it must be a complete sample.
    expect_keys(objs[0], {"wi", "weight", "pdf", "delta", "lobe"});
  }
}

TEST(CliFormat, AlbedoFields) {
  for (const auto& extra : std::initializer_list<std::vector<std::string>>
       {std::vector<std::string>{"--theta", "30"}, std::vector<std::string>{"--hemispherical"},
        std::vector<std::string>{"--theta", "30", "--phi", "45", "--inside"}}) {
    std::vector<std::string> args = {"albedo", "--bsdf", kFormatDielectric, "--samples", "20000"};
    args.insert(args.end(), extra.begin(), extra.end());
    const json j = run_one(args);
    expect_keys(j, {"theta", "reflectance", "transmittance", "albedo", "stderr",
                    "stderr_reflectance", "stderr_transmittance"});
    for (const char* k : {"reflectance", "transmittance", "albedo", "stderr", "stderr_reflectance",
                          "stderr_transmittance"}) {
      SCOPED_TRACE(k);
      color3(j[k]);
    }
  }
  const json j = run_one({"albedo", "--bsdf", kFormatDiffuse, "--theta", "37.5", "--samples", "20000"});
  EXPECT_DOUBLE_EQ(num(j, "theta"), 37.5);
}

TEST(CliFormat, FresnelFields) {
  const json d = run_one({"fresnel", "--eta", "1.5", "--theta", "30"});
  expect_keys(d, {"Rs", "Rp", "R", "T", "cos_t"});
  EXPECT_FALSE(d.contains("schlick")) << "schlick only with --schlick: " << d.dump();
  EXPECT_TRUE(d["cos_t"].is_number());

  const json s = run_one({"fresnel", "--eta", "1.5", "--theta", "30", "--schlick"});
  expect_keys(s, {"Rs", "Rp", "R", "T", "cos_t", "schlick"});
  EXPECT_TRUE(s["schlick"].is_number());

  const json c = run_one({"fresnel", "--eta", "0.2", "--k", "3", "--theta", "30", "--schlick"});
  expect_keys(c, {"Rs", "Rp", "R", "T", "cos_t", "schlick"});
  EXPECT_TRUE(c["cos_t"].is_null()) << "cos_t is null for a conductor: " << c.dump();

  const json tir = run_one({"fresnel", "--eta", fmt(1 / 1.5), "--theta", "60"});
  EXPECT_TRUE(tir["cos_t"].is_null()) << "cos_t is null under TIR: " << tir.dump();
}

// Round-trip precision (SPEC §1): a double result must carry ~17 significant digits, so
// it matches an independent double computation far below what %g's 6 digits would give.
TEST(CliFormat, FresnelPrintsDoublesWithFullPrecision) {
  const json j = run_one({"fresnel", "--eta", "1.5", "--theta", "45"});
  const double ci = std::cos(deg(45)), st = std::sin(deg(45)) / 1.5, ct = std::sqrt(1 - st * st);
  const double rs = std::pow((ci - 1.5 * ct) / (ci + 1.5 * ct), 2);
  EXPECT_NEAR(num(j, "Rs"), rs, 1e-15);
  EXPECT_NEAR(num(j, "cos_t"), ct, 1e-15);
}

// Float results carry %.9g: diffuse f = rho/pi agrees with float arithmetic to ~1 ulp.
TEST(CliFormat, EvalPrintsFloatsWithFullPrecision) {
  const auto objs = run_lines({"eval", "--bsdf", kFormatDiffuse}, "0 0 1 0 0.6 0.8\n", 1);
  ASSERT_EQ(objs.size(), 1u);
  const auto f = color3(objs[0]["f"]);
  const double rho[3] = {0.2, 0.4, 0.6};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(f[i], rho[i] / kPi, 2e-8 * rho[i] / kPi) << i;
}

// No number is printed in a form JSON rejects; checked on the raw text.
TEST(CliFormat, RawNumbersAreValidJson) {
  const RunResult r = run_gonio({"sample", "--bsdf", R"({"type":"mirror"})"},
                                "0 0 1 0 0 0\n0.5 -0.5 0.7 0.1 0.2 0.3\n");
  EXPECT_EQ(r.status, 0) << describe(r);
  // JSON has no leading '+', no bare '.5', no hex.
  for (const char* bad : {":+", ",+", "[+", ":.", ",.", "[.", ":-.", ",-.", "[-.", "0x"})
    EXPECT_EQ(r.out.find(bad), std::string::npos) << bad << " in " << r.out;
  parse_json_lines(r);
}

}  // namespace
}  // namespace gonio_cli_test
