// The grid of anisotropic albedo tables behind AnisotropicAlbedoBlend
// (gonio/bxdf/anisotropic_albedo.h): made on first use, kept for the process.

#include "gonio/bxdf/anisotropic_albedo.h"

#include <atomic>

namespace gonio {
namespace {

using Blend = AnisotropicAlbedoBlend;
constexpr int kDistributionTypes = 2;  // GGX, Beckmann
// Zero-initialised (static storage): a null entry is a node not made yet.
std::atomic<const AnisotropicAlbedo*> g_node_tables[kDistributionTypes][Blend::kNodes][Blend::kNodes];

// The node's value of α: 2^(lowest octave + i / nodes per octave).
Float node_alpha(int i) {
  return Float(std::exp2(double(Blend::kLowestOctave) + double(i) / Blend::kNodesPerOctave));
}

const AnisotropicAlbedo* node_table(MicrofacetType type, int ix, int iy) {
  std::atomic<const AnisotropicAlbedo*>& slot = g_node_tables[type == MicrofacetType::GGX ? 0 : 1][ix][iy];
  if (const AnisotropicAlbedo* t = slot.load(std::memory_order_acquire)) return t;
  MicrofacetDistribution d;
  d.type = type;
  d.alpha_x = node_alpha(ix);
  d.alpha_y = node_alpha(iy);
  std::unique_ptr<AnisotropicAlbedo> made = AnisotropicAlbedo::make(d);
  const AnisotropicAlbedo* expected = nullptr;
  // Another thread may have made the same node meanwhile: keep the first, drop ours.
  if (slot.compare_exchange_strong(expected, made.get(), std::memory_order_acq_rel)) return made.release();
  return expected;
}

// The grid coordinate of α (clamped to the grid) as a node index and the weight of the next.
void locate(Float alpha, int& i, Float& t) {
  const double u = (std::log2(std::max(double(alpha), 1e-30)) - Blend::kLowestOctave) * Blend::kNodesPerOctave;
  const double c = std::clamp(u, 0.0, double(Blend::kNodes - 1));
  i = std::min(int(c), Blend::kNodes - 2);
  t = Float(c - i);
}

}  // namespace

AnisotropicAlbedoBlend AnisotropicAlbedoBlend::at(const MicrofacetDistribution& d) {
  int ix = 0, iy = 0;
  Float tx = 0, ty = 0;
  locate(d.alpha_x, ix, tx);
  locate(d.alpha_y, iy, ty);
  Blend b;
  const Float w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  const int dx[4] = {0, 1, 0, 1}, dy[4] = {0, 0, 1, 1};
  for (size_t k = 0; k < 4; ++k) {
    // A node of weight 0 is not made (a roughness on a node reads one table), except the
    // first, which marks the blend active.
    if (!(w[k] > 0) && k > 0) continue;
    b.table[k] = node_table(d.type, ix + dx[k], iy + dy[k]);
    b.weight[k] = w[k];
    b.avg += w[k] * b.table[k]->average();
  }
  return b;
}

}  // namespace gonio
