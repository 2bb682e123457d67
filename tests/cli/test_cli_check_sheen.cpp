// gonio check on a model that is not reciprocal by construction (the LTC sheen, issue 34):
// reciprocity is reported n/a with its reason, in the table and in --json, and the check
// passes.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

TEST(CliCheckSheen, ReciprocityNotApplicableWithItsReason) {
  const RunResult t = run_gonio({"check", "--bsdf", R"({"type":"sheen","roughness":0.3})"});
  ASSERT_EQ(t.status, 0) << describe(t);
  bool seen = false;
  std::istringstream lines(t.out);
  for (std::string line; std::getline(lines, line);)
    if (line.find("  reciprocity ") == 0) {
      seen = true;
      EXPECT_NE(line.find(" n/a "), std::string::npos) << line;
      EXPECT_NE(line.find("not applicable: the LTC sheen"), std::string::npos) << line;
      EXPECT_EQ(line.find("FAIL"), std::string::npos) << line;
    }
  EXPECT_TRUE(seen) << t.out;
  EXPECT_NE(t.out.find("all properties hold"), std::string::npos) << t.out;

  const RunResult j = run_gonio({"check", "--json", "--bsdf", R"({"type":"sheen","roughness":0.3})"});
  ASSERT_EQ(j.status, 0) << describe(j);
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_TRUE(doc["pass"].get<bool>());
  bool found = false;
  for (const auto& p : doc["properties"]) {
    if (p["name"] == "reciprocity") {
      found = true;
      EXPECT_TRUE(p["figure"].is_null());
      EXPECT_FALSE(p["applicable"].get<bool>());
      EXPECT_NE(p["reason"].get<std::string>().find("f(wo, wi) != f(wi, wo)"), std::string::npos);
    } else {
      EXPECT_FALSE(p.contains("applicable")) << p.dump();
    }
  }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace gonio_cli_test
