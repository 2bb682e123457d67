#pragma once
// A ray tracer made for the periodic height fields of heightfield.h (issue 13): no BVH,
// only the grid itself and a maximum mipmap over it.
//
// Structure (Tevs, Ihrke & Seidel 2008, "Maximum mipmaps for fast, accurate, and scalable
// dynamic height field rendering", §3): level 0 is each cell's [min, max] height over its
// four corners (both triangles); level L holds the [min, max] of 2^L × 2^L cells.
// Only levels whose node size 2^L divides n are built, so every level tiles the periodic
// patch exactly and a node never straddles the tile's border (a power-of-two n gets
// the whole pyramid, an odd n only the cells).
//
// Traversal: a 2-D DDA over integer node indices (unwrapped: the ray never leaves the
// plane; heights and nodes are read at the indices modulo n, which is the periodic
// wrapping, with no cut at the border). At each node the ray's height interval over the
// node's footprint is compared with the node's [min, max]: disjoint, the ray steps past
// the node (and climbs a level when it enters a new parent); overlapping, it descends,
// and at a cell it is tested against the cell's two triangles. Cells are visited in the
// order the ray meets them, so the first cell with a hit holds the nearest hit. Where the
// ray passes through (or within rounding of) a node's corner, the DDA would step
// diagonally; the two cells touching that corner from the side are then tested too,
// because the ray meets the surface at the vertex there and the facet the edge functions
// assign it to may be in either (without this, rays aimed at vertices slipped through).
//
// Triangles: watertight ray–triangle tests (Woop, Benthin & Wald 2013, "Watertight
// ray/triangle intersection", JCGT 2(1), §3–4): the vertices are moved into a frame in
// which the ray runs along an axis, and the three 2-D edge functions decide. Each edge
// function is computed once per edge from its two vertices in one fixed order (left to
// right, bottom to top, (i+1, j) to (i, j+1) on the diagonal) and negated for the
// triangle that runs along it the other way, so neighbouring triangles — in the same
// cell or across a cell border — see exactly opposite values: a ray cannot pass between
// them. The arithmetic is double, the heights the field's floats.
//
// A cell's triangles are heightfield.h's: lower-left (i, j), (i+1, j), (i, j+1) — triangle
// 0 — and upper-right (i+1, j), (i+1, j+1), (i, j+1) — triangle 1.

#include <cstdint>
#include <vector>

#include "gonio/math/vec3.h"
#include "gonio/measure/heightfield.h"

namespace gonio::measure {

class HeightFieldTracer {
 public:
  struct Hit {
    double t;                 // the ray parameter of the hit, +inf for none up to tmax
    Vec3 ng;                  // the facet's normal, unnormalised, z > 0
    int i = -1, j = -1;       // the cell (in [0, n)), and its triangle (0 or 1)
    int triangle = -1;
    std::uint32_t wraps = 0;  // tile borders crossed (x and y counted apart)
    bool overflow = false;    // gave up after more than max_wraps crossings
  };
  struct Stats {  // work counters (optional, for the benchmark)
    std::uint64_t nodes = 0;  // node visits (every level, cells included)
    std::uint64_t cells = 0;  // cells whose triangles were tested
  };

  // Throws InputError for a field that is not n × n with n ≥ 1 or holds non-finite heights.
  explicit HeightFieldTracer(const HeightField& field);

  // The first facet along o + t d, 0 ≤ t ≤ tmax (world coordinates: o anywhere in the
  // plane, d need not be unit; t is in units of |d|). Stops early with overflow = true once
  // the ray has crossed more than max_wraps tile borders. start_level: the mipmap level the
  // walk starts at (0 for a ray leaving a facet, whose next facet is usually near); < 0
  // chooses one from the ray's horizontal reach. It changes the work, not the answer.
  Hit intersect(const double o[3], const double d[3], double tmax, std::uint32_t max_wraps,
                Stats* stats = nullptr, int start_level = -1) const;

  int n() const { return n_; }
  int levels() const { return int(offsets_.size()) + 1; }
  // Level L's node (a, b) (a, b in [0, n >> L)): its [min, max] height (level 0: the cells).
  float node_min(int level, int a, int b) const;
  float node_max(int level, int a, int b) const;
  std::size_t memory_bytes() const;

 private:
  // Memory layout, for locality: a ray reads the cells along its path, and consecutive
  // rays enter near each other, so what matters is how many cache lines a path touches.
  // The heights are stored in blocks of 4 × 4 (when 4 divides n), one 64-byte line each;
  // the cells' own bounds (level 0) are not stored but taken from their corners; the upper
  // levels' bounds are 16-bit codes, rounded outwards (min down, max up) on a grid of
  // (z_hi − z_lo) / 65535, also in 4 × 4 blocks: 4 bytes per node.
  // The index of (a, b) in a side × side array so laid out. It is separable, a column
  // part plus a row part, so a cell's four corners take two of each, not four full indices.
  // Forced inline: GCC otherwise kept height() a call in intersect's node walk (three calls
  // per cell visited), which is too large a function for its inlining limits.
  [[gnu::always_inline]] static std::size_t blocked_column(std::size_t a, std::size_t side) {
    return (side & 3) != 0 ? a : (a >> 2) * 16 + (a & 3);
  }
  [[gnu::always_inline]] static std::size_t blocked_row(std::size_t b, std::size_t side) {
    return (side & 3) != 0 ? b * side : (b >> 2) * (4 * side) + (b & 3) * 4;
  }
  [[gnu::always_inline]] static std::size_t blocked(std::size_t a, std::size_t b, std::size_t side) {
    return blocked_column(a, side) + blocked_row(b, side);
  }
  [[gnu::always_inline]] std::size_t height_column(int i) const { return blocked_column(std::size_t(i), std::size_t(n_)); }
  [[gnu::always_inline]] std::size_t height_row(int j) const { return blocked_row(std::size_t(j), std::size_t(n_)); }
  [[gnu::always_inline]] float height(int i, int j) const { return z_[height_column(i) + height_row(j)]; }
  const std::uint16_t* node(int level, int a, int b) const {  // level ≥ 1
    const std::size_t m = std::size_t(n_ >> level);
    return &codes_[offsets_[std::size_t(level - 1)] + 2 * blocked(std::size_t(a), std::size_t(b), m)];
  }
  int n_ = 0;
  double h_ = 1, inv_h_ = 1;                        // cell side and its reciprocal
  std::vector<float> z_;                            // the heights, blocked
  std::vector<std::uint16_t> codes_;                // levels 1, 2, ...: (min, max) codes per node
  std::vector<std::size_t> offsets_;                // where level L ≥ 1 starts in codes_
  double z_lo_ = 0, z_step_ = 1, inv_step_ = 1;     // a code q stands for z_lo_ + q · z_step_
  double margin_ = 0;                       // slack of the interval test (float heights)
};

}  // namespace gonio::measure
