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
  const double inv = 1 / std::sqrt(x * x + y * y + z * z);
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
  constexpr double kHuge = std::numeric_limits<double>::max();
  if (!(ma >= 0x1p-500 && ma <= 0x1p500 && mb >= 0x1p-500 && mb <= 0x1p500)) [[unlikely]] {
    // Zero, non-finite or in need of scaling: one at a time.
    if (!(ma > 0 && ma <= kHuge && mb > 0 && mb <= kHuge)) return false;
    wa = *unit_direction(a[0], a[1], a[2]);
    wb = *unit_direction(b[0], b[1], b[2]);
    return true;
  }
  const V x{a[0], b[0]}, y{a[1], b[1]}, z{a[2], b[2]};
  const V inv = 1 / lane_sqrt(x * x + y * y + z * z);
  const V ux = x * inv, uy = y * inv, uz = z * inv;
  wa = Vec3{Float(ux[0]), Float(uy[0]), Float(uz[0])};
  wb = Vec3{Float(ux[1]), Float(uy[1]), Float(uz[1])};
  return true;
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
