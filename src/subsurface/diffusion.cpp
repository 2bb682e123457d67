// Photon beam diffusion (Habel, Christensen & Jarosz 2013) tabulated per channel, and the
// slab of `gonio subsurface` by the diffusion method. The two PBD integrals over depth are
// computed here in double, once per radius of the table, by the midpoint rule in log depth
// (the integrands vary on the scale of r near the surface and of the mean free path below,
// which a log grid resolves for every r of the table alike).

#include "gonio/subsurface/diffusion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gonio/fresnel.h"
#include "gonio/subsurface/henyey_greenstein.h"
#include "gonio/subsurface/subsurface.h"
#include "gonio/subsurface/sw_bxdf.h"

namespace gonio {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInv4Pi = 1 / (4 * kPi);

// The medium of one channel and what PBD derives from it once.
struct PbdMedium {
  double sigma_s, sigma_a, g, eta;
  double sps, spt, rhop;  // reduced σs′ = (1 − g) σs (similarity relation), σt′, ρ′ = σs′/σt′
  double D, sigma_tr;     // Grosjean's diffusion coefficient and the effective transport coefficient
  double ze, c_phi, c_e;  // extrapolation depth (negative: above the surface) and exitance weights

  PbdMedium(double ss, double sa, double g_, double eta_) : sigma_s(ss), sigma_a(sa), g(g_), eta(eta_) {
    sps = (1 - g) * sigma_s;
    spt = sigma_a + sps;
    rhop = sps / spt;
    // Grosjean's non-classical diffusion coefficient D = (2σa + σs′) / (3 σt′²) (d'Eon 2012,
    // "A better dipole", eq. 5; pbrt-v3 eq. 15.24), σtr = √(σa / D).
    D = (2 * sigma_a + sps) / (3 * spt * spt);
    sigma_tr = std::sqrt(sigma_a / D);
    // The boundary of d'Eon & Irving 2011 (eqs. 11–13; pbrt-v3 §15.5.2): Fresnel moments of
    // light inside the medium reaching the surface (relative index 1/η crossed outward),
    // ze = −2D (1 + 3 FM2) / (1 − 2 FM1), E = cΦ φ + cE D ∂φ/∂n with
    // cΦ = (1 − 2 FM1)/4, cE = (1 − 3 FM2)/2.
    const double fm1 = fresnel_moment(1, 1 / eta), fm2 = fresnel_moment(2, 1 / eta);
    ze = -2 * D * (1 + 3 * fm2) / (1 - 2 * fm1);
    c_phi = 0.25 * (1 - 2 * fm1);
    c_e = 0.5 * (1 - 3 * fm2);
  }

  // Radiant exitance at distance r from a unit point source at depth zr: the dipole
  // (Farrell et al. 1992; real source at zr, mirror source at zv = 2 ze − zr above the
  // surface; fluence φ = (e^{−σtr dr}/dr − e^{−σtr dv}/dv) / (4π D)), times the factor
  // κ = 1 − e^{−2σt′(dr + zr)} of Habel et al. 2013 (§4.2) that suppresses the dipole's
  // overestimate close to the source. Habel et al. 2013, eq. 10 with pbrt-v3 §15.5.3.
  double dipole_exitance(double r, double zr) const {
    const double zv = -zr + 2 * ze;
    const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
    const double er = std::exp(-sigma_tr * dr), ev = std::exp(-sigma_tr * dv);
    const double phi = kInv4Pi / D * (er / dr - ev / dv);
    const double dphi = kInv4Pi * (zr * (1 + sigma_tr * dr) * er / (dr * dr * dr) -
                                   zv * (1 + sigma_tr * dv) * ev / (dv * dv * dv));
    const double kappa = -std::expm1(-2 * spt * (dr + zr));
    return kappa * (c_phi * phi + c_e * dphi);
  }

  // Multiple scattering: the beam refracted in at normal incidence scatters (reduced) at
  // depth t with density σs′ e^{−σt′ t} per unit length and unit entered power, each such
  // point a dipole: Rms(r) = ρ′ ∫0^∞ σs′ e^{−σt′ t} E(r, t) dt. The second factor ρ′ is
  // PBD's as pbrt-v3 evaluates it (BeamDiffusionMS, ρ′² with depths drawn ∝ σt′ e^{−σt′ t});
  // against the exact half-space (Chandrasekhar's H-function, η = 1, g = 0) it brings the
  // total Rd within +11 % at ϖ = 0.5 where one ρ′ is +55 % (docs/subsurface-diffusion.md).
  double multiple(double r, int n) const {
    const double ell = 1 / spt;
    const double lo = std::log(1e-5 * std::min(std::max(r, 1e-3 * ell), ell)), hi = std::log(60 * ell);
    const double ds = (hi - lo) / n;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double t = std::exp(lo + (i + 0.5) * ds);
      sum += sps * std::exp(-spt * t) * dipole_exitance(r, t) * t;  // dt = t ds
    }
    return rhop * sum * ds;
  }

  // Single scattering of the unreduced beam (Habel et al. 2013, §4.3; pbrt-v3 eq. 15.28):
  // scattered at depth t towards the exit point at distance d = √(r² + t²), cosine
  // μo = t/d with the normal, phase p at the angle between the beam (down) and that
  // direction (up), attenuated over d, spread over the surface by μo/d², transmitted by
  // 1 − Fr(μo) from inside: Rss(r) = ∫ σs e^{−σt t} p e^{−σt d} (1 − Fr) μo/d² dt. Depths
  // above tc = r √(η² − 1) only: shallower points reach r beyond the critical angle.
  double single(double r, int n) const {
    const double st = sigma_s + sigma_a;
    const double tc = eta > 1 ? r * std::sqrt(eta * eta - 1) : 0.0;
    const double ell = 1 / st;
    const double lo = std::log(1e-5 * std::min(std::max(r, 1e-3 * ell), ell)), hi = std::log(60 * ell);
    const double ds = (hi - lo) / n;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double tau = std::exp(lo + (i + 0.5) * ds);
      const double t = tc + tau;
      const double d2 = r * r + t * t, d = std::sqrt(d2);
      const double mu = t / d;
      // Henyey–Greenstein between the beam (down) and the way up to r: cos = −μo.
      const double phase = hg_phase(static_cast<Float>(-mu), static_cast<Float>(g));
      const double tr = 1 - fresnel_dielectric(-mu, eta);
      sum += sigma_s * std::exp(-st * (t + d)) * phase * tr * mu / d2 * tau;  // dt = τ ds
    }
    return sum * ds;
  }
};

// ∫1^q x^(b+1) dx (the power-law segment's mass in units of r_k²), and the x in [1, q]
// below which a fraction v of it lies.
double segment_mass(double b, double log_q) {
  const double a = (b + 2) * log_q;
  return std::abs(a) < 1e-9 ? log_q : std::expm1(a) / (b + 2);
}
double segment_invert(double b, double log_q, double v) {
  const double a = (b + 2) * log_q;
  if (std::abs(a) < 1e-9) return std::exp(v * log_q);
  return std::exp(std::log1p(v * std::expm1(a)) / (b + 2));
}

constexpr double kTwoPi = 2 * kPi;
constexpr double kLogStep = 0.04;      // ln q: 25 table nodes per e-fold of r
constexpr double kMaxSlopeNear0 = -1.9;  // Sp ~ r^b below r0 needs b > −2 to integrate
constexpr double kRmaxFraction = 0.999;

}  // namespace

RadialProfile::RadialProfile(Float sigma_s, Float sigma_a, Float g, Float eta, int quadrature_points) {
  const double ss = sigma_s, sa = sigma_a;
  if (!(ss > 0) || !(sa >= 0) || !(std::abs(g) < 1) || !(eta > 0) || !std::isfinite(ss) || !std::isfinite(sa))
    return;  // no scattering: an empty profile (Sp = 0, Rd = 0, nothing to sample)
  const PbdMedium m(ss, sa, g, eta);
  if (!(m.spt > 0) || !std::isfinite(m.D)) return;
  const int nq = std::max(16, quadrature_points);
  // The table spans 10⁻³ transport mean free paths to where the slowest decay, e^{−σtr r}
  // of diffusion or e^{−σt r} of single scattering, is down by e^{−40} (at most 10⁴ mean
  // free paths: without absorption the profile falls as r^−3 only, and 10⁻⁴ of Rd lies
  // beyond).
  const double ell = 1 / m.spt;
  const double decay = std::min(m.sigma_tr, ss + sa);
  double r_hi = decay > 0 ? 40 / decay : 1e4 * ell;
  r_hi = std::clamp(r_hi, 10 * ell, 1e4 * ell);
  r0_ = 1e-3 * ell;
  const int n = static_cast<int>(std::ceil(std::log(r_hi / r0_) / kLogStep));
  log_q_ = std::log(r_hi / r0_) / n;
  std::vector<double> sp(static_cast<size_t>(n + 1));
  int last = -1;
  for (int k = 0; k <= n; ++k) {
    const double r = r0_ * std::exp(k * log_q_);
    const double v = m.multiple(r, nq) + m.single(r, nq);
    if (!(v > 1e-300) || !std::isfinite(v)) break;
    sp[static_cast<size_t>(k)] = v;
    last = k;
  }
  if (last < 1) return;
  log_sp_.resize(static_cast<size_t>(last + 1));
  slope_.resize(static_cast<size_t>(last + 1));
  for (int k = 0; k <= last; ++k) log_sp_[static_cast<size_t>(k)] = std::log(sp[static_cast<size_t>(k)]);
  for (int k = 0; k < last; ++k)
    slope_[static_cast<size_t>(k)] = (log_sp_[static_cast<size_t>(k) + 1] - log_sp_[static_cast<size_t>(k)]) / log_q_;
  slope_[static_cast<size_t>(last)] = 0;  // unused: Sp is 0 beyond the last node
  // The first slope continues below r0, kept integrable.
  const double b0 = std::max(slope_[0], kMaxSlopeNear0);
  cdf_.assign(static_cast<size_t>(last + 1), 0);
  cdf_[0] = kTwoPi * sp[0] * r0_ * r0_ / (b0 + 2);
  for (int k = 0; k < last; ++k) {
    const double rk = r0_ * std::exp(k * log_q_);
    cdf_[static_cast<size_t>(k) + 1] =
        cdf_[static_cast<size_t>(k)] + kTwoPi * sp[static_cast<size_t>(k)] * rk * rk * segment_mass(slope_[static_cast<size_t>(k)], log_q_);
  }
  // Energy conservation: a half-space cannot return more power than entered it. The exact
  // transport returns all of it only without absorption (Chandrasekhar 1960, §26: the
  // albedo 1 − H(1)√(1 − ϖ) of a semi-infinite medium is 1 at ϖ = 1 and below 1 else).
  // PBD is an approximation that does not conserve energy: with little absorption its
  // total overshoots (σa = 0: 2π ∫ Sp r dr = 1.093 at η = 1, 1.035 at η = 1.3,
  // docs/subsurface.md). Where 2π ∫ Sp r dr > 1 the profile is divided by it, so that it returns
  // exactly what entered (continuous in the medium: the factor is 1 at the threshold);
  // below, PBD is left as Habel et al. give it.
  if (cdf_.back() > 1) {
    const double excess = cdf_.back(), shift = std::log(excess);
    for (double& v : log_sp_) v -= shift;
    for (double& v : cdf_) v /= excess;
  }
  log_sp_f_.assign(log_sp_.begin(), log_sp_.end());
  step_f_.resize(log_sp_.size());
  for (size_t k = 0; k < slope_.size(); ++k) step_f_[k] = static_cast<float>(slope_[k] * log_q_);
  inv_r0_ = static_cast<float>(1 / r0_);
  inv_log_q_ = static_cast<float>(1 / log_q_);
  b0_ = static_cast<float>(b0 * log_q_);
  const double total = cdf_.back();
  rd_ = static_cast<Float>(total);
  n_max_ = last;
  for (int k = 0; k <= last; ++k)
    if (cdf_[static_cast<size_t>(k)] >= kRmaxFraction * total) {
      n_max_ = k;
      break;
    }
  n_max_ = std::max(n_max_, 1);
  r_max_ = static_cast<Float>(r0_ * std::exp(n_max_ * log_q_));
  norm_ = 1 / cdf_[static_cast<size_t>(n_max_)];
}

Float RadialProfile::Sp(Float r) const {
  if (log_sp_f_.empty() || !(r >= 0)) return 0;
  // x = ln(r / r0) / ln q: node k = ⌊x⌋, r ≥ 10⁻⁶ r0 so that Sp(0) stays finite.
  const float x = std::log(std::max(r * inv_r0_, 1e-6f)) * inv_log_q_;
  const int last = static_cast<int>(log_sp_f_.size()) - 1;
  if (x < 0) return std::exp(log_sp_f_[0] + b0_ * x);
  if (!(x <= static_cast<float>(last))) return 0;
  const int k = std::min(static_cast<int>(x), last);
  return std::exp(log_sp_f_[static_cast<size_t>(k)] + step_f_[static_cast<size_t>(k)] * (x - static_cast<float>(k)));
}

Float RadialProfile::pdf_r(Float r) const {
  if (!(norm_ > 0) || !(r <= r_max_)) return 0;
  return static_cast<Float>(Sp(r) * norm_);
}

Float RadialProfile::sample_r(Float u) const {
  if (!(norm_ > 0)) return 0;
  const double uu = u >= 0 ? std::min(double(u), 1.0) : 0.0;  // NaN → 0
  const double target = uu * cdf_[static_cast<size_t>(n_max_)];
  // First node whose cumulative mass exceeds the target: the segment ends there.
  const auto begin = cdf_.begin(), end = cdf_.begin() + n_max_ + 1;
  const int j = static_cast<int>(std::upper_bound(begin, end, target) - begin);
  double r;
  if (j == 0) {
    const double b0 = std::max(slope_[0], kMaxSlopeNear0);
    const double v = target / cdf_[0];
    r = r0_ * std::pow(v, 1 / (b0 + 2));
  } else {
    const int k = std::min(j, n_max_) - 1;  // segment [r_k, r_k+1]
    const double lo = cdf_[static_cast<size_t>(k)], hi = cdf_[static_cast<size_t>(k) + 1];
    const double v = hi > lo ? std::clamp((target - lo) / (hi - lo), 0.0, 1.0) : 0.0;
    r = r0_ * std::exp(k * log_q_) * segment_invert(slope_[static_cast<size_t>(k)], log_q_, v);
  }
  return std::min(static_cast<Float>(r), r_max_);
}

template <typename C>
DiffusionProfileT<C>::DiffusionProfileT(const MediumT<C>& medium, Float eta, int quadrature_points) : eta_(eta) {
  for (int c = 0; c < C::size(); ++c) {
    // A channel with the medium of an earlier one (every channel of a grey medium) takes
    // its table: the same numbers, without the 2 × 1024 depths per radius again.
    int same = 0;
    while (same < c && !(medium.sigma_s[same] == medium.sigma_s[c] && medium.sigma_a[same] == medium.sigma_a[c])) ++same;
    ch_[static_cast<size_t>(c)] = same < c ? ch_[static_cast<size_t>(same)]
                                           : RadialProfile(medium.sigma_s[c], medium.sigma_a[c], medium.g, eta, quadrature_points);
    rd_[c] = ch_[static_cast<size_t>(c)].Rd();
  }
}

template <typename C>
C DiffusionProfileT<C>::Sp(Float r) const {
  C v;
  for (int c = 0; c < C::size(); ++c) v[c] = ch_[static_cast<size_t>(c)].Sp(r);
  return v;
}

template class DiffusionProfileT<Color>;
template class DiffusionProfileT<SampledSpectrum>;

// The dipole's exitance cΦ φ + cE D ∂φ/∂n over the plane, with the two integrals
// (d = √(r² + z²), dA = 2π r dr = 2π d dd)
//   ∫ e^{−σ d}/d dA = 2π e^{−σ|z|}/σ,   ∫ z (1 + σ d) e^{−σ d}/d³ dA = 2π sign(z) e^{−σ|z|}
// for the real source at zr = z and the image at zv = 2 ze − z (above: |zv| = z + 2|ze|):
//   ∫ φ = (e^{−σ z} − e^{−σ|zv|}) / (2 D σ),   ∫ D ∂φ/∂n = (e^{−σ z} + e^{−σ|zv|}) / 2.
// As σ → 0 the first tends to |ze|/D = 2 (1 + 3 FM2)/(1 − 2 FM1), so P → (1 + 3 FM2)/2 +
// (1 − 3 FM2)/2 = 1.
DipoleEscape::DipoleEscape(const Medium& medium, Float eta) {
  for (int c = 0; c < Color::size(); ++c) {
    const double ss = medium.sigma_s[c], sa = medium.sigma_a[c];
    if (!((1 - double(medium.g)) * ss + sa > 0)) continue;  // no interaction: no source either
    const PbdMedium m(ss, sa, medium.g, eta);
    const double x = 2 * m.sigma_tr * -m.ze;  // 2 σtr |ze|
    const double spread = x > 0 ? -std::expm1(-x) / x : 1.0;  // (1 − e^{−x})/x → 1
    const double p0 = m.c_phi * (-m.ze / m.D) * spread + 0.5 * m.c_e * (1 + std::exp(-x));
    sigma_tr_[c] = Float(m.sigma_tr);
    at_surface_[c] = Float(std::clamp(p0, 0.0, 1.0));
  }
}

Color DipoleEscape::operator()(Float depth) const {
  Color p;
  const Float z = std::max(depth, Float(0));
  for (int c = 0; c < Color::size(); ++c) p[c] = std::min(Float(1), at_surface_[c] * std::exp(-sigma_tr_[c] * z));
  return p;
}

SlabResult slab_diffusion(const Subsurface& material) {
  const DiffusionProfile profile(material.medium, material.eta);
  // The quadrature's error: the same table at half the depths per radius.
  const DiffusionProfile coarse(material.medium, material.eta, 512);
  const Float entry = 1 - fresnel_dielectric(Float(1), material.eta);  // 1 − F(0)
  SlabResult out;
  out.Rd = profile.Rd() * entry;
  for (int c = 0; c < Color::size(); ++c) out.stderr_[c] = std::abs(profile.Rd()[c] - coarse.Rd()[c]) * entry;
  for (Float r : slab_profile_radii(material.medium)) out.profile.push_back({r, profile.Sp(r) * entry});
  return out;
}

}  // namespace gonio
