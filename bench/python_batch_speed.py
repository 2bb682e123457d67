#!/usr/bin/env python3
"""Batch speed of the Python module (issue 16): eval/s of Lambert and of the GGX rough
conductor on arrays of 10^6 directions, from Python, as a user calls it:

    PYTHONPATH=build/python /usr/bin/python3 bench/python_batch_speed.py [--n 1000000] [--threads 2]

Each figure is the best of --repeat calls of Material.eval on float64 (N, 3) arrays
(random directions over the upper hemisphere, unnormalised as a user would pass them), the
output arrays allocated by each call as usual. Results go to docs/benchmarks.md by hand.
Targets: >= 100 M/s Lambert, >= 20 M/s rough conductor, on 2 cores.
"""

import argparse
import os
import platform
import time

import numpy as np

import gonio

CASES = [
    ("diffuse (Lambert)", '{"type":"diffuse","reflectance":0.5}', 100e6),
    ("roughconductor GGX, Au, alpha 0.3", '{"type":"roughconductor","material":"Au","alpha":0.3}', 20e6),
    ("roughconductor GGX, Au, alpha 0.3, multiscatter",
     '{"type":"roughconductor","material":"Au","alpha":0.3,"multiscatter":true}', None),
    ("plastic, rough coat", '{"type":"plastic","reflectance":0.5,"alpha":0.2}', None),
]


def rate(m, wo, wi, threads, repeat):
    """(wall, cpu): elements per wall-clock second and per CPU-second of the process (all
    threads), each the best of `repeat` calls. On a loaded machine the CPU figure is the
    steadier one: 2 x the 1-thread CPU rate is what 2 idle cores would give if the work
    scales."""
    wall = cpu = float("inf")
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        m.eval(wo, wi, threads=threads)
        wall = min(wall, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return len(wo) / wall, len(wo) / cpu


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeat", type=int, default=15)
    a = p.parse_args()
    rng = np.random.default_rng(1)
    wo = rng.normal(size=(a.n, 3))
    wi = rng.normal(size=(a.n, 3))
    wo[:, 2] = np.abs(wo[:, 2])
    wi[:, 2] = np.abs(wi[:, 2])
    print("gonio %s, numpy %s, Python %s, %d elements, threads=%d, %d cores, load %s"
          % (gonio.__version__, np.__version__, platform.python_version(), a.n, a.threads, os.cpu_count(),
             " ".join("%.2f" % x for x in os.getloadavg())))
    print("%-48s %24s %24s" % ("", "1 thread: wall, per CPU-s", "%d threads: wall, per CPU-s" % a.threads))
    for name, text, target in CASES:
        m = gonio.Material(text)
        w1, c1 = rate(m, wo, wi, 1, a.repeat)
        wt, ct = rate(m, wo, wi, a.threads, a.repeat)
        goal = "" if target is None else ("  target %.0f M/s: %s" % (target / 1e6, "met" if wt >= target else "missed"))
        print("%-48s %9.1f %9.1f M/s    %9.1f %9.1f M/s%s" % (name, w1 / 1e6, c1 / 1e6, wt / 1e6, ct / 1e6, goal))


if __name__ == "__main__":
    main()
