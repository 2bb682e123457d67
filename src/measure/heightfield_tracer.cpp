// The maximum-mipmap height-field tracer of include/gonio/measure/heightfield_tracer.h.
#include "gonio/measure/heightfield_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "gonio/error.h"

namespace gonio::measure {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The highest level a query starts at (it climbs on from there when the ray runs above
// the surface): docs/benchmarks.md, "gonio measure", for the choice.
constexpr int kMaxStartLevel = 4;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

// floor(v) for |v| < 2^62 by truncation, corrected below zero: libm's floor is a call on
// baseline x86-64 (no rounding instruction before SSE4.1), and the walk takes one per step.
std::int64_t floor_int(double v) {
  const std::int64_t t = std::int64_t(v);
  return t - std::int64_t(double(t) > v);
}

}  // namespace

HeightFieldTracer::HeightFieldTracer(const HeightField& field) {
  const int n = field.n;
  if (n < 1 || n > 32766 || field.z.size() != std::size_t(n) * std::size_t(n))
    throw InputError("surface: the height field must be n x n with 1 <= n <= 32766, got n = " + std::to_string(n));
  if (!(field.size > 0) || !std::isfinite(field.size))
    throw InputError("surface: the patch size must be a positive number, got " + format_number(field.size));
  double zabs = 0;
  for (const float z : field.z) {
    if (!std::isfinite(z)) throw InputError("surface: the height field holds a non-finite height");
    zabs = std::max(zabs, double(std::abs(z)));
  }
  // The ray's height at a node's border is computed in double, to far better than this;
  // the slack keeps a ray that grazes a node's highest corner from skipping it, and covers
  // the rounding of the decoded bounds.
  margin_ = 1e-9 * (zabs + field.spacing());
  n_ = n;
  h_ = field.spacing();
  inv_h_ = 1 / h_;
  z_.resize(std::size_t(n) * std::size_t(n));
  double lo = kInfinity, hi = -kInfinity;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float z = field.z[std::size_t(i) + std::size_t(n) * std::size_t(j)];
      z_[blocked(std::size_t(i), std::size_t(j), std::size_t(n))] = z;
      lo = std::min(lo, double(z)), hi = std::max(hi, double(z));
    }
  z_lo_ = lo;
  z_step_ = hi > lo ? (hi - lo) / 65535 : 1;
  inv_step_ = 1 / z_step_;
  // Level L from level L − 1 (level 0: the cells' corners), while the node size 2^L still
  // divides n (so that the nodes tile the periodic patch). The bounds are carried exactly
  // (in float) from level to level and rounded outwards only when stored.
  std::vector<float> fine(2 * std::size_t(n) * std::size_t(n));  // exact (min, max), row-major
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float a = field.at(i, j), b = field.at(i + 1, j), c = field.at(i, j + 1), d = field.at(i + 1, j + 1);
      fine[2 * (std::size_t(i) + std::size_t(n) * j)] = std::min({a, b, c, d});
      fine[2 * (std::size_t(i) + std::size_t(n) * j) + 1] = std::max({a, b, c, d});
    }
  for (int level = 1; n % (1 << level) == 0; ++level) {
    const int m = n >> level;
    std::vector<float> coarse(2 * std::size_t(m) * std::size_t(m));
    std::vector<std::uint16_t> codes(2 * std::size_t(m) * std::size_t(m));
    for (int b = 0; b < m; ++b)
      for (int a = 0; a < m; ++a) {
        float mn = std::numeric_limits<float>::infinity(), mx = -mn;
        for (int q = 0; q < 2; ++q)
          for (int p = 0; p < 2; ++p) {
            const float* c = &fine[2 * (std::size_t(2 * a + p) + std::size_t(2 * m) * std::size_t(2 * b + q))];
            mn = std::min(mn, c[0]);
            mx = std::max(mx, c[1]);
          }
        coarse[2 * (std::size_t(a) + std::size_t(m) * b)] = mn;
        coarse[2 * (std::size_t(a) + std::size_t(m) * b) + 1] = mx;
        std::uint16_t* q = &codes[2 * blocked(std::size_t(a), std::size_t(b), std::size_t(m))];
        q[0] = std::uint16_t(std::clamp(std::floor((mn - z_lo_) / z_step_), 0.0, 65535.0));
        q[1] = std::uint16_t(std::clamp(std::ceil((mx - z_lo_) / z_step_), 0.0, 65535.0));
      }
    offsets_.push_back(codes_.size());
    codes_.insert(codes_.end(), codes.begin(), codes.end());
    fine = std::move(coarse);
  }
}

float HeightFieldTracer::node_min(int level, int a, int b) const {
  if (level > 0) return float(z_lo_ + node(level, a, b)[0] * z_step_);
  const int a1 = (a + 1) % n_, b1 = (b + 1) % n_;
  return std::min({height(a, b), height(a1, b), height(a, b1), height(a1, b1)});
}

float HeightFieldTracer::node_max(int level, int a, int b) const {
  if (level > 0) return float(z_lo_ + node(level, a, b)[1] * z_step_);
  const int a1 = (a + 1) % n_, b1 = (b + 1) % n_;
  return std::max({height(a, b), height(a1, b), height(a, b1), height(a1, b1)});
}

std::size_t HeightFieldTracer::memory_bytes() const {
  std::size_t b = z_.size() * sizeof(float);
  b += codes_.size() * sizeof(std::uint16_t);
  return b;
}

HeightFieldTracer::Hit HeightFieldTracer::intersect(const double o[3], const double d[3], double tmax,
                                                    std::uint32_t max_wraps, Stats* stats, int start_level) const {
  Hit hit;
  hit.t = kInfinity;
  if (!(tmax >= 0)) return hit;
  // Grid coordinates: x and y in cells (cell (i, j) is [i, i+1) × [j, j+1)), z as it is;
  // d is scaled alike, so t is the same parameter as in world coordinates.
  const double inv_h = inv_h_;
  const double org[3] = {o[0] * inv_h, o[1] * inv_h, o[2]};
  const double dir[3] = {d[0] * inv_h, d[1] * inv_h, d[2]};
  if (!(std::isfinite(org[0]) && std::isfinite(org[1]) && std::isfinite(org[2]) && std::isfinite(dir[0]) &&
        std::isfinite(dir[1]) && std::isfinite(dir[2])))
    return hit;

  // Woop et al. 2013 §3: kz the dominant axis of d, kx and ky the others (swapped when
  // d[kz] < 0, which keeps the triangles' winding); the shear (Sx, Sy, Sz) maps the ray to
  // the +z axis from the origin.
  int kz = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(dir[k]) > std::abs(dir[kz])) kz = k;
  if (dir[kz] == 0) return hit;
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (dir[kz] < 0) std::swap(kx, ky);
  const double sx_shear = dir[kx] / dir[kz], sy_shear = dir[ky] / dir[kz], sz_shear = 1 / dir[kz];

  struct V2 {
    double x, y, z;  // sheared x, y and scaled z of a vertex relative to the origin
  };
  // Every vertex is transformed by this one function of its grid position and height, so
  // a vertex shared by several triangles has the same coordinates in each of them.
  // As rows of a matrix (rel[kx] − Sx rel[kz] = Σ_k Mx[k] rel[k], exactly: the other
  // coefficients are 0 and 1), so that no component is picked by a run-time index.
  double mx[3] = {0, 0, 0}, my[3] = {0, 0, 0}, mz[3] = {0, 0, 0};
  mx[kx] = 1, mx[kz] = -sx_shear;
  my[ky] = 1, my[kz] = -sy_shear;
  mz[kz] = sz_shear;
  auto vertex = [&](std::int64_t gx, std::int64_t gy, float z) {
    const double rx = double(gx) - org[0], ry = double(gy) - org[1], rz = double(z) - org[2];
    return V2{mx[0] * rx + mx[1] * ry + mx[2] * rz, my[0] * rx + my[1] * ry + my[2] * rz,
              mz[0] * rx + mz[1] * ry + mz[2] * rz};
  };
  // The 2-D edge function of the directed edge P → Q (twice the signed area of the ray's
  // point with P and Q): each edge is evaluated in one fixed direction only.
  auto edge = [](const V2& p, const V2& q) { return p.x * q.y - p.y * q.x; };
  // A triangle with edge values w_a (the edge opposite vertex a), w_b, w_c: a hit unless the
  // values have mixed signs (Woop's test, edges included) or all vanish; t = Σ w z / Σ w.
  auto triangle = [tmax](double wa, double wb, double wc, double za, double zb, double zc) {
    // (Bitwise, all six comparisons then one branch: the signs are random from cell to cell.)
    if ((int(wa < 0) | int(wb < 0) | int(wc < 0)) & (int(wa > 0) | int(wb > 0) | int(wc > 0))) return kInfinity;
    const double det = wa + wb + wc;
    if (det == 0) return kInfinity;
    const double t = (wa * za + wb * zb + wc * zc) / det;
    return t >= 0 && t <= tmax ? t : kInfinity;
  };

  const std::int64_t n = n_;
  const int top = levels() - 1;
  // The starting cell: the one the ray enters, so on a border the one it moves into.
  std::int64_t ix = floor_int(org[0]), iy = floor_int(org[1]);
  if (dir[0] < 0 && double(ix) == org[0]) --ix;
  if (dir[1] < 0 && double(iy) == org[1]) --iy;
  // The current tile's corner (a query from trace() starts in the tile [0, n]²).
  std::int64_t bx = ix >= 0 && ix < n ? 0 : floor_div(ix, n) * n, by = iy >= 0 && iy < n ? 0 : floor_div(iy, n) * n;
  const int step_x = dir[0] > 0 ? 1 : dir[0] < 0 ? -1 : 0, step_y = dir[1] > 0 ? 1 : dir[1] < 0 ? -1 : 0;
  const double inv_dx = step_x ? 1 / dir[0] : 0, inv_dy = step_y ? 1 / dir[1] : 0;
  // The node's border the ray leaves through along x is x0 + s (moving up) or x0 (moving
  // down, or not at all); none along an axis the ray does not move on: the distance to it
  // is (border − origin) · 0 + ∞. Written so, as arithmetic rather than a choice per node:
  // the compiler turned the choice into branches, which mispredicted where queries of
  // different directions alternate (entry and exit).
  const double far_x = step_x > 0 ? 1 : 0, far_y = step_y > 0 ? 1 : 0;
  const double never_x = step_x ? 0 : kInfinity, never_y = step_y ? 0 : kInfinity;
  std::uint32_t wraps = 0;
  // The triangles of the cell at grid position (gx, gy) (unwrapped), whose corners (i, j),
  // (i+1, j), (i, j+1), (i+1, j+1) modulo n have the heights za, zb, zc, zd (the caller has
  // them already): on a hit, fills `hit` and returns true.
  auto test_cell = [&](std::int64_t gx, std::int64_t gy, int i, int j, float za, float zb, float zc, float zd) {
    if (stats) ++stats->cells;
    const V2 A = vertex(gx, gy, za), B = vertex(gx + 1, gy, zb), C = vertex(gx, gy + 1, zc),
             D = vertex(gx + 1, gy + 1, zd);
    // Edges in their fixed directions: bottom A→B, top C→D, left A→C, right B→D, diagonal B→C.
    const double e_ab = edge(A, B), e_cd = edge(C, D), e_ac = edge(A, C), e_bd = edge(B, D), e_bc = edge(B, C);
    // Triangle 0 (A, B, C): opposite A the edge B→C, opposite B C→A, opposite C A→B.
    const double t0 = triangle(e_bc, -e_ac, e_ab, A.z, B.z, C.z);
    // Triangle 1 (B, D, C): opposite B the edge D→C, opposite D C→B, opposite C B→D.
    const double t1 = triangle(-e_cd, -e_bc, e_bd, B.z, D.z, C.z);
    if (!(t0 < kInfinity || t1 < kInfinity)) return false;
    const bool upper = t1 < t0;
    hit.t = upper ? t1 : t0;
    hit.i = i, hit.j = j, hit.triangle = upper ? 1 : 0;
    // The facet's normal ∝ (−∂z/∂x, −∂z/∂y, 1) from its forward differences.
    hit.ng = upper ? Vec3{Float(double(zc) - zd), Float(double(zb) - zd), Float(h_)}
                   : Vec3{Float(double(za) - zb), Float(double(za) - zc), Float(h_)};
    hit.wraps = wraps;
    return true;
  };

  // The starting level: given, or from the ray's horizontal reach up to tmax in cells
  // (a node about a quarter of it: a ray that crosses the slab steeply needs only the
  // cells it starts over, a grazing one skips the space above the surface in large steps).
  if (start_level < 0) {
    const double reach = std::min(tmax, 1e12) * std::sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    start_level = 0;
    while (start_level < kMaxStartLevel && reach >= double(4 << (start_level + 1)) - 4) ++start_level;
  }
  int level = std::min({top, start_level, kMaxStartLevel});
  double z_t = org[2];  // the ray's height at t
  const double inv_step = inv_step_;
  for (;;) {
    const std::int64_t s = std::int64_t(1) << level;
    const std::int64_t ax = (ix - bx) >> level, ay = (iy - by) >> level;  // the node in its tile
    const std::int64_t x0 = bx + (ax << level), y0 = by + (ay << level);  // its lower corner (cells)
    const double tx = (double(x0) + far_x * double(s) - org[0]) * inv_dx + never_x;
    const double ty = (double(y0) + far_y * double(s) - org[1]) * inv_dy + never_y;
    const double t1 = std::min(std::min(tx, ty), tmax);
    if (stats) ++stats->nodes;
    // The ray's heights over the node's footprint against the node's [min, max] (a cell's
    // from its corners).
    const double zb = org[2] + dir[2] * t1;
    // (The lower of the two is z_t for a rising ray, zb otherwise: org + dir t rounds
    // monotonically in t.)
    const double ray_lo = std::min(z_t, zb) - margin_, ray_hi = std::max(z_t, zb) + margin_;
    if (level > 0) {
      const std::size_t side = std::size_t(n_ >> level);
      const std::uint16_t* nd = &codes_[offsets_[std::size_t(level - 1)] +
                                        2 * blocked(std::size_t(ax), std::size_t(ay), side)];
      // In code units: the node overlaps iff code_min ≤ (ray_hi − z_lo) / step and
      // code_max ≥ (ray_lo − z_lo) / step.
      if ((ray_hi - z_lo_) * inv_step >= double(nd[0]) && (ray_lo - z_lo_) * inv_step <= double(nd[1])) {
        --level;
        continue;
      }
    } else {
      const int i = int(ix - bx), j = int(iy - by);
      const int i1 = i + 1 == n_ ? 0 : i + 1, j1 = j + 1 == n_ ? 0 : j + 1;
      const std::size_t col0 = height_column(i), col1 = height_column(i1), row0 = height_row(j), row1 = height_row(j1);
      const float c0 = z_[col0 + row0], c1 = z_[col1 + row0], c2 = z_[col0 + row1], c3 = z_[col1 + row1];
      if (ray_hi >= double(std::min(std::min(c0, c1), std::min(c2, c3))) &&
          ray_lo <= double(std::max(std::max(c0, c1), std::max(c2, c3))) && test_cell(ix, iy, i, j, c0, c1, c2, c3))
        return hit;
    }
    if (!(std::min(tx, ty) < tmax)) {  // no border before tmax: the ray ends in this node
      hit.wraps = wraps;
      return hit;
    }
    // Through (or within rounding of) the node's corner: the two cells that touch the
    // corner from the side nodes are tested too. The DDA's corner decision and the
    // triangles' edge functions are computed differently, and the ray, passing a vertex
    // there, may meet the surface in a facet of either (a vertex has six).
    if (step_x && step_y && std::abs(tx - ty) <= 1e-9 * std::max(tx, ty)) {
      const std::int64_t cx = step_x > 0 ? x0 + s : x0 - 1, cy = step_y > 0 ? y0 + s : y0 - 1;
      // cx, cy: the column and row beyond the corner; lx, ly: this node's corner cell's.
      const std::int64_t lx = step_x > 0 ? x0 + s - 1 : x0, ly = step_y > 0 ? y0 + s - 1 : y0;
      auto wrapped = [&](std::int64_t g, std::int64_t base) {
        const std::int64_t l = g - base;
        return int(l < 0 ? l + n : l >= n ? l - n : l);
      };
      auto test_side_cell = [&](std::int64_t gx, std::int64_t gy) {
        const int i = wrapped(gx, bx), j = wrapped(gy, by);
        const int i1 = i + 1 == n_ ? 0 : i + 1, j1 = j + 1 == n_ ? 0 : j + 1;
        return test_cell(gx, gy, i, j, height(i, j), height(i1, j), height(i, j1), height(i1, j1));
      };
      if (test_side_cell(cx, ly) || test_side_cell(lx, cy)) return hit;
    }
    // Step into the next node: across the border the ray meets first (both at a corner);
    // the other index stays inside this node's range, where the ray still is.
    const std::int64_t old_x = ix, old_y = iy;
    if (tx <= ty) ix = step_x > 0 ? x0 + s : x0 - 1;
    else if (step_x) ix = std::clamp(floor_int(org[0] + dir[0] * ty), x0, x0 + s - 1);
    if (ty <= tx) iy = step_y > 0 ? y0 + s : y0 - 1;
    else if (step_y) iy = std::clamp(floor_int(org[1] + dir[1] * tx), y0, y0 + s - 1);
    z_t = zb;
    // Periodic wrapping: a new tile is only a new origin for the indices modulo n.
    if (ix - bx >= n) bx += n, ++wraps;
    else if (ix < bx) bx -= n, ++wraps;
    if (iy - by >= n) by += n, ++wraps;
    else if (iy < by) by -= n, ++wraps;
    if (wraps > max_wraps) {
      hit.wraps = wraps;
      hit.overflow = true;
      return hit;
    }
    // Climb one level when the ray has entered a new parent node (one at a time: climbing
    // to every new ancestor at once cost more visits, descending again, than it saved).
    if (level < top && ((ix >> (level + 1)) != (old_x >> (level + 1)) || (iy >> (level + 1)) != (old_y >> (level + 1))))
      ++level;
  }
}

}  // namespace gonio::measure
