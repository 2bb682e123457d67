"""The scaling figures of docs/distributed.md (issue 37): a 640x360 render in 64 passes on a
LocalCluster of 1 and of 2 single-threaded worker processes, the same passes one after the
other in this process (no Dask), and the cost of a task that does nothing.

    PYTHONPATH=build/python /usr/bin/python3 bench/distributed_bench.py [--spp 64] [--passes 64]

With --fit, the same for fitting: 16 MERL tables (made by `Material.tabulate` from 16 rough
conductors and plastics) x 2 models (roughconductor, plastic), 32 tasks.

    PYTHONPATH=build/python /usr/bin/python3 bench/distributed_bench.py --fit
"""

import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np

import gonio
import gonio.distributed as gd


def scene_file(width, height):
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "scenes", "bench_small.json")) as f:
        s = json.load(f)
    s["camera"]["width"], s["camera"]["height"] = width, height
    fd, path = tempfile.mkstemp(suffix=".json")
    with os.fdopen(fd, "w") as f:
        json.dump(s, f)
    return path


def noop(x):
    return x


def fit_bench():
    tmp = tempfile.mkdtemp()
    tables = []
    for i in range(16):
        alpha = 0.08 + 0.04 * i
        m = ({"type": "roughconductor", "material": ["Au", "Cu", "Ag", "Al"][i % 4], "alpha": alpha} if i < 8 else
             {"type": "plastic", "reflectance": [0.2 + 0.05 * i, 0.3, 0.4], "alpha": alpha})
        path = os.path.join(tmp, "%02d.binary" % i)
        gonio.Material(m).tabulate(path)
        tables.append(path)
    models = ["roughconductor", "plastic"]
    try:
        t = time.perf_counter()
        serial = [gonio.fit(tb, md) for tb in tables for md in models]
        serial_s = time.perf_counter() - t
        n = len(serial)
        print("serial, no Dask: %.2f s (%.0f ms per fit)" % (serial_s, 1e3 * serial_s / n))
        times = {}
        for w in (1, 2):
            gd._quiet_dask()
            with gd.cluster(workers=w) as c:
                c.submit(noop, 0).result()
                t = time.perf_counter()
                got = gd.fit(tables, models, client=c)
                times[w] = time.perf_counter() - t
            same = all(g["material"] == s_["material"] and g["error"] == s_["error"] for g, s_ in zip(got, serial))
            print("%d worker(s): %.2f s; results equal to the serial fits: %s" % (w, times[w], same))
        print("speed-up 2 over 1: %.2fx" % (times[1] / times[2]))
        print("overhead per fit task on 1 worker: %.1f ms" % (1e3 * (times[1] - serial_s) / n))
    finally:
        for tb in tables:
            os.remove(tb)
        os.rmdir(tmp)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--passes", type=int, default=64)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--fit", action="store_true", help="the fitting figures instead of the render's")
    a = ap.parse_args()
    if a.fit:
        return fit_bench()
    path = scene_file(a.width, a.height)
    try:
        # The passes in this process, one thread each, no Dask: the work itself.
        t = time.perf_counter()
        scene = gonio.Scene(path)
        for p in range(a.passes):
            gonio.render(scene, threads=1, sample_range=gd.pass_range(p, a.spp, a.passes))
        serial = time.perf_counter() - t
        print("serial, 1 thread, no Dask: %.2f s (%.1f ms per pass)" % (serial, 1e3 * serial / a.passes))
        images, times = {}, {}
        for w in (1, 2):
            gd._quiet_dask()
            with gd.cluster(workers=w) as c:
                c.submit(noop, 0).result()
                t = time.perf_counter()
                futs = [c.submit(noop, i, pure=False) for i in range(500)]
                c.gather(futs)
                per_noop = (time.perf_counter() - t) / 500
                gd.render(path, 2, 2, client=c)  # loads the scene on the workers
                t = time.perf_counter()
                images[w] = gd.render(path, a.spp, a.passes, client=c)
                times[w] = time.perf_counter() - t
            print("%d worker(s): %.2f s; an empty task: %.2f ms" % (w, times[w], 1e3 * per_noop))
        print("speed-up 2 over 1: %.2fx" % (times[1] / times[2]))
        print("overhead per pass task on 1 worker: %.1f ms (%.1f%% of a pass)"
              % (1e3 * (times[1] - serial) / a.passes, 100 * (times[1] - serial) / serial))
        print("bit-identical 1 vs 2 workers:", bool(np.array_equal(images[1], images[2])))
    finally:
        os.remove(path)


if __name__ == "__main__":
    sys.exit(main())
