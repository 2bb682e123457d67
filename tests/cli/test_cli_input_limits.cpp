// Input that once crashed, hung or misled gonio (issue 9): nesting and size limits,
// bounded reads of devices, one-line errors whatever the user typed, decimal integer
// options within SPEC §3's ranges, float-sized material numbers, and write errors on
// stdout. Every case keeps the SPEC §3 contract: exit 2, one stderr line, empty stdout.

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

const std::string kLimitsGoodEvalLine = "0 0 1 0 0.6 0.8\n";
const std::string kLimitsDiffuse = R"({"type":"diffuse","reflectance":0.5})";

// n arrays nested inside one another: "[[[...]]]" (JSON depth n).
std::string nested_arrays(size_t n) { return std::string(n, '[') + std::string(n, ']'); }

// A blend whose first part is a blend, `levels` deep, around a diffuse leaf.
std::string nested_blends(size_t levels) {
  std::string open, close;
  for (size_t i = 0; i < levels; ++i) {
    open += R"({"type":"blend","weight":0.5,"bsdfs":[)";
    close += R"(,{"type":"diffuse"}]})";
  }
  return open + R"({"type":"diffuse"})" + close;
}

// The error line carries no control character: nothing but printable text and its
// final newline (control characters the user typed are shown escaped).
void expect_printable_line(const RunResult& r) {
  ASSERT_FALSE(r.err.empty()) << describe(r);
  for (size_t i = 0; i + 1 < r.err.size(); ++i) {
    const auto c = static_cast<unsigned char>(r.err[i]);
    EXPECT_FALSE(c < 0x20 || c == 0x7f) << "control byte " << int(c) << " at " << i << " in: " << r.err;
  }
}

// ---------------------------------------------------------------------------------------
// JSON nesting: depth <= 64, checked before the parser builds anything.

TEST(CliInputLimits, DeeplyNestedJsonIsRejectedQuickly) {
  // 100,000 deep (a 200 KB file) crashed the error formatting with a stack overflow (exit 139).
  const TempFile deep(nested_arrays(100000));
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult r = run_gonio({"eval", "--bsdf", "@" + deep.path()}, kLimitsGoodEvalLine);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  expect_bad_input(r, {deep.path(), "nested", "64"});
  EXPECT_LT(seconds, 2.0);
}

TEST(CliInputLimits, NestingLimitIsExactly64) {
  // Depth 64 (an object holding 63 arrays) reaches the material parser, which names the
  // unknown field; depth 65 is refused as too deep, at the line and column of the 65th bracket.
  const std::string ok = R"({"type":"diffuse","x":)" + nested_arrays(63) + "}";
  expect_bad_input(run_gonio({"eval", "--bsdf", ok}, kLimitsGoodEvalLine), {"unknown parameter 'x'"});
  const std::string deep = R"({"type":"diffuse","x":)" + nested_arrays(64) + "}";
  const RunResult r = run_gonio({"eval", "--bsdf", deep}, kLimitsGoodEvalLine);
  expect_bad_input(r, {"--bsdf", "nested deeper than 64", "column 86"});
}

TEST(CliInputLimits, DuplicateKeysAreRefused) {
  // nlohmann keeps the last of two equal keys: {"eta": "x", "eta": 1.5} was accepted,
  // the first value unseen (found by fuzz_material). Keys compare decoded.
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"plastic","eta":"x","eta":1.5})"}, kLimitsGoodEvalLine),
                   {"--bsdf", "duplicate key \"eta\"", "line 1, column 29"});
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"diffuse","\u0074ype":"mirror"})"}, kLimitsGoodEvalLine),
                   {"duplicate key \"type\"", "column 19"});
  // The same key in two different objects, and a key's text inside a string value, are fine.
  const auto objs = run_lines(
      {"eval", "--bsdf", R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse","reflectance":1},{"type":"diffuse","reflectance":0}]})"},
      kLimitsGoodEvalLine, 1);
  ASSERT_EQ(objs.size(), 1u);
  EXPECT_NEAR(color3(objs[0]["f"])[0], 0.5 / kPi, 1e-6);
}

TEST(CliInputLimits, TenThousandNestedBlendsFailFast) {
  const TempFile blends(nested_blends(10000));
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult r = run_gonio({"eval", "--bsdf", "@" + blends.path()}, kLimitsGoodEvalLine, 20);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  expect_bad_input(r, {"nested"});
  EXPECT_LT(seconds, 2.0);
}

TEST(CliInputLimits, BlendNestingIsBounded) {
  // 8 levels (256 leaves at most) evaluate; 9 are refused, naming the blend limit.
  const auto objs = run_lines({"eval", "--bsdf", nested_blends(8)}, kLimitsGoodEvalLine, 1);
  ASSERT_EQ(objs.size(), 1u);
  // Every level halves the diffuse leaf's share: (0.5 (0.5 (... 1/π))) plus the other
  // parts, all diffuse with reflectance 0.5 by default: f = 0.5/π throughout.
  EXPECT_NEAR(color3(objs[0]["f"])[0], 0.5 / kPi, 1e-6);
  expect_bad_input(run_gonio({"eval", "--bsdf", nested_blends(9)}, kLimitsGoodEvalLine), {"blend", "nested", "8"});
}

// ---------------------------------------------------------------------------------------
// File size: every read is bounded (16 MiB for a material or scene), devices included.

TEST(CliInputLimits, MaterialFileLargerThanTheLimitIsRejected) {
  // A valid material padded with spaces to 16 MiB + 1 byte.
  std::string text = kLimitsDiffuse;
  text.resize((size_t(16) << 20) + 1, ' ');
  const TempFile big(text);
  expect_bad_input(run_gonio({"eval", "--bsdf", "@" + big.path()}, kLimitsGoodEvalLine),
                   {big.path(), "too large", "16 MiB"});
  // Exactly at the limit it is read and parsed.
  text.resize(size_t(16) << 20);
  const TempFile at_limit(text);
  run_lines({"eval", "--bsdf", "@" + at_limit.path()}, kLimitsGoodEvalLine, 1);
}

TEST(CliInputLimits, EndlessDeviceIsReadOnlyUpToTheLimit) {
  // /dev/zero never ends; reading it whole hung gonio until memory ran out.
  const RunResult r = run_gonio({"eval", "--bsdf", "@/dev/zero"}, kLimitsGoodEvalLine, 10);
  expect_bad_input(r, {"/dev/zero", "too large"});
}

TEST(CliInputLimits, MaterialFromStdinDevice) {
  // /dev/stdin is one more file: read through the same bounded reader.
  const RunResult r = run_gonio({"albedo", "--bsdf", "@/dev/stdin", "--theta", "0"}, kLimitsDiffuse);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.out.find("\"albedo\":[0.5,0.5,0.5]"), std::string::npos) << describe(r);
  expect_bad_input(run_gonio({"eval", "--bsdf", "@/tmp"}, kLimitsGoodEvalLine), {"/tmp", "directory"});
}

// ---------------------------------------------------------------------------------------
// Requests that cannot have their memory (issue 39): refused before any work, naming the
// bound; an allocation that fails anyway is "out of memory", exit 2, not an internal
// error. The runs are limited to 2 GB of address space, so that a regression fails with
// bad_alloc instead of taking the machine's memory.

constexpr rlim_t kLimitsAddressSpace = rlim_t(2) << 30;

TEST(CliInputLimits, GantryOfTooManyReadingsIsRefusedBeforeTheFirstRay) {
  const std::string gantry =
      R"({"theta_i":{"from":0,"to":80,"count":10000},"theta_o":{"from":0,"to":80,"count":10000}})";
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult r = run_gonio_limited({"measure", "--surface", R"({"type":"flat","material":{"type":"diffuse"}})",
                                         "--gantry", gantry, "--samples", "1000"},
                                        {0, kLimitsAddressSpace}, 20);
  expect_bad_input(r, {"--gantry", "100000000 readings", "1000000"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
}

TEST(CliInputLimits, FilmOfTooManyPixelsIsRefusedBeforeRendering) {
  const TempFile scene(R"({"camera":{"width":16384,"height":16384}})");
  const std::string image = scene.path() + ".png";
  const RunResult r = run_gonio_limited({"render", scene.path(), "-o", image}, {0, kLimitsAddressSpace}, 20);
  expect_bad_input(r, {scene.path(), "/camera", "268435456 pixels", "33554432"});
  EXPECT_FALSE(std::filesystem::exists(image));
}

TEST(CliInputLimits, AllocationThatFailsIsOutOfMemoryNotAnInternalError) {
  // A film within the bound (8192 x 4096) needs over 1 GB; under a 512 MB limit its first
  // buffer cannot be had, which was "internal error: std::bad_alloc", exit 3.
  if (!kCanLimitAddressSpace) GTEST_SKIP() << "no address-space limit under AddressSanitizer";
  const TempFile scene(R"({"camera":{"width":8192,"height":4096}})");
  const std::string image = scene.path() + ".png";
  const RunResult r =
      run_gonio_limited({"render", scene.path(), "-o", image, "--spp", "1", "--threads", "1"}, {0, rlim_t(512) << 20});
  expect_bad_input(r, {"out of memory"});
  EXPECT_FALSE(std::filesystem::exists(image));
}

// ---------------------------------------------------------------------------------------
// A NUL byte in JSON text (issue 39): the parser took it for the end of the input and
// silently ignored whatever followed it.

TEST(CliInputLimits, NulByteInMaterialFileIsRefusedWithItsOffset) {
  const std::string text = std::string(R"({"type":"diffuse"})") + '\0' + R"({"type":"mirror","x":1})";
  const TempFile file(text);
  expect_bad_input(run_gonio({"eval", "--bsdf", "@" + file.path()}, kLimitsGoodEvalLine),
                   {file.path(), "NUL", "offset 18"});
}

TEST(CliInputLimits, NulByteInSceneAndSurfaceFilesIsRefused) {
  // A NUL after a complete object, where the rest is no longer looked at.
  const TempFile surface(std::string(R"({"type":"flat","material":{"type":"diffuse"}})") + '\0');
  expect_bad_input(run_gonio({"measure", "--surface", "@" + surface.path(), "--preview", "/nonexistent/p.png"}),
                   {surface.path(), "NUL", "offset 45"});
  const TempFile scene(std::string("{}") + '\0' + "garbage");
  const std::string image = scene.path() + ".png";
  expect_bad_input(run_gonio({"render", scene.path(), "-o", image}), {scene.path(), "NUL", "offset 2"});
  EXPECT_FALSE(std::filesystem::exists(image));
}

// ---------------------------------------------------------------------------------------
// One line, whatever the user typed: control characters in echoed text are escaped.

TEST(CliInputLimits, ControlCharactersInEchoedTextAreEscaped) {
  struct Case {
    std::vector<std::string> args;
    std::string stdin_text;
    std::string shown;  // how the control character must appear
  };
  const std::vector<Case> cases = {
      {{"eval", "--bsdf", R"({"type":"velvet\nrug"})"}, kLimitsGoodEvalLine, "velvet\\nrug"},
      {{"eval", "--bsdf", R"({"type":"diffuse","a\tb":1})"}, kLimitsGoodEvalLine, "a\\tb"},
      {{"eval", "--bsdf", R"({"type":"diffuse","a\u0001b":1})"}, kLimitsGoodEvalLine, "a\\x01b"},
      {{"eval", "--bsdf", "@/nonexistent\nfile"}, kLimitsGoodEvalLine, "/nonexistent\\nfile"},
      {{"eval", "--bsdf", kLimitsDiffuse}, "0 0 1 0 0.6 0.8\x01\n", "0.8\\x01"},
      {{"albedo", "--bsdf", kLimitsDiffuse, "--theta", "1\n2"}, "", "1\\n2"},
      {{"nosuch\ncommand"}, "", "nosuch\\ncommand"},
      {{"eval", "--bsdf", kLimitsDiffuse, "--mode", "radiance\r"}, kLimitsGoodEvalLine, "radiance\\r"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.shown);
    const RunResult r = run_gonio(c.args, c.stdin_text);
    expect_bad_input(r, {c.shown});
    expect_printable_line(r);
  }
}

// ---------------------------------------------------------------------------------------
// Integer options: decimal only, within SPEC §3's ranges (--samples 1 to 10^12,
// --seed 0 to 2,147,483,647).

TEST(CliInputLimits, SamplesAndSeedOutOfRangeOrNotDecimal) {
  const std::vector<std::string> albedo = {"albedo", "--bsdf", R"({"type":"phong","kd":0.2,"ks":0.3,"exponent":10})",
                                           "--theta", "30"};
  auto with = [&](const char* opt, const std::string& v) {
    auto a = albedo;
    a.push_back(opt);
    a.push_back(v);
    return a;
  };
  for (const std::string v : {"0", "-1", "1000000000001", "99999999999999999999", "0x10", "1e3", "1.5", "", "12abc"}) {
    SCOPED_TRACE("--samples " + v);
    expect_bad_input(run_gonio(with("--samples", v)), {"--samples"});
  }
  for (const std::string v : {"-1", "2147483648", "99999999999999999999", "0x10", "1e3", "0.5", " 7"}) {
    SCOPED_TRACE("--seed " + v);
    expect_bad_input(run_gonio(with("--seed", v)), {"--seed"});
  }
  // The ends of the ranges that are cheap to run.
  for (const auto& [opt, v] : std::vector<std::pair<const char*, std::string>>{
           {"--samples", "1"}, {"--seed", "0"}, {"--seed", "2147483647"}}) {
    SCOPED_TRACE(std::string(opt) + " " + v);
    auto a = with(opt, v);
    if (std::string(opt) == "--seed") a.insert(a.end(), {"--samples", "1000"});
    run_one(a);
  }
}

// ---------------------------------------------------------------------------------------
// Material numbers must fit a float; a positive-only one must not round to 0 or a denormal.

TEST(CliInputLimits, MaterialNumbersThatUnderflowAFloatAreRejected) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"type":"roughconductor","material":"Au","alpha":1e-320})", "alpha"},
      {R"({"type":"roughconductor","material":"Au","alpha":[0.1,1e-39]})", "alpha"},
      {R"({"type":"roughdielectric","alpha":1e-46})", "alpha"},
      {R"({"type":"ward","kd":0.1,"ks":0.1,"alpha":1e-40})", "alpha"},
      {R"({"type":"ashikhminshirley","rd":0.1,"rs":0.1,"nu":1e-320,"nv":10})", "nu"},
      {R"({"type":"plastic","alpha":2e-39})", "alpha"},
  };
  for (const auto& [bsdf, field] : cases) {
    SCOPED_TRACE(bsdf);
    expect_bad_input(run_gonio({"eval", "--bsdf", bsdf}, kLimitsGoodEvalLine), {field, "float"});
  }
  // The smallest normal float (1.18e-38) is still a (smooth) roughness.
  run_lines({"eval", "--bsdf", R"({"type":"roughconductor","material":"Au","alpha":1.2e-38})"}, kLimitsGoodEvalLine, 1);
}

// ---------------------------------------------------------------------------------------
// Write errors on stdout: exit 2 and one line, not silence (exit 3) or success (check).

TEST(CliInputLimits, FullStdoutIsReported) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> runs = {
      {{"eval", "--bsdf", kLimitsDiffuse}, kLimitsGoodEvalLine},
      {{"sample", "--bsdf", kLimitsDiffuse}, "0 0 1 0.5 0.5 0.5\n"},
      {{"albedo", "--bsdf", kLimitsDiffuse, "--theta", "30"}, ""},
      {{"fresnel", "--eta", "1.5", "--theta", "30"}, ""},
      {{"table"}, ""},
      {{"check", "--bsdf", R"({"type":"mirror"})"}, ""},  // printf, not std::cout; the quickest check
  };
  for (const auto& [args, in] : runs) {
    SCOPED_TRACE(args.front());
    const RunResult r = run_gonio_stdout_to("/dev/full", args, in, 120);
    expect_bad_input(r, {"cannot write to stdout", "no space left"});
  }
}

}  // namespace
}  // namespace gonio_cli_test
