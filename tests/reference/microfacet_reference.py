#!/usr/bin/env python3
"""Independent reference values for tests/unit/test_microfacet.cpp.

Written from the papers in angle form, separately from the C++ code:
  GGX D (Walter et al. 2007, eq. 33): alpha² / (π cos⁴θm (alpha² + tan²θm)²)   (isotropic)
  Smith Λ (Heitz 2014, eqs. 72, 86): GGX (−1 + sqrt(1 + alpha² tan²θ)) / 2,
      Beckmann (erf(a) − 1)/2 + exp(−a²)/(2 a sqrt(π)), a = 1/(alpha tan θ)
  height-correlated G2 = 1 / (1 + Λ(o) + Λ(i))                (Heitz 2014, eq. 99)
  Walter et al. 2007: h_r = sign(i·n)(i + o) normalised (eq. 13); f_r (eq. 20);
      h_t = −(η_i i + η_o o) normalised (eq. 16); f_t (eq. 21), radiance transport.
  Fresnel: exact unpolarised dielectric, angle form.
Directions are unit vectors (x, y, z) with z the normal; 'o' is wo, 'i' is wi.
"""
import math

def norm(v):
    l = math.sqrt(sum(c * c for c in v)); return tuple(c / l for c in v)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def sph(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))

def D_ggx(m, a):
    c = m[2]
    if c <= 0: return 0.0
    t2 = (1 - c * c) / (c * c)
    return a * a / (math.pi * c ** 4 * (a * a + t2) ** 2)

def lam_ggx(w, a):
    c = abs(w[2]); t2 = (1 - c * c) / (c * c)
    return (-1 + math.sqrt(1 + a * a * t2)) / 2

def lam_beckmann(w, a):
    c = abs(w[2]); t = math.sqrt(1 - c * c) / c
    if t == 0: return 0.0
    x = 1 / (a * t)
    return (math.erf(x) - 1) / 2 + math.exp(-x * x) / (2 * x * math.sqrt(math.pi))

def fresnel(cos_i, eta):  # eta = n_t / n_i, cos_i > 0
    s_t = math.sqrt(max(0.0, 1 - cos_i * cos_i)) / eta
    if s_t >= 1: return 1.0
    ti, tt = math.acos(cos_i), math.asin(s_t)
    if ti == 0: return ((eta - 1) / (eta + 1)) ** 2
    rs = math.sin(ti - tt) / math.sin(ti + tt); rp = math.tan(ti - tt) / math.tan(ti + tt)
    return (rs * rs + rp * rp) / 2

def rough_dielectric(o, i, a, eta_inside):
    """Radiance-mode BSDF value, GGX, for the pair (wo = o, wi = i)."""
    n_o = 1.0 if o[2] > 0 else eta_inside
    n_i = 1.0 if i[2] > 0 else eta_inside
    G2 = 1 / (1 + lam_ggx(o, a) + lam_ggx(i, a))
    if o[2] * i[2] > 0:
        h = norm(tuple(x + y for x, y in zip(o, i)))
        if h[2] < 0: h = tuple(-c for c in h)
        c = dot(o, h)
        # Fresnel for light on o's side: eta relative to that side
        F = fresnel(abs(c), (eta_inside if o[2] > 0 else 1 / eta_inside))
        return D_ggx(h, a) * G2 * F / (4 * abs(o[2]) * abs(i[2]))
    h = norm(tuple(-(n_i * x + n_o * y) for x, y in zip(i, o)))
    if h[2] < 0: h = tuple(-c for c in h)
    ih, oh = dot(i, h), dot(o, h)
    # Fresnel at the microfacet for light arriving from i's side
    F = fresnel(abs(ih), n_o / n_i)
    return (abs(ih) * abs(oh) / (abs(i[2]) * abs(o[2]))) * n_o ** 2 * (1 - F) * G2 * D_ggx(h, a) \
        / (n_i * ih + n_o * oh) ** 2

if __name__ == "__main__":
    print("Lambda_ggx(alpha=1, 60deg) =", repr(lam_ggx(sph(60, 0), 1.0)))
    print("Lambda_beckmann(alpha=1, tan=1 i.e. 45deg) =", repr(lam_beckmann(sph(45, 0), 1.0)))
    print("Lambda_beckmann(alpha=0.5, 70deg) =", repr(lam_beckmann(sph(70, 0), 0.5)))
    print("D_ggx(alpha=0.3, 20deg) =", repr(D_ggx(sph(20, 0), 0.3)))
    cases = [((30, 10), (50, 200), 0.3, 1.5), ((30, 10), (150, 200), 0.3, 1.5),
             ((140, 40), (20, 250), 0.5, 1.5), ((60, 0), (160, 170), 0.2, 1.33),
             ((10, 0), (170, 190), 0.1, 0.7)]
    for (to, po), (ti, pi), a, eta in cases:
        v = rough_dielectric(sph(to, po), sph(ti, pi), a, eta)
        print(f"rough_dielectric wo=({to},{po}) wi=({ti},{pi}) alpha={a} eta={eta}: {v!r}")
