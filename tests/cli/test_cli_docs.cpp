// The documentation in the repository keeps up with the tool: docs/cli.md has a section
// for every subcommand and mentions every option its --help lists; README.md and docs/*.md
// link only to files inside the repository that exist.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

std::string read_source_file(const std::string& rel) {
  std::ifstream in(std::string(GONIO_SOURCE_DIR) + "/" + rel, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool mentions_option(const std::string& text, const std::string& option) {
  for (size_t at = text.find(option); at != std::string::npos; at = text.find(option, at + 1)) {
    const size_t end = at + option.size();
    if (end == text.size() || !(std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '-')) return true;
  }
  return false;
}

TEST(CliDocs, EverySubcommandAndOptionIsInDocsCliMd) {
  const std::string doc = read_source_file("docs/cli.md");
  ASSERT_FALSE(doc.empty());
  const auto names = gonio_subcommands();
  EXPECT_GE(names.size(), 8u);
  for (const auto& name : names) {
    EXPECT_NE(doc.find("\n## `gonio " + name), std::string::npos) << "docs/cli.md has no section for " << name;
    const RunResult help = run_gonio({name, "--help"});
    ASSERT_EQ(help.status, 0) << describe(help);
    // Option lines of CLI11's help: "  -o,--output TEXT ...", "  --spp INT ...".
    std::istringstream lines(help.out);
    std::string line;
    while (std::getline(lines, line)) {
      const size_t first = line.find_first_not_of(' ');
      if (first == std::string::npos || line[first] != '-') continue;
      std::string names_part = line.substr(first, line.find(' ', first) - first);
      std::stringstream parts(names_part);
      std::string opt;
      while (std::getline(parts, opt, ',')) {
        if (opt.rfind("--", 0) != 0 || opt == "--help") continue;
        EXPECT_TRUE(mentions_option(doc, opt)) << "docs/cli.md does not mention " << name << " " << opt;
      }
    }
  }
}

// Markdown links [text](target) and images ![alt](target) in README.md and docs/*.md:
// no link leaves the repository, and every file linked to exists.
TEST(CliDocs, LinksStayInsideTheRepository) {
  std::vector<std::string> files = {"README.md", "CONTRIBUTING.md", "CHANGELOG.md"};
  for (const auto& e : std::filesystem::directory_iterator(std::string(GONIO_SOURCE_DIR) + "/docs"))
    if (e.path().extension() == ".md") files.push_back("docs/" + e.path().filename().string());
  const std::regex link(R"(\]\(([^)\s]+)\))");
  size_t checked = 0;
  for (const auto& rel : files) {
    const std::string text = read_source_file(rel);
    if (text.empty()) continue;  // CONTRIBUTING.md and CHANGELOG.md may not exist on every branch
    const std::filesystem::path dir = std::filesystem::path(GONIO_SOURCE_DIR) / std::filesystem::path(rel).parent_path();
    for (std::sregex_iterator it(text.begin(), text.end(), link), end; it != end; ++it) {
      std::string target = (*it)[1].str();
      EXPECT_EQ(target.find("://"), std::string::npos) << rel << " links outside the repository: " << target;
      EXPECT_EQ(target.rfind("mailto:", 0), std::string::npos) << rel << ": " << target;
      target = target.substr(0, target.find('#'));
      if (target.empty()) continue;  // an anchor in the same file
      const auto path = (dir / target).lexically_normal();
      EXPECT_TRUE(std::filesystem::exists(path)) << rel << " links to a missing file: " << target;
      const auto inside = std::filesystem::relative(path, std::filesystem::path(GONIO_SOURCE_DIR));
      EXPECT_NE(inside.string().rfind("..", 0), 0u) << rel << " links out of the repository: " << target;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10u);
}

// A newcomer reads README.md through (issue 55): what gonio is, the two commands, a
// picture, a short tour, the model table, at most 150 lines; the rest is in docs/. And
// docs/benchmarks.md stays under 500 lines (older figures go to benchmarks-history.md).
size_t count_doc_lines(const std::string& text) {
  size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  if (!text.empty() && text.back() != '\n') ++lines;
  return lines;
}

TEST(CliDocs, ReadmeAndBenchmarksStayShort) {
  const std::string readme = read_source_file("README.md");
  ASSERT_FALSE(readme.empty());
  EXPECT_LE(count_doc_lines(readme), 150u) << "README.md is longer than 150 lines: move detail to docs/";
  const std::string bench = read_source_file("docs/benchmarks.md");
  ASSERT_FALSE(bench.empty());
  EXPECT_LT(count_doc_lines(bench), 500u) << "docs/benchmarks.md has 500 lines or more: move older figures to docs/benchmarks-history.md";
}

// NOTICE names every data file, and every data file names its source in its first lines.
TEST(CliDocs, NoticeListsEveryDataFile) {
  const std::string notice = read_source_file("NOTICE");
  ASSERT_FALSE(notice.empty());
  EXPECT_NE(notice.find("MIT"), std::string::npos);
  size_t files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(std::string(GONIO_SOURCE_DIR) + "/data")) {
    if (!e.is_regular_file()) continue;
    ++files;
    const std::string name = e.path().filename().string();
    EXPECT_NE(notice.find(name), std::string::npos) << "NOTICE does not list data file " << e.path();
    std::ifstream in(e.path());
    std::string line;
    bool source = false;
    for (int i = 0; i < 5 && std::getline(in, line); ++i) source |= line.rfind("# Source:", 0) == 0;
    EXPECT_TRUE(source) << e.path() << " does not state its source (# Source: ...) in its first lines";
  }
  EXPECT_GE(files, 14u);
}

}  // namespace
}  // namespace gonio_cli_test
