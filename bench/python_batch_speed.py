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
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        m.eval(wo, wi, threads=threads)
        best = min(best, time.perf_counter() - t)
    return len(wo) / best


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
    for name, text, target in CASES:
        m = gonio.Material(text)
        r1 = rate(m, wo, wi, 1, a.repeat)
        rt = rate(m, wo, wi, a.threads, a.repeat)
        goal = "" if target is None else ("  target %.0f M/s: %s" % (target / 1e6, "met" if rt >= target else "MISSED"))
        print("%-50s 1 thread %7.1f M/s   %d threads %7.1f M/s%s" % (name, r1 / 1e6, a.threads, rt / 1e6, goal))


if __name__ == "__main__":
    main()
