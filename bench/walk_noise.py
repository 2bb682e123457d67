"""Per-pixel noise of the subsurface random walk on a sphere under a quad light (issue 38;
docs/benchmarks.md, "Guided random walk"): the relative standard deviation of a pixel's
value between independent renders (seeds), per pixel of the sphere, its median over them.

    /usr/bin/python3 bench/walk_noise.py [--alpha 0.3] [--light 1.0] [--spp 16] [--seeds 8]
        [--material '{"type": "diffuse"}'] [--walk '{"nee": false}']

The sphere (radius 1) is `subsurface` with mfp 0.001 and albedo 0.8 (so it should look
almost like a diffuse surface), boundary eta 1.33 and roughness alpha (0: smooth); one
quad light of side --light at distance 4, no environment.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from walk_error import read_exr  # noqa: E402


def scene(a):
    if a.material:
        mat = json.loads(a.material)
    else:
        mat = {"type": "subsurface", "eta": 1.33, "albedo": 0.8, "mfp": 0.001}
        if a.alpha > 0:
            mat["alpha"] = a.alpha
        if a.walk:
            mat.update(json.loads(a.walk))
    s = a.light
    return {
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 28, "width": a.size, "height": a.size},
        "render": {"spp": a.spp, "max_depth": 64},
        "materials": {"m": mat},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
        "lights": [{"type": "quad", "corner": [-s / 2, 4, -s / 2], "edge1": [s, 0, 0], "edge2": [0, 0, s],
                    "radiance": 10 / (s * s)}],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gonio", default="build/bin/gonio")
    ap.add_argument("--alpha", type=float, default=0.3)
    ap.add_argument("--light", type=float, default=1.0)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seeds", type=int, default=16)
    ap.add_argument("--size", type=int, default=48)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--material", default="")
    ap.add_argument("--walk", default="")
    a = ap.parse_args()
    imgs, rates = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "s.json")
        with open(path, "w") as f:
            json.dump(scene(a), f)
        for seed in range(a.seeds):
            out = os.path.join(tmp, "o.exr")
            r = subprocess.run([a.gonio, "render", path, "--seed", str(seed + 1), "--threads", str(a.threads), "-o", out],
                               capture_output=True, text=True, check=True)
            imgs.append(read_exr(out).mean(axis=2))
    stack = np.array(imgs)
    mean, std = stack.mean(axis=0), stack.std(axis=0, ddof=1)
    # The pixels that see the sphere where it faces the light (normal's y > 0.3), found by
    # tracing the camera's pinhole rays (the scene's camera above) against the sphere.
    n = a.size
    half = np.tan(np.radians(28 / 2))
    px = (np.arange(n) + 0.5) / n * 2 - 1
    X, Y = np.meshgrid(px * half, -px * half)
    D = np.stack([X, Y, -np.ones_like(X)], axis=-1)
    D /= np.linalg.norm(D, axis=-1, keepdims=True)
    o = np.array([0, 0, 5.0])
    b = (D @ o)
    disc = b * b - (o @ o - 1)
    t = -b - np.sqrt(np.maximum(disc, 0))
    ny = (o + D * t[..., None])[..., 1]
    lit = (disc > 0.02) & (ny > 0.3)
    # Pooled over the lit pixels: the RMS of a pixel's standard deviation over the mean of
    # their values (a per-pixel ratio is undefined where every seed gave 0).
    rel = np.sqrt((std[lit] ** 2).mean()) / mean[lit].mean()
    zero = (stack[:, lit] == 0).mean()
    with np.errstate(divide="ignore", invalid="ignore"):
        per = np.where(mean[lit] > 0, std[lit] / mean[lit], np.inf)
    print("  per-pixel relative std: median %.1f %%, quartiles %.1f %% %.1f %%" % tuple(100 * np.percentile(per, [50, 25, 75])))
    print("alpha %g light %g spp %d: relative std per pixel (pooled over %d lit pixels) %.1f %%; lit pixels at 0: %.1f %%; "
          "lit mean %.4g" % (a.alpha, a.light, a.spp, lit.sum(), 100 * rel, 100 * zero, mean[lit].mean()))


if __name__ == "__main__":
    main()
