// gonio_adversarial: the adversarial sweep of issue 9 (tools/adversarial_sweep.h says what
// is drawn and what fails). Every extreme material gets the same number of draws; one
// line per material, then the totals. Exit 0 when no call failed, 1 otherwise.
//
//   build/bin/gonio_adversarial [--calls N] [--seed S] [--only SUBSTRING]
// N is the total number of BxDF calls (default 1e8), split evenly over the materials.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "adversarial_sweep.h"

int main(int argc, char** argv) {
  double calls = 1e8;
  std::uint64_t seed = 1;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--calls") && has_value) calls = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && has_value) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--only") && has_value) only = argv[++i];
    else {
      std::fprintf(stderr, "usage: gonio_adversarial [--calls N] [--seed S] [--only SUBSTRING]\n");
      return 2;
    }
  }
  if (!(calls >= 1 && calls <= 1e15)) {
    std::fprintf(stderr, "gonio_adversarial: --calls must be in [1, 1e15]\n");
    return 2;
  }
  std::vector<std::string> materials;
  for (const std::string& m : gonio::adversarial::extreme_materials())
    if (only.empty() || m.find(only) != std::string::npos) materials.push_back(m);
  if (materials.empty()) {
    std::fprintf(stderr, "gonio_adversarial: no material matches --only %s\n", only.c_str());
    return 2;
  }
  // 6 to 10 calls per draw (f and pdf at the sampled direction only for non-delta
  // samples, none after a failed sample): 6 makes the total at least N.
  const auto draws = static_cast<std::uint64_t>(calls / 6 / double(materials.size())) + 1;
  const auto start = std::chrono::steady_clock::now();
  gonio::adversarial::Tally total;
  int failed_materials = 0;
  for (size_t k = 0; k < materials.size(); ++k) {
    gonio::BxDF m;
    try {
      m = gonio::parse_material(materials[k], "sweep");
    } catch (const gonio::InputError& e) {
      std::printf("REJECTED %s: %s\n", materials[k].c_str(), e.what());
      ++failed_materials;
      continue;
    }
    const auto t = gonio::adversarial::sweep(m, draws, seed * 1000003 + k);
    total.calls += t.calls;
    total.value += t.value;
    total.agree += t.agree;
    total.weight += t.weight;
    total.max_weight = std::max(total.max_weight, t.max_weight);
    failed_materials += t.failures() > 0;
    std::printf("%s %s calls %llu value %llu agree %llu weight %llu max_weight %.3g%s%s\n",
                t.failures() ? "FAIL" : "ok  ", materials[k].c_str(), (unsigned long long)t.calls,
                (unsigned long long)t.value, (unsigned long long)t.agree, (unsigned long long)t.weight, t.max_weight,
                t.failures() ? "\n     first: " : "", t.first_failure.c_str());
    std::fflush(stdout);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("total: %zu materials, %llu calls in %.1f s (%.3g calls/s); failures: value %llu, agree %llu, "
              "weight %llu; materials failing %d; largest weight %.3g\n",
              materials.size(), (unsigned long long)total.calls, seconds, double(total.calls) / seconds,
              (unsigned long long)total.value, (unsigned long long)total.agree, (unsigned long long)total.weight,
              failed_materials, total.max_weight);
  return failed_materials ? 1 : 0;
}
