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
#include "gonio/merl/coverage.h"
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

// One ray of the table's incidences: drawn, traced, and (for an upward exit) binned. The
// pilot and the estimate draw their rays through this one function, so they sample the
// same density.
struct TableRay {
  TraceResult trace;
  int band = 0;           // the 1° band of θi as drawn
  bool scored = false;    // left upwards with wo.z > 0: `score` holds its bin and value
  Score score{};
};

TableRay trace_table_ray(const Microsurface& surface, const IncidenceSampler& incidence, std::uint64_t k_in_block,
                         bool full_block, Pcg32& rng) {
  TableRay r;
  const double pick = rng.next_double(), u_cos = rng.next_double();
  const double cos_i = incidence.draw(pick, u_cos), phi_i = 2 * kPiD * rng.next_double();
  const double sin_i = std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
  const Vec3 wi{Float(sin_i * std::cos(phi_i)), Float(sin_i * std::sin(phi_i)), Float(cos_i)};
  double u, v;
  entry_point(k_in_block, full_block, rng, u, v);
  r.trace = surface.trace(u, v, -wi, rng);
  // The band of cos θi as drawn (rounding at a band's edge may move a ray drawn in one
  // band to its neighbour, whose p is then used: a change of 10⁻¹⁶ in cos θi).
  r.band = IncidenceSampler::band(cos_i);
  const Vec3& wo = r.trace.direction;
  if (r.trace.fate != Fate::Up || !(wo.z > 0)) return r;
  const MerlBin bin = merl_bin_of(wo, wi);  // float angles (merl_bins.h)
  const double scale = incidence.inv_p(r.band) / wo.z;
  r.scored = true;
  r.score.entry = std::uint32_t(MerlTable::index(bin.i, bin.j, bin.k));
  for (int c = 0; c < 3; ++c) r.score.value[c] = double(r.trace.weight[c]) * scale;
  return r;
}

struct BlockResult {
  RayCounts counts;
  std::vector<Score> scores;  // in ray order while tracing
  std::vector<Score> sorted;  // the same grouped by θh slab, ray order kept within a slab
  std::array<std::uint32_t, kSlabs + 1> slab_start;  // slab s is sorted[slab_start[s] .. slab_start[s+1])
  std::vector<double> band;  // per band: rays, Σw (3), Σw² (3)
};

// The pilot's rays (table.h): each upward exit's entry and score (its channels' sum).
struct PilotScore {
  std::uint32_t entry;
  double value;
};
struct PilotBlock {
  std::vector<PilotScore> scores;
};

// The two passes' random streams (block_stream's task): the pilot's rays are independent
// of the estimate's.
constexpr std::uint64_t kEstimateTask = 0x7ab1e, kPilotTask = 0x7ab1e9170;

// A lower bound on the rays of N that a Lambertian sample (any albedo) sends into entry
// (i, j, k): N ∫∫_B p(ωi) cos θo/π dωi dωo with p(ωi) ≥ 1/(4π) (the uniform half of the
// incidences), and ∫∫_B cos θo = ∫∫_B cos θh cos θd (zi + zo = 2 cos θh cos θd, and the
// bin holds each pair with its swap) ≥ M_B cos θh1 cos θd1 at the bin's far corner.
double reference_rays(double n, double measure, int i, int j) {
  const double th1 = std::pow(double(i + 1) / MerlTable::kThetaH, 2) * kPiD / 2;
  const double td1 = double(j + 1) / MerlTable::kThetaD * kPiD / 2;
  return n * measure * std::cos(th1) * std::cos(td1) / (4 * kPiD * kPiD);
}

// The pilot's rule (table.h). Its scores s in the bin give an effective number of rays
// n = (Σs)² / Σs² (the count, for equal scores; fewer where a few rays carry most of the
// sum, as near the horizon or where the incidence density changes within the bin), which
// scaled to the estimate's N must reach K even after taking off three of its standard
// deviations (√n): among the many bins that expect few rays, some pilot counts come out
// two deviations high.
bool pilot_expects(double sum, double sum2, double pilot_to_estimate, double k) {
  const double n = sum2 > 0 ? sum * sum / sum2 : 0.0;
  return (n - 3 * std::sqrt(n)) * pilot_to_estimate >= k;
}

// What an entry's estimate and its decision need, summed over a region of bins: the
// measure, the geometric bound, the pilot's Σs and Σs², and the estimate's Σ and Σ² per
// channel.
struct Pool {
  double measure = 0, reference = 0, pilot = 0, pilot2 = 0, sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  Pool& operator+=(const Pool& o) {
    measure += o.measure, reference += o.reference, pilot += o.pilot, pilot2 += o.pilot2;
    for (int c = 0; c < 3; ++c) sum[c] += o.sum[c], sum2[c] += o.sum2[c];
    return *this;
  }
  // a − b, for the sums of a prefix; the rounding of a difference of prefixes is kept
  // from going below zero.
  static Pool difference(const Pool& a, const Pool& b) {
    Pool d;
    d.measure = std::max(0.0, a.measure - b.measure), d.reference = std::max(0.0, a.reference - b.reference);
    d.pilot = std::max(0.0, a.pilot - b.pilot), d.pilot2 = std::max(0.0, a.pilot2 - b.pilot2);
    for (int c = 0; c < 3; ++c)
      d.sum[c] = std::max(0.0, a.sum[c] - b.sum[c]), d.sum2[c] = std::max(0.0, a.sum2[c] - b.sum2[c]);
    return d;
  }
};

struct TableSums {
  const ZeroedArray<double>& sum;
  const ZeroedArray<double>& sum2;
  const ZeroedArray<double>& pilot_sum;
  const ZeroedArray<double>& pilot_sum2;
  const std::vector<double>& measure;
};

// The φd windows (±bins) and the (θh, θd) boxes of whole rows (±bins) a sparse entry
// tries in turn (table.h).
constexpr int kPhiWindows[] = {1, 2, 4, 8, 16, 32, 64};
constexpr int kRowBoxes[] = {0, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 90};

// Writes every entry (table.h): own, pooled, or missing below the horizon; its standard
// error and support; and the counts.
void fill_entries(TableReading& out, const TableSums& in, std::uint64_t n, double pilot_to_estimate, double k_min) {
  constexpr int H = MerlTable::kThetaH, D = MerlTable::kThetaD, P = MerlTable::kPhiD;
  const double nd = double(n);
  auto enough = [&](const Pool& r) {
    return r.reference >= k_min || pilot_expects(r.pilot, r.pilot2, pilot_to_estimate, k_min);
  };
  // reference_rays per unit measure, per (θh, θd) row.
  std::vector<double> reference_per_measure(std::size_t(H) * D);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < D; ++j) reference_per_measure[std::size_t(i) * D + std::size_t(j)] = reference_rays(nd, 1.0, i, j);
  auto bin_pool = [&](int i, int j, std::size_t e) {
    Pool b;
    b.measure = in.measure[e];
    if (!(b.measure > 0)) return b;  // wholly below the horizon: no part of any region
    b.reference = reference_per_measure[std::size_t(i) * D + std::size_t(j)] * b.measure;
    b.pilot = in.pilot_sum[e], b.pilot2 = in.pilot_sum2[e];
    for (int c = 0; c < 3; ++c) b.sum[c] = in.sum[3 * e + c], b.sum2[c] = in.sum2[3 * e + c];
    return b;
  };
  // Whole rows: row[i][j] summed over φd, and their prefix over θh per θd column
  // (column[j][i] = rows 0 .. i−1), so that a box of rows costs one difference per θd.
  std::vector<Pool> row(std::size_t(H) * D), column(std::size_t(D) * (H + 1));
  tbb::parallel_for(0, H, [&](int i) {
    for (int j = 0; j < D; ++j) {
      Pool t;
      for (int k = 0; k < P; ++k) t += bin_pool(i, j, MerlTable::index(i, j, k));
      row[std::size_t(i) * D + std::size_t(j)] = t;
    }
  });
  for (int j = 0; j < D; ++j)
    for (int i = 0; i < H; ++i) {
      Pool c = column[std::size_t(j) * (H + 1) + std::size_t(i)];
      c += row[std::size_t(i) * D + std::size_t(j)];
      column[std::size_t(j) * (H + 1) + std::size_t(i) + 1] = c;
    }
  out.stderr_f.assign(3 * MerlTable::kEntries, 0.0f);
  out.support.assign(MerlTable::kEntries, 0);
  struct SlabCounts {
    std::uint64_t filled = 0, by_pilot = 0, pooled = 0, zero = 0, missing = 0, above[3] = {0, 0, 0};
  };
  std::vector<SlabCounts> counts(H);
  tbb::parallel_for(0, H, [&](int i) {
    SlabCounts& sc = counts[std::size_t(i)];
    std::vector<Pool> prefix(P + 1);
    for (int j = 0; j < D; ++j) {
      for (int k = 0; k < P; ++k) {
        prefix[std::size_t(k) + 1] = prefix[std::size_t(k)];
        prefix[std::size_t(k) + 1] += bin_pool(i, j, MerlTable::index(i, j, k));
      }
      // φd bins k−w .. k+w, taken around the period of 180 bins.
      auto window = [&](int k, int w) {
        const int lo = k - w, hi = k + w + 1;  // [lo, hi)
        if (lo >= 0 && hi <= P) return Pool::difference(prefix[std::size_t(hi)], prefix[std::size_t(lo)]);
        Pool r = lo < 0 ? Pool::difference(prefix[P], prefix[std::size_t(lo + P)]) : Pool::difference(prefix[P], prefix[std::size_t(lo)]);
        r += lo < 0 ? Pool::difference(prefix[std::size_t(hi)], prefix[0]) : Pool::difference(prefix[std::size_t(hi - P)], prefix[0]);
        return r;
      };
      // The region of whole rows (kRowBoxes), found once per row when first needed.
      bool have_box = false;
      Pool box;
      std::uint32_t box_bins = 0;
      auto row_box = [&] {
        if (have_box) return;
        have_box = true;
        for (const int d : kRowBoxes) {
          const int i0 = std::max(0, i - d), i1 = std::min(H - 1, i + d), j0 = std::max(0, j - d), j1 = std::min(D - 1, j + d);
          box = Pool{};
          for (int jj = j0; jj <= j1; ++jj)
            box += Pool::difference(column[std::size_t(jj) * (H + 1) + std::size_t(i1) + 1],
                                    column[std::size_t(jj) * (H + 1) + std::size_t(i0)]);
          box_bins = std::uint32_t((i1 - i0 + 1) * (j1 - j0 + 1) * P);
          if (enough(box)) return;
        }
      };
      for (int k = 0; k < P; ++k) {
        const std::size_t e = MerlTable::index(i, j, k);
        const Pool own = bin_pool(i, j, e);
        // A bin of measure 0 by merl_bins' quadrature whose centre is still above the
        // horizon (merl/coverage.h; none is known, but the two are computed apart)
        // would be read by the measured model: it is pooled.
        if (!(own.measure > 0) && !merl_entry_above_horizon(i, j, k)) {
          float* f = &out.table.rgb[3 * e];
          f[0] = f[1] = f[2] = MerlTable::kMissing;
          ++sc.missing;
          continue;
        }
        const Pool* region = &own;
        Pool pooled;
        std::uint32_t bins = 1;
        const bool by_geometry = own.measure > 0 && own.reference >= k_min;
        if (own.measure > 0 && (by_geometry || pilot_expects(own.pilot, own.pilot2, pilot_to_estimate, k_min))) {
          ++sc.filled;
          if (!by_geometry) ++sc.by_pilot;
        } else {
          ++sc.pooled;
          region = &pooled;
          bool found = false;
          for (const int w : kPhiWindows) {
            pooled = window(k, w);
            bins = std::uint32_t(2 * w + 1);
            if (enough(pooled)) {
              found = true;
              break;
            }
          }
          if (!found) {
            row_box();
            region = &box;
            bins = box_bins;
          }
        }
        out.support[e] = bins;
        if (!(region->measure > 0)) {  // nothing above the horizon around it: not reached by the rule above
          float* f = &out.table.rgb[3 * e];
          f[0] = f[1] = f[2] = 0;
          ++sc.zero;
          continue;
        }
        // The mean score over all N rays (zero for those elsewhere) and its standard
        // error, per unit of the region's measure.
        const double scale = 1 / region->measure;
        double worst = 0;  // the largest relative standard error over the channels
        bool zero = true;
        for (int c = 0; c < 3; ++c) {
          const double mean = region->sum[c] / nd;
          const double var = n > 1 ? std::max(0.0, region->sum2[c] / nd - mean * mean) / (nd - 1) : 0.0;
          out.table.rgb[3 * e + std::size_t(c)] = float(mean * scale);
          out.stderr_f[3 * e + std::size_t(c)] = float(std::sqrt(var) * scale);
          if (mean > 0) zero = false, worst = std::max(worst, std::sqrt(var) / mean);
        }
        if (zero) {
          ++sc.zero;
          continue;
        }
        for (int q = 0; q < 3; ++q)
          if (worst > kTableErrorLevels[q]) ++sc.above[q];
      }
    }
  });
  std::uint64_t above[3] = {0, 0, 0};
  for (const SlabCounts& sc : counts) {
    out.filled += sc.filled, out.filled_by_pilot += sc.by_pilot, out.pooled += sc.pooled;
    out.zero += sc.zero, out.missing += sc.missing;
    for (int q = 0; q < 3; ++q) above[q] += sc.above[q];
  }
  const std::uint64_t nonzero = out.filled + out.pooled - out.zero;
  for (int q = 0; q < 3; ++q) out.fraction_above[q] = nonzero > 0 ? double(above[q]) / double(nonzero) : 0.0;
}

}  // namespace

std::uint64_t table_pilot_rays(std::uint64_t samples) {
  return std::max<std::uint64_t>(1, (std::max<std::uint64_t>(1, samples) + 3) / 4);
}

TableReading measure_table(const Microsurface& surface, const RunOptions& options, const TableOptions& table) {
  TableReading out;
  const std::uint64_t n = std::max<std::uint64_t>(1, options.samples);
  const std::uint64_t blocks = (n + kBlockRays - 1) / kBlockRays;
  const std::uint64_t n_pilot = table_pilot_rays(n);
  const std::uint64_t pilot_blocks = (n_pilot + kBlockRays - 1) / kBlockRays;
  const IncidenceSampler incidence;
  const std::vector<double>& measure = merl_bin_measures();
  const std::uint64_t total_blocks = pilot_blocks + blocks;
  // The caller's progress over both passes: a pass of `span` blocks after `before` others.
  auto progress = [&](std::uint64_t before, std::uint64_t span) -> std::function<void(double)> {
    if (!options.progress) return {};
    return [&, before, span](double part) {
      options.progress((double(before) + part * double(span)) / double(total_blocks));
    };
  };

  // The rays of block `block` of a pass of `rays` rays on the stream `task`, each given
  // to `use` (a block's stream and strata as trace_table_ray draws them).
  auto trace_block = [&](std::uint64_t task, std::uint64_t block, std::uint64_t rays, auto&& use) {
    Pcg32 rng(options.seed, block_stream(task, block));
    const std::uint64_t first = block * kBlockRays, last = std::min(rays, first + kBlockRays);
    for (std::uint64_t k = first; k < last; ++k)
      use(trace_table_ray(surface, incidence, k - first, last - first == kBlockRays, rng));
  };

  // The pilot: n/4 rays of their own, whose scores are summed per entry for the rule and
  // used for nothing else.
  ZeroedArray<double> pilot_sum(MerlTable::kEntries), pilot_sum2(MerlTable::kEntries);
  detail::run_blocks<PilotBlock>(
      pilot_blocks, options.threads, progress(0, pilot_blocks), [](PilotBlock& r) { r.scores.clear(); },
      [&](std::uint64_t block, PilotBlock& r) {
        r.scores.reserve(kBlockRays);
        trace_block(kPilotTask, block, n_pilot, [&](const TableRay& t) {
          if (t.scored) r.scores.push_back({t.score.entry, t.score.value[0] + t.score.value[1] + t.score.value[2]});
        });
      },
      [&](std::uint64_t, const PilotBlock& r) {
        for (const PilotScore& s : r.scores) pilot_sum[s.entry] += s.value, pilot_sum2[s.entry] += s.value * s.value;
      });

  ZeroedArray<double> sum(3 * MerlTable::kEntries), sum2(3 * MerlTable::kEntries);
  std::vector<double> band(7 * kBands, 0.0);
  std::vector<const BlockResult*> batch;  // the current batch's results, merged at its end

  detail::run_blocks<BlockResult>(
      blocks, options.threads, progress(pilot_blocks, blocks),
      [](BlockResult& r) {
        r.counts = {};
        r.scores.clear();
        r.band.assign(7 * kBands, 0.0);
      },
      [&](std::uint64_t block, BlockResult& r) {
        r.scores.reserve(kBlockRays);
        trace_block(kEstimateTask, block, n, [&](const TableRay& t) {
          r.counts.add(t.trace);
          double* bd = &r.band[7 * std::size_t(t.band)];
          bd[0] += 1;
          if (t.trace.fate != Fate::Up) return;
          for (int c = 0; c < 3; ++c)
            bd[1 + c] += t.trace.weight[c], bd[4 + c] += double(t.trace.weight[c]) * t.trace.weight[c];
          if (t.scored) r.scores.push_back(t.score);
        });
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
            }
        });
        batch.clear();
      });

  out.pilot_rays = n_pilot;
  fill_entries(out, TableSums{sum, sum2, pilot_sum, pilot_sum2, measure}, n, double(n) / double(n_pilot),
               table.min_expected_rays);
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
