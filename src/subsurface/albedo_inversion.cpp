// The artist's albedo table (albedo_inversion.h).

#include "gonio/subsurface/albedo_inversion.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <thread>

#include "gonio/fresnel.h"
#include "slab_path.h"

namespace gonio {

SlabAlbedoTable::SlabAlbedoTable(const BxDF& boundary, Float eta, Float g) {
  entering_ = 1 - fresnel_dielectric(1.0, double(eta));
  // No absorption: σs = 1 (distances in mean free paths), so the walk's weight stays that
  // of the boundary and every path's events are counted.
  Medium m;
  m.sigma_s = Color(1);
  m.sigma_a = Color(0);
  m.g = g;
  constexpr std::uint64_t kBlock = kSlabBlock;
  const std::uint64_t blocks = kAlbedoTablePaths / kBlock;
  std::vector<std::vector<double>> sums(blocks, std::vector<double>(kAlbedoTableMaxSteps + 1, 0.0));
  auto run = [&](std::uint64_t b) {
    Pcg32 rng(0x5eed'a1be'd0ULL, b);  // fixed: the same table in every run
    for (std::uint64_t i = 0; i < kBlock; ++i) {
      WalkStats stats;
      Float r = -1;
      const Color c = detail::trace_slab_path(boundary, m, rng, r, stats, kAlbedoTableMaxSteps);
      if (r >= 0 && stats.steps <= kAlbedoTableMaxSteps) sums[b][stats.steps] += c.average();
    }
  };
  const unsigned threads = unsigned(std::min<std::uint64_t>(std::max(1u, std::thread::hardware_concurrency()), blocks));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (std::uint64_t b = t; b < blocks; b += threads) run(b);
    });
  for (std::uint64_t b = 0; b < blocks; b += threads) run(b);
  for (auto& th : pool) th.join();
  weight_.assign(kAlbedoTableMaxSteps + 1, 0.0);
  for (const auto& s : sums)  // in block order: deterministic
    for (size_t n = 0; n < s.size(); ++n) weight_[n] += s[n];
  for (double& w : weight_) w /= double(kAlbedoTablePaths);
}

double SlabAlbedoTable::albedo(double ssa) const {
  ssa = std::clamp(ssa, 0.0, 1.0);
  // Σ_n w_n ϖ^n by Horner's rule from the highest n.
  double s = 0;
  for (size_t n = weight_.size(); n-- > 0;) s = s * ssa + weight_[n];
  return entering_ > 0 ? s / entering_ : 0.0;
}

double SlabAlbedoTable::single_scattering_albedo(double target) const {
  if (!(target > 0)) return 0;
  if (target >= albedo(1)) return 1;
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (albedo(mid) < target ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

std::shared_ptr<const SlabAlbedoTable> SlabAlbedoTable::get(const BxDF& boundary, Float eta, Float g,
                                                            const std::string& key) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const SlabAlbedoTable>> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto table = std::make_shared<const SlabAlbedoTable>(boundary, eta, g);
  const std::lock_guard<std::mutex> lock(mutex);
  return cache.try_emplace(key, std::move(table)).first->second;
}

}  // namespace gonio
