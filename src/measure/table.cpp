// The MERL table mode of include/gonio/measure/table.h.
#include "gonio/measure/table.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "gonio/math/constants.h"
#include "gonio/measure/merl_bins.h"
#include "waves.h"

namespace gonio::measure {
namespace {

constexpr int kBands = 90;
// A θh slab: the entries of one θh index, contiguous in MerlTable::index.
constexpr std::size_t kSlabEntries = std::size_t(MerlTable::kThetaD) * MerlTable::kPhiD;
constexpr int kSlabs = MerlTable::kThetaH;

// A zeroed array for the table's accumulators (tens of MB), 2 MiB-aligned and marked for
// transparent huge pages where the system has them (madvise; the default "madvise" mode
// of many Linux systems gives none otherwise): the first touch of a 4 KiB page is a page
// fault, and the 76 MB of sums and counts cost about 0.1 µs per ray of a 2 M-ray table
// on the measuring machine (docs/benchmarks.md). Contents are the same either way.
template <typename T>
class ZeroedArray {
 public:
  explicit ZeroedArray(std::size_t n) {
    constexpr std::size_t kAlign = std::size_t(2) << 20;
    bytes_ = (n * sizeof(T) + kAlign - 1) / kAlign * kAlign;
    p_ = static_cast<T*>(std::aligned_alloc(kAlign, bytes_));
    if (!p_) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
    madvise(p_, bytes_, MADV_HUGEPAGE);  // advice only: ignored where unsupported
#endif
    std::memset(static_cast<void*>(p_), 0, bytes_);
  }
  ~ZeroedArray() { std::free(p_); }
  ZeroedArray(const ZeroedArray&) = delete;
  ZeroedArray& operator=(const ZeroedArray&) = delete;
  T& operator[](std::size_t i) { return p_[i]; }
  const T& operator[](std::size_t i) const { return p_[i]; }

 private:
  T* p_ = nullptr;
  std::size_t bytes_ = 0;
};

// The incidences (table.h): with probability 1/2 uniform on the hemisphere, else in one of
// the 90 one-degree bands of θi chosen uniformly, uniform in solid angle within it. Both
// are uniform in solid angle within a band, so p(ωi) is constant on band b:
//   p_b = 1/2 · 1/(2π) + 1/2 · 1/90 · 1/Ω_b,  Ω_b = 2π (cos b° − cos (b+1)°).
class IncidenceSampler {
 public:
  IncidenceSampler() {
    for (int b = 0; b <= kBands; ++b) cos_edge_[b] = b == kBands ? 0.0 : std::cos(b * kPiD / 180);
    for (int b = 0; b < kBands; ++b) {
      const double omega = 2 * kPiD * (cos_edge_[b] - cos_edge_[b + 1]);
      inv_p_[b] = 1 / (0.5 / (2 * kPiD) + 0.5 / (kBands * omega));
    }
  }
  // cos θi in (0, 1] (never exactly grazing), from two uniform numbers in [0, 1) and a
  // third that picks the half.
  double draw(double pick, double u) const {
    if (pick < 0.5) return 1 - u;
    const int b = std::min(kBands - 1, int(2 * pick * kBands) - kBands);  // pick ∈ [0.5, 1): the band
    return cos_edge_[b + 1] + (cos_edge_[b] - cos_edge_[b + 1]) * (1 - u);
  }
  static int band(double cos_i) { return std::min(kBands - 1, int(std::acos(cos_i) / kPiD * 180)); }
  double inv_p(int band) const { return inv_p_[band]; }

 private:
  double cos_edge_[kBands + 1];
  double inv_p_[kBands];
};

struct Score {
  std::uint32_t entry;
  double value[3];  // w / (p cos θo): a float would overflow for an exit within 1e-38 of grazing
};

struct BlockResult {
  RayCounts counts;
  std::vector<Score> scores;  // in ray order while tracing
  std::vector<Score> sorted;  // the same grouped by θh slab, ray order kept within a slab
  std::array<std::uint32_t, kSlabs + 1> slab_start;  // slab s is sorted[slab_start[s] .. slab_start[s+1])
  std::vector<double> band;  // per band: rays, Σw (3), Σw² (3)
};

}  // namespace

TableReading measure_table(const Microsurface& surface, const RunOptions& options) {
  TableReading out;
  const std::uint64_t n = std::max<std::uint64_t>(1, options.samples);
  const std::uint64_t blocks = (n + kBlockRays - 1) / kBlockRays;
  const IncidenceSampler incidence;
  const std::vector<double>& measure = merl_bin_measures();

  ZeroedArray<double> sum(3 * MerlTable::kEntries), sum2(3 * MerlTable::kEntries);
  ZeroedArray<std::uint32_t> count(MerlTable::kEntries);
  std::vector<double> band(7 * kBands, 0.0);
  std::vector<const BlockResult*> batch;  // the current batch's results, merged at its end

  detail::run_blocks<BlockResult>(
      blocks, options.threads, options.progress,
      [](BlockResult& r) {
        r.counts = {};
        r.scores.clear();
        r.band.assign(7 * kBands, 0.0);
      },
      [&](std::uint64_t block, BlockResult& r) {
        Pcg32 rng(options.seed, block_stream(0x7ab1e, block));
        const std::uint64_t first = block * kBlockRays, last = std::min(n, first + kBlockRays);
        r.scores.reserve(kBlockRays);
        for (std::uint64_t k = first; k < last; ++k) {
          const double pick = rng.next_double(), u_cos = rng.next_double();
          const double cos_i = incidence.draw(pick, u_cos), phi_i = 2 * kPiD * rng.next_double();
          const double sin_i = std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
          const Vec3 wi{Float(sin_i * std::cos(phi_i)), Float(sin_i * std::sin(phi_i)), Float(cos_i)};
          double u, v;
          entry_point(k - first, last - first == kBlockRays, rng, u, v);
          const TraceResult t = surface.trace(u, v, -wi, rng);
          r.counts.add(t);
          // The band of cos θi as drawn (rounding at a band's edge may move a ray drawn in
          // one band to its neighbour, whose p is then used: a change of 10⁻¹⁶ in cos θi).
          const int b = IncidenceSampler::band(cos_i);
          double* bd = &r.band[7 * std::size_t(b)];
          bd[0] += 1;
          if (t.fate != Fate::Up) continue;
          for (int c = 0; c < 3; ++c) bd[1 + c] += t.weight[c], bd[4 + c] += double(t.weight[c]) * t.weight[c];
          const Vec3& wo = t.direction;
          if (!(wo.z > 0)) continue;
          const MerlBin bin = merl_bin_of(wo, wi);  // float angles (merl_bins.h)
          const double scale = incidence.inv_p(b) / wo.z;
          Score s;
          s.entry = std::uint32_t(MerlTable::index(bin.i, bin.j, bin.k));
          for (int c = 0; c < 3; ++c) s.value[c] = double(t.weight[c]) * scale;
          r.scores.push_back(s);
        }
        // Group the scores by θh slab (a stable counting sort), so that the merge can give
        // each slab to its own thread and walk memory that fits in the caches.
        std::array<std::uint32_t, kSlabs + 1> start{};
        for (const Score& s : r.scores) ++start[s.entry / kSlabEntries + 1];
        for (int b = 0; b < kSlabs; ++b) start[b + 1] += start[b];
        r.slab_start = start;
        r.sorted.resize(r.scores.size());
        for (const Score& s : r.scores) r.sorted[start[s.entry / kSlabEntries]++] = s;
      },
      [&](std::uint64_t block, const BlockResult& r) {
        out.counts += r.counts;
        for (std::size_t k = 0; k < band.size(); ++k) band[k] += r.band[k];
        // run_blocks hands over a batch's blocks in order and keeps them until the batch
        // ends; the batch's scores are summed then, the slabs in parallel and each slab's
        // blocks in block order, so every entry adds its scores in the order of the rays
        // (blocks in order, rays in order within a block) whatever the thread count.
        batch.push_back(&r);
        if ((block + 1) % detail::kBatchBlocks != 0 && block + 1 != blocks) return;
        tbb::parallel_for(0, kSlabs, [&](int slab) {
          for (const BlockResult* b : batch)
            for (std::uint32_t q = b->slab_start[slab]; q < b->slab_start[slab + 1]; ++q) {
              const Score& s = b->sorted[q];
              for (int c = 0; c < 3; ++c) {
                sum[3 * std::size_t(s.entry) + c] += s.value[c];
                sum2[3 * std::size_t(s.entry) + c] += s.value[c] * s.value[c];
              }
              ++count[s.entry];
            }
        });
        batch.clear();
      });

  out.stderr_f.assign(3 * MerlTable::kEntries, 0.0f);
  for (std::size_t e = 0; e < MerlTable::kEntries; ++e) {
    float* f = &out.table.rgb[3 * e];
    if (count[e] == 0 || !(measure[e] > 0)) {
      f[0] = f[1] = f[2] = MerlTable::kMissing;
      ++out.missing;
      continue;
    }
    ++out.filled;
    // The mean score over all N rays (zero for those elsewhere) and its standard error.
    const double scale = 1 / measure[e];
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[3 * e + c] / double(n);
      const double var = n > 1 ? std::max(0.0, sum2[3 * e + c] / double(n) - mean * mean) / double(n - 1) : 0.0;
      f[c] = float(mean * scale);
      out.stderr_f[3 * e + c] = float(std::sqrt(var) * scale);
    }
  }
  out.bands.resize(kBands);
  for (int b = 0; b < kBands; ++b) {
    AlbedoBand& a = out.bands[std::size_t(b)];
    a.theta_lo = b, a.theta_hi = b + 1;
    const double* bd = &band[7 * std::size_t(b)];
    a.rays = std::uint64_t(bd[0]);
    for (int c = 0; c < 3; ++c) {
      const double m = bd[0] > 0 ? bd[1 + c] / bd[0] : 0.0;
      const double var = bd[0] > 1 ? std::max(0.0, bd[4 + c] / bd[0] - m * m) / (bd[0] - 1) : 0.0;
      a.albedo[c] = Float(m);
      a.stderr_albedo[c] = Float(std::sqrt(var));
    }
  }
  return out;
}

}  // namespace gonio::measure
