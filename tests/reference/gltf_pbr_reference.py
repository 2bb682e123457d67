#!/usr/bin/env python3
"""gltf_pbr reference values (issues 57, 58): the glTF 2.0 BRDF written from the Khronos texts,
not from the C++ (include/gonio/bxdf/gltf_pbr.h). Writes data/gltf_pbr.jsonl (eval records,
tests/unit/test_reference_values.cpp).

Sources, each formula in the specification's own form:
  * glTF 2.0 specification, Appendix B: B.3.2 V_GGX (height-correlated Smith, as
    V = 0.5 / (NdotL sqrt(NdotV^2 (1 - a^2) + a^2) + NdotV sqrt(NdotL^2 (1 - a^2) + a^2))),
    B.3.3 D_GGX = a^2 / (pi (NdotH^2 (a^2 - 1) + 1)^2), a = roughness^2, B.2.2 conductor_fresnel
    (Schlick with F0 = baseColor), B.2.5 mix(dielectric, metal, metallic).
  * KHR_materials_specular "Implementation" with KHR_materials_ior: f0 = min(((ior-1)/(ior+1))^2
    specularColor, 1) specular, f90 = specular, dielectric = F spec + (1 - max(F)) diffuse.
  * KHR_materials_clearcoat: mix(material, coat_brdf, clearcoat * F(0.04, VdotH)).
  * KHR_materials_anisotropy: alpha_t = mix(alpha, 1, strength^2), alpha_b = alpha, D and V in
    the frame turned by anisotropyRotation.
  * KHR_materials_transmission, thin-walled: the specular lobe with L mirrored through the
    surface, tinted by baseColor, replacing the diffuse by the transmission factor.
  * KHR_materials_diffuse_transmission: Lambertian, diffuseTransmissionColor / pi on the other side.
  * KHR_materials_volume (thickness > 0): Walter et al. 2007 eq. 21 without F (radiance mode
    n_wo^2 K, importance n_wi^2 K, K = |o.h||i.h| D G2 / (|o.z||i.z| (o.h + eta i.h)^2)), with the
    (1 - max F) of the fresnel mix read at the outside direction's o.h.
gonio's documented choices (docs/gltf_pbr.md) are followed: alpha at least 0.002; Fresnel at V.H;
a transmission's factors from the outside direction. Sheen is checked in the C++ unit test
(its albedo table), not here.
"""

import json
import math
import os
import random

MIN_ALPHA = 2e-3


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def unit(a):
    n = math.sqrt(dot(a, a))
    return [a[0] / n, a[1] / n, a[2] / n]


def turn(w, r):
    c, s = math.cos(r), math.sin(r)
    return [c * w[0] + s * w[1], -s * w[0] + c * w[1], w[2]]


def d_ggx(h, at, ab):
    e = (h[0] / at) ** 2 + (h[1] / ab) ** 2 + h[2] ** 2
    return 1 / (math.pi * at * ab * e * e)


def v_ggx(v, l, at, ab):
    gv = abs(l[2]) * math.sqrt((at * v[0]) ** 2 + (ab * v[1]) ** 2 + v[2] ** 2)
    gl = abs(v[2]) * math.sqrt((at * l[0]) ** 2 + (ab * l[1]) ** 2 + l[2] ** 2)
    return 0.5 / (gv + gl)


def sw(c):
    return (1 - c) ** 5


def alphas(p):
    a = max(p.get("roughness", 1) ** 2, MIN_ALPHA)
    s = p.get("anisotropy_strength", 0)
    return a + (1 - a) * s * s, a


def col(p, key, default):
    v = p.get(key, default)
    return list(v) if isinstance(v, list) else [v, v, v]


def fresnel_d(p, c):
    ior = p.get("ior", 1.5)
    sc = col(p, "specular_color", 1)
    s = p.get("specular", 1)
    f0 = [min(((ior - 1) / (ior + 1)) ** 2 * x, 1) * s for x in sc]
    return [x + (s - x) * sw(c) for x in f0]


def reflection(p, v, l):
    h = unit([v[0] + l[0], v[1] + l[1], v[2] + l[2]])
    c = dot(v, h)
    at, ab = alphas(p)
    r = p.get("anisotropy_rotation", 0)
    spec = v_ggx(turn(v, r), turn(l, r), at, ab) * d_ggx(turn(h, r), at, ab)
    base = col(p, "base_color", 1)
    m = p.get("metallic", 1)
    t = p.get("transmission", 0)
    dt = p.get("diffuse_transmission", 0)
    fd = fresnel_d(p, c)
    fmax = max(fd)
    out = []
    for k in range(3):
        diel = fd[k] * spec + (1 - fmax) * (1 - t) * (1 - dt) * base[k] / math.pi
        metal = (base[k] + (1 - base[k]) * sw(c)) * spec
        out.append((1 - m) * diel + m * metal)
    cc = p.get("clearcoat", 0)
    if cc > 0:
        ac = max(p.get("clearcoat_roughness", 0) ** 2, MIN_ALPHA)
        fc = cc * (0.04 + 0.96 * sw(c))
        coat = v_ggx(v, l, ac, ac) * d_ggx(h, ac, ac)
        out = [x * (1 - fc) + fc * coat for x in out]
    return out


def transmission(p, wo, wi, mode):
    """wo and wi on opposite sides; thin-walled, mirrored so that wo is above."""
    volume = p.get("thickness", 0) > 0 and p.get("transmission", 0) > 0
    if not volume and wo[2] < 0:
        wo, wi = [wo[0], wo[1], -wo[2]], [wi[0], wi[1], -wi[2]]
    wo_out = wo[2] > 0
    a, b = (wo, wi) if wo_out else (wi, wo)
    m = p.get("metallic", 1)
    t = p.get("transmission", 0)
    dt = p.get("diffuse_transmission", 0)
    cc = p.get("clearcoat", 0)
    base = col(p, "base_color", 1)
    dtc = col(p, "diffuse_transmission_color", 1)

    def weight(c):
        return (1 - m) * (1 - max(fresnel_d(p, c))) * (1 - cc * (0.04 + 0.96 * sw(c)))

    bm = [b[0], b[1], -b[2]]
    hm = unit([a[0] + bm[0], a[1] + bm[1], a[2] + bm[2]])
    cm = dot(a, hm)
    out = [(1 - t) * dt * dtc[k] * weight(cm) / math.pi for k in range(3)]
    at, ab = alphas(p)
    r = p.get("anisotropy_rotation", 0)
    if t > 0 and m < 1:
        if not volume:
            spec = v_ggx(turn(a, r), turn(bm, r), at, ab) * d_ggx(turn(hm, r), at, ab)
            out = [out[k] + base[k] * t * weight(cm) * spec for k in range(3)]
        else:
            eta = p.get("ior", 1.5)
            h = unit([a[0] + eta * b[0], a[1] + eta * b[1], a[2] + eta * b[2]])
            if h[2] < 0:
                h = [-h[0], -h[1], -h[2]]
            ha, hb = dot(a, h), dot(b, h)
            if ha > 0 and hb < 0:
                ta, tb, th = turn(a, r), turn(b, r), turn(h, r)

                def lam(w):
                    t2 = ((at * w[0]) ** 2 + (ab * w[1]) ** 2) / (w[2] ** 2)
                    return (-1 + math.sqrt(1 + t2)) / 2

                g2 = 1 / (1 + lam(ta) + lam(tb))
                kk = ha * -hb * d_ggx(th, at, ab) * g2 / (abs(a[2] * b[2]) * (ha + eta * hb) ** 2)
                n_wo2, n_wi2 = (1, eta * eta) if wo_out else (eta * eta, 1)
                nf = n_wo2 if mode == "radiance" else n_wi2
                out = [out[k] + base[k] * t * weight(ha) * kk * nf for k in range(3)]
    return out


def f(p, wo, wi, mode):
    if wo[2] > 0 and wi[2] > 0:
        return reflection(p, wo, wi)
    volume = p.get("thickness", 0) > 0 and p.get("transmission", 0) > 0
    if wo[2] < 0 and wi[2] < 0:
        if volume:
            return None  # the glass seen from inside: not recorded here
        return reflection(p, [wo[0], wo[1], -wo[2]], [wi[0], wi[1], -wi[2]])
    return transmission(p, wo, wi, mode)


MATERIALS = [
    {"type": "gltf_pbr", "base_color": [0.8, 0.5, 0.2], "metallic": 0, "roughness": 0.5},
    {"type": "gltf_pbr", "base_color": [0.95, 0.64, 0.54], "metallic": 1, "roughness": 0.3},
    {"type": "gltf_pbr", "base_color": [0.4, 0.6, 0.9], "metallic": 0.4, "roughness": 0.7, "specular": 0.6,
     "specular_color": [1, 0.5, 0.2], "ior": 2.0},
    {"type": "gltf_pbr", "base_color": [0.7, 0.1, 0.1], "metallic": 0, "roughness": 0.6, "clearcoat": 0.9,
     "clearcoat_roughness": 0.3},
    {"type": "gltf_pbr", "base_color": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.5, "anisotropy_strength": 0.6,
     "anisotropy_rotation": 0.9},
    {"type": "gltf_pbr", "base_color": [0.9, 0.8, 0.6], "metallic": 0, "roughness": 0.3, "transmission": 0.7},
    {"type": "gltf_pbr", "base_color": [1, 0.9, 0.8], "metallic": 0, "roughness": 0.4, "transmission": 1,
     "thickness": 1, "ior": 1.6},
    {"type": "gltf_pbr", "base_color": [0.6, 0.6, 0.6], "metallic": 0, "roughness": 0.5, "diffuse_transmission": 0.5,
     "diffuse_transmission_color": [0.2, 0.8, 0.3]},
]


def direction(rng, side):
    mu = 0.1 + 0.85 * rng.random()
    phi = 2 * math.pi * rng.random()
    s = math.sqrt(1 - mu * mu)
    return [s * math.cos(phi), s * math.sin(phi), side * mu]


def refracted(rng, wo, eta):
    """wo refracted through a facet normal within about 25 degrees of the surface normal."""
    h = unit([0.4 * (rng.random() - 0.5), 0.4 * (rng.random() - 0.5), 1])
    if wo[2] < 0:
        h = [-h[0], -h[1], -h[2]]
    e = eta if wo[2] > 0 else 1 / eta
    c = dot(wo, h)
    s2 = (1 - c * c) / (e * e)
    if s2 >= 1:
        return [-wo[0], -wo[1], -wo[2]]
    ct = math.sqrt(1 - s2)
    return unit([-wo[k] / e + h[k] * (c / e - ct) for k in range(3)])


def main():
    rng = random.Random(58)
    lines = []
    for mat in MATERIALS:
        for mode in ("radiance", "importance"):
            for so, si in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                for _ in range(3):
                    wo, wi = direction(rng, so), direction(rng, si)
                    if so != si and mat.get("thickness", 0) > 0:
                        wi = refracted(rng, wo, mat.get("ior", 1.5))  # where the refraction lobe is
                    val = f(mat, wo, wi, mode)
                    if val is None:
                        continue
                    lines.append(json.dumps({"material": mat, "mode": mode, "wo": wo, "wi": wi, "f": val,
                                             "rtol": 2e-4, "atol": 1e-6}, sort_keys=True))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "gltf_pbr.jsonl")
    with open(out, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(out, len(lines), "records")


if __name__ == "__main__":
    main()
