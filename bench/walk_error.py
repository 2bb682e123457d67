"""Efficiency and colour noise of the renderer's subsurface random walk (issue 38 items 4
and 5; docs/benchmarks.md, "Guided random walk"), on scenes/marble.json scaled down.

Error: the MSE of N-spp images against a reference of many more samples (another seed);
time: the renderer's own samples/s figure (`gonio render`, one thread unless --threads);
efficiency = 1 / (time per sample x MSE). Sparkles: the fraction of pixels with luminance
> 0.05 whose hue is more than 30 degrees from the median hue of their 3x3 neighbourhood,
also counted by the reference's HSV saturation. --seeds 0 only makes the reference.

    /usr/bin/python3 bench/walk_error.py [--scene scenes/marble.json] [--width 100 --height 75]
        [--spp 16] [--reference-spp 1024] [--seeds 3] [--sparkle-spp 384] [--walk '{"guided": false}']

The images are read from gonio's ZIP-compressed EXR output by read_exr below (standard
library + numpy). --reference FILE.npy reuses (or writes) a reference.
"""

import argparse
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np


def read_exr(path):
    """A scanline EXR of FLOAT channels, uncompressed or ZIP (16 lines a block), as H x W x 3 RGB."""
    with open(path, "rb") as f:
        data = f.read()
    assert struct.unpack_from("<I", data, 0)[0] == 20000630, "not an EXR file"
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos); name = data[pos:end].decode(); pos = end + 1
        end = data.index(b"\0", pos); typ = data[pos:end].decode(); pos = end + 1
        size = struct.unpack_from("<i", data, pos)[0]; pos += 4
        attrs[name] = (typ, data[pos:pos + size]); pos += size
    pos += 1
    chl, channels = attrs["channels"][1], []
    p = 0
    while chl[p] != 0:
        end = chl.index(b"\0", p); name = chl[p:end].decode(); p = end + 1
        ptype = struct.unpack_from("<i", chl, p)[0]; p += 16
        assert ptype == 2, "only FLOAT channels"
        channels.append(name)
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    comp = attrs["compression"][1][0]
    lines = {0: 1, 3: 16}[comp]
    nblocks = (h + lines - 1) // lines
    offsets = struct.unpack_from("<%dQ" % nblocks, data, pos)
    img = np.zeros((h, len(channels), w), dtype=np.float32)
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        raw = data[off + 8:off + 8 + size]
        n = min(lines, y1 - y + 1)
        expected = n * len(channels) * w * 4
        if comp == 3 and size < expected:
            t = np.frombuffer(zlib.decompress(raw), dtype=np.uint8).astype(np.int32)
            t = (np.cumsum(t - 128) + 128 * 1) & 0xFF  # undo the predictor: d[i] = t[i] - t[i-1] + 128
            t[:] = t  # (first byte is stored as-is: cumsum of (t0-128) + 128 = t0)
            t = t.astype(np.uint8)
            half = (len(t) + 1) // 2
            out = np.empty_like(t)
            out[0::2] = t[:half]
            out[1::2] = t[half:]
            raw = out.tobytes()
        block = np.frombuffer(raw, dtype="<f4").reshape(n, len(channels), w)
        img[y - y0:y - y0 + n] = block
    order = [channels.index(c) for c in "RGB"]
    return img[:, order, :].transpose(0, 2, 1).astype(np.float64)


def render(a, scene, spp, seed, out):
    with tempfile.NamedTemporaryFile("w", suffix=".json", dir=os.path.dirname(os.path.abspath(a.scene)),
                                     delete=False) as f:
        json.dump(scene, f)
        path = f.name
    try:
        r = subprocess.run([a.gonio, "render", path, "--spp", str(spp), "--seed", str(seed), "--threads",
                            str(a.threads), "-o", out], capture_output=True, text=True, check=True)
    finally:
        os.unlink(path)
    m = re.search(r"([0-9.]+) (k|M|G|)samples/s", r.stderr)
    rate = float(m.group(1)) * {"": 1, "k": 1e3, "M": 1e6, "G": 1e9}[m.group(2)]
    return read_exr(out), 1 / rate


def hue(img):
    """HSV hue in degrees."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return np.degrees(np.arctan2(np.sqrt(3) * (g - b), 2 * r - g - b)) % 360


def sparkle_pixels(img):
    """The flagged pixels (hue > 30 degrees from the 3x3 neighbourhood's median hue) and the
    bright ones (luminance > 0.05), as boolean images."""
    lum = 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]
    h = hue(img)
    H, W = h.shape
    pad = np.pad(h, 1, mode="edge")
    nb = np.stack([pad[dy:dy + H, dx:dx + W] for dy in range(3) for dx in range(3)], axis=-1)
    # median of angles: the median of the neighbours' hues unwrapped around the centre's
    d = (nb - h[..., None] + 180) % 360 - 180
    med = np.median(d, axis=-1)
    bright = lum > 0.05
    return (np.abs(med) > 30) & bright, bright


def sparkle_fraction(img):
    far, bright = sparkle_pixels(img)
    return float(np.count_nonzero(far)) / max(1, int(np.count_nonzero(bright))), int(np.count_nonzero(far)), int(np.count_nonzero(bright))


def saturation(img):
    """HSV saturation, (max - min) / max."""
    mx, mn = img.max(axis=-1), img.min(axis=-1)
    return np.where(mx > 0, (mx - mn) / np.maximum(mx, 1e-30), 0)


def sparkles_by_saturation(img, ref):
    """The flagged share among the bright pixels, by the reference's saturation: hue is noise
    where the colour is near grey, whatever the estimator (docs/subsurface.md)."""
    far, bright = sparkle_pixels(img)
    sat = saturation(ref)
    rows = []
    for lo, hi in [(0, 0.02), (0.02, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 1.01)]:
        m = bright & (sat >= lo) & (sat < hi)
        rows.append("[%.2f, %.2f): %d of %d" % (lo, hi, int(np.count_nonzero(far & m)), int(np.count_nonzero(m))))
    return "; ".join(rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scenes/marble.json")
    ap.add_argument("--width", type=int, default=100)
    ap.add_argument("--height", type=int, default=75)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--reference", default="", help="a .npy reference to reuse, or to write if missing")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--sparkle-spp", type=int, default=0, help="also measure the sparkle fraction at this spp")
    ap.add_argument("--walk", default="", help="JSON merged into the marble material (e.g. '{\"guided\": false}')")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--save", default="", help="write the sparkle image (.npy) here")
    ap.add_argument("--gonio", default="build/bin/gonio")
    a = ap.parse_args()
    with open(a.scene) as f:
        scene = json.load(f)
    scene["camera"]["width"], scene["camera"]["height"] = a.width, a.height
    if a.walk:
        for m in scene["materials"].values():
            if m.get("type") == "subsurface":
                m.update(json.loads(a.walk))
    with tempfile.TemporaryDirectory() as d:
        out = d + "/x.exr"
        if a.reference and os.path.exists(a.reference):
            ref = np.load(a.reference)
            print("reference: %s, image mean %s" % (a.reference, " ".join("%.5f" % m for m in ref.mean(axis=(0, 1)))))
        else:
            ref, t = render(a, scene, a.reference_spp, 1000, out)
            print("reference: %d spp, %dx%d, %.1f s, image mean %s" % (a.reference_spp, a.width, a.height,
                  t * a.reference_spp * a.width * a.height, " ".join("%.5f" % m for m in ref.mean(axis=(0, 1)))))
            if a.reference:
                np.save(a.reference, ref)
        errs, times = [], []
        for seed in range(a.seeds):
            img, t = render(a, scene, a.spp, seed + 1, out)
            errs.append(float(np.mean((img - ref) ** 2)))
            times.append(t)
        if errs:
            mse = float(np.mean(errs))
            t = float(np.median(times))
            print("walk %s: %d spp MSE %.4e (seeds: %s)  time per sample %.4g s  efficiency 1/(t MSE) %.4g  image mean %s" % (
                a.walk or "(scene's)", a.spp, mse, " ".join("%.3e" % e for e in errs), t, 1 / (t * mse),
                " ".join("%.5f" % m for m in img.mean(axis=(0, 1)))))
        if a.sparkle_spp:
            img, t = render(a, scene, a.sparkle_spp, 7, out)
            if a.save:
                np.save(a.save, img)
            frac, n, nb = sparkle_fraction(img)
            print("sparkles at %d spp: %.3f %% (%d of %d pixels with luminance > 0.05)" % (a.sparkle_spp, 100 * frac, n, nb))
            print("  flagged by the reference's saturation: " + sparkles_by_saturation(img, ref))
    return 0


if __name__ == "__main__":
    sys.exit(main())
