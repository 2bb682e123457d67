#!/usr/bin/env python3
"""The RGL round trip of docs/measured.md (issue 59): a gonio material → `gonio tabulate
--format rgl` → the `rgl` material, compared by the relative RMS of f·cos θi over the
hemisphere of wi (4000 Fibonacci points, equal area) at several θo, RGB averaged.

Usage: tools/rgl_roundtrip.py GONIO_BINARY [OUTDIR]
Prints one Markdown table row per material: name, file size, the errors at θo."""
import json, math, os, subprocess, sys

gonio = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else "."
materials = [
    ("diffuse", {"type": "diffuse", "reflectance": [0.7, 0.5, 0.3]}),
    ("GGX Au α 0.1", {"type": "roughconductor", "alpha": 0.1, "material": "Au"}),
    ("GGX Au α 0.4", {"type": "roughconductor", "alpha": 0.4, "material": "Au"}),
    ("GGX Cu α [0.1, 0.4]", {"type": "roughconductor", "alpha": [0.1, 0.4], "material": "Cu"}),
    ("plastic α 0.2", {"type": "plastic", "reflectance": [0.2, 0.4, 0.8], "alpha": 0.2}),
    ("openpbr car paint", {"type": "openpbr", "base_color": [0.6, 0.05, 0.05], "base_metalness": 0.3,
                           "specular_roughness": 0.3, "coat_weight": 1, "coat_roughness": 0.05}),
]
thetas = [0, 30, 60, 80]
n = 4000


def evaluate(bsdf, lines):
    r = subprocess.run([gonio, "eval", "--bsdf", json.dumps(bsdf)], input="\n".join(lines) + "\n",
                       capture_output=True, text=True, check=True)
    return [sum(json.loads(l)["f"]) / 3 for l in r.stdout.splitlines()]


for name, bsdf in materials:
    path = os.path.join(out, name.split()[0].lower() + "-" + str(abs(hash(name)) % 10000) + ".bsdf")
    subprocess.run([gonio, "tabulate", "--bsdf", json.dumps(bsdf), "--format", "rgl", "-o", path],
                   check=True, capture_output=True)
    row = [name, "%.2f MB" % (os.path.getsize(path) / 1e6)]
    for t in thetas:
        th, po = math.radians(t), 0.3
        wo = (math.sin(th) * math.cos(po), math.sin(th) * math.sin(po), math.cos(th))
        lines, cos = [], []
        for k in range(n):
            z = (k + 0.5) / n
            r = math.sqrt(1 - z * z)
            ph = k * 2.39996322972865
            lines.append("%r %r %r %r %r %r" % (*wo, r * math.cos(ph), r * math.sin(ph), z))
            cos.append(z)
        a = evaluate(bsdf, lines)
        b = evaluate({"type": "rgl", "file": path}, lines)
        num = sum(((x - y) * c) ** 2 for x, y, c in zip(a, b, cos))
        den = sum((x * c) ** 2 for x, c in zip(a, cos))
        row.append("%.4f" % math.sqrt(num / den))
    print("| " + " | ".join(row) + " |")
