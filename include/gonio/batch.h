#pragma once
// Batch evaluation: one model over arrays of directions, spans in and spans out. The
// model's type is resolved once per call (one std::visit around the loop), so the loop
// body is that model's own inline code: no virtual call, no variant dispatch and no
// allocation per element. Serial: a caller that wants threads splits the arrays into
// chunks (the Python module does, python/parallel.h); the core stays free of threading
// libraries. Shared by `gonio eval`, `gonio sample` and the Python module.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>

#include "gonio/bxdf.h"
#include "gonio/fresnel.h"  // lane_sqrt

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

namespace gonio {

// A direction as a user gives it (a line of stdin, a row of a numpy array): normalised in
// double, then rounded to Float. Components far from 1 are first scaled by a power of two,
// which is exact, so that their squares neither overflow nor vanish; the result is the
// same as without the scaling wherever that would not overflow. One square root and one
// division per direction: this runs twice per element of every batch call. nullopt for a
// zero or non-finite vector (the caller names the row).
[[gnu::always_inline]] inline std::optional<Vec3> unit_direction(double x, double y, double z) {
  const double m = std::max({std::abs(x), std::abs(y), std::abs(z)});
  if (!(m > 0) || !(m <= std::numeric_limits<double>::max())) return std::nullopt;
  if (m < 0x1p-500 || m > 0x1p500) [[unlikely]] {
    const int e = std::ilogb(m);
    x = std::scalbn(x, -e);
    y = std::scalbn(y, -e);
    z = std::scalbn(z, -e);
  }
  const double s = x * x + y * y + z * z;
  // A NaN after the first component can slip past std::max (NaN compares false), never
  // past the sum of squares.
  if (std::isnan(s)) [[unlikely]] return std::nullopt;
  const double inv = 1 / std::sqrt(s);
  return Vec3{Float(x * inv), Float(y * inv), Float(z * inv)};
}

// unit_direction of two vectors a and b at once, their arithmetic in the two lanes of one
// SSE register: sqrtpd and divpd round each lane as sqrtsd and divsd do (IEEE 754), so the
// results are bit for bit those of unit_direction, for half the divider's time (the square
// root and the division are most of a batch evaluation of a cheap model). False when
// either is zero or not finite; the outputs are then unspecified.
[[gnu::always_inline]] inline bool unit_direction_pair(const double a[3], const double b[3], Vec3& wa, Vec3& wb) {
  using V = double __attribute__((vector_size(16)));
  const double ma = std::max({std::abs(a[0]), std::abs(a[1]), std::abs(a[2])});
  const double mb = std::max({std::abs(b[0]), std::abs(b[1]), std::abs(b[2])});
  if (!(ma >= 0x1p-500 && ma <= 0x1p500 && mb >= 0x1p-500 && mb <= 0x1p500)) [[unlikely]] {
    // Zero, non-finite or in need of scaling: one at a time, unit_direction deciding which
    // (a NaN after the first component passes std::max, so no test on ma and mb can).
    const auto ua = unit_direction(a[0], a[1], a[2]), ub = unit_direction(b[0], b[1], b[2]);
    if (!ua || !ub) return false;
    wa = *ua, wb = *ub;
    return true;
  }
  const V x{a[0], b[0]}, y{a[1], b[1]}, z{a[2], b[2]};
  const V s = x * x + y * y + z * z;
  if (std::isnan(s[0]) || std::isnan(s[1])) [[unlikely]] return false;  // as in unit_direction
  const V inv = 1 / lane_sqrt(s);
  const V ux = x * inv, uy = y * inv, uz = z * inv;
  wa = Vec3{Float(ux[0]), Float(uy[0]), Float(uz[0])};
  wb = Vec3{Float(ux[1]), Float(uy[1]), Float(uz[1])};
  return true;
}

namespace batch_detail {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define GONIO_BATCH_AVX2 1
// unit_direction_pair over four rows at a time, in 256-bit registers: each lane does the
// scalar operations in the scalar order (vsqrtpd, vdivpd and vcvtpd2ps round as sqrtsd,
// divsd and cvtsd2ss do), so every row is bit for bit unit_direction's. "avx2" does not
// enable FMA, so no multiply-add is contracted. Any row outside the scalar fast path's
// range (or not finite) sends its group of four through unit_direction_pair. Run only
// where the processor has AVX2 (unit_direction_rows checks). (Helpers rather than
// lambdas: a lambda does not inherit its enclosing function's target.)

// Lane k: component c of row k of the rows of three doubles at p.
[[gnu::target("avx2")]] inline __m256d row_column_avx2(const double* p, int c) {
  return _mm256_set_pd(p[9 + c], p[6 + c], p[3 + c], p[c]);
}
// The scalar fast path's condition lane by lane: every |component| ≤ 2^500 (false for a
// NaN) and one of them ≥ 2^−500.
[[gnu::target("avx2")]] inline __m256d in_fast_range_avx2(__m256d x, __m256d y, __m256d z) {
  const __m256d sign = _mm256_set1_pd(-0.0), lo = _mm256_set1_pd(0x1p-500), hi = _mm256_set1_pd(0x1p500);
  const __m256d ax = _mm256_andnot_pd(sign, x), ay = _mm256_andnot_pd(sign, y), az = _mm256_andnot_pd(sign, z);
  const __m256d bounded = _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(ax, hi, _CMP_LE_OQ), _mm256_cmp_pd(ay, hi, _CMP_LE_OQ)),
                                        _mm256_cmp_pd(az, hi, _CMP_LE_OQ));
  const __m256d not_tiny = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(ax, lo, _CMP_GE_OQ), _mm256_cmp_pd(ay, lo, _CMP_GE_OQ)),
                                        _mm256_cmp_pd(az, lo, _CMP_GE_OQ));
  return _mm256_and_pd(bounded, not_tiny);
}
// x · (1 / √(x² + y² + z²)), the sum left to right as in unit_direction, rounded to float.
[[gnu::target("avx2")]] inline void unit_rows_avx2(__m256d x, __m256d y, __m256d z, Vec3* out) {
  const __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z));
  const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(s));
  alignas(16) float fx[4], fy[4], fz[4];
  _mm_store_ps(fx, _mm256_cvtpd_ps(_mm256_mul_pd(x, inv)));
  _mm_store_ps(fy, _mm256_cvtpd_ps(_mm256_mul_pd(y, inv)));
  _mm_store_ps(fz, _mm256_cvtpd_ps(_mm256_mul_pd(z, inv)));
  for (int k = 0; k < 4; ++k) out[k] = Vec3{fx[k], fy[k], fz[k]};
}
// Returns the rows done (a multiple of 4); ok is cleared if a pair was refused.
[[gnu::target("avx2")]] inline std::size_t unit_direction_rows_avx2(const double* a, const double* b, std::size_t n,
                                                                    Vec3* wa, Vec3* wb, bool& ok) {
  std::size_t j = 0;
  for (; j + 4 <= n; j += 4) {
    const double *p = a + 3 * j, *q = b + 3 * j;
    const __m256d ax = row_column_avx2(p, 0), ay = row_column_avx2(p, 1), az = row_column_avx2(p, 2);
    const __m256d bx = row_column_avx2(q, 0), by = row_column_avx2(q, 1), bz = row_column_avx2(q, 2);
    if (_mm256_movemask_pd(_mm256_and_pd(in_fast_range_avx2(ax, ay, az), in_fast_range_avx2(bx, by, bz))) != 0xF)
        [[unlikely]] {
      for (std::size_t k = 0; k < 4; ++k) ok = unit_direction_pair(p + 3 * k, q + 3 * k, wa[j + k], wb[j + k]) && ok;
      continue;
    }
    unit_rows_avx2(ax, ay, az, wa + j);
    unit_rows_avx2(bx, by, bz, wb + j);
  }
  return j;
}
#endif
}  // namespace batch_detail

// unit_direction_pair for n rows of a and b (each n × 3 doubles, row after row): four
// rows at a time where the processor has AVX2, the same bits either way. False when a
// pair was refused; the outputs of that pair are then unspecified, and the caller looks
// for it row by row.
inline bool unit_direction_rows(const double* a, const double* b, std::size_t n, Vec3* wa, Vec3* wb) {
  bool ok = true;
  std::size_t j = 0;
#ifdef GONIO_BATCH_AVX2
  // __builtin_cpu_supports checks that the OS saves the AVX registers too.
  static const bool avx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
  if (avx2) j = batch_detail::unit_direction_rows_avx2(a, b, n, wa, wb, ok);
#endif
  for (; j < n; ++j) ok = unit_direction_pair(a + 3 * j, b + 3 * j, wa[j], wb[j]) && ok;
  return ok;
}

// sample()'s three uniform numbers, each in [0, 1): u_lobe picks the lobe.
struct SampleUniforms {
  Float lobe = 0, u1 = 0, u2 = 0;
};

// What one sample became; None where sample() returned nothing.
enum class BatchLobe : std::uint8_t { None = 0, Reflection = 1, Transmission = 2 };

// Where sample_batch writes, one entry per input element. Where there is no sample, wi
// and weight are 0, pdf 0, delta 0 and lobe None. For a delta sample, pdf holds the
// discrete probability of its lobe (SPEC §3 prints it as null).
template <typename C>
struct SampleBatch {
  std::span<Vec3> wi;
  std::span<C> weight;
  std::span<Float> pdf;
  std::span<std::uint8_t> delta;  // 0 or 1 (the layout of a numpy bool array)
  std::span<BatchLobe> lobe;
};

namespace batch_detail {
inline void check_size(std::size_t n, std::size_t m, const char* what) {
  if (m != n) throw std::invalid_argument(std::string("gonio batch: ") + what + " has the wrong length");
}
}  // namespace batch_detail

// f (1/sr, no cosine) and pdf of every pair (wo[i], wi[i]), unit vectors in the local frame.
template <typename C>
void eval_batch(const BxDFT<C>& bxdf, std::span<const Vec3> wo, std::span<const Vec3> wi, TransportMode mode,
                std::span<C> f, std::span<Float> pdf) {
  const std::size_t n = wo.size();
  batch_detail::check_size(n, wi.size(), "wi");
  batch_detail::check_size(n, f.size(), "f");
  batch_detail::check_size(n, pdf.size(), "pdf");
  std::visit(
      [&](const auto& m) {
        for (std::size_t i = 0; i < n; ++i) {
          const BSDFEvalT<C> e = model_eval(m, wo[i], wi[i], mode);
          f[i] = e.f;
          pdf[i] = e.pdf;
        }
      },
      bxdf.models());
}

// pdf alone.
template <typename C>
void pdf_batch(const BxDFT<C>& bxdf, std::span<const Vec3> wo, std::span<const Vec3> wi, TransportMode mode,
               std::span<Float> pdf) {
  const std::size_t n = wo.size();
  batch_detail::check_size(n, wi.size(), "wi");
  batch_detail::check_size(n, pdf.size(), "pdf");
  std::visit(
      [&](const auto& m) {
        for (std::size_t i = 0; i < n; ++i) pdf[i] = m.pdf(wo[i], wi[i], mode);
      },
      bxdf.models());
}

// One sample per element: sample(wo[i], u[i].lobe, u[i].u1, u[i].u2, mode).
template <typename C>
void sample_batch(const BxDFT<C>& bxdf, std::span<const Vec3> wo, std::span<const SampleUniforms> u,
                  TransportMode mode, const SampleBatch<C>& out) {
  const std::size_t n = wo.size();
  batch_detail::check_size(n, u.size(), "u");
  batch_detail::check_size(n, out.wi.size(), "wi");
  batch_detail::check_size(n, out.weight.size(), "weight");
  batch_detail::check_size(n, out.pdf.size(), "pdf");
  batch_detail::check_size(n, out.delta.size(), "delta");
  batch_detail::check_size(n, out.lobe.size(), "lobe");
  std::visit(
      [&](const auto& m) {
        for (std::size_t i = 0; i < n; ++i) {
          const auto s = m.sample(wo[i], u[i].lobe, u[i].u1, u[i].u2, mode);
          if (s) {
            out.wi[i] = s->wi;
            out.weight[i] = s->weight;
            out.pdf[i] = s->pdf;
            out.delta[i] = s->delta ? 1 : 0;
            out.lobe[i] = s->lobe == Lobe::Reflection ? BatchLobe::Reflection : BatchLobe::Transmission;
          } else {
            out.wi[i] = Vec3{};
            out.weight[i] = C{};
            out.pdf[i] = 0;
            out.delta[i] = 0;
            out.lobe[i] = BatchLobe::None;
          }
        }
      },
      bxdf.models());
}

}  // namespace gonio
