"""Error per sample of the renderer's samplers (issue 38; docs/benchmarks.md, "Samplers"):
the MSE of N-spp images against a reference of many more samples of the same build, for
each sampler, in RGB and spectral mode. The MSE is averaged over several seeds (each
image's error is itself noisy); the reference uses the independent sampler and another
seed, so that a bias of the others would show as error. The mean of every image over its
pixels is printed beside the reference's, as a second check of bias.

    PYTHONPATH=build/python /usr/bin/python3 bench/sampler_error.py [--scene scenes/bench_small.json]
        [--spp 64] [--reference-spp 2048] [--seeds 4] [--spectral]
"""

import argparse
import json
import sys
import time

import numpy as np

import gonio


def render(scene, sampler, spp, seed, spectral):
    s = json.loads(json.dumps(scene))
    s.setdefault("render", {})
    s["render"].update({"sampler": sampler, "spectral": spectral})
    t = time.perf_counter()
    img = gonio.render(json.dumps(s), spp=spp, seed=seed)
    return np.asarray(img, dtype=np.float64), time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scenes/bench_small.json")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reference-spp", type=int, default=2048)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--spectral", action="store_true")
    ap.add_argument("--samplers", default="independent,sobol,zsobol")
    ap.add_argument("--reference-sampler", default="independent",
                    help="the reference's sampler: independent by default, so that a bias of the others shows")
    a = ap.parse_args()
    with open(a.scene) as f:
        scene = json.load(f)
    ref, tref = render(scene, a.reference_sampler, a.reference_spp, 1000, a.spectral)
    print("reference: %d spp in %.1f s (%s), image mean %s" % (a.reference_spp, tref, "spectral" if a.spectral else "RGB",
                                                            " ".join("%.5f" % m for m in ref.mean(axis=(0, 1)))))
    base = None
    for sampler in a.samplers.split(","):
        errs, times = [], []
        for seed in range(a.seeds):
            img, t = render(scene, sampler, a.spp, seed + 1, a.spectral)
            errs.append(float(np.mean((img - ref) ** 2)))
            times.append(t)
        mse = float(np.mean(errs))
        means = " ".join("%.5f" % m for m in img.mean(axis=(0, 1)))
        if base is None:
            base = mse
        print("%-12s MSE %.4e (seeds: %s)  relative to %s: %.3f  median time %.2f s  image mean %s" % (
            sampler, mse, " ".join("%.3e" % e for e in errs), a.samplers.split(",")[0], mse / base,
            float(np.median(times)), means))
    return 0


if __name__ == "__main__":
    sys.exit(main())
