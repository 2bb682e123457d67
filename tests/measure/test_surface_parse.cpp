// parse_surface (include/gonio/measure/surface.h): every type parses, every bad field is
// one InputError line that names it.
#include <gtest/gtest.h>

#include <string>

#include "gonio/error.h"
#include "gonio/measure/surface.h"

namespace gm = gonio::measure;

namespace {

// The message of the InputError that parsing `json` throws ("" when none is thrown).
[[maybe_unused]] std::string error_of(const std::string& json, const std::string& base_dir = "") {
  try {
    gm::parse_surface(json, "--surface", base_dir);
  } catch (const gonio::InputError& e) {
    return e.what();
  }
  return "";
}

constexpr const char* kWhite = R"("material": {"type": "mirror"})";

}  // namespace

TEST(SurfaceParse, FlatIsOneCellOfHeightZero) {
  const gm::Surface s = gm::parse_surface(std::string(R"({"type": "flat", )") + kWhite + "}");
  EXPECT_EQ(s.type, "flat");
  ASSERT_EQ(s.field.n, 1);
  ASSERT_EQ(s.field.z.size(), 1u);
  EXPECT_EQ(s.field.z[0], 0.0f);
  EXPECT_EQ(s.field.size, 1.0);
}

TEST(SurfaceParse, GaussianDefaults) {
  const gm::Surface s =
      gm::parse_surface(std::string(R"({"type": "gaussian", "alpha": 0.3, "resolution": 64, )") + kWhite + "}");
  EXPECT_EQ(s.type, "gaussian");
  EXPECT_EQ(s.field.n, 64);
  EXPECT_EQ(s.field.z.size(), 64u * 64u);
}
