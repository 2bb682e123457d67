"""Where spectral mode's extra noise comes from (issue 38, item 2; docs/benchmarks.md,
"Spectral noise"). For RGB and spectral mode of one scene, the MSE of N-spp images
against a reference of many more samples of the same mode, split into a luminance part and
a chromatic part: with e the error of a pixel (linear sRGB) and g(e) the mean of its three
channels, MSE = mean(|e|²)/3 = mean(g²) + mean(|e − g·(1, 1, 1)|²)/3 exactly (the grey
direction and the plane orthogonal to it). Spectral mode's wavelength noise is mostly
chromatic (a sample's four wavelengths make a colour of their own); noise shared with RGB
mode (light, direction, roulette) is mostly grey.

Variants, each measured in both modes against its own reference:
  base          the scene as written
  no-roulette   "rr_depth" beyond "max_depth": no Russian roulette, so what roulette on
                the spectral throughput adds shows as the difference to base

    PYTHONPATH=build/python /usr/bin/python3 bench/spectral_noise.py [--scene scenes/bench_small.json]
        [--spp 64] [--reference-spp 1024] [--seeds 3]
"""

import argparse
import json
import sys

import numpy as np

import gonio


def render(scene, spp, seed, spectral, sampler, variant):
    s = json.loads(json.dumps(scene))
    r = s.setdefault("render", {})
    r.update({"spectral": spectral, "sampler": sampler})
    if variant == "no-roulette":
        r["rr_depth"] = max(int(r.get("max_depth", 16)) + 1, 2)
    return np.asarray(gonio.render(json.dumps(s), spp=spp, seed=seed), dtype=np.float64)


def split_mse(img, ref):
    e = img - ref
    g = e.mean(axis=-1)
    total = float(np.mean(e * e))
    chroma = float(np.mean((e - g[..., None]) ** 2))
    return total, float(np.mean(g * g)), chroma


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scenes/bench_small.json")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--sampler", default="zsobol")
    ap.add_argument("--variants", default="base,no-roulette")
    a = ap.parse_args()
    with open(a.scene) as f:
        scene = json.load(f)
    print("scene %s, %d spp against %d spp (independent sampler, seed 1000), %s sampler, %d seeds"
          % (a.scene, a.spp, a.reference_spp, a.sampler, a.seeds))
    print("variant       mode      MSE          grey         chromatic    chromatic share")
    for variant in a.variants.split(","):
        for spectral in (False, True):
            ref = render(scene, a.reference_spp, 1000, spectral, "independent", variant)
            parts = np.array([split_mse(render(scene, a.spp, seed, spectral, a.sampler, variant), ref)
                              for seed in range(1, a.seeds + 1)]).mean(axis=0)
            print("%-13s %-9s %.4e   %.4e   %.4e   %.2f" % (variant, "spectral" if spectral else "rgb", parts[0],
                                                             parts[1], parts[2], parts[2] / parts[0]))
            sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
