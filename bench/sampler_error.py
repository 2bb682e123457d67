"""Error per sample of the renderer's samplers (issue 38; docs/benchmarks.md, "Samplers"):
the MSE of N-spp images against a reference of many more samples of the same build, for
each sampler, in RGB and spectral mode. The MSE is averaged over several seeds (each
image's error is itself noisy); the reference uses the independent sampler and another
seed, so that a bias of the others would show as error. The mean of every image over its
pixels is printed beside the reference's, as a second check of bias.

    PYTHONPATH=build/python /usr/bin/python3 bench/sampler_error.py [--scene scenes/bench_small.json]
        [--spp 64] [--reference-spp 2048] [--seeds 4] [--spectral]

With --light-samplers bvh,uniform,power the same is done for the light selection
strategies ("render": {"light_sampler"}) under the scene's sampler, the reference using
the first of them and another seed; --cli-time N also times each strategy by the median
of N runs of `gonio render` (its own samples/s figure) and prints the efficiency
1 / (time x MSE) relative to the first.
"""

import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import gonio


def render(scene, sampler, spp, seed, spectral, light_sampler=None):
    s = json.loads(json.dumps(scene))
    s.setdefault("render", {})
    s["render"].update({"sampler": sampler, "spectral": spectral})
    if light_sampler:
        s["render"]["light_sampler"] = light_sampler
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
    ap.add_argument("--light-samplers", default="",
                    help="compare these light selection strategies (e.g. bvh,uniform,power) instead of the samplers")
    ap.add_argument("--cli-time", type=int, default=0,
                    help="with --light-samplers: time each by the median samples/s of this many `gonio render` runs")
    ap.add_argument("--gonio", default="build/bin/gonio")
    a = ap.parse_args()
    with open(a.scene) as f:
        scene = json.load(f)
    if a.light_samplers:
        return compare_light_samplers(a, scene)
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


def cli_seconds_per_sample(a, light_sampler):
    """The median over a.cli_time runs of 1 / (the renderer's own samples/s figure)."""
    rates = []
    with tempfile.TemporaryDirectory() as d:
        for _ in range(a.cli_time):
            r = subprocess.run([a.gonio, "render", a.scene, "--spp", str(a.spp), "--light-sampler", light_sampler,
                                "-o", d + "/x.exr"], capture_output=True, text=True, check=True)
            m = re.search(r"([0-9.]+) (k|M|G|)samples/s", r.stderr)
            rates.append(float(m.group(1)) * {"": 1, "k": 1e3, "M": 1e6, "G": 1e9}[m.group(2)])
    return 1 / statistics.median(rates)


def compare_light_samplers(a, scene):
    names = a.light_samplers.split(",")
    sampler = scene.get("render", {}).get("sampler", "zsobol")
    ref, tref = render(scene, sampler, a.reference_spp, 1000, a.spectral, names[0])
    print("reference: %s, %d spp in %.1f s, image mean %s" % (names[0], a.reference_spp, tref,
                                                             " ".join("%.5f" % m for m in ref.mean(axis=(0, 1)))))
    base = None
    for name in names:
        errs, times = [], []
        for seed in range(a.seeds):
            img, t = render(scene, sampler, a.spp, seed + 1, a.spectral, name)
            errs.append(float(np.mean((img - ref) ** 2)))
            times.append(t)
        mse = float(np.mean(errs))
        t = cli_seconds_per_sample(a, name) if a.cli_time else float(np.median(times))
        eff = 1 / (t * mse)
        if base is None:
            base = (mse, eff)
        print("%-8s MSE %.4e (seeds: %s)  relative MSE %.3f  %s %.4g s  efficiency relative to %s: %.2f  image mean %s" % (
            name, mse, " ".join("%.3e" % e for e in errs), mse / base[0],
            "time per sample" if a.cli_time else "median time", t, names[0], eff / base[1],
            " ".join("%.5f" % m for m in img.mean(axis=(0, 1)))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
