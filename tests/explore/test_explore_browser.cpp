// The page in a real browser (issue 36): headless Chromium (Debian `chromium`, installed
// by scripts/setup.sh) loads it from a server in this process and prints the DOM once its
// requests are done (--virtual-time-budget). The page lists every error it meets in
// #errors and marks each view it drew (data-drawn on its canvas); a material whose
// parameters are wrong shows the CLI's message. Skipped where Chromium is missing.

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../cli/run_gonio.h"
#include "explore/server.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string find_chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (::access(p, X_OK) == 0) return p;
  return "";
}

// Runs argv, returns its stdout (stderr is dropped: Chromium reports missing D-Bus there).
std::string capture(const std::vector<std::string>& args) {
  int out[2];
  if (::pipe(out) != 0) return "";
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addclose(&fa, out[0]);
  std::vector<std::string> a = args;
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(out[1]);
  std::string text;
  if (rc == 0) {
    char buf[4096];
    for (ssize_t n; (n = ::read(out[0], buf, sizeof buf)) > 0;) text.append(buf, size_t(n));
    ::waitpid(pid, nullptr, 0);
  }
  ::close(out[0]);
  return text;
}

class ExploreBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = find_chromium();
    if (chromium_.empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
    profile_ = fs::temp_directory_path() / ("gonio_explore_chromium_" + std::to_string(::getpid()));
    gonio::explore::ServerOptions o;
    o.port = 0;
    // A --data with a (dummy) table: the page then offers gonio fit.
    fs::create_directories(profile_ / "data");
    std::ofstream(profile_ / "data" / "table.binary") << "x";
    o.data_dir = (profile_ / "data").string();
    server_ = std::make_unique<gonio::explore::Server>(o);
    server_->bind();
    thread_ = std::thread([this] { server_->run(); });
  }
  void TearDown() override {
    if (!server_) return;
    server_->stop();
    thread_.join();
    fs::remove_all(profile_);
  }

  // The DOM of the page at `hash` once it settled; headless, a 60 s limit.
  std::string dom(const std::string& hash) {
    return capture({"timeout", "60", chromium_, "--headless", "--no-sandbox", "--disable-gpu",
                    "--no-first-run", "--user-data-dir=" + profile_.string(), "--virtual-time-budget=8000",
                    "--dump-dom", server_->url() + hash});
  }

  static std::string state_hash(const json& material, const json& more = json::object()) {
    json state = {{"material", material}, {"theta_i", 40}, {"phi_d", 90}, {"spectral", false},
                  {"wavelength", 550}, {"lobe", "f_cos"}, {"eta", 1.5},
                  {"sphere_passes", 2}};  // the sphere's refinement cut short
    state.update(more);
    std::string s = state.dump(), out = "#";
    const char* hex = "0123456789ABCDEF";
    for (const unsigned char c : s) {
      if (std::isalnum(c) || c == '-' || c == '_' || c == '.') {
        out += char(c);
      } else {
        out += '%';
        out += hex[c >> 4];
        out += hex[c & 15];
      }
    }
    return out;
  }

  std::string chromium_;
  fs::path profile_;
  std::unique_ptr<gonio::explore::Server> server_;
  std::thread thread_;
};

// How often the canvas `id` was drawn (its data-drawn), 0 if never.
int drawn(const std::string& dom, const std::string& id) {
  std::smatch m;
  const std::regex r("<canvas id=\"" + id + "\"[^>]*data-drawn=\"(\\d+)\"");
  return std::regex_search(dom, m, r) ? std::stoi(m[1].str()) : 0;
}

TEST_F(ExploreBrowser, EveryViewIsDrawnWithoutAnError) {
  for (const json& material : {json{{"type", "roughconductor"}, {"alpha", 0.2}, {"material", "Cu"}},
                               json{{"type", "layered"},
                                    {"top", {{"type", "roughdielectric"}, {"alpha", 0.1}}},
                                    {"bottom", {{"type", "diffuse"}, {"reflectance", {0.7, 0.2, 0.1}}}}}}) {
    const std::string d = dom(state_hash(material));
    ASSERT_NE(d.find("<body"), std::string::npos) << "no DOM from chromium";
    EXPECT_NE(d.find("<pre id=\"errors\" hidden=\"\"></pre>"), std::string::npos)
        << "the page met errors: " << d.substr(d.find("<pre id=\"errors\""), 400);
    for (const char* view : {"lobe", "lobe3d", "slice", "albedo", "fresnel", "sphere"}) EXPECT_GE(drawn(d, view), 1) << view;
    EXPECT_NE(d.find("valid: " + material["type"].get<std::string>()), std::string::npos);
    // The fit panel lists the table of --data and the models gonio fit takes.
    EXPECT_NE(d.find("<option value=\"table.binary\">"), std::string::npos);
    EXPECT_NE(d.find("<div id=\"fit-panel\">"), std::string::npos) << "fit panel hidden";
    // The editor was generated from the registry: a row per parameter of the type.
    EXPECT_NE(d.find("<select"), std::string::npos);
  }
}

// Also, in the same page (one Chromium run): the studio environment map, and the latency
// recorder measuring a θi slider's input (state "probe_input") to the redraw of the two
// views it changes. Under --virtual-time-budget the times are virtual: the figures come
// from scripts/explore_latency.mjs; this checks what the recorder records.
TEST_F(ExploreBrowser, ComparisonDrawsBothMaterials) {
  json state = json::parse(R"({"compare": true,
    "material_b": {"type": "roughconductor", "alpha": 0.3, "material": "Au", "distribution": "beckmann"},
    "environment_map": "studio", "probe_input": {"id": "theta-i", "value": 55}})");
  const std::string d = dom(state_hash({{"type", "roughconductor"}, {"alpha", 0.2}, {"material", "Cu"}}, state));
  EXPECT_NE(d.find("<pre id=\"errors\" hidden=\"\"></pre>"), std::string::npos)
      << d.substr(d.find("<pre id=\"errors\""), 400);
  EXPECT_NE(d.find("B valid: roughconductor"), std::string::npos);
  for (const char* view : {"lobe", "slice", "albedo", "fresnel", "sphere", "sphere-b"}) EXPECT_GE(drawn(d, view), 1) << view;
  // The slice figure holds the three panels: wider than alone.
  EXPECT_NE(d.find("<canvas id=\"slice\" width=\"720\""), std::string::npos);
  // The Fresnel view names B's interface (gold) beside A's (copper).
  EXPECT_NE(d.find("B: material Au, R(0°) = "), std::string::npos) << d.substr(d.find("id=\"fresnel-readout\""), 300);
  EXPECT_NE(d.find("B on the right"), std::string::npos);
  // The recorder: one record for the θi input, with the lobe and the 3D lobe redrawn.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(d, m, std::regex("<pre id=\"latency\" hidden=\"\">([^<]*)</pre>"))) << "no latency record";
  const json rec = json::parse(m[1].str(), nullptr, false);
  ASSERT_TRUE(rec.is_object()) << m[1].str();
  bool found = false;
  for (const json& r : rec["records"]) {
    if (r["source"] != "theta-i") continue;
    found = true;
    EXPECT_EQ(r["views"].size(), 2u) << r;
    EXPECT_TRUE(r["views"].contains("lobe") && r["views"].contains("lobe3d")) << r;
    EXPECT_GE(r["total"].get<double>(), r["views"]["lobe"].get<double>()) << r;
  }
  EXPECT_TRUE(found) << rec;
}

// Issue 36: the value under the cursor equals `gonio eval` at that direction. The page
// moves a pointer over pixel (px, py) of the 90² slice (state "probe"); the directions of
// that pixel's centre are computed here from Rusinkiewicz's half/difference angles and
// evaluated by the CLI.
TEST_F(ExploreBrowser, TheSliceCursorReadsWhatGonioEvalPrints) {
  const json m = {{"type", "roughconductor"}, {"alpha", 0.3}, {"material", "Au"}};
  const int n = 90, px = 20, py = 50;
  const std::string d = dom(state_hash(m, {{"phi_d", 60}, {"probe", {{"px", px}, {"py", py}}}}));
  std::smatch mm;
  ASSERT_TRUE(std::regex_search(d, mm, std::regex(R"re(id="slice-readout"[^>]*data-f="(\[[^"]*\])")re")))
      << d.substr(d.find("slice-readout"), 300);
  const json f_page = json::parse(mm[1].str());
  const double deg = 3.14159265358979323846 / 180;
  const double theta_h = (px + 0.5) / n * 90 * deg, theta_d = (1 - (py + 0.5) / n) * 90 * deg, phi_d = 60 * deg;
  // Rusinkiewicz (1998): d in the frame whose pole is h; with φh = 0, wi = Ry(θh) d and
  // wo its mirror image about h.
  const double dx = std::sin(theta_d) * std::cos(phi_d), dy = std::sin(theta_d) * std::sin(phi_d),
               dz = std::cos(theta_d);
  const double wi[3] = {dx * std::cos(theta_h) + dz * std::sin(theta_h), dy,
                        -dx * std::sin(theta_h) + dz * std::cos(theta_h)};
  const double h[3] = {std::sin(theta_h), 0, std::cos(theta_h)};
  const double k = 2 * (wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2]);
  const double wo[3] = {k * h[0] - wi[0], k * h[1] - wi[1], k * h[2] - wi[2]};
  char line[256];
  std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", wo[0], wo[1], wo[2], wi[0], wi[1], wi[2]);
  const auto cli = gonio_cli_test::run_gonio({"eval", "--bsdf", m.dump()}, line);
  ASSERT_EQ(cli.status, 0) << cli.err;
  const json f_cli = json::parse(cli.out)["f"];
  ASSERT_EQ(f_page.size(), 3u);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(f_page[c].get<double>(), f_cli[c].get<double>(), 1e-5 * f_cli[c].get<double>()) << c;
}

TEST_F(ExploreBrowser, ABadMaterialShowsTheCliMessage) {
  const std::string m = R"({"type":"roughconductor","alpha":-0.1,"material":"Au"})";
  const auto cli = gonio_cli_test::run_gonio({"eval", "--bsdf", m}, "0 0 1 0 0 1\n");
  ASSERT_EQ(cli.status, 2);
  const std::string message = cli.err.substr(7, cli.err.size() - 8);  // without "gonio: " and the newline
  // As the DOM serialises text: & < > escaped.
  std::string escaped;
  for (const char c : message) escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
  const std::string d = dom(state_hash(json::parse(m)));
  EXPECT_NE(d.find("class=\"status error\">" + escaped + "<"), std::string::npos) << escaped;
  EXPECT_NE(d.find("<pre id=\"errors\" hidden=\"\"></pre>"), std::string::npos);
}

}  // namespace
