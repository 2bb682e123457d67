#!/usr/bin/env python3
"""openpbr's layering against gonio's `layered` random walk, measured as albedos (issue 35, item 1).

For each pair of layers, the albedo of light arriving at 0°, 45°, 75° and 85° (`gonio albedo`:
the energy the surface returns; for a model that is not reciprocal, the coated `openpbr`, its
light-side figures reflectance_light + transmittance_light) of the `openpbr` material and of the
`layered` stack of the same interface over the same base. Prints a Markdown table
(docs/openpbr.md, "Layering, per layer"). Run from the repository root after a build:

    python3 bench/openpbr_layering.py
"""
import json
import subprocess

G = "build/bin/gonio"
cases = [
 ("specular layer (ior 1.5, roughness 0.3) over a diffuse base 0.8",
  {"type":"openpbr","base_color":0.8,"specular_ior":1.5,"specular_roughness":0.3},
  {"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.09},"bottom":{"type":"eon","reflectance":0.8,"roughness":0},"thickness":0}),
 ("the same over a diffuse base 0.3",
  {"type":"openpbr","base_color":0.3,"specular_ior":1.5,"specular_roughness":0.3},
  {"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.09},"bottom":{"type":"eon","reflectance":0.3,"roughness":0},"thickness":0}),
 ("the same over a white base (1)",
  {"type":"openpbr","base_color":1,"specular_ior":1.5,"specular_roughness":0.3},
  {"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.09},"bottom":{"type":"eon","reflectance":1,"roughness":0},"thickness":0}),
 ("coat (ior 1.6, roughness 0.2) over a metal (F82, base_color 0.9, specular_roughness 0.4)",
  {"type":"openpbr","base_metalness":1,"base_color":0.9,"specular_roughness":0.4,"coat_weight":1,"coat_roughness":0.2,"coat_ior":1.6},
  {"type":"layered","top":{"type":"roughdielectric","eta":1.6,"alpha":0.04},"bottom":{"type":"roughconductor","fresnel":"f82","f0":0.9,"f82":1,"alpha":0.16,"multiscatter": True},"thickness":0}),
 ("coat (ior 1.6, smooth) over a white metal",
  {"type":"openpbr","base_metalness":1,"base_color":1,"specular_roughness":0.4,"coat_weight":1,"coat_roughness":0,"coat_ior":1.6},
  {"type":"layered","top":{"type":"dielectric","eta":1.6},"bottom":{"type":"roughconductor","fresnel":"f82","f0":1,"f82":1,"alpha":0.16,"multiscatter": True},"thickness":0}),
]
thetas = [0, 45, 75, 85]
print("| layers | model | " + " | ".join(f"{t}°" for t in thetas) + " |")
print("|---|---|" + "---:|" * len(thetas))
for name, opb, lay in cases:
    rows = {}
    for label, m in (("openpbr", opb), ("layered", lay)):
        vals = []
        for t in thetas:
            out = subprocess.run([G, "albedo", "--bsdf", json.dumps(m), "--theta", str(t), "--samples", "2000000"],
                                 capture_output=True, text=True, check=True).stdout
            j = json.loads(out.splitlines()[-1])
            a = j["albedo"]
            if "reflectance_light" in j:  # not reciprocal: the light's figure (SPEC §3)
                a = [r + t for r, t in zip(j["reflectance_light"], j["transmittance_light"])]
            vals.append(a[0] if isinstance(a, list) else a)
        rows[label] = vals
    print(f"| {name} | `openpbr` | " + " | ".join(f"{v:.4f}" for v in rows["openpbr"]) + " |")
    print(f"|  | `layered` | " + " | ".join(f"{v:.4f}" for v in rows["layered"]) + " |")
    print(f"|  | openpbr − layered | " + " | ".join(f"{a-b:+.4f}" for a, b in zip(rows["openpbr"], rows["layered"])) + " |")
