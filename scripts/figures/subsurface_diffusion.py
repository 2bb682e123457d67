#!/usr/bin/python3
"""Diffusion against the random walk for docs/subsurface-diffusion.md (issue 14 item 4(e)).

For every named medium of Jensen et al. 2001 (SPEC §2, `"medium"`, η = 1.3, g = 0, 1 scene
unit = 1 mm), runs `gonio subsurface` with `"method": "diffusion"` (photon beam diffusion)
and `"method": "randomwalk"` (the exact volumetric walk), prints a Markdown table of Rd per
channel per method and the profile's relative difference (diffusion − walk) / walk at a
few radii, and draws docs/subsurface-profiles.png (Rd(r) of both methods for four media).

    scripts/figures/subsurface_diffusion.py [--gonio build/bin/gonio] [--samples N] [--seed S]
"""
import argparse
import json
import math
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MEDIA = ["apple", "chicken1", "chicken2", "cream", "ketchup", "marble", "potato",
         "skimmilk", "skin1", "skin2", "wholemilk"]
PLOTTED = ["marble", "skin1", "ketchup", "wholemilk"]
# Radii of the table as multiples of the reference length ℓ of slab_profile_radii (the
# largest transport mean free path of the three channels): the profile's first radius is
# 0.01 ℓ.
TABLE_RADII = [0.1, 1.0, 10.0]


def slab(gonio, medium, method, samples, seed):
    material = json.dumps({"type": "subsurface", "medium": medium, "method": method})
    out = subprocess.run([gonio, "subsurface", "--bsdf", material, "--samples", str(samples),
                          "--seed", str(seed)], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def nearest(profile, r):
    """The profile point whose radius is closest to r (in log r)."""
    return min(profile, key=lambda p: abs(math.log(p[0] / r)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gonio", default="build/bin/gonio")
    ap.add_argument("--samples", type=int, default=1 << 19)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--png", default="docs/subsurface-profiles.png")
    a = ap.parse_args()

    results = {}
    for m in MEDIA:
        results[m] = {meth: slab(a.gonio, m, meth, a.samples, a.seed) for meth in ("diffusion", "randomwalk")}

    def fmt(v):
        return "%.3f" % v

    print("| medium | Rd diffusion (R, G, B) | Rd random walk (R, G, B) ± σ | Rd diff. % | "
          + " | ".join("profile diff. %% at %g ℓ" % x for x in TABLE_RADII) + " |")
    print("|---|---|---|---|" + "---|" * len(TABLE_RADII))
    for m in MEDIA:
        d, w = results[m]["diffusion"], results[m]["randomwalk"]
        ell = d["profile"][0][0] / 0.01
        rd_diff = ", ".join("%+.1f" % (100 * (d["Rd"][c] / w["Rd"][c] - 1)) for c in range(3))
        cells = []
        for x in TABLE_RADII:
            pd, pw = nearest(d["profile"], x * ell), nearest(w["profile"], x * ell)
            cells.append(", ".join("%+.0f" % (100 * (pd[1][c] / pw[1][c] - 1)) if pw[1][c] > 0 and pd[1][c] > 0 else "–"
                                   for c in range(3)))
        print("| %s | %s | %s ± %s | %s | %s |" % (
            m, ", ".join(fmt(v) for v in d["Rd"]), ", ".join(fmt(v) for v in w["Rd"]),
            "/".join("%.3f" % v for v in w["stderr"]), rd_diff, " | ".join(cells)))

    fig, axes = plt.subplots(1, len(PLOTTED), figsize=(4 * len(PLOTTED), 3.6))
    colours = ["tab:red", "tab:green", "tab:blue"]
    for ax, m in zip(axes, PLOTTED):
        peak = max(max(p[1]) for p in results[m]["diffusion"]["profile"])
        ax.set_ylim(peak * 1e-9, peak * 3)
        for meth, style in (("diffusion", "-"), ("randomwalk", "o")):
            prof = results[m][meth]["profile"]
            r = [p[0] for p in prof]
            for c in range(3):
                v = [p[1][c] for p in prof]
                keep = [(ri, vi) for ri, vi in zip(r, v) if vi > 0]
                if style == "-":
                    ax.loglog([k[0] for k in keep], [k[1] for k in keep], style, color=colours[c], lw=1.2)
                else:
                    ax.loglog([k[0] for k in keep], [k[1] for k in keep], style, color=colours[c], ms=2.5,
                              mfc="none")
        ax.set_title("%s (line: diffusion, o: random walk)" % m, fontsize=8)
        ax.set_autoscaley_on(False)
        ax.set_xlabel("r (mm)")
        ax.set_ylabel("Rd(r) (1/mm²)")
        ax.grid(True, which="both", lw=0.2)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print("\nwrote", a.png)


if __name__ == "__main__":
    main()
