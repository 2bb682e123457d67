#!/usr/bin/env python3
"""Independent reference values for the rough `plastic` model (SPEC §2).

Written from the papers, not from the C++ code; standard library only. Writes
tests/reference/data/plastic_rough.jsonl (one JSON record per line) when run:

    python3 tests/reference/plastic_reference.py

The model (Weidlich & Wilkie 2007, §3; Kelemen & Szirmay-Kalos 2001, §2; Kulla & Conty
2017 for the balance through the coat's average albedo): a rough dielectric coat of
relative index eta over a Lambertian base of albedo rho,

  f = f_coat + f_base
  f_coat = D(h) G2(wo, wi) F(wo.h) / (4 cos_o cos_i)        Walter et al. 2007, eq. 20
  f_base = rho (1 - E(mu_i)) (1 - E(mu_o)) / (pi eta^2 (1 - rho F_dr))
  1 - F_dr = (1 - Ebar) / eta^2

with G2 the height-correlated Smith term 1 / (1 + L(wo) + L(wi)) (Heitz 2014, eq. 99),
D and L of GGX (Walter et al. 2007, eq. 33; Heitz 2014, eq. 86) or Beckmann (Walter
et al. 2007, eq. 25; Heitz 2014, eq. 72), F the unpolarised dielectric Fresnel
reflectance in the angle form (Hecht, Optics §4.6: r_s = -sin(ti - tt)/sin(ti + tt),
r_p = tan(ti - tt)/tan(ti + tt)), E(mu) = integral of f_coat cos_i over the hemisphere
(the coat's directional albedo) and Ebar = 2 integral E(mu) mu dmu.

Numerics, all different from the C++ (which reads E from build-time tables made by
visible-normal sampling): E(mu) by a product midpoint rule over the microfacet normal,
parametrised by the classic inversion of D cos(theta_m) (Walter et al. 2007, eqs. 28,
35), so that the weight of each node is G2 F (wo.m) / (cos_o cos theta_m); Ebar by
Gauss-Legendre in s = sqrt(mu).

Tolerances: the C++ interpolates E in (alpha, eta, mu) from tables (errors up to ~1e-3
in E, so up to a few 1e-3 relative in f_base), so rtol = 0.01 on each channel with a small
atol; a separable G in the coat, or the smooth interface's 1 - F coupling, moves f by more
than that at many of the pairs below (those effects are 3 % to 60 %).
"""
import json
import math
import os
import random

# ---------------------------------------------------------------- microfacet terms


def fresnel(cos_i, eta):
    """Unpolarised reflectance, light from outside (index 1) onto eta >= 1."""
    cos_i = min(1.0, max(0.0, cos_i))
    ti = math.acos(cos_i)
    if ti < 1e-9:
        return ((eta - 1) / (eta + 1)) ** 2
    st = math.sin(ti) / eta
    tt = math.asin(st)
    rs = -math.sin(ti - tt) / math.sin(ti + tt)
    if abs(ti + tt - math.pi / 2) < 1e-15:
        rp = 0.0
    else:
        rp = math.tan(ti - tt) / math.tan(ti + tt)
    return (rs * rs + rp * rp) / 2


def D(dist, alpha, cos_m):
    if cos_m <= 0:
        return 0.0
    c2 = cos_m * cos_m
    tan2 = (1 - c2) / c2
    if dist == "ggx":
        return alpha * alpha / (math.pi * c2 * c2 * (alpha * alpha + tan2) ** 2)
    return math.exp(-tan2 / (alpha * alpha)) / (math.pi * alpha * alpha * c2 * c2)


def Lambda(dist, alpha, cos_t):
    if cos_t >= 1:
        return 0.0
    tan_t = math.sqrt(1 - cos_t * cos_t) / cos_t
    if dist == "ggx":
        return (-1 + math.sqrt(1 + alpha * alpha * tan_t * tan_t)) / 2
    a = 1 / (alpha * tan_t)
    return (math.erf(a) - 1) / 2 + math.exp(-a * a) / (2 * a * math.sqrt(math.pi))


def G2(dist, alpha, cos_o, cos_i):
    return 1 / (1 + Lambda(dist, alpha, cos_o) + Lambda(dist, alpha, cos_i))


def coat_f(dist, alpha, eta, wo, wi):
    h = [wo[i] + wi[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in h))
    h = [x / n for x in h]
    c = sum(wo[i] * h[i] for i in range(3))
    return D(dist, alpha, h[2]) * G2(dist, alpha, wo[2], wi[2]) * fresnel(c, eta) / (4 * wo[2] * wi[2])


# ---------------------------------------------------------------- albedos by quadrature


def theta_m_of(dist, alpha, xi):
    # tan^2 theta_m = alpha^2 xi/(1 - xi) (GGX), -alpha^2 ln(1 - xi) (Beckmann)
    if dist == "ggx":
        return math.atan(alpha * math.sqrt(xi / (1 - xi)))
    return math.atan(alpha * math.sqrt(-math.log(1 - xi)))


def coat_albedo(dist, alpha, eta, mu, n_xi=160, n_phi=96):
    """E(mu) = integral of f_coat cos_i d omega_i, written over the microfacet normal m
    (d omega_i = 4 (wo.m) d omega_m) with D cos theta_m d omega_m = d xi d phi / (2 pi)."""
    so = math.sqrt(max(0.0, 1 - mu * mu))
    wo = (so, 0.0, mu)
    lo = Lambda(dist, alpha, mu)
    total = 0.0
    cphi = [math.cos(math.pi * (j + 0.5) / n_phi) for j in range(n_phi)]  # phi in (0, pi), mirrored
    for i in range(n_xi):
        tm = theta_m_of(dist, alpha, (i + 0.5) / n_xi)
        st, ct = math.sin(tm), math.cos(tm)
        for cp in cphi:
            m = (st * cp, 0.0, ct)
            c = wo[0] * m[0] + wo[2] * m[2]
            if c <= 0:
                continue
            wiz = 2 * c * m[2] - wo[2]
            if wiz <= 0:
                continue
            g2 = 1 / (1 + lo + Lambda(dist, alpha, wiz))
            total += g2 * fresnel(c, eta) * c / (mu * ct)
    return total / (n_xi * n_phi)


def gauss_legendre(n):
    """Nodes and weights on [0, 1]."""
    nodes, weights = [], []
    for k in range(1, n + 1):
        x = math.cos(math.pi * (k - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for j in range(2, n + 1):
                p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
            dp = n * (x * p1 - p0) / (x * x - 1)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-15:
                break
        nodes.append((1 - x) / 2)
        weights.append(1 / ((1 - x * x) * dp * dp))
    return nodes, weights


def coat_average(dist, alpha, eta, n=32):
    """Ebar = 2 integral E(mu) mu dmu = 4 integral E(s^2) s^3 ds."""
    xs, ws = gauss_legendre(n)
    return sum(w * 4 * s ** 3 * coat_albedo(dist, alpha, eta, s * s) for s, w in zip(xs, ws))


# ---------------------------------------------------------------- the model


class Plastic:
    def __init__(self, dist, alpha, eta, rho):
        self.dist, self.alpha, self.eta, self.rho = dist, alpha, eta, rho
        self.ebar = coat_average(dist, alpha, eta)
        self.fdr = 1 - (1 - self.ebar) / (eta * eta)

    def json(self):
        m = {"type": "plastic", "alpha": self.alpha, "eta": self.eta, "reflectance": self.rho}
        if self.dist != "ggx":
            m["distribution"] = self.dist
        return m

    def f(self, wo, wi):
        fc = coat_f(self.dist, self.alpha, self.eta, wo, wi)
        eo = coat_albedo(self.dist, self.alpha, self.eta, wo[2])
        ei = coat_albedo(self.dist, self.alpha, self.eta, wi[2])
        eta2 = self.eta * self.eta
        return [fc + r * (1 - ei) * (1 - eo) / (math.pi * eta2 * (1 - r * self.fdr)) for r in self.rho]


def random_direction(rng, min_cos):
    mu = min_cos + (1 - min_cos) * rng.random()
    phi = 2 * math.pi * rng.random()
    s = math.sqrt(1 - mu * mu)
    return (s * math.cos(phi), s * math.sin(phi), mu)


def near_specular(rng, wo, alpha):
    # the mirror direction, turned by up to ~alpha radians: pairs where the coat lobe matters
    x, y, z = -wo[0] + alpha * (rng.random() - 0.5), -wo[1] + alpha * (rng.random() - 0.5), wo[2]
    n = math.sqrt(x * x + y * y + z * z)
    return (x / n, y / n, z / n)


MATERIALS = [
    ("ggx", 0.3, 1.5, [0.9, 0.5, 0.0]),
    ("ggx", 0.1, 1.5, [1.0, 1.0, 1.0]),
    ("beckmann", 0.5, 1.33, [0.2, 0.6, 1.0]),
    ("ggx", 1.0, 2.0, [0.8, 0.8, 0.8]),
    ("beckmann", 0.05, 1.7, [0.0, 0.5, 1.0]),
    ("ggx", 2.5, 1.45, [0.7, 0.3, 0.1]),
]
PAIRS = 24  # per material: half uniform, half near the mirror direction


def main():
    rng = random.Random(20261130)
    here = os.path.dirname(os.path.abspath(__file__))
    os.makedirs(os.path.join(here, "data"), exist_ok=True)
    out = os.path.join(here, "data", "plastic_rough.jsonl")
    with open(out, "w") as fh:
        for dist, alpha, eta, rho in MATERIALS:
            m = Plastic(dist, alpha, eta, rho)
            for p in range(PAIRS):
                wo = random_direction(rng, 0.05)
                wi = random_direction(rng, 0.05) if p % 2 == 0 else near_specular(rng, wo, min(alpha, 0.6))
                if wi[2] < 0.05:
                    wi = random_direction(rng, 0.05)
                rec = {"material": m.json(), "mode": "radiance", "wo": [round(x, 12) for x in wo],
                       "wi": [round(x, 12) for x in wi], "f": [float("%.9g" % v) for v in m.f(wo, wi)],
                       "rtol": 0.01, "atol": 1e-5}
                fh.write(json.dumps(rec) + "\n")
    print(out)


if __name__ == "__main__":
    main()
