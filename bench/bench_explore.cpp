// Server time per request of gonio explore's 2D views (issue 36: at most 30 ms each): the
// request the page sends after a slider moves, over HTTP to a server in this process on
// 127.0.0.1 (keep-alive, as a browser), and the same computation called directly (the
// difference is HTTP and JSON). docs/benchmarks.md has the figures.

#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "explore/server.h"

namespace {

using nlohmann::json;
int g_port = 0;

// The page's requests (src/explore/web/js/app.js): the view, its body beside the material.
struct View {
  const char* name;
  const char* path;
  json extra;
  std::string (*direct)(const std::string&, const gonio::explore::ApiContext&);
};

const std::vector<std::pair<const char*, json>>& materials() {
  static const std::vector<std::pair<const char*, json>> m = {
      {"diffuse", {{"type", "diffuse"}, {"reflectance", {0.8, 0.5, 0.3}}}},
      {"roughconductor", {{"type", "roughconductor"}, {"alpha", 0.2}, {"material", "Cu"}}},
      {"roughdielectric", {{"type", "roughdielectric"}, {"alpha", 0.2}, {"eta", 1.5}}},
      {"blend", {{"type", "blend"}, {"weight", 0.3}, {"bsdfs", {{{"type", "diffuse"}, {"reflectance", 0.7}},
                 {{"type", "roughconductor"}, {"alpha", 0.15}, {"material", "Au"}}}}}},
      {"layered", {{"type", "layered"}, {"top", {{"type", "roughdielectric"}, {"alpha", 0.1}, {"eta", 1.5}}},
                   {"bottom", {{"type", "diffuse"}, {"reflectance", {0.7, 0.2, 0.1}}}}}},
  };
  return m;
}

const std::vector<View>& views() {
  static const std::vector<View> v = {
      {"lobe", "/api/lobe", {{"theta_i", 30}, {"count", 181}}, &gonio::explore::api_lobe},
      {"lobe3d", "/api/lobe3d", {{"theta_i", 30}, {"count_theta", 24}, {"count_phi", 48}},
       &gonio::explore::api_lobe3d},
      {"slice", "/api/slice", {{"phi_d", 90}, {"size", 90}}, &gonio::explore::api_slice},
      // The page's first estimate (256 samples per angle), then its refinement (4,096).
      {"albedo256", "/api/albedo", {{"count", 19}, {"samples", 256}}, &gonio::explore::api_albedo},
      {"albedo", "/api/albedo", {{"count", 19}, {"samples", 4096}}, &gonio::explore::api_albedo},
      {"fresnel", "/api/fresnel", {{"count", 181}}, &gonio::explore::api_fresnel},
      {"slice_point", "/api/slice_point", {{"theta_h", 20}, {"theta_d", 30}, {"phi_d", 90}},
       &gonio::explore::api_slice_point},
      // The sphere's first image (1 sample per pixel), at the page's 128² and at 256².
      {"sphere128", "/api/sphere", {{"size", 128}, {"spp", 1}}, &gonio::explore::api_sphere},
      {"sphere256", "/api/sphere", {{"size", 256}, {"spp", 1}}, &gonio::explore::api_sphere},
  };
  return v;
}

void over_http(benchmark::State& state, std::string path, std::string body) {
  httplib::Client c("127.0.0.1", g_port);
  c.set_keep_alive(true);
  c.set_tcp_nodelay(true);  // as browsers do
  for (auto _ : state) {
    const auto r = c.Post(path.c_str(), body, "application/json");
    if (!r || r->status != 200) {
      state.SkipWithError(r ? r->body.c_str() : "no answer");
      break;
    }
    benchmark::DoNotOptimize(r->body.data());
  }
}

void direct(benchmark::State& state, std::string (*fn)(const std::string&, const gonio::explore::ApiContext&),
            std::string body) {
  const gonio::explore::ApiContext ctx;
  for (auto _ : state) benchmark::DoNotOptimize(fn(body, ctx));
}

}  // namespace

int main(int argc, char** argv) {
  gonio::explore::ServerOptions o;
  o.port = 0;
  gonio::explore::Server server(o);
  server.bind();
  g_port = server.port();
  std::thread serving([&] { server.run(); });
  // The five materials above, then every registry type's example (`example/TYPE`: the
  // material the page starts from when that type is chosen), without a --data directory
  // (an example naming a file is left out).
  std::vector<std::pair<std::string, json>> all(materials().begin(), materials().end());
  for (const json& t : json::parse(gonio::explore::api_materials())["types"]) {
    const std::string ex = t["example"].dump();
    if (ex.find("\"file\"") != std::string::npos || ex.find(".csv") != std::string::npos) continue;
    all.emplace_back("example_" + t["name"].get<std::string>(), t["example"]);
  }
  for (const auto& [mname, material] : all) {
    for (const View& v : views()) {
      json body = v.extra;
      body["bsdf"] = material;
      const std::string name = std::string(v.name) + "/" + mname;
      benchmark::RegisterBenchmark(("http/" + name).c_str(), over_http, std::string(v.path), body.dump())
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(("direct/" + name).c_str(), direct, v.direct, body.dump())
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  server.stop();
  serving.join();
  return 0;
}
