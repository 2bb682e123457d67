#!/usr/bin/env python3
"""Counts how many surfaces of MaterialX documents load, render and pass `gonio check`
(issue 57's real-world measurement; figures in docs/materialx.md, "The MaterialX
repository's documents").

    scripts/mtlx_corpus.py [--gonio PATH] [--jobs N] [--no-check] [--verbose] DIR [DIR ...]

Every *.mtlx under each DIR (recursively) is one document. Its surfaces are the names
`gonio materials --from-mtlx FILE --list` prints (SPEC §2's naming rule); a document whose
list fails is counted as one surface that does not load (with its reason), and a document
with no surface is reported apart (it is left aside by the issue's figure). Each surface:
- load: `gonio materials --from-mtlx FILE --material NAME` exits 0;
- render: a 16 x 16 picture, 1 sample per pixel, of a sphere of that material under a
  quad light (`gonio render`) exits 0;
- check: `gonio check --bsdf {"mtlx": FILE, "material": NAME}` exits 0 (every property
  holds), 1 (some property fails: counted as loaded, not passed) or 2 (refused).
Refusals whose message starts with "image not found" are counted apart too (the issue
leaves aside the surfaces whose images are absent). The last lines tally the refusals'
reasons (their text after the file name and line), most frequent first.
"""

import argparse
import collections
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import tempfile


def run(cmd, timeout=600):
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return -1, "", "timeout after %d s" % timeout


def reason(err):
    line = err.strip().splitlines()[-1] if err.strip() else "(no message)"
    if line.startswith("image not found"):
        return "image not found"
    # Drop the file and line: "PATH: line N: <node> "name": what" -> "<node>: what".
    line = re.sub(r"^[^:]*\.mtlx: (line \d+: )?", "", line)
    line = re.sub(r'^(<[^>]*>) "[^"]*"', r"\1", line)
    line = re.sub(r'"[^"]*"', '"…"', line)
    return line[:140]


def one_surface(gonio, path, name, check):
    result = {"file": path, "name": name}
    code, _, err = run([gonio, "materials", "--from-mtlx", path, "--material", name])
    result["load"] = code == 0
    if code != 0:
        result["reason"] = reason(err)
        return result
    bsdf = {"mtlx": os.path.abspath(path), "material": name}
    scene = {
        "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 40, "width": 16, "height": 16},
        "render": {"spp": 1, "max_depth": 4},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.8, "material": bsdf}],
        "lights": [{"type": "quad", "corner": [-1, 2, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "radiance": 4}],
    }
    with tempfile.TemporaryDirectory() as tmp:
        scene_path = os.path.join(tmp, "scene.json")
        with open(scene_path, "w") as f:
            json.dump(scene, f)
        code, _, err = run([gonio, "render", scene_path, "-o", os.path.join(tmp, "out.exr"), "--threads", "1"])
    result["render"] = code == 0
    if code != 0:
        result["reason"] = "render: " + reason(err)
    if check:
        code, _, err = run([gonio, "check", "--bsdf", json.dumps(bsdf)])
        result["check"] = code == 0
        if code == 2:
            result.setdefault("reason", "check: " + reason(err))
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--gonio", default="gonio")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--no-check", action="store_true")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()

    docs = sorted(os.path.join(root, f) for d in a.dirs for root, _, files in os.walk(d) for f in files if f.endswith(".mtlx"))
    surfaces, results, no_surface = [], [], []
    for path in docs:
        code, out, err = run([a.gonio, "materials", "--from-mtlx", path, "--list"])
        if code != 0:
            results.append({"file": path, "name": "(document)", "load": False, "reason": reason(err)})
            continue
        names = out.split()
        if not names:
            no_surface.append(path)
        surfaces += [(path, n) for n in names]
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results += list(pool.map(lambda s: one_surface(a.gonio, s[0], s[1], not a.no_check), surfaces))

    images = [r for r in results if r.get("reason") == "image not found"]
    counted = [r for r in results if r.get("reason") != "image not found"]
    loaded = [r for r in counted if r["load"]]
    rendered = [r for r in loaded if r.get("render")]
    passed = [r for r in rendered if r.get("check", True)]
    if a.verbose:
        for r in results:
            flags = "".join(k[0].upper() if r.get(k) else "-" for k in ("load", "render", "check"))
            print("%s %s %s%s" % (flags, r["file"], r["name"], ("  " + r["reason"]) if "reason" in r else ""))
    print("documents: %d (no surface: %d)" % (len(docs), len(no_surface)))
    print("surfaces: %d (image absent: %d; counted: %d)" % (len(results), len(images), len(counted)))
    print("load: %d/%d" % (len(loaded), len(counted)))
    print("render: %d/%d" % (len(rendered), len(counted)))
    if not a.no_check:
        print("load + render + check: %d/%d" % (len(passed), len(counted)))
    tally = collections.Counter(r["reason"] for r in counted if "reason" in r)
    for why, n in tally.most_common():
        print("%4d  %s" % (n, why))
    return 0


if __name__ == "__main__":
    sys.exit(main())
