#pragma once
// The diffusion method of a `subsurface` material (issue 14): the radial profile Sp(r) of
// the separable BSSRDF S = (1 − Fr(cos θo)) Sp(‖xo − xi‖) Sw(ωi) (pbrt-v3 §11.4), by
// photon beam diffusion (PBD; Habel, Christensen & Jarosz 2013, "Photon Beam Diffusion:
// A Hybrid Monte Carlo Method for Subsurface Scattering"): the multiple scattering of a
// beam refracted into the medium, as a continuum of dipoles along the beam, plus its
// single scattering, computed from σs, σa, g (through the similarity relation
// σs′ = (1 − g) σs) and η.
//
// What Sp(r) is: the power per unit area leaving the surface at distance r from where a
// unit power *entered* the medium at normal incidence (exit Fresnel included, entry
// loss not: the renderer applies 1 − Fr at the entry point). Rd() = 2π ∫ Sp r dr is the
// fraction of the entered power that leaves. slab_diffusion() reports both relative to
// the *incident* power, i.e. times 1 − F(0) (SPEC §3).

#include <array>
#include <vector>

#include "gonio/color.h"
#include "gonio/subsurface/medium.h"
#include "gonio/subsurface/slab.h"

namespace gonio {

struct Subsurface;

// The profile of one channel (one σs, σa, g), tabulated once at construction on a log
// grid of radii and interpolated as a power law between nodes (log–log linear), so that
// its integral, its sampling and its density are all exact for the interpolant.
class RadialProfile {
 public:
  RadialProfile() = default;
  // quadrature_points: depths per radius in the PBD integrals (the table's accuracy).
  RadialProfile(Float sigma_s, Float sigma_a, Float g, Float eta, int quadrature_points = 1024);

  Float Sp(Float r) const;        // power per unit area at r per unit entered power
  Float Rd() const { return rd_; }  // 2π ∫0^∞ Sp r dr (the table's whole range)
  // r with density 2π r pdf_r(r) on [0, r_max] (inverts the interpolant's CDF exactly).
  Float sample_r(Float u) const;
  // Density over the plane (per unit area) at distance r: Sp(r) / (2π ∫0^r_max Sp r dr)
  // for r ≤ r_max, else 0; ∫0^r_max pdf_r(r) 2π r dr = 1.
  Float pdf_r(Float r) const;
  // The radius holding 99.9 % of Rd (pbrt-v3's choice): the probe sphere's radius. The
  // 0.1 % beyond it is what a renderer sampling this channel alone misses.
  Float r_max() const { return r_max_; }

 private:
  // Node k at r_k = r0 q^k; Sp(r) = exp(log_sp[k] + slope[k] ln(r / r_k)) on [r_k, r_k+1]
  // and the first slope continued below r0 (Sp ~ 1/r there from single scattering).
  std::vector<double> log_sp_, slope_;
  // The same per node in float for Sp(): ln Sp and slope × ln q (Sp is evaluated per
  // sample; float logarithms and exponentials halve its cost, 1e-5 relative).
  std::vector<float> log_sp_f_, step_f_;
  float inv_r0_ = 1, inv_log_q_ = 1, b0_ = 0;
  std::vector<double> cdf_;  // 2π ∫0^r_k Sp r dr, k = 0 … n (cdf_[0] covers [0, r0])
  double r0_ = 1, log_q_ = 1;
  int n_max_ = 0;            // r_max = r0 q^n_max (a node)
  Float rd_ = 0, r_max_ = 0;
  double norm_ = 0;          // 1 / cdf at r_max (0 for an empty profile)
};

// The profile of a medium, one RadialProfile per channel: built once per material.
// Generic in the colour type C whose channels the medium carries (Color in the
// renderer's RGB mode). Spectral mode needs profiles for wavelengths that change per
// path, i.e. a table over the albedo and the optical radius (pbrt-v3's BSSRDFTable) built
// from the same RadialProfile at σt = 1: not done yet.
template <typename C>
class DiffusionProfileT {
 public:
  DiffusionProfileT() = default;
  DiffusionProfileT(const MediumT<C>& medium, Float eta, int quadrature_points = 1024);

  C Sp(Float r) const;
  const C& Rd() const { return rd_; }
  Float sample_r(int channel, Float u) const { return ch_[static_cast<size_t>(channel)].sample_r(u); }
  Float pdf_r(int channel, Float r) const { return ch_[static_cast<size_t>(channel)].pdf_r(r); }
  Float r_max(int channel) const { return ch_[static_cast<size_t>(channel)].r_max(); }
  Float eta() const { return eta_; }
  const RadialProfile& channel(int c) const { return ch_[static_cast<size_t>(c)]; }

 private:
  std::array<RadialProfile, static_cast<size_t>(C::size())> ch_;
  C rd_{0};
  Float eta_ = 1;
};
using DiffusionProfile = DiffusionProfileT<Color>;

// The share of the power of an isotropic point source at depth z below the surface of a
// semi-infinite medium that leaves it, per channel: the exitance of the profile's dipole
// (d'Eon & Irving 2011's boundary; without Habel's near-source factor κ, which is 1 a few
// mean free paths down) integrated over the whole surface, in closed form,
//   P(z) = e^{−σtr z} [cΦ (|ze|/D) (1 − e^{−2σtr|ze|}) / (2σtr|ze|) + (cE/2)(1 + e^{−2σtr|ze|})],
// which is exactly 1 where σa = 0: every particle of a conservative half-space comes back.
// The random-walk slab counts with it the paths it stops at kMaxWalkSteps (hundreds of
// mean free paths deep, where diffusion holds), which it used to drop (slab_walk.h).
class DipoleEscape {
 public:
  DipoleEscape() = default;
  DipoleEscape(const Medium& medium, Float eta);
  Color operator()(Float depth) const;

 private:
  Color sigma_tr_{0}, at_surface_{0};  // P(z) = at_surface e^{−σtr z}
};

// `gonio subsurface` with method "diffusion": the semi-infinite slab at normal incidence.
// Rd = (1 − F(0)) DiffusionProfile::Rd() — relative to the incident power: the entry loss
// is included, the first-surface reflection F(0) is not counted, single scattering is —
// and the profile (1 − F(0)) Sp(r) at slab_profile_radii. stderr is the quadrature's
// error estimate: |Rd − Rd at half the depths per radius|.
SlabResult slab_diffusion(const Subsurface& material);

}  // namespace gonio
