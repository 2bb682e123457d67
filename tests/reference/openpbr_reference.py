#!/usr/bin/env python3
"""Reference records for `openpbr` (issue 35, item 6): its parameter mapping checked
against gonio's independent standalone lobes of models_reference.py.

Standard library only, written from SPEC-OPB (OpenPBR Surface 1.1) and docs/openpbr.md,
not from the C++. Writes tests/reference/data/openpbr.jsonl when run:

    python3 tests/reference/openpbr_reference.py

What is covered (the reductions of the mixture of docs/openpbr.md "Structure" where a
parameter group meets a single standalone lobe):

* metal: base_metalness 1, no coat, no fuzz:
      f = geometry_opacity · ξ · f_conductor(α = r², F82-tint with
          f0 = base_weight·base_color, tint = specular_color, Kulla–Conty compensation)
  (SPEC-OPB "Metal": F82-tint, Hoffman 2023; "Specular": specular_weight ξ scales the
  metal's Fresnel; "Anisotropy": α = r² at zero anisotropy; "Geometry": the opacity
  lerp). Variations: specular_weight 0.5 and 0, base_weight 0.8, geometry_opacity 0.4,
  both transport modes (the metal is reciprocal). No pdf is recorded: the compensated
  metal also samples its multiple-scattering term (not the visible-normal density alone,
  as roughconductor_multiscatter.jsonl has no pdf either), a sampling choice of the C++.
* cut-out: geometry_opacity 0 is a pure pass-through delta, wi = −wo, weight 1.
* transmission (transmission_weight 1, not thin-walled): the rough dielectric of α = r²
  and η = modulated_ior(specular_ior, specular_weight) (models_reference.roughdielectric,
  Walter et al. 2007) plus its Kulla–Conty lobe as docs/design/dielectric-multiscatter.md
  defines it (GlassMs, with this file's own R + T albedo quadrature), reflection and
  transmission from both sides in both modes (importance is the adjoint: transmission
  differs by η²); specular_ior 1.33 and 0.75, specular_weight 0.5, transmission_color.
* thin-walled transmission, specular_roughness 0: the thin sheet's two delta lobes
  (models_reference.thin_sheet) of η_s as sample records (weight × prob), tints included;
  thin-walled subsurface (weight 1, colour 1, base_diffuse_roughness 0): Lambert lobes of
  albedo ½ (1 ∓ g) reflected and transmitted under the specular layer's scaling.
* dielectric base (no metal, transmission, coat, fuzz): f_spec + ρ/π (1 − E_s(μo))
  (1 − E_s(μi))/(1 − Ē_s) over Lambert, and b(μo) b(μi) (1 − E_s)(1 − E_s) f_EON over
  EON with b solved here from the condition docs/openpbr.md states (EonNorm);
  specular_ior 1.8 and 0.75 (the TIR fix), specular_weight 0.5, base_weight.
* coat (coat_darkening 0) over the metal, with roughening, absorption and coat_weight 0.5;
  coat over a bare Lambertian base (specular_weight 0) with darkening 1 and 0.5.
* fuzz over the metal (the sheen lobe of models_reference.sheen, E_fuzz its fitted albedo).
* thin film on the specular layer over a black base (thin_film_reference.film_rgb).
* coat over the dielectric base's specular layer alone (base_weight 0), whose index is
  seen through the coat (η_s = n_b/n_c with the TIR fix, lerped by coat_weight).
* anisotropy on the metal (α_t, α_b of SPEC-OPB's formula, the tangent turned by
  specular_rotation; no compensation lobe there).
* thin film on the metal, grey colours (one effective index (n, k) at every wavelength,
  Gulbrandsen's member matching F82-tint at μ = 1/7), with the mixture's F̄ in Kulla–Conty.

Tolerances (atol per record and channel; rtol 1e-4, or 20× the float-rounding
sensitivity of a narrow lobe as in make_reference_data.py):
* every albedo that gonio reads from an interpolated table (the conductor's and the glass's
  E and Ē, the specular layer's and the coat's E_s, E_c, Ē) may be off by DE = 1.5e-3, as
  for roughconductor_multiscatter.jsonl (README.md); each record's atol is the first-order
  change of its value under that error (the compensation term × DE (1/(1 − E(μo)) +
  1/(1 − E(μi)) + 1/(1 − Ē)), the glass's split x adding 2 DE/(1 − Ē±); the scaled diffuse
  × DE (1/(1 − E_s(μo)) + 1/(1 − E_s(μi)) + 1/(1 − Ē_s)); the coat's through factor × C·A·DE,
  its darkening × 4 DE); a pair whose allowance exceeds 25 % of its term is skipped;
* the EON normalisation adds EON_NORM_TOL = 2e-3 relative (gonio solves b at 64 midpoint
  nodes and interpolates linearly; EonNorm's own 24- and 40-node solutions differ by 1e-4);
* the sheen's albedo table FUZZ_DE = 1.5e-3 against the fit; the film's RGB table
  FILM_DR = 2e-4 in reflectance.
Measured against the C++ on 2026-12-05 every record is within 0.2 of its tolerance (the
largest relative differences: 8.6e-3 where the glass's compensation term dominates, seen
from inside; 1.1e-3 on the coated metal (its compensation term); ≤ 7.3e-4 elsewhere).

Not covered yet (left for later): subsurface but the thin-walled Lambertian case, anisotropy but on the metal, a rough thin-walled sheet,
specular_color on the dielectric lobes (but under a coat), the dielectric base's diffuse under a coat, darkening over any base but a bare Lambertian (E_b, the base's albedo, is
exact only there), the film on the dielectric base's diffuse scaling (per-channel E_s),
geometry_opacity between 0 and 1 over anything but the metal, fuzz over coat, and pdfs.
"""
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import models_reference as R  # noqa: E402

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "openpbr.jsonl")
DE = 1.5e-3  # the albedo tables' interpolation error allowed for (README.md)
# gonio's per-material table of an anisotropic distribution's E(μ, φ) (anisotropic_albedo.h):
# its quadrature and bilinear interpolation error allowed for.
DE_ANISO = 4e-3
FUZZ_DE = 1.5e-3  # gonio's tabulated sheen albedo against the fit R(μ, r)
EON_NORM_TOL = 2e-3
FILM_DR = 2e-4  # gonio's RGB film table (the film's own spectrum reduced, interpolated in cosine) against the exact reduction


def r12(x): return float(f"{x:.12g}")
def vec12(v): return [r12(c) for c in v]


# --- the dielectric interface: SPEC-OPB "Specular" and the single-scattering albedos ------
def modulated_ior(eta, xi):
    """SPEC-OPB eqs. `unmodulated_fresnel`, `modulated_ior`: F_s = ((1 − η)/(1 + η))², the
    index whose normal-incidence reflectance is ξ F_s, of η's side of 1:
    ε = sgn(η − 1) sqrt(ξ F_s), η' = (1 + ε)/(1 − ε) (ξ F_s capped just below 1)."""
    fs = ((1 - eta) / (1 + eta)) ** 2
    s = math.sqrt(min(max(xi * fs, 0.0), 0.99999))
    e = s if eta >= 1 else -s
    return (1 + e) / (1 - e)


def tirfix(eta):
    """SPEC-OPB eq. `specular_ior_ratio_with_tir_fix`: an index below 1 reflects as its inverse."""
    return 1 / eta if eta < 1 else eta


_ALB = {}
def dielectric_albedo(alpha, mu, eta, transmit=True, n_t=24, n_phi=48):
    """Single-scattering albedo of the isotropic GGX interface of relative index eta seen
    from wo at cosine mu (importance mode, no (n_wo/n_wi)²: the energy returned):
      E = ∫ D(m) G2(wo, w) (wo·m)/μo [F(wo·m) for w = wr above + (1 − F) for w = wt below] dωm,
    wr the mirror (Walter et al. 2007 eqs. 13-14), wt the refraction (eq. 40) about m, F the
    exact Fresnel (TIR included); reflection only when not transmit (then F of the
    specular layer). Integrated as models_reference.albedo_E is, in (θm, φm) with
    Gauss–Legendre in θm between the cut-offs where wr or wt cross the horizon, wo·m = 0
    and the critical facet cosine (each found by a sign scan and bisection), so each piece
    is smooth. With F = 1 it reproduces albedo_E to 1e-15 (the same quadrature)."""
    key = (alpha, mu, eta, transmit, n_t, n_phi)
    if key in _ALB: return _ALB[key]
    mf = R.Microfacet("ggx", alpha, alpha)
    wo = (math.sqrt(max(0.0, 1 - mu * mu)), 0.0, mu)
    c_crit = math.sqrt(1 - eta * eta) if eta < 1 else None
    half = math.pi / 2

    def parts(t, ph):
        m = R.sph(t, ph)
        c = R.dot(wo, m)
        wr = R.add(R.scale(m, 2 * c), R.neg(wo))
        ct = math.sqrt(max(0.0, 1 - (1 - c * c) / (eta * eta)))
        wt = R.add(R.scale(R.neg(wo), 1 / eta), R.scale(m, c / eta - ct))
        return m, c, wr, wt

    def edges(ph):
        fns = [lambda t: parts(t, ph)[1], lambda t: parts(t, ph)[2][2]]
        if transmit: fns.append(lambda t: -parts(t, ph)[3][2])
        if c_crit is not None: fns.append(lambda t: parts(t, ph)[1] - c_crit)
        grid = [half * k / 96 for k in range(97)]
        cuts = set()
        for fn in fns:
            vals = [fn(t) for t in grid]
            for a, b, va, vb in zip(grid, grid[1:], vals, vals[1:]):
                if (va > 0) == (vb > 0): continue
                lo, hi = a, b
                for _ in range(60):
                    mid = (lo + hi) / 2
                    if (fn(mid) > 0) == (va > 0): lo = mid
                    else: hi = mid
                cuts.add((lo + hi) / 2)
        return cuts

    total = 0.0
    for j in range(n_phi + 1):  # symmetric about φ = 0: [0, π], doubled
        ph = math.pi * j / n_phi
        w_phi = (0.5 if j in (0, n_phi) else 1.0) * (math.pi / n_phi)
        cuts = sorted({0.0, half} | edges(ph) | {math.atan(k * alpha) for k in (0.5, 1, 2, 4)})
        inner = 0.0
        for a, b in zip(cuts, cuts[1:]):
            if b <= a: continue
            xs, ws = R.gauss_legendre(n_t, a, b)
            for t, w in zip(xs, ws):
                m, c, wr, wt = parts(t, ph)
                if c <= 0: continue
                F = R.fresnel(c, eta)
                g = F * mf.G2(wo, wr) if wr[2] > 0 else 0.0
                if transmit and F < 1 and wt[2] < 0: g += (1 - F) * mf.G2(wo, wt)
                inner += w * math.sin(t) * mf.D(m) * g * c / mu
        total += w_phi * inner
    _ALB[key] = 2 * total
    return _ALB[key]


_AVG = {}
def dielectric_albedo_avg(alpha, eta, transmit=True):
    """Ē = 2 ∫ E(μ) μ dμ (16-point Gauss–Legendre in μ)."""
    key = (alpha, eta, transmit)
    if key not in _AVG:
        _AVG[key] = R.cosine_average(lambda mu: dielectric_albedo(alpha, mu, eta, transmit), n=16)
    return _AVG[key]


def fresnel_avg(eta):
    """F̄(η) = 2 ∫ F(μ) μ dμ, split at the critical cosine (a square-root edge) when η < 1."""
    cuts = (0.0, math.sqrt(1 - eta * eta), 1.0) if eta < 1 else (0.0, 1.0)
    return R.cosine_average(lambda mu: R.fresnel(mu, eta), n=64, pieces=cuts)


def upper_direction(rng):
    c = rng.uniform(0.1, 1.0)
    ph = rng.uniform(0, 2 * math.pi)
    s = math.sqrt(1 - c * c)
    return R.norm(tuple(vec12((s * math.cos(ph), s * math.sin(ph), c))))


def metal_of(opb):
    """The standalone conductor an openpbr metal reduces to, and its overall factor."""
    r = opb.get("specular_roughness", 0.3)
    bw = opb.get("base_weight", 1.0)
    f0 = [bw * c for c in R.col(opb.get("base_color", 0.8))]
    cond = {"type": "roughconductor", "alpha": r * r, "fresnel": "f82", "f0": f0,
            "f82": R.col(opb.get("specular_color", 1.0)), "multiscatter": True}
    factor = opb.get("geometry_opacity", 1.0) * opb.get("specular_weight", 1.0)
    return cond, factor


def metal_records(opb, rng, n):
    cond, factor = metal_of(opb)
    parts = R.multiscatter_parts(cond)
    recs = []
    while len(recs) < n:
        wo, wi = upper_direction(rng), upper_direction(rng)
        eo, ei = (R.albedo_E("ggx", cond["alpha"], w[2]) for w in (wo, wi))
        allowance = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - parts[1]))
        if allowance > 0.25: continue
        single = R.roughconductor_single(cond, wo, wi)
        ms = R.roughconductor_ms_term(cond, wo, wi, parts)
        f = [factor * (a + b) for a, b in zip(single, ms)]
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        rec = {"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
               "rtol": 1e-4, "atol": [r12(factor * allowance * m + 1e-7) for m in ms]}
        recs.append(rec)
    return recs


# --- transmission: the rough dielectric with its Kulla–Conty lobe ---------------------------
def glass_of(opb):
    """SPEC-OPB "Translucent base", docs/openpbr.md "Structure": transmission_weight 1 (no
    metal, coat, fuzz) leaves f_glass, the rough dielectric of α = r² and the index
    specular_ior modulated by specular_weight (eq. `modulated_ior`), with its multiple-
    scattering compensation (docs/design/dielectric-multiscatter.md, Kulla & Conty 2017);
    the reflection from outside tinted by specular_color, the refraction by
    transmission_color (transmission_depth 0), the whole by geometry_opacity."""
    r = opb.get("specular_roughness", 0.3)
    eta = modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0))
    return {"type": "roughdielectric", "alpha": r * r, "eta": eta}


class GlassMs:
    """Kulla & Conty 2017's dielectric compensation as docs/design/dielectric-multiscatter.md
    formulates it (importance mode, + outside, − inside, η = n_in/n_out):
      reflection ±: r± (1 − E±(μo))(1 − E±(μi)) / (π (1 − Ē±))
      transmission out→in: t₊ (1 − E₊(μo))(1 − E₋(μi)) / (π (1 − Ē₋)), in→out: t₋ (…₋)(…₊)/(π(1 − Ē₊)),
      t₊ = (1 − F̄(η)) x, t₋ = (1 − F̄(1/η))(1 − x), r = 1 − t, x = (1 − Ē₋)/((1 − Ē₊) + (1 − Ē₋)).
    Radiance mode is the adjoint, f_rad(wo, wi) = f_imp(wi, wo) (Veach 1997 §5.2)."""
    def __init__(self, alpha, eta):
        self.alpha, self.eta = alpha, eta
        self.e_avg = {True: dielectric_albedo_avg(alpha, eta), False: dielectric_albedo_avg(alpha, 1 / eta)}
        mo, mi = 1 - self.e_avg[True], 1 - self.e_avg[False]
        x = mi / (mo + mi)
        self.t = {True: (1 - fresnel_avg(eta)) * x, False: (1 - fresnel_avg(1 / eta)) * (1 - x)}

    def E(self, outside, mu):
        return dielectric_albedo(self.alpha, mu, self.eta if outside else 1 / self.eta)

    def f_imp(self, wo, wi):
        so, si = wo[2] > 0, wi[2] > 0
        split = (1 - self.t[so]) if so == si else self.t[so]
        return split * (1 - self.E(so, abs(wo[2]))) * (1 - self.E(si, abs(wi[2]))) / (math.pi * (1 - self.e_avg[si]))

    def f(self, wo, wi, mode):
        return self.f_imp(wo, wi) if mode == "importance" else self.f_imp(wi, wo)

    def allowance(self, wo, wi):
        """Relative error of the term from gonio's interpolated tables (DE in each E and
        Ē; the split x and (1 − Ē) move by at most DE/(1 − Ē) each)."""
        so, si = wo[2] > 0, wi[2] > 0
        return DE * (1 / (1 - self.E(so, abs(wo[2]))) + 1 / (1 - self.E(si, abs(wi[2])))
                     + 2 / (1 - self.e_avg[True]) + 2 / (1 - self.e_avg[False]))


def direction_on(rng, upper):
    w = upper_direction(rng)
    return w if upper else (w[0], w[1], -w[2])


def sensitivity_of(fn, wo, wi, rng):
    """Largest relative change of fn when the directions move by float rounding (the C++
    holds them in float): a narrow lobe needs a wider rtol (20× this, as make_reference_data)."""
    base, worst = fn(wo, wi), 0.0
    for _ in range(3):
        pert = lambda w: R.norm(tuple(c * (1 + rng.uniform(-1.2e-7, 1.2e-7)) for c in w))
        g = fn(pert(wo), pert(wi))
        if abs(base) > 1e-30: worst = max(worst, abs(g - base) / abs(base))
    return worst


def glass_records(opb, rng, n):
    """Reflection and transmission pairs from outside and from inside, both modes."""
    gl = glass_of(opb)
    ms = GlassMs(gl["alpha"], gl["eta"])
    spec = R.col(opb.get("specular_color", 1.0))
    tint = R.col(opb.get("transmission_color", 1.0))
    kinds = [(True, True), (True, False), (False, True), (False, False)]
    recs = []
    while len(recs) < n:
        so, si = kinds[len(recs) % 4]
        mode = "radiance" if (len(recs) // 4) % 2 == 0 else "importance"
        wo, wi = direction_on(rng, so), direction_on(rng, si)
        single = R.roughdielectric(gl, wo, wi, mode)[0]
        if single < 1e-3: continue  # outside the lobe: keep pairs where the lobe is
        extra = ms.f(wo, wi, mode)
        allow = ms.allowance(wo, wi)
        if allow > 0.25: continue
        sens = sensitivity_of(lambda a, b: R.roughdielectric(gl, a, b, mode)[0], wo, wi, rng)
        if so == si: c = spec if so else [1.0] * 3   # reflection: tinted from outside only
        else: c = tint
        f = [k * (single + extra) for k in c]
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": r12(max(1e-4, 20 * sens)), "atol": [r12(k * allow * extra + 1e-7) for k in c]})
    return recs


# --- the dielectric base: specular layer over a Lambertian diffuse -----------------------
def dielectric_base_records(opb, rng, n):
    """docs/openpbr.md "Structure" with M = T = C = F = 0, base_diffuse_roughness 0:
      f = f_spec + ρ/π (1 − E_s(μo))(1 − E_s(μi)) / (1 − Ē_s),  ρ = base_weight·base_color,
    f_spec = specular_color F(h·wo; η_s) D G2/(4 μo μi) (Walter et al. 2007 eq. 20), η_s =
    tirfix(modulated_ior(specular_ior, specular_weight)), E_s the reflection-only albedo of
    that lobe with the untinted F (SPEC-OPB "Glossy-diffuse": N = 1/(1 − Ē_s) for Lambert,
    docs/openpbr.md "Layering, per layer"). Reciprocal: both modes give the same f."""
    r = opb.get("specular_roughness", 0.3)
    alpha = r * r
    eta = tirfix(modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0)))
    rho = [opb.get("base_weight", 1.0) * c for c in R.col(opb.get("base_color", 0.8))]
    spec = R.col(opb.get("specular_color", 1.0))
    e_avg = dielectric_albedo_avg(alpha, eta, transmit=False)
    lobe = {"type": "roughconductor", "alpha": alpha, "eta": [eta] * 3, "k": [0.0] * 3}
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        single = R.roughconductor_single(lobe, wo, wi)[0]  # F of index η, k = 0: the dielectric's
        eo, ei = (dielectric_albedo(alpha, w[2], eta, transmit=False) for w in (wo, wi))
        scale = (1 - eo) * (1 - ei) / (1 - e_avg)
        diff = [p / math.pi * scale for p in rho]
        sens = sensitivity_of(lambda a, b: R.roughconductor_single(lobe, a, b)[0], wo, wi, rng)
        spec_f = [k * single for k in spec]
        allow = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - e_avg))
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi),
                     "f": vec12([a + b for a, b in zip(spec_f, diff)]),
                     "rtol": r12(max(1e-4, 20 * sens * max(sf / (sf + d) for sf, d in zip(spec_f, diff)))),
                     "atol": [r12(allow * d + 1e-7) for d in diff]})
    return recs


# --- thin-walled transmission: the smooth sheet ------------------------------------------
def sheet_samples(opb, rng, n):
    """geometry_thin_walled, transmission_weight 1, specular_roughness 0 (SPEC-OPB
    "Thin-walled case"; docs/openpbr.md "Structure": the `thindielectric` sheet of the
    specular layer's index η_s = tirfix(modulated_ior(specular_ior, specular_weight))):
    two delta lobes, the mirror with R and the straight pass with T (models_reference.
    thin_sheet: incoherent sum of the sheet's internal reflections), the reflection tinted
    by specular_color and the pass by transmission_color. The record is the lobe's
    coefficient weight × prob (the lobe choice is the sampler's), u0 = 0 for the mirror and
    u0 → 1 for the pass, both modes (the sheet does not change the index)."""
    eta = tirfix(modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0)))
    spec = R.col(opb.get("specular_color", 1.0))
    tint = R.col(opb.get("transmission_color", 1.0))
    recs = []
    while len(recs) < n:
        wo = direction_on(rng, rng.random() < 0.5)
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        Rr, Tt = R.thin_sheet(abs(wo[2]), eta)
        if len(recs) % 4 < 2:
            sample = {"wi": vec12(R.mirror_dir(wo)), "lobe": "reflection", "weight_x_prob": vec12([k * Rr for k in spec])}
            u0 = 0.0
        else:
            sample = {"wi": vec12(R.neg(wo)), "lobe": "transmission", "weight_x_prob": vec12([k * Tt for k in tint])}
            u0 = 0.999999
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "u": [u0, 0.5, 0.5],
                     "sample": sample, "rtol": 1e-4, "atol": 1e-6})
    return recs


# --- the dielectric base over EON: the separable normalisation b(μo) b(μi) -------------------
class EonNorm:
    """docs/openpbr.md "Layering, per layer": for base_diffuse_roughness r > 0 the diffuse
    under the specular layer is b(μo) b(μi) (1 − E_s(μo))(1 − E_s(μi)) f_EON, b such that
    the white base reflects exactly 1 − E_s(μo):
      b(μ) ∫₀¹ K(μ, μ') (1 − E_s(μ')) b(μ') μ' dμ' = 1,
    K the azimuthal integral of the albedo-1 EON lobe (Portsmouth, Kutz & Hill 2025):
      K = 2π A + 2 r A sinθo sinθi (1/max(μo, μi) − 1) + 2 (1 − E_F(μo))(1 − E_F(μi))/(1 − Ē_F)
    (∫ s/t dφ over the half where s > 0 gives 2 sinθo sinθi/max(μo, μi), the other half
    −2 sinθo sinθi; ρ_ms = 1 at ρ = 1). Solved here on its own terms: the continuous
    equation at n Gauss–Legendre nodes by the symmetric scaling b ← b/sqrt(b Kb) to a fixed
    point, b at any μ its Nyström interpolant 1/∫ K(μ, ·)(1 − E_s) b μ'. (gonio solves the
    same condition at 64 midpoint nodes and interpolates linearly; the difference is a
    discretisation error, allowed for in the records' atol.)"""
    def __init__(self, r, alpha, eta, n=40):
        self.r, self.alpha, self.eta = r, alpha, eta
        self.A = 1 / (math.pi + (math.pi / 2 - 2 / 3) * r)
        self.ef_avg = R.eon_E_avg(r)
        self.mu, self.w = R.gauss_legendre(n, 0.0, 1.0)
        self.es = [self.E_s(m) for m in self.mu]
        self.c = [(1 - e) * m * w for e, m, w in zip(self.es, self.mu, self.w)]
        b = [1.0] * n
        for _ in range(500):
            nb = [bi / math.sqrt(bi * self._kb(m, b)) for bi, m in zip(b, self.mu)]
            done = max(abs(x - y) for x, y in zip(nb, b)) < 1e-14
            b = nb
            if done: break
        self.b = b

    def E_s(self, mu):
        return dielectric_albedo(self.alpha, mu, self.eta, transmit=False) if self.eta != 1 else 0.0

    def K(self, mo, mi):
        so, si = math.sqrt(1 - mo * mo), math.sqrt(1 - mi * mi)
        ms = 2 * (1 - R.eon_E(self.r, math.acos(mo))) * (1 - R.eon_E(self.r, math.acos(mi))) / (1 - self.ef_avg)
        return 2 * math.pi * self.A + 2 * self.r * self.A * so * si * (1 / max(mo, mi) - 1) + ms

    def _kb(self, mo, b):
        return sum(self.K(mo, m) * c * bj for m, c, bj in zip(self.mu, self.c, b))

    def at(self, mu):
        return 1 / self._kb(mu, self.b)


def eon_base_records(opb, rng, n):
    """The dielectric base with base_diffuse_roughness r > 0:
      f = f_spec + b(μo) b(μi) (1 − E_s(μo))(1 − E_s(μi)) f_EON(ρ, r)   (EonNorm; f_spec as
    in dielectric_base_records; f_EON models_reference.eon). Reciprocal, both modes."""
    r_s = opb.get("specular_roughness", 0.3)
    alpha = r_s * r_s
    eta = tirfix(modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0)))
    rho = [opb.get("base_weight", 1.0) * c for c in R.col(opb.get("base_color", 0.8))]
    rd = opb["base_diffuse_roughness"]
    norm_ = EonNorm(rd, alpha, eta)
    lobe = {"type": "roughconductor", "alpha": alpha, "eta": [eta] * 3, "k": [0.0] * 3}
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        single = R.roughconductor_single(lobe, wo, wi)[0]
        eo, ei = (norm_.E_s(w[2]) for w in (wo, wi))
        scale = norm_.at(wo[2]) * norm_.at(wi[2]) * (1 - eo) * (1 - ei)
        diff = [d * scale for d in R.eon({"roughness": rd, "reflectance": rho}, wo, wi, mode)]
        sens = sensitivity_of(lambda a, b: R.roughconductor_single(lobe, a, b)[0], wo, wi, rng)
        allow = DE * (1 / (1 - eo) + 1 / (1 - ei)) + EON_NORM_TOL
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi),
                     "f": vec12([single + d for d in diff]),
                     "rtol": r12(max(1e-4, 20 * sens * max(single / (single + d) for d in diff))),
                     "atol": [r12(allow * d + 1e-7) for d in diff]})
    return recs


# --- coat over a base --------------------------------------------------------------------
def coat_albedo_seen(opb, ac, eta_c, wo, wi, v, metal):
    """The coat's albedo E_c that the layers below see: OpenPBR's view-dependent form,
    E_c(v) (v = wo in radiance mode, wi in importance mode), or, with gonio's extension
    `reciprocal_layering` (docs/openpbr.md), 1 − t_c from both directions' albedos: for a
    diffuse base t_c = (1 − E_o)(1 − E_i)/(1 − Ē_c), for a specular one min(1 − E_o, 1 − E_i)."""
    if not opb.get("reciprocal_layering", False):
        return dielectric_albedo(ac, v[2], eta_c, transmit=False)
    eo_c = dielectric_albedo(ac, wo[2], eta_c, transmit=False)
    ei_c = dielectric_albedo(ac, wi[2], eta_c, transmit=False)
    t_c = (min(1 - eo_c, 1 - ei_c) if metal
           else (1 - eo_c) * (1 - ei_c) / (1 - dielectric_albedo_avg(ac, eta_c, transmit=False)))
    return 1 - t_c


def coat_records(opb, rng, n):
    """docs/openpbr.md "Structure" with F = 0 (SPEC-OPB "Coat", eq.
    `coat_layering_formula_with_albedo_scaling`):
      f = C f_coat + lerp(1, A (1 − E_c(v)), C) Δ f_base,  v = wo (radiance) or wi (importance),
    f_coat = F(h·wo; η_c) D G2/(4 μo μi) (α_c = r_c², η_c = coat_ior), E_c its reflection-only
    albedo, A = coat_color^((1/μt_o + 1/μt_i)/2) with μt the cosine refracted into the coat
    (SPEC-OPB "View-dependent absorption"). Two bases, each reduced to a standalone lobe:
    * metal (base_metalness 1, coat_darkening 0, Δ = 1): f_base = ξ f_conductor of the
      roughened r' = lerp(r, min(1, r⁴ + 2 r_c⁴)^¼, C) (SPEC-OPB "Roughening"; the metal's
      F82 is not changed by the coat);
    * Lambert with no specular layer (specular_weight 0: ξ F_s = 0, η' = 1, E_s = 0): f_base =
      ρ/π, and darkening Δ = lerp(1, (1 − K)/(1 − ρ K), C·coat_darkening), K = 1 − (1 −
      Ē_c)/η_c² (SPEC-OPB "Darkening"; E_b = ρ is this base's albedo exactly)."""
    C = opb.get("coat_weight", 0.0)
    rc = opb.get("coat_roughness", 0.0)
    ac, eta_c = rc * rc, tirfix(opb.get("coat_ior", 1.6))
    coat_lobe = {"type": "roughconductor", "alpha": ac, "eta": [eta_c] * 3, "k": [0.0] * 3}
    kappa = R.col(opb.get("coat_color", 1.0))
    metal = opb.get("base_metalness", 0) == 1
    if metal:
        rb = opb.get("specular_roughness", 0.3)
        rr = rb + (min(1.0, rb ** 4 + 2 * rc ** 4) ** 0.25 - rb) * C
        cond, factor = metal_of({**opb, "specular_roughness": rr})
        parts = R.multiscatter_parts(cond)
        delta = [1.0] * 3
    else:
        rho = [opb.get("base_weight", 1.0) * c for c in R.col(opb.get("base_color", 0.8))]
        e_avg_c = dielectric_albedo_avg(ac, eta_c, transmit=False)
        K = 1 - (1 - e_avg_c) / (eta_c * eta_c)
        t = C * opb.get("coat_darkening", 1.0)
        delta = [1 + ((1 - K) / (1 - p * K) - 1) * t for p in rho]

    def mu_t(mu): return math.sqrt(1 - (1 - mu * mu) / (eta_c * eta_c))
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        v = wo if mode == "radiance" else wi
        A = [k ** ((1 / mu_t(wo[2]) + 1 / mu_t(wi[2])) / 2) for k in kappa]
        ec = coat_albedo_seen(opb, ac, eta_c, wo, wi, v, metal)
        through = [1 - C + C * a * (1 - ec) for a in A]
        fc = C * R.roughconductor_single(coat_lobe, wo, wi)[0]
        if metal:
            eo, ei = (R.albedo_E("ggx", cond["alpha"], w[2]) for w in (wo, wi))
            allowance = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - parts[1]))
            if allowance > 0.25: continue
            single = R.roughconductor_single(cond, wo, wi)
            ms = R.roughconductor_ms_term(cond, wo, wi, parts)
            base = [factor * (a + b) for a, b in zip(single, ms)]
            base_atol = [factor * allowance * m for m in ms]
        else:
            base = [p / math.pi for p in rho]
            base_atol = [0.0] * 3
        f = [fc + th * d * b for th, d, b in zip(through, delta, base)]
        # E_c(v) and Ē_c go through gonio's table (DE each): the through factor moves by
        # C·A·DE, Δ by |dΔ/Δ| = (1 − ρ) dK/((1 − ρK)(1 − K)) ≤ DE/(η_c² (1 − K)²) relative
        # (dK = dĒ_c/η_c²), below 4 DE for the coats of main() (1 − K ≥ 0.35).
        # (reciprocal_layering: three table albedos in the through factor, each over 1 − Ē_c
        # or a square root: 4 DE.)
        k_rl = 4 if opb.get("reciprocal_layering", False) else 1
        atol = [th * d * ba + C * a * k_rl * DE * d * abs(b) + 4 * DE * th * abs(b) * (d != 1.0) + 1e-7
                for th, d, b, ba, a in zip(through, delta, base, base_atol, A)]
        sens = sensitivity_of(lambda a, b: R.roughconductor_single(coat_lobe, a, b)[0], wo, wi, rng)
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": r12(max(1e-4, 20 * sens * max(fc / x for x in f))), "atol": [r12(x) for x in atol]})
    return recs


def coat_over_specular_records(opb, rng, n):
    """The coat over the dielectric base's specular layer alone (base_weight 0: a black
    diffuse; coat_darkening 0: Δ = 1), so that the base's Fresnel sees the coat
    (SPEC-OPB "Coat", eq. `specular_ior_ratio_with_tir_fix`):
      η_s = tirfix(modulated(lerp(n_b, tirfix(n_b/n_c), C), ξ)),  r' = lerp(r, min(1, r⁴ + 2 r_c⁴)^¼, C),
      f = C f_coat + lerp(1, A (1 − E_c(v)), C) specular_color F(h·wo; η_s) D G2/(4 μo μi) (α = r'²),
    f_coat, E_c and A as in coat_records. Both modes."""
    C = opb.get("coat_weight", 0.0)
    rc = opb.get("coat_roughness", 0.0)
    ac, eta_c = rc * rc, tirfix(opb.get("coat_ior", 1.6))
    coat_lobe = {"type": "roughconductor", "alpha": ac, "eta": [eta_c] * 3, "k": [0.0] * 3}
    kappa = R.col(opb.get("coat_color", 1.0))
    rb = opb.get("specular_roughness", 0.3)
    rr = rb + (min(1.0, rb ** 4 + 2 * rc ** 4) ** 0.25 - rb) * C
    nb = opb.get("specular_ior", 1.5)
    eta_s = tirfix(modulated_ior(nb + (tirfix(nb / opb.get("coat_ior", 1.6)) - nb) * C, opb.get("specular_weight", 1.0)))
    spec_lobe = {"type": "roughconductor", "alpha": rr * rr, "eta": [eta_s] * 3, "k": [0.0] * 3}
    tint = R.col(opb.get("specular_color", 1.0))

    def mu_t(mu): return math.sqrt(1 - (1 - mu * mu) / (eta_c * eta_c))
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        v = wo if mode == "radiance" else wi
        A = [k ** ((1 / mu_t(wo[2]) + 1 / mu_t(wi[2])) / 2) for k in kappa]
        ec = coat_albedo_seen(opb, ac, eta_c, wo, wi, v, True)  # a specular lobe below: the min form
        through = [1 - C + C * a * (1 - ec) for a in A]
        fc = C * R.roughconductor_single(coat_lobe, wo, wi)[0]
        fs = R.roughconductor_single(spec_lobe, wo, wi)[0]
        f = [fc + th * t * fs for th, t in zip(through, tint)]
        # E_c(v) goes through gonio's table (DE): the through factor moves by C·A·DE.
        atol = [C * a * DE * t * fs + 1e-7 for a, t in zip(A, tint)]
        sc = sensitivity_of(lambda a, b: R.roughconductor_single(coat_lobe, a, b)[0], wo, wi, rng)
        ss = sensitivity_of(lambda a, b: R.roughconductor_single(spec_lobe, a, b)[0], wo, wi, rng)
        rel = max(sc * fc / min(f), ss * max(th * t * fs for th, t in zip(through, tint)) / min(f))
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": r12(max(1e-4, 20 * rel)), "atol": [r12(x) for x in atol]})
    return recs


# --- fuzz over a base --------------------------------------------------------------------
def fuzz_records(opb, rng, n):
    """docs/openpbr.md "Structure" with C = 0 over the metal (SPEC-OPB "Fuzz", eq.
    `fuzz-layering-approx`):
      f = F f_sheen + (1 − F E_fuzz(v)) ξ f_conductor,  v = wo (radiance) or wi (importance),
    f_sheen models_reference.sheen (Zeltner et al. 2022, color fuzz_color, roughness
    fuzz_roughness) and E_fuzz its directional albedo R(μ_v, r), the fits' dir_albedo (the
    LTC lobe integrates to 1, so ∫ f_sheen μi dωi = R with a white colour)."""
    Fw = opb.get("fuzz_weight", 0.0)
    fr = opb.get("fuzz_roughness", 0.5)
    sheen = {"type": "sheen", "color": R.col(opb.get("fuzz_color", 1.0)), "roughness": fr}
    cond, factor = metal_of(opb)
    parts = R.multiscatter_parts(cond)
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        v = wo if mode == "radiance" else wi
        through = 1 - Fw * R.sheen_fits(min(v[2], 1.0), fr)[2]
        eo, ei = (R.albedo_E("ggx", cond["alpha"], w[2]) for w in (wo, wi))
        allowance = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - parts[1]))
        if allowance > 0.25: continue
        single = R.roughconductor_single(cond, wo, wi)
        ms = R.roughconductor_ms_term(cond, wo, wi, parts)
        base = [factor * (a + b) for a, b in zip(single, ms)]
        fz = [Fw * x for x in R.sheen(sheen, wo, wi, mode)]
        f = [a + through * b for a, b in zip(fz, base)]
        # E_fuzz through gonio's albedo table (FUZZ_DE) and the metal's compensation (DE)
        atol = [through * factor * allowance * m + Fw * FUZZ_DE * b + 1e-7 for m, b in zip(ms, base)]
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": 1e-4, "atol": [r12(x) for x in atol]})
    return recs


# --- thin film on the dielectric specular layer ----------------------------------------------
def film_records(opb, rng, n):
    """docs/openpbr.md "Structure" / SPEC-OPB "Thin film" over a black base (base_weight 0:
    the diffuse term is 0 whatever its scaling), so only the specular layer is left:
      f = specular_color [(1 − w) F(h·wo; η_s) + w R_film(h·wo)] D G2/(4 μo μi),
    w = thin_film_weight, R_film the Airy sum of a film of index thin_film_ior and thickness
    thin_film_thickness (µm) on the substrate of index η_s, reduced to linear sRGB under D65
    (thin_film_reference.film_rgb; Belcour & Barla 2017 eq. 1). Reciprocal, both modes."""
    import thin_film_reference as TF
    r = opb.get("specular_roughness", 0.3)
    alpha = r * r
    eta = tirfix(modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0)))
    w = opb.get("thin_film_weight", 0.0)
    nf, d = opb.get("thin_film_ior", 1.4), 1000 * opb.get("thin_film_thickness", 0.5)
    spec = R.col(opb.get("specular_color", 1.0))
    mf = R.Microfacet("ggx", alpha, alpha)
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), upper_direction(rng)
        m = R.norm(R.add(wo, wi))
        c = R.dot(wo, m)
        lobe = mf.D(m) * mf.G2(wo, wi) / (4 * wo[2] * wi[2])
        rf = TF.film_rgb(c, nf, d, lambda lam: (eta, 0.0))
        F = R.fresnel(c, eta)
        f = [k * ((1 - w) * F + w * x) * lobe for k, x in zip(spec, rf)]
        sens = sensitivity_of(lambda a, b: R.roughconductor_single(
            {"alpha": alpha, "eta": [eta] * 3, "k": [0.0] * 3}, a, b)[0], wo, wi, rng)
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": r12(max(1e-4, 20 * sens)), "atol": [r12(k * w * FILM_DR * lobe + 1e-7) for k in spec]})
    return recs


# --- thin film on the metal ------------------------------------------------------------------
def gulbrandsen(r, g):
    """Gulbrandsen 2014 ("Artist Friendly Metallic Fresnel", JCGT 3(4)): the index of
    reflectivity r at normal incidence and edge parameter g, n between n_max (g = 0, k = 0)
    and n_min (g = 1)."""
    n_min, n_max = (1 - r) / (1 + r), (1 + math.sqrt(r)) / (1 - math.sqrt(r))
    n = g * n_min + (1 - g) * n_max
    return n, math.sqrt(max(0.0, (r * (n + 1) ** 2 - (n - 1) ** 2) / (1 - r)))


def effective_index(f0, tint):
    """SPEC-OPB "Thin-film iridescence" (the F82-tint metal's "best matching effective
    complex IOR", after Gulbrandsen 2014), as docs/openpbr.md states it: Gulbrandsen's member
    whose exact Fresnel at μ = 1/7 is F82-tint's there (tint × Schlick), g by bisection,
    the nearer end of [0, 1] where out of reach."""
    target = R.f82_tint(1 / 7, f0, 1.0) * tint
    at = lambda g: R.fresnel(1 / 7, *gulbrandsen(f0, g))
    if at(0.0) >= target: return gulbrandsen(f0, 0.0)
    if at(1.0) <= target: return gulbrandsen(f0, 1.0)
    lo, hi = 0.0, 1.0
    for _ in range(100):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if at(mid) < target else (lo, mid)
    return gulbrandsen(f0, (lo + hi) / 2)


def metal_film_records(opb, rng, n):
    """The film on the metal (base_metalness 1, no coat or fuzz; docs/openpbr.md "Structure"),
    grey base_color and specular_color, whose upsampled spectra are constant, so that the
    substrate under the film is one effective index (n, k) at every wavelength:
      f = ξ [F(h·wo) D G2/(4 μo μi) + F_ms (1 − E(μo))(1 − E(μi))/(π (1 − Ē))],
      F = (1 − w) F82(c) + w R_film(c),  F_ms = F̄² Ē/(1 − F̄ (1 − Ē)),  F̄ = 2 ∫ F μ dμ,
    w = thin_film_weight, R_film the film's Airy sum over (n, k) reduced to linear sRGB
    (thin_film_reference.film_rgb), Kulla & Conty 2017 with the mixture's F̄. Both modes."""
    import thin_film_reference as TF
    r = opb["specular_roughness"]
    alpha = r * r
    f0, tint = opb.get("base_weight", 1.0) * opb["base_color"], opb["specular_color"]
    w, nf, d = opb["thin_film_weight"], opb.get("thin_film_ior", 1.4), 1000 * opb.get("thin_film_thickness", 0.5)
    xi = opb.get("specular_weight", 1.0)
    nk = effective_index(f0, tint)

    def fresnel_mix(c):
        return [(1 - w) * R.f82_tint(c, f0, tint) + w * x for x in TF.film_rgb(c, nf, d, lambda lam: nk)]
    f_nodes = {}
    def channel(c, j):
        if c not in f_nodes: f_nodes[c] = fresnel_mix(c)
        return f_nodes[c][j]
    f_avg = [R.cosine_average(lambda mu, j=j: channel(mu, j), n=24) for j in range(3)]
    e_avg = R.albedo_E_avg("ggx", alpha)
    f_ms = [fa * fa * e_avg / (1 - fa * (1 - e_avg)) for fa in f_avg]
    mf = R.Microfacet("ggx", alpha, alpha)
    recs = []
    while len(recs) < n:
        wo, wi = upper_direction(rng), upper_direction(rng)
        eo, ei = (R.albedo_E("ggx", alpha, v[2]) for v in (wo, wi))
        allowance = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - e_avg))
        if allowance > 0.25: continue
        m = R.norm(R.add(wo, wi))
        lobe = mf.D(m) * mf.G2(wo, wi) / (4 * wo[2] * wi[2])
        F = fresnel_mix(R.dot(wo, m))
        ms = [fm * (1 - eo) * (1 - ei) / (math.pi * (1 - e_avg)) for fm in f_ms]
        f = [xi * (a * lobe + b) for a, b in zip(F, ms)]
        sens = sensitivity_of(lambda a, b: R.roughconductor_single(
            {"alpha": alpha, "eta": [nk[0]] * 3, "k": [nk[1]] * 3}, a, b)[0], wo, wi, rng)
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        # The table's FILM_DR in F moves the lobe by w FILM_DR lobe, and in F̄ moves F_ms by at
        # most (2 − F̄ (1 − Ē))/(F̄ (1 − F̄ (1 − Ē))) w FILM_DR relative: below 4 here (F̄ > 0.6).
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12(f),
                     "rtol": r12(max(1e-4, 20 * sens)),
                     "atol": [r12(xi * (allowance * b + w * FILM_DR * (lobe + 4 * b)) + 1e-7) for b in ms]})
    return recs


# --- anisotropy: the metal's anisotropic, rotated lobe -----------------------------------------
def aniso_metal_records(opb, rng, n):
    """SPEC-OPB "Anisotropy", eq. `openpbr-anisotropy-formula`: α_t = r² sqrt(2/(1 + (1 − a)²))
    along the tangent and α_b = (1 − a) α_t, a = specular_roughness_anisotropy, the tangent
    turned by specular_rotation (gonio's extension, docs/openpbr.md: a fraction of a turn
    counterclockwise about the normal, so a direction's coordinates in the lobe's frame are
    (c x + s y, −s x + c y, z)). f = ξ (f_single + f_ms) with F82-tint and Kulla & Conty's
    lobe f_ms = F_ms (1 − E(wo))(1 − E(wi)) / (π (1 − Ē)) of the anisotropic distribution's
    own E(ω) (issue 55 §4; models_reference.albedo_E_dir, which integrates it at each
    direction; gonio tabulates it over (μ, φ): DE_ANISO allows for that). Both modes."""
    r, a = opb["specular_roughness"], opb["specular_roughness_anisotropy"]
    at = r * r * math.sqrt(2 / (1 + (1 - a) ** 2))
    ab = (1 - a) * at
    turn = 2 * math.pi * opb.get("specular_rotation", 0.0)
    c, s = math.cos(turn), math.sin(turn)
    rot = lambda w: (c * w[0] + s * w[1], -s * w[0] + c * w[1], w[2])
    bw = opb.get("base_weight", 1.0)
    cond = {"type": "roughconductor", "alpha": [at, ab], "fresnel": "f82",
            "f0": [bw * x for x in R.col(opb.get("base_color", 0.8))], "f82": R.col(opb.get("specular_color", 1.0))}
    mf = R.distribution_of(cond)
    f_avg = [R.f82_average(f0, t) for f0, t in zip(cond["f0"], cond["f82"])]
    e_avg = R.albedo_E_avg_dir(mf)
    f_ms = [fa * fa * e_avg / (1 - fa * (1 - e_avg)) for fa in f_avg]
    xi = opb.get("specular_weight", 1.0)
    recs = []
    while len(recs) < n:
        wo, wi = upper_direction(rng), upper_direction(rng)
        eo, ei = R.albedo_E_dir(mf, rot(wo)), R.albedo_E_dir(mf, rot(wi))
        allowance = DE_ANISO * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - e_avg))
        single = R.roughconductor_single(cond, rot(wo), rot(wi))
        ms = [fm * (1 - eo) * (1 - ei) / (math.pi * (1 - e_avg)) for fm in f_ms]
        sens = sensitivity_of(lambda u, v: R.roughconductor_single(cond, rot(u), rot(v))[0], wo, wi, rng)
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi),
                     "f": vec12([xi * (x + m) for x, m in zip(single, ms)]),
                     "rtol": r12(max(1e-4, 20 * sens)), "atol": [r12(xi * allowance * m + 1e-7) for m in ms]})
    return recs


# --- thin-walled diffuse transmission: the thin-walled subsurface over Lambert -------------
def thin_diffuse_records(opb, rng, n):
    """geometry_thin_walled, subsurface_weight 1, subsurface_color 1, transmission 0,
    base_diffuse_roughness 0 (SPEC-OPB "Thin-walled case"; docs/openpbr.md "Structure": the
    subsurface is ½ S (1 ∓ g) of an albedo-1 lobe reflected / transmitted, g =
    subsurface_scatter_anisotropy, under the specular layer like the diffuse):
      reflection   f_spec + (1 − g)/(2π) (1 − E_s(μo))(1 − E_s(μi))/(1 − Ē_s),
      transmission          (1 + g)/(2π) (1 − E_s(μo))(1 − E_s(|μi|))/(1 − Ē_s),
    f_spec and E_s as in dielectric_base_records. Both modes (the lobes are reciprocal)."""
    r = opb.get("specular_roughness", 0.3)
    alpha = r * r
    eta = tirfix(modulated_ior(opb.get("specular_ior", 1.5), opb.get("specular_weight", 1.0)))
    g = opb.get("subsurface_scatter_anisotropy", 0.0)
    e_avg = dielectric_albedo_avg(alpha, eta, transmit=False)
    lobe = {"type": "roughconductor", "alpha": alpha, "eta": [eta] * 3, "k": [0.0] * 3}
    recs = []
    while len(recs) < n:
        mode = "radiance" if len(recs) % 2 == 0 else "importance"
        wo, wi = upper_direction(rng), direction_on(rng, len(recs) % 4 < 2)
        eo, ei = (dielectric_albedo(alpha, abs(w[2]), eta, transmit=False) for w in (wo, wi))
        scale = (1 - eo) * (1 - ei) / (1 - e_avg)
        if wi[2] > 0:
            single = R.roughconductor_single(lobe, wo, wi)[0]
            sens = sensitivity_of(lambda a, b: R.roughconductor_single(lobe, a, b)[0], wo, wi, rng)
            diff = (1 - g) / (2 * math.pi) * scale
        else:
            single, sens, diff = 0.0, 0.0, (1 + g) / (2 * math.pi) * scale
        allow = DE * (1 / (1 - eo) + 1 / (1 - ei) + 1 / (1 - e_avg))
        recs.append({"material": opb, "mode": mode, "wo": vec12(wo), "wi": vec12(wi), "f": vec12([single + diff] * 3),
                     "rtol": r12(max(1e-4, 20 * sens * single / (single + diff))),
                     "atol": r12(allow * diff + 1e-7)})
    return recs


def main():
    rng = random.Random(135)
    recs = []
    tint = {"base_metalness": 1, "base_color": [0.95, 0.64, 0.3], "specular_color": [0.9, 0.6, 0.5]}
    for extra in ({"specular_roughness": 0.8},
                  {"specular_roughness": 0.6, "specular_weight": 0.5, "base_weight": 0.8},
                  {"specular_roughness": 0.7, "geometry_opacity": 0.4},
                  {"specular_roughness": 0.7, "specular_weight": 0}):
        recs += metal_records({"type": "openpbr", **tint, **extra}, rng, 12)
    # geometry_opacity 0: only the pass-through is left (SPEC-OPB "Geometry")
    for k in range(4):
        wo = upper_direction(rng)
        for mode in ("radiance", "importance"):
            recs.append({"material": {"type": "openpbr", "geometry_opacity": 0}, "mode": mode,
                         "wo": vec12(wo), "u": [0.25 * k + 0.1, 0.5, 0.5],
                         "sample": {"wi": vec12(R.neg(wo)), "lobe": "transmission", "weight": [1.0, 1.0, 1.0]},
                         "rtol": 1e-4, "atol": 1e-6})
    # transmission (not thin-walled): the rough dielectric with its compensation
    for extra in ({"specular_roughness": 0.5},
                  {"specular_roughness": 0.8, "specular_ior": 1.33},
                  {"specular_roughness": 0.6, "specular_weight": 0.5},
                  {"specular_roughness": 0.5, "specular_ior": 0.75},
                  {"specular_roughness": 0.7, "transmission_color": [0.9, 0.5, 0.3]}):
        recs += glass_records({"type": "openpbr", "transmission_weight": 1, **extra}, rng, 16)
    # thin-walled smooth sheet
    for extra in ({}, {"specular_ior": 1.33, "transmission_color": [0.9, 0.5, 0.3]},
                  {"specular_weight": 0.5}, {"specular_ior": 0.75}):
        recs += sheet_samples({"type": "openpbr", "geometry_thin_walled": True, "transmission_weight": 1,
                               "specular_roughness": 0, **extra}, rng, 8)
    # dielectric base over Lambert
    for extra in ({"specular_roughness": 0.4},
                  {"specular_roughness": 0.7, "specular_ior": 1.8, "base_weight": 0.7},
                  {"specular_roughness": 0.5, "specular_weight": 0.5},
                  {"specular_roughness": 0.5, "specular_ior": 0.75}):
        recs += dielectric_base_records({"type": "openpbr", "base_color": [0.9, 0.6, 0.2], **extra}, rng, 12)
    # dielectric base over EON
    for extra in ({"specular_roughness": 0.4, "base_diffuse_roughness": 0.5},
                  {"specular_roughness": 0.6, "specular_ior": 1.8, "base_diffuse_roughness": 1.0}):
        recs += eon_base_records({"type": "openpbr", "base_color": [0.9, 0.6, 0.2], **extra}, rng, 12)
    # coat over the metal (no darkening) and over a bare Lambertian base (with darkening)
    metal = {"type": "openpbr", **tint}
    for extra in ({"coat_weight": 1, "coat_roughness": 0.3, "coat_darkening": 0, "specular_roughness": 0.5},
                  {"coat_weight": 0.5, "coat_roughness": 0.5, "coat_ior": 1.8, "coat_darkening": 0,
                   "specular_roughness": 0.6, "coat_color": [0.9, 0.7, 0.5]}):
        recs += coat_records({**metal, **extra}, rng, 12)
    lam = {"type": "openpbr", "base_color": [0.9, 0.6, 0.2], "specular_weight": 0}
    for extra in ({"coat_weight": 1, "coat_roughness": 0.3, "coat_darkening": 0},
                  {"coat_weight": 1, "coat_roughness": 0.4, "coat_darkening": 1},
                  {"coat_weight": 0.6, "coat_roughness": 0.5, "coat_ior": 1.4, "coat_darkening": 0.5,
                   "coat_color": [0.8, 0.9, 0.6]}):
        recs += coat_records({**lam, **extra}, rng, 12)
    # the same with reciprocal_layering (gonio's extension): over the metal and over Lambert
    recs += coat_records({**metal, "coat_weight": 0.8, "coat_roughness": 0.3, "coat_darkening": 0,
                          "specular_roughness": 0.5, "reciprocal_layering": True}, rng, 12)
    recs += coat_records({**lam, "coat_weight": 1, "coat_roughness": 0.4, "coat_darkening": 1,
                          "reciprocal_layering": True}, rng, 12)
    # fuzz over the metal
    for extra in ({"fuzz_weight": 1, "fuzz_roughness": 0.5},
                  {"fuzz_weight": 0.6, "fuzz_roughness": 0.3, "fuzz_color": [1.0, 0.5, 0.2]}):
        recs += fuzz_records({**metal, "specular_roughness": 0.6, **extra}, rng, 12)
    # thin-walled subsurface over Lambert: diffuse reflection and transmission
    for extra in ({"subsurface_scatter_anisotropy": 0.4}, {"subsurface_scatter_anisotropy": -0.3, "specular_ior": 1.8}):
        recs += thin_diffuse_records({"type": "openpbr", "geometry_thin_walled": True, "subsurface_weight": 1,
                                      "subsurface_color": 1, "specular_roughness": 0.5, **extra}, rng, 12)
    # thin film on the specular layer over a black base
    for extra in ({"thin_film_weight": 1, "thin_film_thickness": 0.3, "thin_film_ior": 2.0},
                  {"thin_film_weight": 0.7, "thin_film_thickness": 0.45, "thin_film_ior": 1.33, "specular_ior": 1.6}):
        recs += film_records({"type": "openpbr", "base_weight": 0, "specular_roughness": 0.4, **extra}, rng, 10)
    # thin film on the metal (grey colours: one effective index at every wavelength)
    for extra in ({"thin_film_weight": 1, "thin_film_thickness": 0.35, "thin_film_ior": 1.5},
                  {"thin_film_weight": 0.6, "thin_film_thickness": 0.5, "thin_film_ior": 2.0, "specular_weight": 0.7}):
        recs += metal_film_records({"type": "openpbr", "base_metalness": 1, "base_color": 0.7, "specular_color": 0.85,
                                    "specular_roughness": 0.5, **extra}, rng, 10)
    # anisotropy on the metal, with and without a rotated tangent
    for extra in ({"specular_roughness": 0.5, "specular_roughness_anisotropy": 0.7},
                  {"specular_roughness": 0.6, "specular_roughness_anisotropy": 0.4, "specular_rotation": 0.15,
                   "specular_weight": 0.8}):
        recs += aniso_metal_records({"type": "openpbr", **tint, **extra}, rng, 12)
    # coat over the dielectric base's specular layer (its index seen through the coat)
    for extra in ({"coat_weight": 1, "coat_roughness": 0.3, "coat_ior": 1.6, "specular_ior": 1.5,
                   "specular_roughness": 0.4},
                  {"coat_weight": 0.6, "coat_roughness": 0.2, "coat_ior": 1.8, "specular_ior": 1.4,
                   "specular_roughness": 0.5, "specular_color": [1.0, 0.8, 0.6], "coat_color": [0.9, 0.8, 0.7]},
                  {"coat_weight": 1, "coat_roughness": 0.25, "coat_ior": 1.3, "specular_ior": 2.0,
                   "specular_roughness": 0.3, "specular_weight": 0.6}):
        recs += coat_over_specular_records({"type": "openpbr", "base_weight": 0, "coat_darkening": 0, **extra}, rng, 10)
    with open(OUT, "w") as fh:
        for rec in recs:
            fh.write(json.dumps(rec, sort_keys=True) + "\n")
    print(f"{OUT}: {len(recs)} records")


if __name__ == "__main__":
    main()
