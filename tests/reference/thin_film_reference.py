#!/usr/bin/env python3
"""Thin-film reflectance (issue 34; SPEC §2 "thin_film"), written from the papers, not from
the C++ (python3 stdlib only). Run it to print the figures that tests/unit/test_thin_film.cpp
hard-codes.

Airy summation of one film (Belcour & Barla 2017, "A Practical Extension to Microfacet
Theory for the Modeling of Varying Iridescence", eq. 1; Born & Wolf §1.6.4): light from
index 1 at angle θ1 onto a film of index n_f and thickness d over a substrate of complex
index N = n + i k, per polarization
    r = (r12 + r23 e^{iΔ}) / (1 + r12 r23 e^{iΔ}),   Δ = (2π/λ) · 2 n_f d cos θ_f,
with the Fresnel amplitudes in angle form (Snell: sin θ_f = sin θ1 / n_f, and
N cos θ3 = sqrt(N² − sin²θ1), the root with Im ≥ 0):
    r_ij,s = (n_i cos θi − n_j cos θj) / (n_i cos θi + n_j cos θj),
    r_ij,p = (n_j cos θi − n_i cos θj) / (n_j cos θi + n_i cos θj),
R = (|r_s|² + |r_p|²) / 2.
RGB: XYZ = ∫ R D65 x̄ȳz̄ dλ / ∫ D65 ȳ dλ over the 1 nm rows of the CIE 1931 2° table (trapezoid
rule, D65 linear between its 5 nm rows; CIE 15:2004 §7.1), then IEC 61966-2-1 to linear
sRGB, clamped to [0, 1] — models_reference.metal_reflectance_rgb's reduction.
"""
import cmath
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import models_reference as M  # noqa: E402


def airy(cos1, nf, d, n3, k3, lam):
    """(R, R_s, R_p) of the film-covered interface; d and lam in the same unit."""
    c1 = min(1.0, abs(cos1))
    s1 = math.sqrt(max(0.0, 1 - c1 * c1))
    sf = s1 / nf
    cf = cmath.sqrt(1 - sf * sf)
    N = complex(n3, k3)
    w3 = cmath.sqrt(N * N - s1 * s1)  # N cos θ3
    if w3.imag < 0: w3 = -w3
    c3 = w3 / N
    r12s = (c1 - nf * cf) / (c1 + nf * cf)
    r12p = (nf * c1 - cf) / (nf * c1 + cf)
    r23s = (nf * cf - N * c3) / (nf * cf + N * c3)
    r23p = (N * cf - nf * c3) / (N * cf + nf * c3)
    e = cmath.exp(1j * 4 * math.pi * nf * d * cf / lam)
    rs = (r12s + r23s * e) / (1 + r12s * r23s * e)
    rp = (r12p + r23p * e) / (1 + r12p * r23p * e)
    Rs, Rp = min(1.0, abs(rs) ** 2), min(1.0, abs(rp) ** 2)
    return (Rs + Rp) / 2, Rs, Rp


def film_rgb(cos1, nf, d, substrate):
    """Linear sRGB of the film's reflectance spectrum at cos1; substrate(λ) -> (n, k)."""
    cmf = M._read_columns(os.path.join(M._DATA, "cie", "cie1931_2deg_cmf.csv"))
    d65 = M._read_columns(os.path.join(M._DATA, "cie", "cie_illuminant_d65.csv"))
    xyz, norm = [0.0, 0.0, 0.0], 0.0
    for i, (lam, xb, yb, zb) in enumerate(cmf):
        h = 0.5 * ((lam - cmf[i - 1][0] if i > 0 else 0.0) + (cmf[i + 1][0] - lam if i + 1 < len(cmf) else 0.0))
        e = M._lerp_rows(d65, lam, 1) or 0.0
        n, k = substrate(lam)
        r = airy(cos1, nf, d, n, k, lam)[0]
        for j, bar in enumerate((xb, yb, zb)): xyz[j] += h * r * e * bar
        norm += h * e * yb
    return [min(1.0, max(0.0, sum(m * v / norm for m, v in zip(row, xyz)))) for row in M._XYZ_TO_SRGB]


def gold(lam):
    rows = M._read_columns(os.path.join(M._DATA, "metals", "Au.csv"))
    return M._lerp_rows(rows, lam, 1), M._lerp_rows(rows, lam, 2)


if __name__ == "__main__":
    print("MgF2 on glass, normal incidence, 550 nm:", airy(1.0, 1.38, 99.6, 1.5, 0.0, 550.0)[0])
    print("# airy cases: cos1, nf, d, n3, k3, lambda, R")
    for c, nf, d, n3, k3, lam in ((1.0, 1.38, 99.6, 1.5, 0.0, 550.0), (0.8, 1.38, 99.6, 1.5, 0.0, 450.0),
                                 (0.3, 1.33, 300.0, 1.0, 0.0, 600.0), (0.6, 1.33, 500.0, 1.0, 0.0, 520.0),
                                 (0.95, 2.0, 150.0, 1.5, 0.0, 700.0), (0.1, 1.5, 1000.0, 1.5, 0.0, 400.0),
                                 (0.7, 1.45, 250.0, 0.2, 3.6, 650.0), (0.2, 1.8, 80.0, 1.1, 2.4, 450.0),
                                 (1.0, 1.5, 400.0, 0.5, 2.0, 500.0), (0.5, 1.2, 2000.0, 2.4, 0.0, 633.0)):
        print("{%r, %r, %r, %r, %r, %r, %.15g}," % (c, nf, d, n3, k3, lam, airy(c, nf, d, n3, k3, lam)[0]))
    print("# rgb: soap film nf 1.33 d 400 on air, cos 1 and 0.5; oil nf 1.5 d 300 on gold, cos 0.9")
    for args in ((1.0, 1.33, 400.0, lambda l: (1.0, 0.0)), (0.5, 1.33, 400.0, lambda l: (1.0, 0.0)),
                 (0.9, 1.5, 300.0, gold)):
        print("{%.15g, %.15g, %.15g}," % tuple(film_rgb(*args)))
