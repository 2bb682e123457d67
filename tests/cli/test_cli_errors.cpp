// SPEC §3 error contract: bad input exits with status 2, prints exactly one line on
// stderr that names the problem (SPEC §2: material errors name the field; stdin errors
// name the line), and prints nothing at all on stdout — not even the results of good
// lines that came before the bad one.

#include <sstream>
#include <string>
#include <vector>

#include "run_gonio.h"
#include "gonio/material.h"

#include <algorithm>

namespace gonio_cli_test {
namespace {

const std::string kGoodEvalLine = "0 0 1 0 0.6 0.8\n";
const std::string kGoodSampleLine = "0 0 1 0.5 0.5 0.5\n";
const std::string kDiffuse = R"({"type":"diffuse","reflectance":0.5})";

// Every --bsdf error is checked through eval, sample and albedo alike.
void expect_bsdf_rejected(const std::string& bsdf, std::initializer_list<std::string> mentions) {
  SCOPED_TRACE("--bsdf " + bsdf);
  {
    SCOPED_TRACE("eval");
    expect_bad_input(run_gonio({"eval", "--bsdf", bsdf}, kGoodEvalLine), mentions);
  }
  {
    SCOPED_TRACE("sample");
    expect_bad_input(run_gonio({"sample", "--bsdf", bsdf}, kGoodSampleLine), mentions);
  }
  {
    SCOPED_TRACE("albedo");
    expect_bad_input(run_gonio({"albedo", "--bsdf", bsdf, "--theta", "30", "--samples", "20000"}),
                     mentions);
  }
}

// ---------------------------------------------------------------------------------------
// --bsdf: JSON syntax, types, parameters, ranges, files

TEST(CliBsdfErrors, MalformedJson) {
  expect_bsdf_rejected(R"({"type":"diffuse",})", {"json"});
  expect_bsdf_rejected(R"({"type":"diffuse")", {"json"});
  expect_bsdf_rejected("diffuse", {"json"});
  expect_bsdf_rejected("", {});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":0.5} trailing)", {"json"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":NaN})", {"json"});
}

TEST(CliBsdfErrors, NotAnObjectOrNoType) {
  expect_bsdf_rejected("[1,2,3]", {});
  expect_bsdf_rejected("42", {});
  expect_bsdf_rejected(R"({"reflectance":0.5})", {"type"});
  expect_bsdf_rejected(R"({"type":7})", {"type"});
}

TEST(CliBsdfErrors, UnknownType) {
  expect_bsdf_rejected(R"({"type":"velvet"})", {"velvet"});
  expect_bsdf_rejected(R"({"type":"Diffuse"})", {"Diffuse"});
}

// Types listed in SPEC §2 that this build does not implement yet must be rejected too.
TEST(CliBsdfErrors, UnimplementedSpecTypesRejected) {
  const std::vector<std::string> types = {
      R"({"type":"roughconductor","alpha":0.2,"material":"Au"})",
      R"({"type":"roughdielectric","alpha":0.2})",
      R"({"type":"orennayar","reflectance":0.5,"sigma":20})",
      R"({"type":"phong","kd":0.3,"ks":0.3,"exponent":20})",
      R"({"type":"blinnphong","kd":0.3,"ks":0.3,"exponent":20})",
      R"({"type":"ward","kd":0.3,"ks":0.3,"alpha":0.2})",
      R"({"type":"ashikhminshirley","rd":0.3,"rs":0.3,"nu":10,"nv":10})",
      R"({"type":"plastic","reflectance":0.5})",
      R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse"},{"type":"mirror"}]})",
      R"({"type":"measured","file":"x.binary"})",
  };
  const auto& known = gonio::material_type_names();
  for (const auto& t : types) {
    const std::string name = json::parse(t)["type"].get<std::string>();
    // Types this build implements are covered elsewhere; the rest must be rejected.
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    SCOPED_TRACE(name);
    const RunResult r = run_gonio({"eval", "--bsdf", t}, kGoodEvalLine);
    expect_bad_input(r, {name});
  }
}

TEST(CliBsdfErrors, UnknownParameter) {
  expect_bsdf_rejected(R"({"type":"diffuse","colour":0.5})", {"colour"});
  expect_bsdf_rejected(R"({"type":"mirror","reflectance":1,"roughness":0.1})", {"roughness"});
  expect_bsdf_rejected(R"({"type":"dielectric","eta":1.5,"k":1})", {"k"});
  expect_bsdf_rejected(R"({"type":"conductor","material":"Au","alpha":0.1})", {"alpha"});
}

TEST(CliBsdfErrors, DiffuseReflectanceOutOfRange) {
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":1.5})", {"reflectance", "1.5"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":[0.2,1.5,0.2]})", {"reflectance", "1.5"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":-0.1})", {"reflectance", "-0.1"});
  expect_bsdf_rejected(R"({"type":"mirror","reflectance":2})", {"reflectance", "2"});
}

TEST(CliBsdfErrors, BadColourShapeOrType) {
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":[0.2,0.4]})", {"reflectance"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":[0.2,0.4,0.5,0.6]})", {"reflectance"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":"0.5"})", {"reflectance"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":[0.2,"x",0.5]})", {"reflectance"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":null})", {"reflectance"});
  // 1e400 overflows a double: rejected, naming the number (as a JSON error) or the field.
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":1e400})", {"1e400"});
  expect_bsdf_rejected(R"({"type":"dielectric","eta":"1.5"})", {"eta"});
}

TEST(CliBsdfErrors, DielectricEtaOutOfRange) {
  expect_bsdf_rejected(R"({"type":"dielectric","eta":-1})", {"eta", "-1"});
  expect_bsdf_rejected(R"({"type":"dielectric","eta":0})", {"eta", "0"});
}

// SPEC §2's own example of an error that names the field, word for word; a value above
// the range names the upper bound.
TEST(CliBsdfErrors, RangeErrorNamesTheBoundBroken) {
  expect_bsdf_rejected(R"({"type":"roughconductor","alpha":-0.1})", {"roughconductor: alpha must be > 0, got -0.1"});
  expect_bsdf_rejected(R"({"type":"roughconductor","alpha":0})", {"roughconductor: alpha must be > 0, got 0"});
  expect_bsdf_rejected(R"({"type":"roughconductor","alpha":11})", {"roughconductor: alpha must be <= 10, got 11"});
  expect_bsdf_rejected(R"({"type":"diffuse","reflectance":1.5})", {"reflectance must be in [0, 1], got 1.5"});
}

TEST(CliBsdfErrors, ConductorOutOfRange) {
  expect_bsdf_rejected(R"({"type":"conductor","eta":1.2,"k":-1})", {"k", "-1"});
  expect_bsdf_rejected(R"({"type":"conductor","eta":[0.2,0.3,0.4],"k":[3,-1,2]})", {"k", "-1"});
  expect_bsdf_rejected(R"({"type":"conductor","eta":-0.5,"k":3})", {"eta", "-0.5"});
  expect_bsdf_rejected(R"({"type":"conductor","eta":0,"k":3})", {"eta"});
  expect_bsdf_rejected(R"({"type":"conductor","fresnel":"schlick","f0":1.5})", {"f0", "1.5"});
}

TEST(CliBsdfErrors, ConductorWithNothingGiven) {
  expect_bsdf_rejected(R"({"type":"conductor"})", {"conductor"});
  expect_bsdf_rejected(R"({"type":"conductor","fresnel":"exact"})", {"conductor"});
  expect_bsdf_rejected(R"({"type":"conductor","fresnel":"schlick"})", {"conductor"});
}

TEST(CliBsdfErrors, ConductorF0WithoutSchlick) {
  expect_bsdf_rejected(R"({"type":"conductor","f0":0.9})", {"f0"});
  expect_bsdf_rejected(R"({"type":"conductor","fresnel":"exact","f0":0.9})", {"f0"});
}

TEST(CliBsdfErrors, ConductorUnknownMetalOrFresnel) {
  expect_bsdf_rejected(R"({"type":"conductor","material":"Unobtainium"})", {"Unobtainium"});
  expect_bsdf_rejected(R"({"type":"conductor","material":"au"})", {"au"});
  expect_bsdf_rejected(R"({"type":"conductor","material":"Au","fresnel":"fancy"})", {"fresnel", "fancy"});
}

TEST(CliBsdfErrors, NonexistentFile) {
  const std::string path = "/nonexistent-dir-gonio/no-such-material.json";
  expect_bsdf_rejected("@" + path, {"no-such-material.json"});
}

TEST(CliBsdfErrors, FileWithBadContents) {
  TempFile f(R"({"type":"dielectric","eta":-2})", "gonio_cli_bsdf");
  expect_bsdf_rejected("@" + f.path(), {"eta"});
  TempFile g(R"({"type":"dielectric",)", "gonio_cli_bsdf");
  expect_bsdf_rejected("@" + g.path(), {"json"});
}

TEST(CliBsdfErrors, BadModeValue) {
  expect_bad_input(run_gonio({"eval", "--bsdf", kDiffuse, "--mode", "photons"}, kGoodEvalLine),
                   {"mode"});
  expect_bad_input(run_gonio({"sample", "--bsdf", kDiffuse, "--mode", "photons"}, kGoodSampleLine),
                   {"mode"});
}

TEST(CliBsdfErrors, MissingBsdfOption) {
  expect_bad_input(run_gonio({"eval"}, kGoodEvalLine), {"bsdf"});
  expect_bad_input(run_gonio({"sample"}, kGoodSampleLine), {"bsdf"});
  expect_bad_input(run_gonio({"albedo", "--theta", "30"}), {"bsdf"});
}

// ---------------------------------------------------------------------------------------
// stdin of eval and sample

struct StdinCase {
  std::string name;
  std::string input;
  std::vector<std::string> mentions;
};

void expect_stdin_rejected(const std::string& sub, const StdinCase& c) {
  SCOPED_TRACE(sub + " / " + c.name + ": " + c.input);
  const RunResult r = run_gonio({sub, "--bsdf", kDiffuse}, c.input);
  EXPECT_EQ(r.status, 2) << describe(r);
  EXPECT_EQ(r.out, "") << describe(r);
  EXPECT_EQ(split_lines(r.err).size(), 1u) << describe(r);
  for (const auto& m : c.mentions)
    EXPECT_TRUE(contains_ci(r.err, m)) << "stderr should mention '" << m << "'\n" << describe(r);
}

// Bad lines that are bad for both eval and sample (six numbers either way).
const std::vector<StdinCase> kCommonBadLines = {
    {"five numbers", "0 0 1 0.5 0.5\n", {"line 1"}},
    {"seven numbers", "0 0 1 0.5 0.5 0.5 0.5\n", {"line 1"}},
    {"one number", "1\n", {"line 1"}},
    {"a word", "0 0 1 0.5 abc 0.5\n", {"line 1", "abc"}},
    {"only words", "hello world\n", {"line 1"}},
    {"nan", "0 0 1 0.5 nan 0.5\n", {"line 1"}},
    {"NaN", "NaN 0 1 0.5 0.5 0.5\n", {"line 1"}},
    {"inf", "0 0 inf 0.5 0.5 0.5\n", {"line 1"}},
    {"-infinity", "0 0 1 -infinity 0.5 0.5\n", {"line 1"}},
    {"overflow", "0 0 1e999 0.5 0.5 0.5\n", {"line 1"}},
    {"zero wo", "0 0 0 0.5 0.5 0.5\n", {"line 1", "wo"}},
    {"negative zero wo", "-0 0 -0 0.5 0.5 0.5\n", {"line 1", "wo"}},
    {"trailing garbage on number", "0 0 1x 0.5 0.5 0.5\n", {"line 1"}},
};

TEST(CliStdinErrors, EvalBadLines) {
  for (const auto& c : kCommonBadLines) expect_stdin_rejected("eval", c);
  expect_stdin_rejected("eval", {"zero wi", "0 0 1 0 0 0\n", {"line 1", "wi"}});
  expect_stdin_rejected("eval", {"zero wi later", "0 0 1 0 0 1\n1 2 3 0 0 0\n", {"line 2", "wi"}});
}

TEST(CliStdinErrors, SampleBadLines) {
  for (const auto& c : kCommonBadLines) expect_stdin_rejected("sample", c);
}

TEST(CliStdinErrors, SampleUOutsideUnitInterval) {
  expect_stdin_rejected("sample", {"u0 = 1", "0 0 1 1.0 0.5 0.5\n", {"line 1", "u0"}});
  expect_stdin_rejected("sample", {"u0 = -0.1", "0 0 1 -0.1 0.5 0.5\n", {"line 1", "u0"}});
  expect_stdin_rejected("sample", {"u1 = 1", "0 0 1 0.5 1 0.5\n", {"line 1", "u1"}});
  expect_stdin_rejected("sample", {"u2 = 1.5", "0 0 1 0.5 0.5 1.5\n", {"line 1", "u2"}});
  expect_stdin_rejected("sample", {"u2 = -1e-300", "0 0 1 0.5 0.5 -1e-300\n", {"line 1", "u2"}});
  expect_stdin_rejected("sample", {"u1 = 2 on line 2", "0 0 1 0.5 0.5 0.5\n0 0 1 0.5 2 0.5\n",
                                   {"line 2", "u1"}});
}

// A bad line after good ones: nothing at all may reach stdout, and the line is named.
TEST(CliStdinErrors, BadLineAfterGoodLinesGivesNoOutput) {
  const std::string eval_in = "0 0 1 0 0.6 0.8\n0 0.6 0.8 0 0 1\n0 0 1 0 0.6\n0 0 1 0 0 1\n";
  expect_stdin_rejected("eval", {"eval line 3", eval_in, {"line 3"}});
  const std::string sample_in = "0 0 1 0.1 0.2 0.3\n0 0 1 0.4 0.5 0.6\n0 0 1 0.7 nan 0.9\n";
  expect_stdin_rejected("sample", {"sample line 3", sample_in, {"line 3"}});
  // Many good lines first (more than any small output buffer) and then a bad one.
  std::string many;
  for (int i = 0; i < 5000; ++i) many += "0.1 0.2 0.9 -0.3 0.1 0.8\n";
  expect_stdin_rejected("eval", {"eval line 5001", many + "1 2 3\n", {"line 5001"}});
  std::string many_s;
  for (int i = 0; i < 5000; ++i) many_s += "0.1 0.2 0.9 0.3 0.1 0.8\n";
  expect_stdin_rejected("sample", {"sample line 5001", many_s + "0 0 1 1 0 0\n", {"line 5001"}});
}

TEST(CliStdinErrors, DielectricAndMirrorAlsoValidate) {
  for (const std::string bsdf : {R"({"type":"dielectric"})", R"({"type":"mirror"})",
                                 R"({"type":"conductor","material":"Cu"})"}) {
    SCOPED_TRACE(bsdf);
    expect_bad_input(run_gonio({"eval", "--bsdf", bsdf}, kGoodEvalLine + "0 0 0 0 0 1\n"),
                     {"line 2"});
    expect_bad_input(run_gonio({"sample", "--bsdf", bsdf}, kGoodSampleLine + "0 0 1 0.5 0.5 1\n"),
                     {"line 2"});
  }
}

// ---------------------------------------------------------------------------------------
// albedo options

const std::string kSamples = "20000";

TEST(CliAlbedoErrors, NeitherThetaNorHemispherical) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--samples", kSamples}),
                   {"theta", "hemispherical"});
}

TEST(CliAlbedoErrors, ThetaOutOfRange) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "91", "--samples", kSamples}),
                   {"theta", "91"});
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "-1", "--samples", kSamples}),
                   {"theta"});
}

TEST(CliAlbedoErrors, ThetaNan) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "nan", "--samples", kSamples}),
                   {"theta"});
}

TEST(CliAlbedoErrors, ThetaInf) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "inf", "--samples", kSamples}),
                   {"theta"});
}

TEST(CliAlbedoErrors, ThetaNotANumber) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "thirty"}), {"theta"});
}

TEST(CliAlbedoErrors, SamplesZeroOrBad) {
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "30", "--samples", "0"}),
                   {"samples"});
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "30", "--samples", "-5"}),
                   {"samples"});
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "30", "--samples", "many"}),
                   {"samples"});
}

TEST(CliAlbedoErrors, ThetaAndHemisphericalTogether) {
  const RunResult r = run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "30", "--hemispherical"});
  expect_bad_input(r, {});
}

// ---------------------------------------------------------------------------------------
// fresnel options

TEST(CliFresnelErrors, EtaNotPositive) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "0", "--theta", "30"}), {"eta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "-1", "--theta", "30"}), {"eta", "-1"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "-1.5", "--k", "2", "--theta", "30"}), {"eta"});
}

TEST(CliFresnelErrors, EtaNotFinite) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "nan", "--theta", "30"}), {"eta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "inf", "--theta", "30"}), {"eta"});
}

TEST(CliFresnelErrors, NegativeK) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--k", "-1", "--theta", "30"}), {"k", "-1"});
}

TEST(CliFresnelErrors, KNotFinite) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--k", "nan", "--theta", "30"}), {"k"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--k", "inf", "--theta", "30"}), {"k"});
}

TEST(CliFresnelErrors, ThetaOutOfRange) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "100"}), {"theta", "100"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "-5"}), {"theta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "90.000001"}), {"theta"});
}

TEST(CliFresnelErrors, ThetaNotFinite) {
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "nan"}), {"theta"});
}

TEST(CliFresnelErrors, MissingOptions) {
  expect_bad_input(run_gonio({"fresnel", "--theta", "30"}), {"eta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5"}), {"theta"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "glass", "--theta", "30"}), {"eta"});
}

// ---------------------------------------------------------------------------------------
// Floating-point options are decimal, as stdin numbers and integer options are (issue 39):
// CLI11 alone read "" as 0 and 0x10, 0x1p-2 as 16, 0.25.

TEST(CliNumberErrors, EmptyAndHexFloatValuesAreRefused) {
  const std::string diffuse = kDiffuse;
  // Hexadecimal in every option: EveryFloatingPointOptionIsDecimal.
  const std::vector<std::vector<std::string>> cases = {
      {"fresnel", "--eta", "1.5", "--theta", ""},
      {"fresnel", "--eta", "1.5", "--k", "0x1p-2", "--theta", "30"},
      {"fresnel", "--eta", "1.5", "--theta", "", "--mueller"},
      {"albedo", "--bsdf", diffuse, "--theta", "", "--samples", "16"},
      {"spectrum", "--rgb", "", "0.5", "0.5"},
      {"slice", "--bsdf", diffuse, "-o", "/nonexistent/s.png", "--diff-range", ""},
      {"render", "-o", "/nonexistent/r.png", "--polarized", "--polarizer", ""},
  };

  for (const auto& args : cases) {
    SCOPED_TRACE(args[0] + " " + args[args.size() - 2] + " '" + args.back() + "'");
    const std::string& bad = *std::find_if(args.begin(), args.end(), [](const std::string& a) {
      return a.empty() || a.find("0x") != std::string::npos;
    });
    expect_bad_input(run_gonio(args), {"'" + bad + "'", "decimal"});
  }
}

TEST(CliNumberErrors, EveryFloatingPointOptionIsDecimal) {
  // Every option a --help lists as FLOAT (FLOAT x N: N values), found from the tool
  // itself, so that an option added later without the check fails here. CLI11 checks
  // the values before the required options, so the option alone is enough.
  size_t options = 0;
  for (const std::string& sub : gonio_subcommands()) {
    const RunResult help = run_gonio({sub, "--help"});
    for (const std::string& line : split_lines(help.out)) {
      std::stringstream words(line);
      std::string option, type, times;
      size_t n = 1;
      words >> option >> type >> times;
      if (option.rfind("--", 0) != 0 || type != "FLOAT") continue;
      if (times == "x") words >> n;
      std::vector<std::string> args = {sub, option};
      for (size_t i = 0; i < n; ++i) args.push_back(i == 0 ? "0x10" : "1");
      SCOPED_TRACE(sub + " " + option);
      expect_bad_input(run_gonio(args), {option, "'0x10' is not a decimal number"});
      ++options;
    }
  }
  EXPECT_GE(options, 12u);  // albedo 3, fresnel 4, render 1, slice 3, spectrum 1
}

TEST(CliNumberErrors, SliceDiffRangeZeroIsRefused) {
  // 0 was taken as "automatic"; the documented range is a fraction > 0.
  expect_bad_input(run_gonio({"slice", "--bsdf", kDiffuse, "-o", "/nonexistent/s.png", "--diff-range", "0"}),
                   {"--diff-range", "0"});
}

// ---------------------------------------------------------------------------------------
// command line as a whole

TEST(CliCommandErrors, NoSubcommand) {
  expect_bad_input(run_gonio({}), {});
}

TEST(CliCommandErrors, UnknownSubcommand) {
  expect_bad_input(run_gonio({"frobnicate"}), {});
}

// SPEC §3 asks for a line that names the problem; for an unknown subcommand that is
// its name.
TEST(CliCommandErrors, UnknownSubcommandIsNamed) {
  expect_bad_input(run_gonio({"frobnicate"}), {"frobnicate"});
  expect_bad_input(run_gonio({"frobnicate", "--eta", "1.5"}), {"frobnicate"});
}

TEST(CliCommandErrors, UnknownOption) {
  expect_bad_input(run_gonio({"eval", "--bsdf", kDiffuse, "--frobnicate"}, kGoodEvalLine),
                   {"--frobnicate"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "30", "--polarisation", "s"}),
                   {"--polarisation"});
  expect_bad_input(run_gonio({"albedo", "--bsdf", kDiffuse, "--theta", "30", "--spp", "4"}),
                   {"--spp"});
  expect_bad_input(run_gonio({"sample", "--bsdf", kDiffuse, "--seed", "4"}, kGoodSampleLine),
                   {"--seed"});
  expect_bad_input(run_gonio({"--frobnicate", "eval", "--bsdf", kDiffuse}, kGoodEvalLine),
                   {"--frobnicate"});
}

TEST(CliCommandErrors, OptionMissingItsValue) {
  expect_bad_input(run_gonio({"eval", "--bsdf"}, kGoodEvalLine), {"bsdf"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta"}), {"theta"});
}

}  // namespace
}  // namespace gonio_cli_test
