#!/usr/bin/python3
"""Theory against measurement for docs/gonioreflectometer.md (issue 13 item 4).

Measures Gaussian microsurfaces of alpha = 0.1, 0.3, 0.6, 1.0 with white mirror facets
(F = 1) with `gonio measure` (a gantry in the plane of incidence, and a full MERL table),
evaluates gonio's single-scattering and multiple-scattering Beckmann models with
`gonio albedo` and `gonio eval`, fits the analytic models to each table with `gonio fit`,
and draws the figures docs/gonioreflectometer-theory-*.png and prints the Markdown tables.

    scripts/figures/gonioreflectometer_theory.py [--gonio build/bin/gonio] [--data DIR]

Measurements are cached in DIR (default build/theory-data): a second run only redraws.
Delete DIR (or pass --remeasure) to measure again.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ALPHAS = [float(a) for a in os.environ.get("THEORY_ALPHAS", "0.1,0.3,0.6,1.0").split(",")]
RESOLUTION = 1024
CORRELATION = 8 / RESOLUTION  # 8 grid cells: 128 x 128 correlation lengths on the patch
SURFACE_SEED = 1
THETA_I = [0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 88]
LOBE_THETA_I = [0, 40, 70]
THETA_O = {"from": 1, "to": 89, "count": 45}  # every 2 degrees
APERTURE = 2.0
GANTRY_RAYS_PER_INCIDENCE = 400_000
TABLE_RAYS = 16_000_000
THREADS = 2
WHITE = {"type": "mirror", "reflectance": 1}
# The fits of roughconductor to each table: (distribution, metric, Kulla-Conty's lobe).
FITS = [("beckmann", "log", False), ("beckmann", "ngan", False), ("ggx", "log", False), ("ggx", "ngan", False),
        ("beckmann", "log", True), ("beckmann", "ngan", True)]


def surface(alpha):
    return {"type": "gaussian", "alpha": alpha, "resolution": RESOLUTION, "correlation": CORRELATION,
            "seed": SURFACE_SEED, "material": WHITE}


def model(alpha, multiscatter, distribution="beckmann"):
    m = {"type": "roughconductor", "distribution": distribution, "alpha": alpha, "fresnel": "schlick", "f0": 1}
    if multiscatter:
        m["multiscatter"] = True
    return m


def run(cmd, log):
    t = time.time()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    log.write(" ".join(cmd) + f"\n  ({time.time() - t:.1f} s)\n")
    log.flush()
    return out


def run_stdin(cmd, text, log):
    out = subprocess.run(cmd, input=text, check=True, capture_output=True, text=True).stdout
    log.write(" ".join(cmd) + " < directions\n")
    return out


def measure(gonio, data, remeasure):
    os.makedirs(data, exist_ok=True)
    log = open(os.path.join(data, "commands.log"), "a")
    gantry = {"theta_i": THETA_I, "phi_i": 0, "theta_o": THETA_O, "phi_o": [0, 180], "aperture": APERTURE}
    for a in ALPHAS:
        g = os.path.join(data, f"gantry-{a}.json")
        if remeasure or not os.path.exists(g):
            print(f"alpha {a}: gantry", file=sys.stderr)
            run([gonio, "measure", "--surface", json.dumps(surface(a)), "--gantry", json.dumps(gantry),
                 "--samples", str(GANTRY_RAYS_PER_INCIDENCE * len(THETA_I)), "--threads", str(THREADS),
                 "--seed", "1", "--json", g], log)
        t = os.path.join(data, f"table-{a}.binary")
        s = os.path.join(data, f"table-{a}.json")
        if remeasure or not os.path.exists(s):
            print(f"alpha {a}: table", file=sys.stderr)
            out = run([gonio, "measure", "--surface", json.dumps(surface(a)), "-o", t, "--samples",
                       str(TABLE_RAYS), "--threads", str(THREADS), "--seed", "2"], log)
            open(s, "w").write(out)
        f = os.path.join(data, f"fit-{a}.json")
        fits = json.load(open(f)) if os.path.exists(f) and not remeasure else {}
        wanted = [(f"{dist}-{metric}{'-multiscatter' if ms else ''}", dist, metric, ms)
                  for dist, metric, ms in FITS]
        if any(key not in fits for key, *_ in wanted):
            print(f"alpha {a}: fits", file=sys.stderr)
            for key, dist, metric, ms in wanted:
                if key not in fits:
                    fits[key] = json.loads(run(
                        [gonio, "fit", "--data", t, "--model", "roughconductor", "--distribution", dist,
                         "--metric", metric] + (["--init", '{"multiscatter":true}'] if ms else []), log))
            json.dump(fits, open(f, "w"))
        m = os.path.join(data, f"models-{a}.json")
        if remeasure or not os.path.exists(m) or "cone" not in json.load(open(m)):
            print(f"alpha {a}: models", file=sys.stderr)
            res = json.load(open(m)) if os.path.exists(m) and not remeasure else {}
            res["cone"] = APERTURE
            for ms in [False, True]:
                key = "multi" if ms else "single"
                bsdf = json.dumps(model(a, ms))
                if key + "_albedo" not in res:
                    alb = [json.loads(l) for l in run([gonio, "albedo", "--bsdf", bsdf, "--theta-range", "0", "89",
                                                         "90", "--samples", "1000000"], log).splitlines()]
                    res[key + "_albedo"] = [[r["theta"], r["albedo"][0], r["stderr"][0]] for r in alb]
                lobes = {}
                for ti in LOBE_THETA_I:
                    lobes[str(ti)] = cone_lobe(gonio, bsdf, ti, log)
                res[key + "_lobes"] = lobes
            json.dump(res, open(m, "w"))


def cone_lobe(gonio, bsdf, ti, log):
    """The model as each gantry detector reads it: f averaged over the detector's cone with
    the weight cos θ (gantry.h: f = ∫_cone f cos θ dω / ∫_cone cos θ dω), by the midpoint
    rule on 8 × 16 points of the cone's own polar angles. Returns [[signed θo, f], ...]."""
    b = math.radians(APERTURE)
    rings = [((k + 0.5) * b / 8) for k in range(8)]
    turns = [((k + 0.5) * 2 * math.pi / 16) for k in range(16)]
    wi = direction(ti, 0)
    lines, weights, dets = [], [], []
    for to in np.linspace(THETA_O["from"], THETA_O["to"], THETA_O["count"]):
        for po in [0, 180]:
            t, p = math.radians(to), math.radians(po)
            c = direction(to, po)
            u = [math.cos(t) * math.cos(p), math.cos(t) * math.sin(p), -math.sin(t)]
            w = [-math.sin(p), math.cos(p), 0]
            ws = []
            for r in rings:
                for q in turns:
                    o = [math.cos(r) * c[k] + math.sin(r) * (math.cos(q) * u[k] + math.sin(q) * w[k]) for k in range(3)]
                    lines.append(" ".join(map(repr, o + wi)) + "\n")
                    ws.append(math.sin(r) * max(o[2], 0))
            weights.append(ws)
            dets.append(float(to) if po == 0 else -float(to))
    out = run_stdin([gonio, "eval", "--bsdf", bsdf], "".join(lines), log).splitlines()
    vals, n = [], len(rings) * len(turns)
    for k, (x, ws) in enumerate(zip(dets, weights)):
        fs = [json.loads(l)["f"][0] for l in out[k * n:(k + 1) * n]]
        vals.append([x, sum(f * wgt for f, wgt in zip(fs, ws)) / sum(ws)])
    return sorted(vals)


def direction(theta, phi):
    t, p = math.radians(theta), math.radians(phi)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def load(data, a):
    return (json.load(open(os.path.join(data, f"gantry-{a}.json"))),
            json.load(open(os.path.join(data, f"table-{a}.json"))),
            json.load(open(os.path.join(data, f"fit-{a}.json"))),
            json.load(open(os.path.join(data, f"models-{a}.json"))))


def plot(data, docs):
    # (a) albedo vs theta_i
    fig, axes = plt.subplots(1, 4, figsize=(12, 3.2), sharey=True)
    for ax, a in zip(axes, ALPHAS):
        g, _, _, m = load(data, a)
        ti = [inc["theta_i"] for inc in g["incidences"]]
        al = [inc["albedo"][0] for inc in g["incidences"]]
        se = [inc["stderr_albedo"][0] for inc in g["incidences"]]
        s = np.array(m["single_albedo"])
        mu = np.array(m["multi_albedo"])
        ax.plot(s[:, 0], s[:, 1], "C0-", label="single scattering (Smith)")
        ax.plot(mu[:, 0], mu[:, 1], "C1--", label="multiscatter (Kulla-Conty)")
        ax.errorbar(ti, al, yerr=[2 * x for x in se], fmt="ko", ms=3, label="measured (±2σ)")
        ax.set_title(f"α = {a}")
        ax.set_xlabel("θi (degrees)")
        ax.set_xlim(0, 90)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("albedo")
    axes[0].set_ylim(0.45, 1.04)
    axes[0].legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "gonioreflectometer-theory-albedo.png"), dpi=80)
    plt.close(fig)

    # (b) lobes in the plane of incidence; negative theta_o = phi_o 180 (the specular side)
    fig, axes = plt.subplots(len(LOBE_THETA_I), 4, figsize=(12, 7.5))
    for col, a in enumerate(ALPHAS):
        g, _, _, m = load(data, a)
        for row, ti in enumerate(LOBE_THETA_I):
            ax = axes[row][col]
            inc = next(i for i in g["incidences"] if i["theta_i"] == ti)
            x = [d["theta_o"] * (1 if d["phi_o"] == 0 else -1) for d in inc["detectors"]]
            y = [d["f"][0] * math.cos(math.radians(d["theta_o"])) for d in inc["detectors"]]
            e = [2 * d["stderr"][0] * math.cos(math.radians(d["theta_o"])) for d in inc["detectors"]]
            for key, style, lab in [("single", "C0-", "single scattering"), ("multi", "C1--", "multiscatter")]:
                l = np.array(m[key + "_lobes"][str(ti)])
                ax.plot(l[:, 0], l[:, 1] * np.cos(np.radians(np.abs(l[:, 0]))), style, lw=1, label=lab)
            ax.errorbar(x, y, yerr=e, fmt="ko", ms=2, elinewidth=0.8, label="measured (±2σ)")
            ax.set_xlim(-90, 90)
            ax.grid(alpha=0.3)
            if row == 0:
                ax.set_title(f"α = {a}")
            if col == 0:
                ax.set_ylabel(f"θi = {ti}°: f cos θo")
            if row == len(LOBE_THETA_I) - 1:
                ax.set_xlabel("θo (degrees; < 0: specular side)")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "gonioreflectometer-theory-lobes.png"), dpi=72)
    plt.close(fig)

    # (c) fitted alpha against the true alpha
    fig, ax = plt.subplots(figsize=(4.2, 3.6))
    fitrows = []
    for key, mk, lab in [("beckmann-log", "o", "Beckmann, log"), ("beckmann-ngan", "s", "Beckmann, ngan"),
                         ("ggx-log", "^", "GGX, log"), ("ggx-ngan", "v", "GGX, ngan"),
                         ("beckmann-log-multiscatter", "D", "Beckmann + multiscatter, log"),
                         ("beckmann-ngan-multiscatter", "x", "Beckmann + multiscatter, ngan")]:
        xs, ys = [], []
        for a in ALPHAS:
            _, _, f, _ = load(data, a)
            xs.append(a)
            ys.append(f[key]["material"]["alpha"])
        ax.plot(xs, ys, mk, label=lab, mfc="none")
    for a in ALPHAS:
        _, t, f, _ = load(data, a)
        fitrows.append((a, {k: (v["material"]["alpha"], v["material"]["f0"][0], v["error"]) for k, v in f.items()},
                        t["rays"]))
    ax.plot([0, 1.05], [0, 1.05], "k:", lw=1, label="fitted = true")
    ax.axhline(0.99, color="0.6", lw=0.8)
    ax.set_xlabel("true α of the surface")
    ax.set_ylabel("fitted α (roughconductor)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "gonioreflectometer-theory-fit.png"), dpi=80)
    plt.close(fig)

    # Tables (Markdown, on stdout)
    print("| α | θi | measured albedo | single scattering | multiscatter |")
    print("|---|---|---|---|---|")
    for a in ALPHAS:
        g, _, _, m = load(data, a)
        s, mu = np.array(m["single_albedo"]), np.array(m["multi_albedo"])
        for inc in g["incidences"]:
            t = inc["theta_i"]
            k = int(np.argmin(np.abs(s[:, 0] - t)))
            print(f"| {a} | {t:g}° | {inc['albedo'][0]:.5f} ± {inc['stderr_albedo'][0]:.1g} | "
                  f"{s[k, 1]:.4f} ± {s[k, 2]:.1g} | {mu[k, 1]:.4f} ± {mu[k, 2]:.1g} |")
    print()
    print("| α | θi | θo (specular side) | measured f ± σ | single scattering | multiscatter |")
    print("|---|---|---|---|---|---|")
    for a in ALPHAS:
        g, _, _, m = load(data, a)
        for ti in LOBE_THETA_I:
            inc = next(i for i in g["incidences"] if i["theta_i"] == ti)
            side = [d for d in inc["detectors"] if d["phi_o"] == 180]
            d = min(side, key=lambda d: abs(d["theta_o"] - ti))
            vals = []
            for key in ["single", "multi"]:
                l = np.array(m[key + "_lobes"][str(ti)])
                vals.append(np.interp(-d["theta_o"], l[:, 0], l[:, 1]))
            print(f"| {a} | {ti}° | {d['theta_o']:g}° | {d['f'][0]:.3f} ± {d['stderr'][0]:.3f} | "
                  f"{vals[0]:.3f} | {vals[1]:.3f} |")
    print()
    print("| α | fit | fitted α | fitted f0 | error |")
    print("|---|---|---|---|---|")
    for a, fits, _ in fitrows:
        for k, (fa, f0, err) in fits.items():
            print(f"| {a} | {k} | {fa:.4f} | {f0:.4f} | {err:.4g} |")
    print()
    for a in ALPHAS:
        g, t, _, _ = load(data, a)
        c = g["incidences"][0]["rays"]
        print(f"alpha {a}: gantry {g['rays_per_incidence']} rays/incidence, bounces/ray at 0 deg "
              f"{c['bounces'] / c['launched']:.3f}; table {t['rays']['launched']} rays, filled {t['filled']}, "
              f"{t['seconds']:.0f} s, lost {t['rays']['lost']}, down {t['rays']['down']}")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--gonio", default="build/bin/gonio")
    p.add_argument("--data", default="build/theory-data")
    p.add_argument("--docs", default="docs")
    p.add_argument("--remeasure", action="store_true")
    args = p.parse_args()
    measure(args.gonio, args.data, args.remeasure)
    plot(args.data, args.docs)


if __name__ == "__main__":
    main()
