// SPEC §3: every subcommand prints --help (exit 0, text on stdout, nothing on stderr).

#include <ostream>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

struct HelpCase {
  std::string subcommand;              // "" = the top level
  std::vector<std::string> mentions;   // options the help text must list
};

// Readable test names in ctest's listing instead of a byte dump.
void PrintTo(const HelpCase& c, std::ostream* os) { *os << "gonio " << c.subcommand << " --help"; }

class CliHelp : public ::testing::TestWithParam<HelpCase> {};

TEST_P(CliHelp, LongAndShortHelpExitZero) {
  const HelpCase& c = GetParam();
  for (const char* flag : {"--help", "-h"}) {
    std::vector<std::string> args;
    if (!c.subcommand.empty()) args.push_back(c.subcommand);
    args.push_back(flag);
    const RunResult r = run_gonio(args);
    EXPECT_EQ(r.status, 0) << flag << "\n" << describe(r);
    EXPECT_EQ(r.err, "") << flag << "\n" << describe(r);
    EXPECT_FALSE(r.out.empty()) << flag << "\n" << describe(r);
    for (const auto& m : c.mentions)
      EXPECT_TRUE(contains_ci(r.out, m)) << "help should mention " << m << "\n" << describe(r);
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllSubcommands, CliHelp,
    ::testing::Values(HelpCase{"", {"eval", "sample", "albedo", "fresnel", "table", "materials"}},
                      HelpCase{"eval", {"--bsdf", "--mode"}},
                      HelpCase{"sample", {"--bsdf", "--mode", "--count", "--seed"}},
                      HelpCase{"albedo",
                               {"--bsdf", "--theta", "--theta-range", "--phi", "--hemispherical", "--inside",
                                "--samples", "--seed"}},
                      HelpCase{"fresnel", {"--eta", "--k", "--material", "--theta", "--theta-range", "--schlick"}},
                      HelpCase{"materials", {"TYPE", "--markdown"}},
                      HelpCase{"spectrum", {"--rgb", "--emission"}},
                      HelpCase{"table", {}}),
    [](const ::testing::TestParamInfo<HelpCase>& p) {
      return p.param.subcommand.empty() ? std::string("toplevel") : p.param.subcommand;
    });

// --help wins over otherwise missing required options and over bad stdin.
TEST(CliHelpMisc, HelpNeedsNoRequiredOptions) {
  const RunResult r = run_gonio({"eval", "--help"}, "not numbers\n");
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "") << describe(r);
}

TEST(CliHelpMisc, TableRuns) {
  const RunResult r = run_gonio({"table"});
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "") << describe(r);
  EXPECT_FALSE(r.out.empty());
  EXPECT_FALSE(contains_ci(r.out, "nan")) << r.out;
}

}  // namespace
}  // namespace gonio_cli_test
