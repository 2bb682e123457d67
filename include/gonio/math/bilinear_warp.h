#pragma once
// A piecewise-bilinear density on [0, 1]² and its sample warp by inversion (marginal in y,
// then conditional in x), optionally conditioned on up to three parameters between whose
// grid values the density is interpolated linearly: the "bilinearly interpolated
// conditional 2-D warp" of Dupuy & Jakob 2018 (§5, the luminance and VNDF warps of the
// RGL `.bsdf` format). Derivation (ours): on a patch with corner values v00, v10, v01, v11
// the density is bilinear; integrating it over x gives a row density linear in y, whose
// CDF is quadratic: y = t solves a·t + (b − a)·t²/2 = r, solved as
// t = 2r / (a + √(a² + 2(b − a)r)) (no cancellation, a = b included). The conditional
// CDF in x given y is the linear blend of the two node rows' CDFs, inverted alike.
//
// Data layout: [param_0, ..., param_{k-1}, ny, nx], last axis contiguous, each slice
// normalized at construction to integrate to 1 (or, with normalize = false, kept as given,
// for the tables that are only interpolated). Interpolating normalized slices keeps the
// density normalized, and the CDFs interpolate with it, so sample, eval and invert agree.
// Evaluation allocates nothing.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gonio {

class BilinearWarp2D {
 public:
  static constexpr int kMaxParams = 3;
  // Up to 2^kMaxParams slices with weights: where a parameter point falls in the grid.
  struct Slices {
    std::array<std::uint32_t, 1 << kMaxParams> offset{};  // in slices
    std::array<float, 1 << kMaxParams> weight{};
    int count = 0;
  };

  BilinearWarp2D() = default;
  // nx, ny ≥ 2 nodes; params[k] the increasing grid values of parameter k (≥ 1 each).
  // Throws std::invalid_argument on inconsistent sizes or a slice of zero integral when
  // building CDFs (the caller turns it into an InputError naming the field).
  BilinearWarp2D(std::uint32_t nx, std::uint32_t ny, std::span<const float> data,
                 std::vector<std::vector<float>> params, bool normalize, bool build_cdf)
      : nx_(nx), ny_(ny), params_(std::move(params)) {
    if (nx < 2 || ny < 2) throw std::invalid_argument("fewer than 2 nodes along an axis");
    if (params_.size() > kMaxParams) throw std::invalid_argument("more than 3 parameters");
    std::size_t slices = 1;
    strides_.assign(params_.size(), 0);
    for (int k = int(params_.size()) - 1; k >= 0; --k) {
      const auto& p = params_[std::size_t(k)];
      if (p.empty()) throw std::invalid_argument("a parameter with no values");
      for (std::size_t i = 1; i < p.size(); ++i)
        if (!(p[i] > p[i - 1])) throw std::invalid_argument("parameter values not increasing");
      strides_[std::size_t(k)] = std::uint32_t(slices);
      slices *= p.size();
    }
    const std::size_t n = std::size_t(nx) * ny;
    if (data.size() != slices * n) throw std::invalid_argument("data size does not match the shape");
    data_.assign(data.begin(), data.end());
    if (build_cdf) {
      cond_.assign(slices * n, 0.f);
      marg_.assign(slices * ny, 0.f);
    }
    for (std::size_t s = 0; s < slices; ++s) {
      float* d = data_.data() + s * n;
      if (!normalize) continue;
      // Grid units: each patch has area 1; the density on [0,1]² is this times the patch count.
      std::vector<double> c(n), m(ny);
      for (std::uint32_t y = 0; y < ny; ++y) {
        double acc = 0;
        c[y * nx] = 0;
        for (std::uint32_t x = 0; x + 1 < nx; ++x) {
          acc += 0.5 * (double(d[y * nx + x]) + d[y * nx + x + 1]);
          c[y * nx + x + 1] = acc;
        }
      }
      double acc = 0;
      m[0] = 0;
      for (std::uint32_t y = 0; y + 1 < ny; ++y) {
        acc += 0.5 * (c[y * nx + nx - 1] + c[(y + 1) * nx + nx - 1]);
        m[y + 1] = acc;
      }
      if (!(acc > 0) || !std::isfinite(acc)) {
        if (build_cdf) throw std::invalid_argument("a slice of zero or non-finite integral");
        continue;
      }
      const double norm = double(nx - 1) * double(ny - 1) / acc;  // density on [0,1]²
      for (std::size_t i = 0; i < n; ++i) d[i] = float(d[i] * norm);
      if (build_cdf) {
        for (std::size_t i = 0; i < n; ++i) cond_[s * n + i] = float(c[i] / acc);
        for (std::uint32_t y = 0; y < ny; ++y) marg_[s * ny + y] = float(m[y] / acc);
      }
    }
  }

  std::uint32_t nx() const { return nx_; }
  std::uint32_t ny() const { return ny_; }
  std::size_t param_count() const { return params_.size(); }

  // Where the parameter point p[0..k) falls: the slices to blend and their weights
  // (clamped to the grid's range).
  Slices locate(const float* p) const {
    Slices s;
    s.count = 1;
    s.offset[0] = 0;
    s.weight[0] = 1;
    for (std::size_t k = 0; k < params_.size(); ++k) {
      const auto& v = params_[k];
      if (v.size() == 1) continue;
      const auto it = std::upper_bound(v.begin() + 1, v.end() - 1, p[k]);
      const std::size_t i = std::size_t(it - v.begin()) - 1;
      float w = (p[k] - v[i]) / (v[i + 1] - v[i]);
      w = std::clamp(std::isfinite(w) ? w : 0.f, 0.f, 1.f);
      const int c = s.count;
      for (int j = 0; j < c; ++j) {
        s.offset[std::size_t(j + c)] = s.offset[std::size_t(j)] + std::uint32_t(i + 1) * strides_[k];
        s.weight[std::size_t(j + c)] = s.weight[std::size_t(j)] * w;
        s.offset[std::size_t(j)] += std::uint32_t(i) * strides_[k];
        s.weight[std::size_t(j)] *= 1 - w;
      }
      s.count = 2 * c;
    }
    return s;
  }

  // The density at x, y ∈ [0, 1] (normalized tables: w.r.t. area on [0, 1]²).
  float eval(float x, float y, const Slices& s) const {
    const Cell c = cell(x, y);
    const std::size_t n = std::size_t(nx_) * ny_;
    const std::size_t i = std::size_t(c.j) * nx_ + c.i;
    float v00 = 0, v10 = 0, v01 = 0, v11 = 0;
    for (int k = 0; k < s.count; ++k) {
      const float* d = data_.data() + s.offset[std::size_t(k)] * n + i;
      const float w = s.weight[std::size_t(k)];
      v00 += w * d[0];
      v10 += w * d[1];
      v01 += w * d[nx_];
      v11 += w * d[nx_ + 1];
    }
    return (1 - c.t) * ((1 - c.s) * v00 + c.s * v10) + c.t * ((1 - c.s) * v01 + c.s * v11);
  }

  struct Result {
    float x, y, pdf;
  };

  // Warps the uniform (u1, u2) to a point of the density; pdf is the density there.
  Result sample(float u1, float u2, const Slices& s) const {
    constexpr float kLo = 1e-7f, kHi = 1 - 6e-8f;
    u1 = std::clamp(u1, kLo, kHi);
    u2 = std::clamp(u2, kLo, kHi);
    const std::size_t n = std::size_t(nx_) * ny_;
    auto marg = [&](std::uint32_t j) { return blend(marg_.data(), ny_, j, s); };
    auto cond = [&](std::size_t idx) { return blend(cond_.data(), n, idx, s); };
    // Row: the last index j with M(j) <= u2.
    std::uint32_t lo = 0, hi = ny_ - 1;
    while (hi - lo > 1) {
      const std::uint32_t mid = (lo + hi) / 2;
      if (marg(mid) <= u2) lo = mid;
      else hi = mid;
    }
    const std::uint32_t j = lo;
    const float r0 = cond(std::size_t(j) * nx_ + nx_ - 1), r1 = cond(std::size_t(j + 1) * nx_ + nx_ - 1);
    const float t = solve(r0, r1, u2 - marg(j));
    // Column: the conditional CDF at y, the blend of rows j and j + 1.
    auto row_cdf = [&](std::uint32_t i) {
      return (1 - t) * cond(std::size_t(j) * nx_ + i) + t * cond(std::size_t(j + 1) * nx_ + i);
    };
    const float target = u1 * row_cdf(nx_ - 1);
    lo = 0;
    hi = nx_ - 1;
    while (hi - lo > 1) {
      const std::uint32_t mid = (lo + hi) / 2;
      if (row_cdf(mid) <= target) lo = mid;
      else hi = mid;
    }
    const std::uint32_t i = lo;
    float v00 = 0, v10 = 0, v01 = 0, v11 = 0;
    for (int k = 0; k < s.count; ++k) {
      const float* d = data_.data() + s.offset[std::size_t(k)] * n + std::size_t(j) * nx_ + i;
      const float w = s.weight[std::size_t(k)];
      v00 += w * d[0];
      v10 += w * d[1];
      v01 += w * d[nx_];
      v11 += w * d[nx_ + 1];
    }
    const float c0 = (1 - t) * v00 + t * v01, c1 = (1 - t) * v10 + t * v11;
    // Density (on [0,1]²) integrated over one patch column is (c0 + c1)/2/(nx−1); cond is
    // in units of the whole, so rescale.
    const float sx = solve(c0, c1, (target - row_cdf(i)) * float(nx_ - 1) * float(ny_ - 1));
    const float pdf = (1 - sx) * c0 + sx * c1;
    return {(float(i) + sx) / float(nx_ - 1), (float(j) + t) / float(ny_ - 1), pdf};
  }

  // The inverse of sample: the uniform point that warps to (x, y), and the density there.
  Result invert(float x, float y, const Slices& s) const {
    const Cell c = cell(x, y);
    const std::size_t n = std::size_t(nx_) * ny_;
    auto marg = [&](std::uint32_t j) { return blend(marg_.data(), ny_, j, s); };
    auto cond = [&](std::size_t idx) { return blend(cond_.data(), n, idx, s); };
    const std::size_t base = std::size_t(c.j) * nx_ + c.i;
    float v00 = 0, v10 = 0, v01 = 0, v11 = 0;
    for (int k = 0; k < s.count; ++k) {
      const float* d = data_.data() + s.offset[std::size_t(k)] * n + base;
      const float w = s.weight[std::size_t(k)];
      v00 += w * d[0];
      v10 += w * d[1];
      v01 += w * d[nx_];
      v11 += w * d[nx_ + 1];
    }
    const float c0 = (1 - c.t) * v00 + c.t * v01, c1 = (1 - c.t) * v10 + c.t * v11;
    const float pdf = (1 - c.s) * c0 + c.s * c1;
    const float scale = 1.f / (float(nx_ - 1) * float(ny_ - 1));
    const std::size_t r0i = std::size_t(c.j) * nx_, r1i = r0i + nx_;
    const float row_at_x = (1 - c.t) * cond(r0i + c.i) + c.t * cond(r1i + c.i) +
                           (c0 * c.s + 0.5f * (c1 - c0) * c.s * c.s) * scale;
    const float r0 = cond(r0i + nx_ - 1), r1 = cond(r1i + nx_ - 1);
    const float row_total = (1 - c.t) * r0 + c.t * r1;
    const float u1 = row_total > 0 ? row_at_x / row_total : 0.f;
    const float u2 = marg(c.j) + r0 * c.t + 0.5f * (r1 - r0) * c.t * c.t;
    return {std::clamp(u1, 0.f, 1.f), std::clamp(u2, 0.f, 1.f), pdf};
  }

 private:
  struct Cell {
    std::uint32_t i, j;
    float s, t;
  };
  Cell cell(float x, float y) const {
    const float gx = std::clamp(std::isfinite(x) ? x : 0.f, 0.f, 1.f) * float(nx_ - 1);
    const float gy = std::clamp(std::isfinite(y) ? y : 0.f, 0.f, 1.f) * float(ny_ - 1);
    const std::uint32_t i = std::min(std::uint32_t(gx), nx_ - 2), j = std::min(std::uint32_t(gy), ny_ - 2);
    return {i, j, gx - float(i), gy - float(j)};
  }
  static float blend(const float* table, std::size_t slice, std::size_t idx, const Slices& s) {
    float v = 0;
    for (int k = 0; k < s.count; ++k) v += s.weight[std::size_t(k)] * table[s.offset[std::size_t(k)] * slice + idx];
    return v;
  }
  // t ∈ [0, 1] with a·t + (b − a)·t²/2 = r (a, b ≥ 0 the linear density's end values).
  static float solve(float a, float b, float r) {
    r = std::max(r, 0.f);
    const float den = a + std::sqrt(std::max(a * a + 2 * (b - a) * r, 0.f));
    return den > 0 ? std::clamp(2 * r / den, 0.f, 1.f) : 0.f;
  }

  std::uint32_t nx_ = 2, ny_ = 2;
  std::vector<std::vector<float>> params_;
  std::vector<std::uint32_t> strides_;
  std::vector<float> data_, cond_, marg_;
};

}  // namespace gonio
