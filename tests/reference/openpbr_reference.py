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

Tolerances: the conductor's compensation term goes through gonio's interpolated albedo
tables (error up to ~1.5e-3 in E), so each record's atol is that allowance times the
multiple-scattering term, as for roughconductor_multiscatter.jsonl (see README.md).
Not covered yet (left for later): the dielectric base with the b(μ) normalisation, coat,
fuzz, transmission, subsurface, thin-walled, thin film, anisotropy.
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


def r12(x): return float(f"{x:.12g}")
def vec12(v): return [r12(c) for c in v]


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
    with open(OUT, "w") as fh:
        for rec in recs:
            fh.write(json.dumps(rec, sort_keys=True) + "\n")
    print(f"{OUT}: {len(recs)} records")


if __name__ == "__main__":
    main()
