// gonio explore's JSON API over HTTP (issue 36, SPEC §3): a server on a free port in this
// process, asked as the page asks it, its answers checked against closed forms written
// here (Lambert's ρ/π, Fresnel at normal incidence, Brewster's and the critical angle),
// against the CLI run on the same input (the error messages, /api/eval's numbers), and for
// the safety rules (Host, Origin, files outside --data, the page fetching nothing).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <tuple>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "../cli/run_gonio.h"
#include "explore/api.h"
#include "explore/server.h"
#include "explore/web_files.h"

namespace {

using nlohmann::json;
using gonio_cli_test::run_gonio;
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

// One server for the suite, with a --data directory the file tests fill.
class ExploreApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    data_dir() = fs::temp_directory_path() / ("gonio_explore_test_" + std::to_string(::getpid()));
    fs::create_directories(data_dir());
    gonio::explore::ServerOptions o;
    o.port = 0;
    o.data_dir = data_dir().string();
    server() = std::make_unique<gonio::explore::Server>(o);
    server()->bind();
    thread() = std::thread([] { server()->run(); });
  }
  static void TearDownTestSuite() {
    server()->stop();
    thread().join();
    server().reset();
    fs::remove_all(data_dir());
  }
  static std::unique_ptr<gonio::explore::Server>& server() {
    static std::unique_ptr<gonio::explore::Server> s;
    return s;
  }
  static std::thread& thread() {
    static std::thread t;
    return t;
  }
  static fs::path& data_dir() {
    static fs::path p;
    return p;
  }

  static httplib::Client client() {
    httplib::Client c("127.0.0.1", server()->port());
    c.set_read_timeout(60);
    return c;
  }
  // POST path with `body`; the status and the parsed answer.
  static std::pair<int, json> post(const std::string& path, const json& body) {
    auto c = client();
    const auto res = c.Post(path.c_str(), body.dump(), "application/json");
    if (!res) return {-1, json()};
    return {res->status, json::parse(res->body, nullptr, false)};
  }
};

const json kLambert = {{"type", "diffuse"}, {"reflectance", {0.2, 0.5, 0.8}}};

TEST_F(ExploreApi, LobeOfLambertIsRhoOverPiAtEveryAngle) {
  const auto [status, d] = post("/api/lobe", {{"bsdf", kLambert}, {"theta_i", 40}, {"count", 37}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_EQ(d["theta_o"].size(), 37u);
  EXPECT_DOUBLE_EQ(d["mirror"].get<double>(), -40);
  const double rho[3] = {0.2, 0.5, 0.8};
  for (size_t i = 0; i < 37; ++i) {
    const double theta_o = -90 + 5.0 * double(i);
    EXPECT_NEAR(d["theta_o"][i].get<double>(), theta_o, 1e-12);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(d["f"][i][c].get<double>(), rho[c] / kPi, 1e-6) << i;
      EXPECT_NEAR(d["f_cos"][i][c].get<double>(), rho[c] / kPi * std::cos(theta_o * kPi / 180), 1e-6) << i;
    }
  }
}

TEST_F(ExploreApi, Lobe3dCoversTheHemisphere) {
  const auto [status, d] = post("/api/lobe3d", {{"bsdf", kLambert}, {"theta_i", 30}, {"count_theta", 6},
                                                {"count_phi", 8}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_EQ(d["f"].size(), 7u * 8u);
  // Luminance of ρ/π (Rec. 709 weights), times cos θo for f_cos.
  const double y = (0.2126 * 0.2 + 0.7152 * 0.5 + 0.0722 * 0.8) / kPi;
  for (int r = 0; r <= 6; ++r)
    for (int p = 0; p < 8; ++p) {
      const size_t i = size_t(r * 8 + p);
      EXPECT_NEAR(d["f"][i].get<double>(), y, 1e-6);
      EXPECT_NEAR(d["f_cos"][i].get<double>(), y * std::cos(15.0 * r * kPi / 180), 1e-6);
    }
  // A glossy lobe peaks towards the mirror direction: φo = 180°, θo near θi.
  const auto [s2, g] = post("/api/lobe3d", {{"bsdf", {{"type", "roughconductor"}, {"alpha", 0.1}, {"material", "Au"}}},
                                            {"theta_i", 30}, {"count_theta", 24}, {"count_phi", 48}});
  ASSERT_EQ(s2, 200);
  size_t best = 0;
  for (size_t i = 0; i < g["f"].size(); ++i)
    if (g["f"][i].get<double>() > g["f"][best].get<double>()) best = i;
  EXPECT_EQ(best % 48, 24u);                // φo = 180°
  EXPECT_NEAR(double(best / 48), 8, 1);     // θo = 8 × 3.75° = 30°
}

TEST_F(ExploreApi, SpectralLobeOfAFlatSpectrumIsItsValueOverPi) {
  const json flat = {{"type", "diffuse"}, {"reflectance", {{"spectrum", {{360, 0.3}, {830, 0.3}}}}}};
  const auto [status, d] = post("/api/lobe", {{"bsdf", flat}, {"theta_i", 10}, {"count", 5}, {"wavelength", 600}});
  ASSERT_EQ(status, 200) << d;
  EXPECT_EQ(d["channels"], 1);
  for (const auto& f : d["f"]) {
    ASSERT_EQ(f.size(), 1u);
    EXPECT_NEAR(f[0].get<double>(), 0.3 / kPi, 1e-6);
  }
  const auto [bad, e] = post("/api/lobe", {{"bsdf", flat}, {"wavelength", 200}});
  EXPECT_EQ(bad, 400);
  EXPECT_NE(e["error"].get<std::string>().find("wavelength must be a number of nanometres in [360, 830]"),
            std::string::npos)
      << e;
}

TEST_F(ExploreApi, FresnelOfADielectricAtNormalIncidenceBrewsterAndCritical) {
  for (const double eta : {1.33, 1.5, 2.4}) {
    const auto [status, d] = post("/api/fresnel", {{"bsdf", {{"type", "dielectric"}, {"eta", eta}}}, {"count", 91}});
    ASSERT_EQ(status, 200) << d;
    const json& out = d["channels"][0]["outside"];
    const json& in = d["channels"][0]["inside"];
    const double r0 = std::pow((eta - 1) / (eta + 1), 2);  // Hecht, Optics, eq. 4.47
    EXPECT_NEAR(out["R"][0].get<double>(), r0, 1e-12);
    EXPECT_NEAR(out["Rs"][0].get<double>(), r0, 1e-12);
    EXPECT_NEAR(in["R"][0].get<double>(), r0, 1e-12);  // the same from inside
    EXPECT_NEAR(out["brewster"].get<double>(), std::atan(eta) * 180 / kPi, 1e-9);
    EXPECT_NEAR(in["brewster"].get<double>(), std::atan(1 / eta) * 180 / kPi, 1e-9);
    EXPECT_TRUE(out["critical"].is_null());
    EXPECT_NEAR(in["critical"].get<double>(), std::asin(1 / eta) * 180 / kPi, 1e-9);
    // Total reflection from inside past the critical angle, full reflection at grazing.
    EXPECT_NEAR(in["R"][90].get<double>(), 1, 1e-12);
    EXPECT_NEAR(out["R"][90].get<double>(), 1, 1e-9);
  }
}

TEST_F(ExploreApi, FresnelOfAConductorAtNormalIncidence) {
  const double n = 0.2, k = 3.0;
  const auto [status, d] = post("/api/fresnel", {{"eta", n}, {"k", k}, {"count", 10}});
  ASSERT_EQ(status, 200) << d;
  const double r0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);  // Born & Wolf §14.2
  EXPECT_NEAR(d["channels"][0]["outside"]["R"][0].get<double>(), r0, 1e-12);
  EXPECT_TRUE(d["channels"][0]["inside"].is_null());
  EXPECT_TRUE(d["channels"][0]["outside"]["pseudo_brewster"].get<bool>());
  // A material with no interface says so (the page then takes an index).
  const auto [s2, none] = post("/api/fresnel", {{"bsdf", kLambert}});
  ASSERT_EQ(s2, 200);
  EXPECT_TRUE(none["interface"].is_null());
  // A layered material's interface is its top's.
  const json layered = {{"type", "layered"},
                        {"top", {{"type", "dielectric"}, {"eta", 1.6}}},
                        {"bottom", {{"type", "diffuse"}}}};
  const auto [s3, top] = post("/api/fresnel", {{"bsdf", layered}, {"count", 2}});
  ASSERT_EQ(s3, 200) << top;
  EXPECT_NEAR(top["channels"][0]["outside"]["R"][0].get<double>(), std::pow(0.6 / 2.6, 2), 1e-12);
}

TEST_F(ExploreApi, AlbedoOfLambertAndOfASmoothDielectric) {
  const auto [status, d] = post("/api/albedo", {{"bsdf", kLambert}, {"count", 4}});
  ASSERT_EQ(status, 200) << d;
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(d["reflectance"][i][1].get<double>(), 0.5, 1e-6);
    EXPECT_NEAR(d["transmittance"][i][1].get<double>(), 0, 1e-12);
  }
  const auto [s2, g] = post("/api/albedo", {{"bsdf", {{"type", "dielectric"}, {"eta", 1.5}}}, {"count", 2}});
  ASSERT_EQ(s2, 200) << g;
  EXPECT_NEAR(g["reflectance"][0][0].get<double>(), 0.04, 1e-6);
  EXPECT_NEAR(g["transmittance"][0][0].get<double>(), 0.96, 1e-6);
}

TEST_F(ExploreApi, SliceOfLambertIsFlatAndTheCursorReadsRhoOverPi) {
  const auto [status, d] = post("/api/slice", {{"bsdf", {{"type", "diffuse"}, {"reflectance", 0.5}}}, {"size", 32},
                                               {"phi_d", 0}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_EQ(d["values"].size(), 32u * 32u);
  int below = 0;
  for (const auto& v : d["values"]) {
    if (v.get<double>() == -1) {
      ++below;
      continue;
    }
    EXPECT_NEAR(v.get<double>(), 0.5 / kPi, 1e-6);
  }
  // At φd = 0, wi dips below the horizon where θh + θd > 90° (wi.z = cos(θh + θd)): the
  // 496 pixel centres above the anti-diagonal, plus those of the 32 on it (θh + θd = 90°
  // exactly) whose wi.z rounds to 0 or below.
  EXPECT_GE(below, 496);
  EXPECT_LE(below, 496 + 32);
  // At φd = 90°, wi.z = cos θh cos θd (Rusinkiewicz 1998): never below.
  const auto [s90, d90] = post("/api/slice", {{"bsdf", kLambert}, {"size", 32}, {"phi_d", 90}});
  ASSERT_EQ(s90, 200);
  for (const auto& v : d90["values"]) EXPECT_GT(v.get<double>(), 0);
  const auto [s2, p] = post("/api/slice_point", {{"bsdf", kLambert}, {"theta_h", 10}, {"theta_d", 20}, {"phi_d", 90}});
  ASSERT_EQ(s2, 200) << p;
  EXPECT_TRUE(p["above"].get<bool>());
  EXPECT_NEAR(p["f"][2].get<double>(), 0.8 / kPi, 1e-6);
  // θh = 10° is the angle between the normal and the half vector of wo and wi.
  double h[3];
  for (int i = 0; i < 3; ++i) h[i] = p["wo"][i].get<double>() + p["wi"][i].get<double>();
  EXPECT_NEAR(std::acos(h[2] / std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2])) * 180 / kPi, 10, 1e-4);
}

// The float32 RGB pixels of an /api/sphere answer.
std::vector<float> sphere_pixels(const json& d) {
  const std::string b64 = d["pixels"];
  std::string bytes;
  int bits = 0;
  std::uint32_t acc = 0;
  for (const char c : b64) {
    const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(k, c);
    if (c == '=' || !at) break;
    acc = acc << 6 | std::uint32_t(at - k);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes += char((acc >> bits) & 0xff);
    }
  }
  std::vector<float> px(bytes.size() / sizeof(float));
  std::memcpy(px.data(), bytes.data(), px.size() * sizeof(float));
  return px;
}

TEST_F(ExploreApi, SliceComparesTwoMaterialsOnOneScale) {
  const json a = {{"type", "diffuse"}, {"reflectance", 0.2}}, b = {{"type", "diffuse"}, {"reflectance", 0.8}};
  const auto [status, d] = post("/api/slice", {{"bsdf", a}, {"compare", b}, {"size", 16}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_EQ(d["values_compare"].size(), 256u);
  for (size_t i = 0; i < 256; ++i) {
    EXPECT_NEAR(d["values"][i].get<double>(), 0.2 / kPi, 1e-6);
    EXPECT_NEAR(d["values_compare"][i].get<double>(), 0.8 / kPi, 1e-6);
  }
  // One scale for both: whole decades around 0.2/π = 0.064 and 0.8/π = 0.25.
  EXPECT_DOUBLE_EQ(d["lo"].get<double>(), 0.01);
  EXPECT_DOUBLE_EQ(d["hi"].get<double>(), 1);
  // A bad second material: the message of gonio slice --compare.
  const std::string bad = R"({"type":"roughconductor","alpha":-0.1,"material":"Au"})";
  const std::string png = (data_dir() / "compare.png").string();
  const auto cli = run_gonio({"slice", "--bsdf", a.dump(), "--compare", bad, "-o", png});
  ASSERT_EQ(cli.status, 2) << cli.err;
  const auto [s2, e] = post("/api/slice", {{"bsdf", a}, {"compare", json::parse(bad)}});
  EXPECT_EQ(s2, 400);
  EXPECT_EQ("gonio: " + e["error"].get<std::string>() + "\n", cli.err);
}

TEST_F(ExploreApi, SphereUnderAPointLightIsLambertsLaw) {
  // The light straight behind the camera, 5 from the centre: 4 from the sphere's nearest
  // point, intensity 16π, so E = 16π / 4² = π there and a Lambertian sphere of albedo ρ has
  // radiance ρ/π · E = ρ at the image centre (inverse-square law and Lambert's cosine law).
  const int n = 64;
  const auto [status, d] = post("/api/sphere", {{"bsdf", {{"type", "diffuse"}, {"reflectance", {0.25, 0.5, 0.75}}}},
                                                {"size", n}, {"spp", 16}, {"light_x", 0}, {"light_y", 0},
                                                {"environment", 0.3}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_EQ(d["width"], n);
  const std::vector<float> px = sphere_pixels(d);
  ASSERT_EQ(px.size(), size_t(n * n * 3));
  const double rho[3] = {0.25, 0.5, 0.75};
  for (int c = 0; c < 3; ++c) {
    double centre = 0;
    for (const int y : {n / 2 - 1, n / 2})
      for (const int x : {n / 2 - 1, n / 2}) centre += px[size_t((y * n + x) * 3 + c)] / 4.0;
    // Plus the environment's 0.3 reflected: ρ · 0.3 · (the visible sky's cosine-weighted
    // fraction, 1 at the nearest point, as nothing else is in the scene).
    EXPECT_NEAR(centre, rho[c] * (1 + 0.3), 0.02 * rho[c]) << c;
    EXPECT_NEAR(px[size_t(c)], 0.3, 1e-6);  // a corner sees the environment
  }
  const auto [bad, e] = post("/api/sphere", {{"bsdf", kLambert}, {"size", 4096}});
  EXPECT_EQ(bad, 400);
  EXPECT_NE(e["error"].get<std::string>().find("size"), std::string::npos);
}

TEST_F(ExploreApi, EvalAnswersWhatGonioEvalPrints) {
  const std::string m = R"({"type":"roughconductor","alpha":[0.1,0.3],"material":"Au"})";
  const json pairs = {{0, 0.5, 1, 0.3, 0, 1}, {0.2, -0.1, 0.7, -0.4, 0.2, 0.9}, {1, 0, 0.2, 0, 1, 0.3}};
  const auto c = client().Post("/api/eval", json({{"bsdf", json::parse(m)}, {"pairs", pairs}}).dump(),
                               "application/json");
  ASSERT_TRUE(c);
  ASSERT_EQ(c->status, 200) << c->body;
  std::string lines;
  for (const auto& p : pairs) {
    for (size_t i = 0; i < 6; ++i) lines += (i ? " " : "") + p[i].dump();
    lines += "\n";
  }
  const auto cli = run_gonio({"eval", "--bsdf", m}, lines);
  ASSERT_EQ(cli.status, 0) << cli.err;
  // The same numbers, printed the same way (%.9g): compare the text of each value.
  std::istringstream out(cli.out);
  std::string line, f_text = "[", pdf_text = "[";
  for (int i = 0; std::getline(out, line); ++i) {
    const std::regex form(R"(\{"f":(\[[^\]]*\]),"pdf":([^}]*)\})");
    std::smatch mm;
    ASSERT_TRUE(std::regex_match(line, mm, form)) << line;
    f_text += (i ? "," : "") + mm[1].str();
    pdf_text += (i ? "," : "") + mm[2].str();
  }
  EXPECT_EQ(c->body, "{\"f\":" + f_text + "],\"pdf\":" + pdf_text + "]}");
}

TEST_F(ExploreApi, ABadMaterialIs400WithTheCliMessage) {
  for (const std::string m : {R"({"type":"roughconductor","alpha":-0.1,"material":"Au"})",
                              R"({"type":"diffuse","reflectance":0.5,"colour":1})", R"({"type":"nosuch"})",
                              R"({"type":"diffuse",)"}) {
    const auto cli = run_gonio({"eval", "--bsdf", m}, "0 0 1 0 0 1\n");
    ASSERT_EQ(cli.status, 2) << m;
    std::string expected = cli.err.substr(std::string("gonio: ").size());
    expected.pop_back();  // the newline
    // The material as text (the JSON editor's case) and, when it parses, as an object.
    for (const char* path : {"/api/validate", "/api/lobe", "/api/slice", "/api/check"}) {
      const auto [status, d] = post(path, {{"bsdf", m}});
      EXPECT_EQ(status, 400) << path << " " << m;
      EXPECT_EQ(d["error"], expected) << path;
    }
    const json parsed = json::parse(m, nullptr, false);
    if (!parsed.is_discarded()) {
      const auto [status, d] = post("/api/albedo", {{"bsdf", parsed}});
      EXPECT_EQ(status, 400);
      EXPECT_EQ(d["error"], expected);
    }
  }
}

TEST_F(ExploreApi, MalformedRequestsAre400WithOneLine) {
  auto c = client();
  for (const std::string body : {"", "not json", "[1,2]", R"({"theta_i":30})",
                                 R"({"bsdf":{"type":"diffuse"},"theta_i":95})",
                                 R"({"bsdf":{"type":"diffuse"},"count":100000})",
                                 R"({"bsdf":{"type":"diffuse"},"count":2.5})"}) {
    const auto res = c.Post("/api/lobe", body, "application/json");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << body;
    const json d = json::parse(res->body, nullptr, false);
    ASSERT_TRUE(d.is_object()) << res->body;
    const std::string e = d["error"];
    EXPECT_FALSE(e.empty());
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  const auto zero = post("/api/eval", {{"bsdf", kLambert}, {"pairs", {{0, 0, 0, 0, 0, 1}}}});
  EXPECT_EQ(zero.first, 400);
  EXPECT_EQ(zero.second["error"], "pairs[0]: wo is a zero vector");
}

TEST_F(ExploreApi, CheckIsTheValidatorsTable) {
  const auto [status, d] = post("/api/check", {{"bsdf", kLambert}});
  ASSERT_EQ(status, 200) << d;
  EXPECT_TRUE(d["pass"].get<bool>());
  std::vector<std::string> names;
  for (const auto& p : d["properties"]) names.push_back(p["name"]);
  // SPEC §3's properties, in its order.
  EXPECT_EQ(names, (std::vector<std::string>{"finite", "reciprocity", "energy", "chi2", "pdf_integral", "consistency",
                                             "isotropy", "linearity", "weights"}));
}

TEST_F(ExploreApi, RegistryListsEveryTypeWithAValidExample) {
  auto c = client();
  const auto res = c.Get("/api/materials");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  const json d = json::parse(res->body);
  // The types of `gonio materials`, in its order.
  const auto cli = run_gonio({"materials"});
  std::istringstream list(cli.out);
  std::vector<std::string> expected, got;
  for (std::string line; std::getline(list, line);) expected.push_back(line.substr(0, line.find(' ')));
  for (const auto& t : d["types"]) got.push_back(t["name"]);
  EXPECT_EQ(got, expected);
  for (const auto& t : d["types"]) {
    if (t["name"] == "measured" || t["name"] == "rgl") continue;  // their examples name a file of --data
    const auto [status, v] = post("/api/validate", {{"bsdf", t["example"]}});
    EXPECT_EQ(status, 200) << t["name"] << ": " << v;
  }
}

TEST_F(ExploreApi, FilesOnlyFromData) {
  {
    std::ofstream(data_dir() / "short.binary") << "not a MERL table";
  }
  fs::create_symlink("/etc/hostname", data_dir() / "out.binary");
  const auto measured = [](const std::string& file) { return json{{"type", "measured"}, {"file", file}}; };
  for (const std::string bad : {"/etc/passwd", "../short.binary", "sub/../../x", "out.binary", "missing.binary"}) {
    const auto [status, d] = post("/api/validate", {{"bsdf", measured(bad)}});
    EXPECT_EQ(status, 400) << bad;
    EXPECT_NE(d["error"].get<std::string>().find("--data"), std::string::npos) << d;
  }
  // A spectrum file is a file too.
  const json spectrum = {{"type", "diffuse"}, {"reflectance", {{"spectrum", "/etc/passwd"}}}};
  EXPECT_EQ(post("/api/validate", {{"bsdf", spectrum}}).first, 400);
  // A file inside --data reaches the MERL reader, whose own message comes back.
  const auto [status, d] = post("/api/validate", {{"bsdf", measured("short.binary")}});
  EXPECT_EQ(status, 400);
  EXPECT_EQ(d["error"].get<std::string>().find("--data"), std::string::npos) << d;
  auto c = client();
  const auto list = c.Get("/api/data");
  ASSERT_TRUE(list);
  EXPECT_EQ(json::parse(list->body)["files"], json::array({"short.binary"}));  // not the symlink
}

// gonio fit from the page: a table tabulated from a known rough gold (gonio tabulate)
// gives back its roughness.
TEST_F(ExploreApi, FitRecoversTheModelOfATabulatedTable) {
  const std::string table = (data_dir() / "gold.binary").string();
  const auto tab = run_gonio({"tabulate", "--bsdf", R"({"type":"roughconductor","alpha":0.15,"material":"Au"})",
                              "-o", table});
  ASSERT_EQ(tab.status, 0) << tab.err;
  const auto [status, d] = post("/api/fit", {{"file", "gold.binary"}, {"model", "roughconductor"}, {"stride", 6}});
  ASSERT_EQ(status, 200) << d;
  EXPECT_NEAR(d["material"]["alpha"].get<double>(), 0.15, 0.0015) << d;
  EXPECT_EQ(d["measured"], json({{"type", "measured"}, {"file", "gold.binary"}}));
  // The fitted material is valid input to every view.
  EXPECT_EQ(post("/api/validate", {{"bsdf", d["material"]}}).first, 200);
  // The measured one too, read once and kept: the second slice is much faster.
  const json measured = {{"bsdf", d["measured"]}, {"size", 32}};
  EXPECT_EQ(post("/api/slice", measured).first, 200);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(post("/api/slice", measured).first, 200);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.05);
  // Files outside --data and unknown models are refused.
  EXPECT_EQ(post("/api/fit", {{"file", "../gold.binary"}, {"model", "roughconductor"}}).first, 400);
  const auto [s2, e] = post("/api/fit", {{"file", "gold.binary"}, {"model", "nosuch"}});
  EXPECT_EQ(s2, 400);
  EXPECT_NE(e["error"].get<std::string>().find("nosuch"), std::string::npos) << e;
  std::filesystem::remove(table);
}

TEST_F(ExploreApi, RefusesOtherHostsAndOrigins) {
  auto c = client();
  const auto get = [&](const httplib::Headers& h) {
    const auto r = c.Get("/api/materials", h);
    return r ? r->status : -1;
  };
  EXPECT_EQ(get({}), 200);
  EXPECT_EQ(get({{"Host", "localhost:9999"}}), 200);  // an SSH tunnel's port
  EXPECT_EQ(get({{"Host", "[::1]:8080"}}), 200);
  EXPECT_EQ(get({{"Host", "evil.example"}}), 403);
  EXPECT_EQ(get({{"Host", "127.0.0.1.evil.example"}}), 403);
  EXPECT_EQ(get({{"Origin", "http://127.0.0.1:1234"}}), 200);
  EXPECT_EQ(get({{"Origin", "http://evil.example"}}), 403);
  EXPECT_EQ(get({{"Origin", "null"}}), 403);
  const auto r = c.Post("/api/lobe", {{"Origin", "https://attacker.example"}}, json({{"bsdf", kLambert}}).dump(),
                        "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403);
}

// Issue 36: stale work is cancelled when a newer request arrives. A long request (seconds
// of work) of one page and view, then a short one of the same: the first stops with 409
// soon after, the second is answered; another view of the same page is left alone.
TEST_F(ExploreApi, ANewerRequestOfTheSameViewStopsTheOlder) {
  const json layered = {{"type", "layered"}, {"top", {{"type", "roughdielectric"}, {"alpha", 0.1}}},
                        {"bottom", {{"type", "diffuse"}}}};
  for (const auto& [endpoint, slow, quick] : std::vector<std::tuple<const char*, json, json>>{
           {"/api/albedo", {{"count", 91}, {"samples", 1 << 16}}, {{"count", 2}, {"samples", 16}}},
           {"/api/sphere", {{"size", 192}, {"spp", 64}}, {{"size", 16}, {"spp", 1}}}}) {
    const char* path = endpoint;  // a plain variable: lambdas may not capture a structured binding (C++20 in clang 14)
    json slow_body = slow, quick_body = quick;
    slow_body["bsdf"] = layered;
    quick_body["bsdf"] = layered;
    const httplib::Headers view = {{"X-Gonio-Session", "test-page"}, {"X-Gonio-View", "v"}};
    const httplib::Headers other_view = {{"X-Gonio-Session", "test-page"}, {"X-Gonio-View", "w"}};
    int first = 0;
    double first_seconds = 0;
    std::thread older([&] {
      auto c = client();
      const auto start = std::chrono::steady_clock::now();
      const auto r = c.Post(path, view, slow_body.dump(), "application/json");
      first_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      first = r ? r->status : -1;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    auto c = client();
    const auto bystander = c.Post(path, other_view, quick_body.dump(), "application/json");
    const auto newer = c.Post(path, view, quick_body.dump(), "application/json");
    older.join();
    ASSERT_TRUE(newer);
    EXPECT_EQ(newer->status, 200) << path;
    ASSERT_TRUE(bystander);
    EXPECT_EQ(bystander->status, 200) << path;
    EXPECT_EQ(first, 409) << path;
    EXPECT_LT(first_seconds, 2.0) << path;  // whole, it takes several seconds
  }
}

// Raw bytes over a socket to the server: what comes back within `timeout_ms` (until it
// closes the connection).
std::string raw_exchange(int port, const std::string& bytes, int timeout_ms = 3000) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(std::uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return "connect failed";
  }
  (void)::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
  ::shutdown(fd, SHUT_WR);
  std::string got;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, int(left.count())) <= 0) break;
    char buf[4096];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    got.append(buf, size_t(n));
  }
  ::close(fd);
  return got;
}

// Malformed HTTP never crashes or hangs the server: each is answered with an error or a
// closed connection within seconds, and the server answers normally afterwards.
TEST_F(ExploreApi, MalformedHttpIsRefusedAndTheServerGoesOn) {
  const std::string host = "Host: 127.0.0.1\r\n";
  // {request, whether it must be refused}: httplib may pass over a header line without a
  // colon, or a request with no Host, and answer; it must not answer the others.
  const std::vector<std::pair<std::string, bool>> cases = {
      {std::string("\x00\xff\xfe garbage\r\n\r\n", 15), true},
      {"GET / HTTP/1.1\r\n" + host + "NoColonHere\r\n\r\n", false},
      {"GET /" + std::string(100000, 'a') + " HTTP/1.1\r\n" + host + "\r\n", true},
      {"GET / HTTP/1.1\r\n" + host + "X-Big: " + std::string(200000, 'b') + "\r\n\r\n", true},
      {"POST /api/lobe HTTP/1.1\r\n" + host + "Content-Length: abc\r\n\r\n{}", true},
      {"POST /api/lobe HTTP/1.1\r\n" + host + "Content-Length: -5\r\n\r\n{}", true},
      {"POST /api/lobe HTTP/1.1\r\n" + host + "Content-Length: 1000\r\n\r\n{\"bsdf\":", true},  // cut short
      {"POST /api/lobe HTTP/1.1\r\n" + host + "Content-Length: 99999999999\r\n\r\n", true},
      {"POST /api/lobe HTTP/1.1\r\n" + host + "Transfer-Encoding: chunked\r\n\r\nzz\r\n", true},
      {"GET / HTTP/9.9\r\n\r\n", false},
      {"\r\n\r\n\r\n", false},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    const std::string answer = raw_exchange(server()->port(), cases[i].first);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 2.9) << "case " << i << " hung";
    if (cases[i].second) {
      EXPECT_EQ(answer.find("HTTP/1.1 200"), std::string::npos) << "case " << i << ": " << answer.substr(0, 80);
    }
    auto c = client();
    const auto ok = c.Get("/api/materials");
    ASSERT_TRUE(ok) << "after case " << i;
    EXPECT_EQ(ok->status, 200);
  }
}

// Issue 36: 20 concurrent sessions are served without an error. Each is a keep-alive
// client (a browser tab) asking every view in turn, a few rounds, all at once.
TEST_F(ExploreApi, TwentyConcurrentSessionsAllAnswered) {
  constexpr int kSessions = 20, kRounds = 3;
  std::atomic<int> ok{0}, failed{0};
  std::vector<std::thread> sessions;
  for (int s = 0; s < kSessions; ++s) {
    sessions.emplace_back([&, s] {
      auto c = client();
      c.set_keep_alive(true);
      c.set_read_timeout(30);
      const json m = {{"type", "roughconductor"}, {"alpha", 0.05 + 0.01 * s}, {"material", "Au"}};
      for (int r = 0; r < kRounds; ++r) {
        for (const auto& [path, extra] : std::vector<std::pair<const char*, json>>{
                 {"/api/validate", json::object()}, {"/api/lobe", {{"theta_i", 10 * r}}},
                 {"/api/slice", {{"size", 64}}}, {"/api/albedo", {{"count", 10}, {"samples", 1024}}},
                 {"/api/fresnel", json::object()}, {"/api/sphere", {{"size", 32}}}}) {
          json body = extra;
          body["bsdf"] = m;
          const auto res = c.Post(path, body.dump(), "application/json");
          if (res && res->status == 200) {
            ++ok;
          } else {
            ++failed;
            ADD_FAILURE() << path << ": " << (res ? std::to_string(res->status) + " " + res->body
                                                  : httplib::to_string(res.error()));
          }
        }
      }
    });
  }
  for (auto& t : sessions) t.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(ok.load(), kSessions * kRounds * 6);
}

TEST_F(ExploreApi, ThePageIsServedAndFetchesNothingOutside) {
  auto c = client();
  const auto index = c.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("<canvas id=\"lobe\""), std::string::npos);
  EXPECT_NE(index->get_header_value("Content-Security-Policy").find("default-src 'self'"), std::string::npos);
  ASSERT_FALSE(gonio::explore::web_files().empty());
  const std::regex external(R"(https?://|//[a-z0-9-]+\.[a-z]{2,}/|\bimport\s*\(|@import)", std::regex::icase);
  for (const auto& f : gonio::explore::web_files()) {
    const auto res = c.Get(("/" + std::string(f.name)).c_str());
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << f.name;
    EXPECT_EQ(res->body, std::string(f.data));
    EXPECT_FALSE(std::regex_search(res->body, external)) << f.name << " names an outside URL";
  }
  const auto missing = c.Get("/../CMakeLists.txt");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
}

}  // namespace

// ---- issue 56: limits, the Host guard on the wire, text ------------------------------

// A raw connection that stays open: bytes sent, the answer read until `needle` shows or
// the time passes.
class RawConnection {
 public:
  explicit RawConnection(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~RawConnection() { close(); }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  bool connected() const { return connected_; }
  void send(const std::string& bytes) const { (void)::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }
  // What arrived until `count` occurrences of `needle` (or the server closed, or the time passed).
  std::string read_until(const std::string& needle, int count, int timeout_ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    const auto occurrences = [&] {
      int n = 0;
      for (size_t at = got_.find(needle); at != std::string::npos; at = got_.find(needle, at + 1)) ++n;
      return n;
    };
    while (occurrences() < count) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || ::poll(&p, 1, int(left.count())) <= 0) break;
      char buf[4096];
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) break;
      got_.append(buf, size_t(n));
    }
    return got_;
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
  bool connected_ = false;
  std::string got_;
};

std::string post_request(const std::string& path, const std::string& body, const std::string& extra_headers = "") {
  return "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n" + extra_headers +
         "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

// Whether `s` is valid UTF-8, by the RFC 3629 §4 table written out here.
bool valid_utf8(const std::string& s) {
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    size_t n = c < 0x80 ? 1 : (c >= 0xC2 && c <= 0xDF) ? 2 : (c >= 0xE0 && c <= 0xEF) ? 3 : (c >= 0xF0 && c <= 0xF4) ? 4 : 0;
    if (n == 0 || i + n > s.size()) return false;
    const auto b1 = static_cast<unsigned char>(n > 1 ? s[i + 1] : 0x80);
    if (n > 1) {
      const unsigned char lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80, hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
      if (b1 < lo || b1 > hi) return false;
    }
    for (size_t k = 2; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    i += n;
  }
  return true;
}

// docs/explore.md promises 413 for a body over 16 MiB (dropped as it arrives, never
// stored): a valid lobe request padded past the limit is refused, one at the limit is
// answered.
TEST_F(ExploreApi, BodyOver16MiBIs413) {
  for (const size_t size : {size_t(16) << 20, (size_t(16) << 20) + 1}) {
    std::string body = json({{"bsdf", kLambert}, {"count", 3}, {"pad", ""}}).dump();
    body.insert(body.size() - 2, size - body.size(), 'x');  // inside the pad's quotes
    ASSERT_EQ(body.size(), size);
    RawConnection c(server()->port());
    ASSERT_TRUE(c.connected());
    c.send(post_request("/api/lobe", body));
    const std::string answer = c.read_until("\r\n", 1, 5000);
    EXPECT_EQ(answer.rfind(size > (size_t(16) << 20) ? "HTTP/1.1 413" : "HTTP/1.1 200", 0), 0u)
        << size << ": " << answer.substr(0, 80);
  }
}

// The authority parser alone (RFC 9110 §7.2, RFC 3986 §3.2.2): the host of host[:port],
// nothing for anything else.
TEST(ExploreHost, AuthorityIsHostAndOptionalPortOnly) {
  using gonio::explore::authority_host;
  EXPECT_EQ(authority_host("localhost:8080"), "localhost");
  EXPECT_EQ(authority_host("LocalHost"), "localhost");
  EXPECT_EQ(authority_host("[::1]:80"), "[::1]");
  EXPECT_EQ(authority_host("127.0.0.1:"), "127.0.0.1");  // RFC 3986: port = *DIGIT
  for (const char* bad : {"[::1].evil.com", "[::1]evil", "[::1]:80.evil.com", "localhost@evil.com",
                          "evil.com@localhost", "localhost/x", "localhost:80x", "localhost:123456", "", ":80",
                          "[]", "[::1", "local host", "[::1%eth0]", "localhost:8080:1"})
    EXPECT_FALSE(authority_host(bad)) << bad;
}

// The Host guard on the wire, without httplib's client in the way: a rebinding page's
// Host, a Host that only starts like this server's, two Host headers, and Origins that
// are empty, a look-alike or carry a path are all refused; the registry is not sent.
TEST_F(ExploreApi, HostAndOriginGuardOnTheWire) {
  const auto status_of = [&](const std::string& headers) {
    const std::string answer =
        raw_exchange(server()->port(), "GET /api/materials HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n");
    EXPECT_EQ(answer.find("\"types\""), std::string::npos) << headers;
    return answer.substr(0, 12);
  };
  EXPECT_EQ(status_of("Host: attacker.example\r\n"), "HTTP/1.1 403");
  EXPECT_EQ(status_of("Host: [::1].evil.com\r\n"), "HTTP/1.1 400");
  EXPECT_EQ(status_of("Host: localhost@evil.com\r\n"), "HTTP/1.1 400");
  EXPECT_EQ(status_of("Host: 127.0.0.1\r\nHost: evil.example\r\n"), "HTTP/1.1 400");
  EXPECT_EQ(status_of("Host: 127.0.0.1\r\nOrigin: \r\n"), "HTTP/1.1 403");
  EXPECT_EQ(status_of("Host: 127.0.0.1\r\nOrigin: http://[::1].evil.com\r\n"), "HTTP/1.1 403");
  EXPECT_EQ(status_of("Host: 127.0.0.1\r\nOrigin: http://localhost:80/x\r\n"), "HTTP/1.1 403");
  EXPECT_EQ(status_of("Host: 127.0.0.1\r\nOrigin: http://localhost\r\nOrigin: http://evil.example\r\n"),
            "HTTP/1.1 403");
  // The same request with this server's names is answered.
  const std::string ok = raw_exchange(server()->port(), "GET /api/materials HTTP/1.1\r\nHost: [::1]:1\r\n"
                                                        "Origin: HTTP://LocalHost:1\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(ok.rfind("HTTP/1.1 200", 0), 0u) << ok.substr(0, 80);
}

// Error messages that quote invalid UTF-8 (a lone byte of a two-byte character in
// nlohmann's "last read", an overlong "%c0%ae" path) are 400 and 404 with the bytes
// escaped, not 500s; excerpts are cut between characters.
TEST_F(ExploreApi, MessagesQuotingInvalidUtf8Are4xxAndValidUtf8) {
  RawConnection c(server()->port());
  ASSERT_TRUE(c.connected());
  c.send(post_request("/api/validate", "{\"bsdf\": \"\xc3\xbf\"}", "Connection: close\r\n"));
  const std::string answer = c.read_until("}", 1, 3000);
  EXPECT_EQ(answer.rfind("HTTP/1.1 400", 0), 0u) << answer;
  const size_t body = answer.find("\r\n\r\n");
  ASSERT_NE(body, std::string::npos);
  const json d = json::parse(answer.substr(body + 4), nullptr, false);
  ASSERT_TRUE(d.is_object()) << answer;
  const std::string e = d["error"];
  EXPECT_TRUE(valid_utf8(e)) << e;
  EXPECT_NE(e.find("\\xc3"), std::string::npos) << e;

  const std::string page = raw_exchange(server()->port(), "GET /%c0%ae HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(page.rfind("HTTP/1.1 404", 0), 0u) << page.substr(0, 80);
  EXPECT_NE(page.find("\\\\xc0\\\\xae"), std::string::npos) << page;  // "\xc0\xae" in JSON

  // A long value of two-byte characters, cut for the message: whole characters only.
  std::string name = "a";  // then the 57th byte of the excerpt is the first of an é
  for (int i = 0; i < 40; ++i) name += "\xc3\xa9";
  const auto [status, v] = post("/api/lobe", {{"bsdf", kLambert}, {"mode", name}});
  EXPECT_EQ(status, 400);
  const std::string m = v["error"];
  EXPECT_TRUE(valid_utf8(m)) << m;
  EXPECT_NE(m.find("..."), std::string::npos) << m;
}

// /api/sphere's counts are integers as every other endpoint's.
TEST_F(ExploreApi, SphereRefusesAFractionalSize) {
  for (const char* key : {"size", "spp", "seed"}) {
    const auto [status, d] = post("/api/sphere", {{"bsdf", kLambert}, {key, 16.5}});
    EXPECT_EQ(status, 400) << key;
    EXPECT_NE(d["error"].get<std::string>().find(key), std::string::npos) << d;
  }
  EXPECT_EQ(post("/api/sphere", {{"bsdf", kLambert}, {"size", 16}}).first, 200);
}

// Requests pipelined on one connection are all answered, in order.
TEST_F(ExploreApi, PipelinedRequestsAreAllAnswered) {
  RawConnection c(server()->port());
  ASSERT_TRUE(c.connected());
  const std::string get = "GET /api/data HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  c.send(get + get + post_request("/api/validate", json({{"bsdf", kLambert}}).dump()));
  const std::string answer = c.read_until("\"valid\":true", 1, 3000);
  size_t n = 0;
  for (size_t at = answer.find("HTTP/1.1 200"); at != std::string::npos; at = answer.find("HTTP/1.1 200", at + 1)) ++n;
  EXPECT_EQ(n, 3u) << answer;
  EXPECT_NE(answer.find("\"valid\":true"), std::string::npos);
}

// The work a request implies is bounded before it starts: a layered material with the
// largest walks (in range: max_depth 10000, samples 64: 1.28e6 steps an evaluation) is
// refused by the albedo, the validation, the sphere and the slice with one line naming
// the estimate (hours of work otherwise).
TEST_F(ExploreApi, LayeredWorkBeyondTheBoundIsRefusedUpFront) {
  const json heavy = {{"type", "layered"},
                      {"top", {{"type", "roughdielectric"}, {"alpha", 0.1}}},
                      {"bottom", {{"type", "diffuse"}}},
                      {"albedo", 1},
                      {"thickness", 1e4},
                      {"max_depth", 10000},
                      {"samples", 64}};
  for (const auto& [path, extra] : std::vector<std::pair<const char*, json>>{
           {"/api/albedo", {{"samples", 4096}}}, {"/api/check", json::object()}, {"/api/sphere", {{"size", 64}}},
           {"/api/slice", {{"size", 128}}}}) {
    json body = extra;
    body["bsdf"] = heavy;
    const auto start = std::chrono::steady_clock::now();
    const auto [status, d] = post(path, body);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << path;
    EXPECT_EQ(status, 400) << path << " " << d;
    EXPECT_NE(d["error"].get<std::string>().find("walk steps"), std::string::npos) << d;
  }
  // The same material with a short walk is computed.
  json light = heavy;
  light["max_depth"] = 100;
  light["samples"] = 1;
  EXPECT_EQ(post("/api/albedo", {{"bsdf", light}, {"count", 3}, {"samples", 64}}).first, 200);
}

// Heavy clients cannot hold the server: 40 validations asked at once get one running, a
// few waiting and 429s for the rest at once, and 40 idle connections besides, while a
// light request is answered within a second; when the clients leave, the validations
// stop and the next one is answered.
TEST_F(ExploreApi, ManyValidationsAndIdleConnectionsLeaveTheServerResponsive) {
  // Seconds of validation, each property well under one.
  const json gold = {{"type", "roughconductor"}, {"alpha", 0.3}, {"material", "Au"}};
  const std::string check = post_request("/api/check", json({{"bsdf", gold}}).dump());
  std::vector<std::unique_ptr<RawConnection>> heavy, idle;
  for (int i = 0; i < 40; ++i) {
    heavy.push_back(std::make_unique<RawConnection>(server()->port()));
    heavy.back()->send(check);
  }
  for (int i = 0; i < 40; ++i) idle.push_back(std::make_unique<RawConnection>(server()->port()));  // say nothing
  int refused = 0;
  for (auto& h : heavy) refused += h->read_until("HTTP/1.1 429", 1, 100).find("HTTP/1.1 429") != std::string::npos;
  EXPECT_GE(refused, 30);
  const auto start = std::chrono::steady_clock::now();
  auto c = client();
  const auto light = c.Get("/api/materials");
  ASSERT_TRUE(light);
  EXPECT_EQ(light->status, 200);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  heavy.clear();
  idle.clear();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the watchdog's look and the waiters' poll
  const auto seconds_of_check = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    const auto [status, d] = post("/api/check", {{"bsdf", kLambert}});
    EXPECT_EQ(status, 200) << d;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // Against the same check on the quiet server (not a fixed time: a sanitizer build runs
  // the validator several times slower): had the heavy validations not stopped, this one
  // would wait for each of them, seconds of gold each.
  const double after_flood = seconds_of_check(), quiet = seconds_of_check();
  EXPECT_LT(after_flood, 1.5 * quiet + 1.0) << "quiet: " << quiet << " s";
}

// The CPU time of this process so far, in seconds.
double process_cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Work whose client has closed the connection stops at its next step (an angle of the
// albedo, a tenth of a second here) instead of running its ten seconds to the end.
TEST_F(ExploreApi, WorkStopsWhenTheClientLeaves) {
  const json body = {{"bsdf", {{"type", "roughconductor"}, {"alpha", 0.3}, {"material", "Au"}}},
                     {"count", 91},
                     {"samples", 1 << 20}};
  const double quiet = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_LT(process_cpu_seconds() - quiet, 0.05) << "work of an earlier test is still running";
  RawConnection c(server()->port());
  ASSERT_TRUE(c.connected());
  c.send(post_request("/api/albedo", body.dump()));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double working = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_GT(process_cpu_seconds() - working, 0.05);  // it is at work
  c.close();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  const double after = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_LT(process_cpu_seconds() - after, 0.05);  // and then it is not
}

// A server with a short time limit per request: work past it stops at its next step
// with a 400 that names the limit.
TEST(ExploreLimits, WorkPastTheTimeLimitStopsWith400) {
  gonio::explore::ServerOptions o;
  o.port = 0;
  o.request_seconds = 0.3;
  gonio::explore::Server server(o);
  server.bind();
  std::thread serving([&] { server.run(); });
  httplib::Client c("127.0.0.1", server.port());
  c.set_read_timeout(60);
  // 91 angles of 2^20 samples of a rough conductor: about ten seconds of work.
  const json body = {{"bsdf", {{"type", "roughconductor"}, {"alpha", 0.3}, {"material", "Au"}}},
                     {"count", 91},
                     {"samples", 1 << 20}};
  const auto start = std::chrono::steady_clock::now();
  const auto r = c.Post("/api/albedo", body.dump(), "application/json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_NE(r->body.find("time limit"), std::string::npos) << r->body;
  EXPECT_LT(seconds, 1.5);
  server.stop();
  serving.join();
}

// Issue 55 §5: an OpenPBR material with a coat has an interface, the coat's (coat_ior);
// without a coat, the base dielectric's (specular_ior): R(0°) = ((n − 1)/(n + 1))².
TEST_F(ExploreApi, FresnelOfACoatIsTheCoatsInterface) {
  for (const auto& [m, source, n] : std::vector<std::tuple<json, std::string, double>>{
           {{{"type", "openpbr"}, {"coat_weight", 1}, {"coat_ior", 1.7}}, "coat_ior", 1.7},
           {{{"type", "openpbr"}, {"specular_ior", 1.4}}, "specular_ior", 1.4}}) {
    const auto [status, d] = post("/api/fresnel", {{"bsdf", m}, {"count", 2}});
    ASSERT_EQ(status, 200) << d;
    ASSERT_EQ(d["interface"], source) << d;
    EXPECT_NEAR(d["channels"][0]["outside"]["R"][0].get<double>(), std::pow((n - 1) / (n + 1), 2), 1e-12) << d;
  }
}

// Issue 55 §5: the plane-of-incidence lobe of a material that transmits shows what it
// transmits: a nearly smooth glass's f below the surface peaks at Snell's refracted
// direction, θt = asin(sin θi / η) on the far side; an opaque material has none.
TEST_F(ExploreApi, LobeOfAGlassShowsItsTransmission) {
  const json glass = {{"type", "roughdielectric"}, {"alpha", 0.03}, {"eta", 1.5}};
  const auto [status, d] = post("/api/lobe", {{"bsdf", glass}, {"theta_i", 40}, {"count", 361}});
  ASSERT_EQ(status, 200) << d;
  ASSERT_TRUE(d["transmission"].get<bool>());
  ASSERT_EQ(d["f_t"].size(), 361u);
  ASSERT_EQ(d["f_cos_t"].size(), 361u);
  size_t peak = 0;
  for (size_t i = 0; i < 361; ++i)
    if (d["f_t"][i][1].get<double>() > d["f_t"][peak][1].get<double>()) peak = i;
  const double theta_t = std::asin(std::sin(40 * kPi / 180) / 1.5) * 180 / kPi;  // 25.37°
  EXPECT_NEAR(d["theta_o"][peak].get<double>(), -theta_t, 1.5) << d["theta_o"][peak];
  EXPECT_GT(d["f_t"][peak][1].get<double>(), 0);
  const auto opaque = post("/api/lobe", {{"bsdf", kLambert}, {"count", 3}});
  EXPECT_FALSE(opaque.second["transmission"].get<bool>());
  EXPECT_FALSE(opaque.second.contains("f_t"));
}
