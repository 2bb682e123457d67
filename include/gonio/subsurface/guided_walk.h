#pragma once
// The random walk of random_walk.h with Dwivedi-guided sampling towards the boundary,
// mixed with the classic walk by one-sample MIS (issue 38 item 4).
//
// Dwivedi sampling (Křivánek & d'Eon 2014, "A zero-variance-based sampling scheme for
// Monte Carlo subsurface scattering", SIGGRAPH Talks; from Dwivedi 1982's exponential
// transform for the half-space): in a medium of single-scattering albedo ϖ the
// asymptotic (diffusion-mode) solution of the transport equation in plane geometry falls
// as e^{−z/ν0} with depth z, where ν0 > 1 solves Case's dispersion relation for
// isotropic scattering
//   1 = ϖ ν0 / 2 · ln((ν0 + 1) / (ν0 − 1))    ⇔    atanh(κ) / κ = 1 / ϖ,  κ = 1/ν0.
// The zero-variance-inspired sampling picks the cosine μ between the new direction and
// the direction out of the surface (the entry point's outward normal) with
//   p(μ) = 1 / (ln((ν0 + 1)/(ν0 − 1)) (ν0 − μ)) = κ / (2 atanh(κ) (1 − κ μ)),  μ ∈ [−1, 1],
// the azimuth uniform, and the distance with the stretched extinction
//   σt' = σt (1 − μ / ν0) = σt (1 − κ μ),
// so that paths heading out travel further and paths heading in stop sooner (the same
// p(μ) and σt' in Meng, Hanika & Dachsbacher 2016, "Improving the Dwivedi sampling
// scheme", CGF 35(4), §3, which also notes that the guided walk alone has unbounded
// weights for paths running parallel to the surface — hence the mixture below).
//
// One-sample MIS (Veach 1997, §9.2.4, balance heuristic) twice over. Techniques: at
// every event the guided one with probability q, the classic one (HG direction, σt_c
// distance) with 1 − q; the direction and the distance are drawn together, so channel
// k's pdf of a segment (ω, t) ending in a scattering event is
//   P_k = (1 − q) f_p(ω) σt_k e^{−σt_k t} + q D_k(ω) σt'_k e^{−σt'_k t},
// f_p the phase function and D_k(ω) = p_{κ_k}(μ) / 2π; a segment reaching the boundary
// at t_b has the survival probabilities e^{−σ t_b} instead of the densities σ e^{−σ t}.
// The integrand in channel j is f_p(ω) σs_j e^{−σt_j t} (f_p(ω) e^{−σt_j t_b} at the
// boundary). Channels: one channel c samples the whole walk, and the weights are the
// balance heuristic over the channels' whole-path pdfs (below). The first segment's
// direction is given (the refraction into the medium): both techniques share it, and
// only its distance is mixed.
// With ϖ = 1 (κ = 0) the guided technique is the classic isotropic one.
//
// Generic in the colour type C; no allocation, no virtual call.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "gonio/math/frame.h"
#include "gonio/subsurface/random_walk.h"

namespace gonio {

// κ = 1/ν0 for the albedo ϖ: the root in (0, 1) of atanh(κ)/κ = 1/ϖ (Křivánek & d'Eon
// 2014; Case & Zweifel 1967's discrete eigenvalue). atanh(κ)/κ increases from 1 at κ = 0
// to ∞ at κ = 1, so bisection in double converges; ϖ ≥ 1 gives κ = 0 (ν0 = ∞: no drift).
inline double dwivedi_kappa(double albedo) {
  if (!(albedo < 1)) return 0;
  if (!(albedo > 0)) return 1 - 1e-7;
  const double target = 1 / albedo;
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (std::atanh(mid) / mid < target) lo = mid;
    else hi = mid;
  }
  return std::min(0.5 * (lo + hi), 1 - 1e-7);
}

// p(μ) of the Dwivedi direction for κ = 1/ν0 (per unit μ; divide by 2π per steradian).
inline double dwivedi_pdf_mu(double mu, double kappa) {
  if (kappa < 1e-7) return 0.5;
  return kappa / (2 * std::atanh(kappa) * (1 - kappa * mu));
}

// μ from ξ ∈ [0, 1) by inverting F(μ) = ln((1 + κ)/(1 − κ μ)) / (2 atanh κ):
// μ = (1 − (1 + κ) e^{−2 ξ atanh κ}) / κ, written with expm1 so that it tends to
// 2ξ − 1 as κ → 0.
// two_atanh_kappa: 2 atanh κ, which a walk computes once for all its steps.
inline double dwivedi_sample_mu(double xi, double kappa, double two_atanh_kappa) {
  if (kappa < 1e-7) return 2 * xi - 1;
  const double a = xi * two_atanh_kappa;
  const double mu = (-std::expm1(-a) - kappa * std::exp(-a)) / kappa;
  return std::clamp(mu, -1.0, 1.0);
}
inline double dwivedi_sample_mu(double xi, double kappa) { return dwivedi_sample_mu(xi, kappa, 2 * std::atanh(kappa)); }

// The guide of a walk: the outward surface normal at the entry point and the probability
// q of the guided technique at each event.
struct WalkGuide {
  Vec3 normal{0, 0, 1};
  Float probability = 0.5f;
  // The medium's κ per channel, then dwivedi_pdf_mu(0, κ) per channel (2N values), made
  // once per medium by the caller (dwivedi_kappa bisects: 60 atanh per channel); null: the
  // walk makes them.
  const double* dwivedi = nullptr;
};

// What a caller may learn of a walk's last segment (the one that reached the boundary):
// whether it started at a scattering event (false: the walk crossed without scattering),
// that event's point and the direction the walk arrived there in (the phase function's
// argument for the last segment). The renderer's next-event estimation through the
// boundary weights the emitter the last segment finds by MIS with these
// (render/path_tracer.cpp).
struct WalkLastEvent {
  bool scattered = false;
  Vec3 point;
  Vec3 d_in;
};

// The default per-event hook: nothing.
struct NoScatterHook {
  template <typename C>
  void operator()(const Vec3&, const Vec3&, const C&) const {}
};

// The classic technique's direction pdf: hg_sample's (isotropic below kHgIsotropicBelow).
inline double hg_sampled_pdf(Float cos_theta, Float g) {
  return std::abs(g) < kHgIsotropicBelow ? double(kInv4Pi) : double(hg_phase(cos_theta, g));
}

// As walk_to_boundary (random_walk.h) — same arguments, results and Russian roulette —
// with the guided technique and the path-level channel MIS described above.
// guide.probability = 0 samples directions and distances as the classic walk (one
// channel per walk).
//
// `on_scatter(x, d_in, beta)` is called at every scattering event x, d_in the direction
// the walk arrived in and beta the path's weight there (the event's σs included, the
// Russian roulette that follows not): an unbiased weight of the path up to x whatever
// the channel sampled, so a caller may add an estimate of what leaves x from there
// (next-event estimation). `last` receives the last segment's start (WalkLastEvent).
template <typename C, typename Boundary, typename OnScatter = NoScatterHook>
bool walk_to_boundary_guided(const MediumT<C>& medium, const Boundary& boundary, const WalkGuide& guide, Vec3 p,
                             Vec3 d, C& beta, Pcg32& rng, typename Boundary::Hit& hit, WalkStats* stats = nullptr,
                             Vec3* d_out = nullptr, std::uint32_t max_steps = kMaxWalkSteps,
                             OnScatter&& on_scatter = OnScatter{}, WalkLastEvent* last = nullptr) {
  constexpr int N = C::size();
  const C sigma_t = medium.sigma_t();
  const double q = std::clamp(double(guide.probability), 0.0, 1.0);
  const Vec3 n = normalize(guide.normal);
  const Frame frame = Frame::from_normal(n);
  double kappa[N], dwivedi_norm[N], two_atanh[N];
  for (int c = 0; c < N; ++c) {
    if (guide.dwivedi) {
      kappa[c] = guide.dwivedi[c];
      dwivedi_norm[c] = guide.dwivedi[N + c];
    } else {
      const double albedo = sigma_t[c] > 0 ? double(medium.sigma_s[c]) / double(sigma_t[c]) : 0.0;
      kappa[c] = dwivedi_kappa(albedo);
      dwivedi_norm[c] = dwivedi_pdf_mu(0, kappa[c]);  // κ / (2 atanh κ): p(μ) = this / (1 − κμ)
    }
    two_atanh[c] = 2 * std::atanh(kappa[c]);
  }
  // Path-level spectral MIS: the channel whose σt (and κ) samples the whole walk is chosen
  // once, with p_c = β_c / Σβ at the entry, and the walk's weight in channel j is the
  // balance heuristic over the channels' whole-path pdfs P_k (Veach 1997 §9.2; the
  // "hero wavelength" of Wilkie et al. 2014 applied to the walk's channels):
  //   β_j ← β_j F_j / Σ_k p_k P_k,
  // F_j the path's integrand in channel j. Kept as W_j = F_j / P_c and R_k = P_k / P_c
  // (R_c = 1), so that β_j = β_j W_j Σβ / Σ_k β_k R_k ≤ β_j W_j / p_c: no channel's weight
  // exceeds 1/p_c times its own analog weight, however long the path. (Choosing the
  // channel anew at every event and weighting each event alone — random_walk.h — lets the
  // ratio of two channels' weights wander as a product of hundreds of factors: the
  // coloured speckle of marble, docs/subsurface.md.)
  double b0[N], total = 0;
  for (int c = 0; c < N; ++c) total += (b0[c] = double(std::max(beta[c], Float(0))));
  if (!(total > 0) || !std::isfinite(total)) return false;
  const double pick = double(rng.next_float()) * total;
  int ch = N - 1;
  double acc = 0;
  for (int c = 0; c < N; ++c) {
    acc += b0[c];
    if (pick < acc) { ch = c; break; }
  }
  double W[N], R[N];
  for (int c = 0; c < N; ++c) W[c] = R[c] = 1;
  bool given = true;  // the first direction is the caller's
  if (last) *last = WalkLastEvent{};
  for (std::uint32_t step = 0; step <= max_steps; ++step) {
    const bool guided = rng.next_float() < q;
    const Vec3 d_prev = d;
    if (!given) {
      const Float u1 = rng.next_float(), u2 = rng.next_float();
      if (guided) {
        const Float mu = Float(dwivedi_sample_mu(u1, kappa[ch], two_atanh[ch]));
        const Float sin_t = std::sqrt(std::max(Float(0), 1 - mu * mu));
        const Float phi = 2 * kPi * u2;
        d = normalize(frame.to_world({sin_t * std::cos(phi), sin_t * std::sin(phi), mu}));
      } else {
        d = hg_sample(d_prev, medium.g, u1, u2);
      }
    }
    const double mu = std::clamp(double(dot(d, n)), -1.0, 1.0);
    const double sigma_ch = guided ? double(sigma_t[ch]) * (1 - kappa[ch] * mu) : double(sigma_t[ch]);
    const Float u = rng.next_float();
    const double t = sigma_ch > 0 ? -std::log1p(-double(u)) / sigma_ch : std::numeric_limits<double>::infinity();

    // Direction densities: the phase function (the integrand's and the classic pdf) and
    // the Dwivedi pdf; 1 for the given first direction.
    const double phase = given ? 1.0 : hg_sampled_pdf(dot(d_prev, d), medium.g);

    const bool to_boundary = boundary_within(boundary, p, d, t, hit);
    const double s = to_boundary ? double(hit.t) : t;
    if (!to_boundary && !std::isfinite(t)) return false;
    if (!to_boundary && step == max_steps) return false;
    double pdf[N], f[N];
    for (int k = 0; k < N; ++k) {
      const double st = sigma_t[k], sg = st * (1 - kappa[k] * mu);
      // In float, as the walk's weights (six per step; expf is the cheaper call).
      const double tr = std::exp(-float(st * s)), tr_g = std::exp(-float(sg * s));
      const double dir_g = given ? 1.0 : dwivedi_norm[k] / (1 - kappa[k] * mu) * double(kInv2Pi);
      pdf[k] = (1 - q) * phase * (to_boundary ? tr : st * tr) + q * dir_g * (to_boundary ? tr_g : sg * tr_g);
      f[k] = phase * (to_boundary ? tr : double(medium.sigma_s[k]) * tr);
    }
    if (!(pdf[ch] > 0)) return false;
    double rmax = 0;
    const double inv_pdf_ch = 1 / pdf[ch];
    for (int k = 0; k < N; ++k) {
      R[k] *= pdf[k] * inv_pdf_ch;
      W[k] *= f[k] * inv_pdf_ch;
      rmax = std::max(rmax, R[k]);
    }
    if (rmax > 1e150) {  // a common factor of W and R cancels: keep them in range
      for (int k = 0; k < N; ++k) R[k] /= rmax, W[k] /= rmax;
    }
    double denom = 0;
    for (int k = 0; k < N; ++k) denom += b0[k] * R[k];
    if (!(denom > 0) || !std::isfinite(denom)) return false;
    const double scale = total / denom;
    for (int k = 0; k < N; ++k) beta[k] = Float(b0[k] * W[k] * scale);
    given = false;
    if (to_boundary) {
      if (d_out) *d_out = d;
      return beta.is_finite();
    }
    p = p + d * Float(t);
    if (stats) ++stats->steps;
    if (last) *last = WalkLastEvent{true, p, d};
    on_scatter(p, d, beta);

    // Russian roulette as in random_walk.h, on the path's current weight.
    const Float m = beta.max_component();
    if (!(m > 0) || !std::isfinite(m)) return false;
    if (m < 1) {
      if (rng.next_float() >= m) return false;
      for (int k = 0; k < N; ++k) W[k] /= double(m);
    }
  }
  return false;
}

}  // namespace gonio
