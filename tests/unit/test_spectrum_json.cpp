// SPEC §2's colour forms → Spectrum (gonio/spectrum/spectrum_json.h): each form gives the
// spectrum it names, and misuse is an error that names the field.

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "gonio/error.h"
#include "gonio/spectrum/spectrum_json.h"

namespace gonio {
namespace {

using nlohmann::json;

Spectrum parse(const char* text, SpectrumUse use) { return parse_spectrum(json::parse(text), "field", use); }

std::string error_of(const char* text, SpectrumUse use) {
  try {
    parse(text, use);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SpectrumJson, EachFormGivesItsSpectrum) {
  EXPECT_EQ(parse("0.25", SpectrumUse::kReflectance).eval(600), Float(0.25));
  // Grey light is white: v · D65 of luminance 1.
  EXPECT_NEAR(parse("3", SpectrumUse::kEmission).eval(560), 3 * d65(560), 1e-5);
  EXPECT_NEAR(parse("[0.9, 0.1, 0.1]", SpectrumUse::kReflectance).eval(650),
              RgbAlbedoSpectrum(0.9f, 0.1f, 0.1f).eval(650), 1e-7);
  EXPECT_NEAR(parse("[4, 1, 0]", SpectrumUse::kEmission).eval(620), RgbIlluminantSpectrum(4, 1, 0).eval(620), 1e-6);
  EXPECT_NEAR(parse(R"({"spectrum": [[400, 0.2], [600, 0.6]]})", SpectrumUse::kReflectance).eval(500), 0.4, 1e-6);
  EXPECT_NEAR(parse(R"({"blackbody": 5000})", SpectrumUse::kEmission).eval(500), BlackbodySpectrum(5000).eval(500), 1e-6);
  EXPECT_NEAR(parse(R"({"illuminant": "D65"})", SpectrumUse::kEmission).eval(450), d65(450), 1e-7);
  EXPECT_NEAR(parse(R"("BK7")", SpectrumUse::kIndex).eval(586), 1.516866, 1e-6);  // a row of data/glasses/BK7.csv
  const Spectrum bk7 = parse(R"({"sellmeier": {"B": [1.03961212, 0.231792344, 1.01046945],
                                                "C": [0.00600069867, 0.0200179144, 103.560653]}})", SpectrumUse::kIndex);
  EXPECT_NEAR(bk7.eval(586), 1.516866, 1e-4);
  EXPECT_EQ(parse("1.5", SpectrumUse::kIndex).eval(700), Float(1.5));
}

TEST(SpectrumJson, CsvFileRelativeToBaseDir) {
  const std::string dir = ::testing::TempDir();
  const std::string name = "gonio_spectrum_json_test.csv";
  {
    std::ofstream f(dir + "/" + name);
    f << "# nm, reflectance\n400, 0.1\n700, 0.7\n";
  }
  const Spectrum s = parse_spectrum(json{{"spectrum", name}}, "reflectance", SpectrumUse::kReflectance, dir);
  EXPECT_NEAR(s.eval(550), 0.4, 1e-6);
  {
    std::ofstream f(dir + "/" + name);
    f << "400, 0.1\n700, 1.7\n";
  }
  try {
    parse_spectrum(json{{"spectrum", name}}, "reflectance", SpectrumUse::kReflectance, dir);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reflectance: a reflectance must be in [0, 1], got 1.7"), std::string::npos) << e.what();
  }
  std::remove((dir + "/" + name).c_str());
}

TEST(SpectrumJson, MisuseNamesTheField) {
  const struct {
    const char* text;
    SpectrumUse use;
    const char* mention;
  } cases[] = {
      {"1.5", SpectrumUse::kReflectance, "[0, 1]"},
      {"-1", SpectrumUse::kEmission, "[0, 1e9]"},
      {"[0.5, 0.5]", SpectrumUse::kReflectance, "3 numbers"},
      {"[1, 1, 1]", SpectrumUse::kIndex, "not RGB"},
      {R"({"blackbody": 5000})", SpectrumUse::kReflectance, "only accepted for emission"},
      {R"({"blackbody": 5})", SpectrumUse::kEmission, "temperature"},
      {R"({"illuminant": "A"})", SpectrumUse::kEmission, "D65"},
      {R"("BK8")", SpectrumUse::kIndex, "unknown glass 'BK8'"},
      {R"("BK7")", SpectrumUse::kReflectance, "only accepted for an index"},
      {R"({"sellmeier": {"B": [1, 0, 0], "C": [0.25, 0, 0]}})", SpectrumUse::kIndex, "pole"},
      {R"({"spectrum": [[500, 0.5], [400, 0.5]]})", SpectrumUse::kReflectance, "increase"},
      {R"({"spectrum": [[-5, 0.5]]})", SpectrumUse::kReflectance, "positive"},
      {R"({"spectrum": [[500, 0.5, 1]]})", SpectrumUse::kReflectance, "[nm, value]"},
      {R"({"spectra": 1})", SpectrumUse::kReflectance, "unknown spectrum form"},
      {R"({"spectrum": 1, "blackbody": 2})", SpectrumUse::kEmission, "expected"},
  };
  for (const auto& c : cases) {
    const std::string m = error_of(c.text, c.use);
    EXPECT_EQ(m.rfind("field", 0), 0u) << c.text << ": " << m;
    EXPECT_NE(m.find(c.mention), std::string::npos) << c.text << ": " << m;
  }
}

}  // namespace
}  // namespace gonio
