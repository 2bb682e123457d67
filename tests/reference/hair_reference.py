#!/usr/bin/env python3
"""Reference values of the hair fibre (`hair`, `chiang_hair_bsdf`; include/gonio/bxdf/hair.h),
written from the papers without gonio's code, stdlib only:

  Chiang, Bitterli, Tappan & Burley 2016, "A Practical and Controllable Hair and Fur Model
  for Production Path Tracing": A_p (eq. 3-6), the trimmed logistic N_p (eqs. 11-13),
  the roughness mappings (eqs. 7-8), the colour inversion (eq. 9);
  d'Eon, Francois, Hill, Letteri & Aubry 2011: M_p as the azimuthal integral of a
  spherical Gaussian (here integrated numerically over the azimuth, not by the Bessel
  closed form the C++ uses), the melanin coefficients (eumelanin (0.419, 0.697, 1.37),
  pheomelanin (0.187, 0.4, 1.05), as pbrt-v4 gives them);
  pbrt-v4 HairBxDF for the frame (fibre along +x, f = S/|wi.z|) and the tilts (R −2α,
  TT +α, TRT +4α).
The h average is an 8-point Gauss–Legendre rule whose nodes are found here by Newton's
method on P_8; the pdf is the mixture the sampler draws (an offset w_k/2, a lobe ∝ the
channel mean of tint_p A_p, M_p, N_p; the residual uniform in azimuth).

    python3 tests/reference/hair_reference.py     # writes tests/reference/data/hair.jsonl
"""
import json
import math
import os
import random

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "hair.jsonl")


def r12(x): return float(f"{x:.12g}")


def gauss_legendre(n):
    """Nodes and weights on [-1, 1] by Newton's method on the Legendre polynomial P_n."""
    xs, ws = [], []
    for i in range(1, n + 1):
        x = math.cos(math.pi * (i - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            dp = n * (x * p1 - p0) / (x * x - 1)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-16:
                break
        xs.append(x)
        ws.append(2 / ((1 - x * x) * dp * dp))
    return xs, ws


GL_X, GL_W = gauss_legendre(8)


def fresnel(cos_i, eta):
    """Unpolarised Fresnel reflectance of a dielectric (Born & Wolf), light from outside."""
    cos_i = min(1.0, max(0.0, cos_i))
    s2 = 1 - cos_i * cos_i
    st2 = s2 / (eta * eta)
    if st2 >= 1:
        return 1.0
    ct = math.sqrt(1 - st2)
    rs = (cos_i - eta * ct) / (cos_i + eta * ct)
    rp = (eta * cos_i - ct) / (eta * cos_i + ct)
    return 0.5 * (rs * rs + rp * rp)


def mp(th_i, th_o, v, n=4096):
    """d'Eon 2011: κ/(4π sinh κ) ∫ exp(κ cos(angle to (−θo, φ=0))) dφ, κ = 1/v."""
    k = 1 / v
    s = 0.0
    for j in range(n):
        phi = 2 * math.pi * (j + 0.5) / n
        c = math.cos(th_i) * math.cos(th_o) * math.cos(phi) - math.sin(th_i) * math.sin(th_o)
        s += math.exp(k * (c - 1))
    s *= 2 * math.pi / n
    return k / (2 * math.pi * (1 - math.exp(-2 * k))) * s


_norm_cache = {}


def logistic(x, s):
    e = math.exp(-abs(x) / s)
    return e / (s * (1 + e) ** 2)


def trimmed_logistic(x, s):
    if s not in _norm_cache:
        n = 20000
        _norm_cache[s] = sum(logistic(-math.pi + 2 * math.pi * (j + 0.5) / n, s) for j in range(n)) * 2 * math.pi / n
    return logistic(x, s) / _norm_cache[s]


def variance(b): return (0.726 * b + 0.812 * b ** 2 + 3.7 * b ** 20) ** 2
def scale(b): return math.sqrt(math.pi / 8) * (0.265 * b + 1.194 * b ** 2 + 5.372 * b ** 22)


def sigma_from_color(c, bn):
    d = 5.969 - 0.215 * bn + 2.532 * bn ** 2 - 10.73 * bn ** 3 + 5.574 * bn ** 4 + 0.245 * bn ** 5
    return (math.log(c) / d) ** 2


def three(x): return list(x) if isinstance(x, list) else [x, x, x]


def model(mat):
    """(sigma_a[3], eta, h or None, v[4], s[3], tints[3][3], alpha radians)"""
    if mat["type"] == "chiang_hair_bsdf":
        vs = [mat.get(k, d) for k, d in (("roughness_R", [0.1, 0.1]), ("roughness_TT", [0.05, 0.05]),
                                            ("roughness_TRT", [0.2, 0.2]))]
        v = [min(1, max(0.001, p[0])) for p in vs]
        s = [min(1, max(0.001, p[1])) * math.sqrt(math.pi / 8) for p in vs]
        return (three(mat.get("absorption_coefficient", 0)), mat.get("ior", 1.55), mat.get("h"), v + [v[2]], s,
                [three(mat.get(k, 1)) for k in ("tint_R", "tint_TT", "tint_TRT")],
                (mat.get("cuticle_angle", 0.5) - 0.5) * math.pi)
    bm, bn = mat.get("beta_m", 0.3), mat.get("beta_n", 0.3)
    if isinstance(bm, list):
        v = [variance(b) for b in bm]
    else:
        v0 = variance(bm)
        v = [v0, v0 / 4, 4 * v0]
    s = [scale(b) for b in three(bn)]
    if "sigma_a" in mat:
        sa = three(mat["sigma_a"])
    elif "color" in mat:
        sa = [sigma_from_color(c, three(bn)[0]) for c in three(mat["color"])]
    else:
        ce = mat.get("eumelanin", 0 if "pheomelanin" in mat else 1.3)
        cp = mat.get("pheomelanin", 0)
        sa = [ce * e + cp * p for e, p in zip((0.419, 0.697, 1.37), (0.187, 0.4, 1.05))]
    return (sa, mat.get("eta", 1.55), mat.get("h"), v + [v[2]], s,
            [three(mat.get(k, 1)) for k in ("tint_R", "tint_TT", "tint_TRT")], math.radians(mat.get("alpha", 2)))


def scatter(mat, wo, wi):
    """S(wo, wi) per channel and the sampling pdf."""
    sa, eta, h, v, s, tint, alpha = model(mat)
    th_o, th_i = math.asin(max(-1, min(1, wo[0]))), math.asin(max(-1, min(1, wi[0])))
    phi = math.atan2(wi[2], wi[1]) - math.atan2(wo[2], wo[1])
    shifts = [-2 * alpha, alpha, 4 * alpha, 0]
    # the tilted θo, folded back into [−π/2, π/2] as |cos θo_p| does
    m = []
    for p in range(4):
        t = th_o + shifts[p]
        if t > math.pi / 2: t = math.pi - t
        if t < -math.pi / 2: t = -math.pi - t
        m.append(mp(th_i, t, v[p]))
    offsets = [(h, 1.0)] if h is not None else [(x, w / 2) for x, w in zip(GL_X, GL_W)]
    S, pdf = [0.0, 0.0, 0.0], 0.0
    for hh, wk in offsets:
        go = math.asin(hh)
        # Bravais' index for the projected ray; θt, γt inside the fibre
        etap = math.sqrt(eta * eta - math.sin(th_o) ** 2) / math.cos(th_o)
        gt = math.asin(hh / etap)
        ct = math.sqrt(1 - (math.sin(th_o) / eta) ** 2)
        F = fresnel(math.cos(th_o) * math.cos(go), eta)
        A = [[0.0] * 3 for _ in range(4)]
        for c in range(3):
            T = math.exp(-sa[c] * 2 * math.cos(gt) / ct)
            A[0][c] = F
            A[1][c] = (1 - F) ** 2 * T
            A[2][c] = A[1][c] * T * F
            A[3][c] = A[2][c] * T * F / (1 - T * F)
        weights = [sum(A[p][c] * tint[min(p, 2)][c] for c in range(3)) / 3 for p in range(4)]
        tot = sum(weights)
        for p in range(4):
            if p < 3:
                x = phi - (2 * p * gt - 2 * go + p * math.pi)
                x = (x + math.pi) % (2 * math.pi) - math.pi
                n = trimmed_logistic(x, s[p])
            else:
                n = 1 / (2 * math.pi)
            for c in range(3):
                S[c] += wk * m[p] * n * A[p][c] * tint[min(p, 2)][c]
            pdf += wk * weights[p] / tot * m[p] * n
    return S, pdf


def unit(rng):
    z = rng.uniform(-1, 1)
    ph = rng.uniform(0, 2 * math.pi)
    r = math.sqrt(1 - z * z)
    w = [r12(r * math.cos(ph)), r12(r * math.sin(ph)), r12(z)]
    n = math.sqrt(sum(c * c for c in w))
    return [c / n for c in w]


MATERIALS = [
    {"type": "hair"},
    {"type": "hair", "h": 0.35, "sigma_a": [0.2, 0.5, 1.2]},
    {"type": "hair", "h": -0.8, "eumelanin": 0.3, "pheomelanin": 0.6, "alpha": -6, "eta": 1.4},
    {"type": "hair", "color": [0.8, 0.55, 0.3], "beta_m": [0.25, 0.4, 0.7], "beta_n": [0.3, 0.5, 0.9]},
    {"type": "hair", "h": 0.1, "beta_m": 0.6, "beta_n": 0.7, "tint_R": [1, 0.5, 0.2], "tint_TT": 0.3, "alpha": 8},
    {"type": "chiang_hair_bsdf", "absorption_coefficient": [0.3, 0.6, 1.4], "cuticle_angle": 0.52,
     "roughness_R": [0.05, 0.4], "roughness_TT": [0.02, 0.3], "roughness_TRT": [0.2, 0.6], "h": 0.2},
]


def main():
    rng = random.Random(60)
    lines = []
    for mat in MATERIALS:
        for _ in range(12):
            wo = unit(rng)
            wi = unit(rng)
            if abs(wi[2]) < 0.02 or abs(wo[0]) > 0.995:
                continue
            S, pdf = scatter(mat, wo, wi)
            f = [x / abs(wi[2]) for x in S]
            lines.append({"material": mat, "mode": "radiance", "wo": wo, "wi": wi, "f": [r12(x) for x in f],
                          "pdf": r12(pdf), "rtol": 3e-3, "atol": 1e-6})
            # the adjoint of the kernel: f_imp(wo, wi) |wi.z| = S(wi, wo); sampled half
            # by radiance's sampler, half uniformly over the sphere
            Si, _ = scatter(mat, wi, wo)
            lines.append({"material": mat, "mode": "importance", "wo": wo, "wi": wi,
                          "f": [r12(x / abs(wi[2])) for x in Si], "pdf": r12(0.5 * pdf + 0.5 / (4 * math.pi)),
                          "rtol": 3e-3, "atol": 1e-6})
    with open(OUT, "w") as fh:
        for rec in lines:
            fh.write(json.dumps(rec) + "\n")
    print(f"{len(lines)} records in {OUT}")


if __name__ == "__main__":
    main()
