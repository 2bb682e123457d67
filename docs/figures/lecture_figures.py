#!/usr/bin/env python3
"""The lecture's figures (docs/lecture.md), made with gonio's Python module.

    PYTHONPATH=build/python /usr/bin/python3 docs/figures/lecture_figures.py OUTDIR [--quick] [--only NAME ...]

docs/figures/make.sh runs it into docs/figures/. --quick: low resolution and few samples
(the test python.lecture uses it to check that every figure is made and not blank).
Prints one line per figure with what it measured.
"""

import argparse
import copy
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import gonio  # noqa: E402
from gonio import plot  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def save(fig, out, name, dpi):
    path = os.path.join(out, name)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


# --- Fig. 1: ideal specular, ideal diffuse, glossy -----------------------------------------


def fig1(out, dpi, quick):
    models = [("ideal specular (mirror)", {"type": "mirror"}),
              ("ideal diffuse (Lambert)", {"type": "diffuse", "reflectance": 0.8}),
              ("glossy (GGX rough aluminium, α = 0.25)", {"type": "roughconductor", "material": "Al", "alpha": 0.25})]
    fig = plt.figure(figsize=(13, 4.6))
    for k, (name, desc) in enumerate(models):
        ax = fig.add_subplot(1, 3, k + 1, projection="polar")
        plot.draw_lobe(ax, gonio.Material(desc), thetas=(45,), samples=180 if quick else 720)
        ax.set_title(name, fontsize=10)
        ax.set_rlabel_position(200)
        ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.28), fontsize=7)
    fig.suptitle("Fig. 1: three reflection models, light at θi = 45° (dotted); "
                 "radius f · |cos θo| in 1/sr (the mirror: its share of the power)", fontsize=10)
    fig.subplots_adjust(bottom=0.22, top=0.82, wspace=0.35)
    return save(fig, out, "fig1-lobes.png", dpi), "mirror, Lambert, rough Al at 45°"


# --- Fig. 7: total internal reflection ----------------------------------------------------


def fig7(out, dpi, quick):
    theta = np.linspace(0, 90, 91 if quick else 901)
    media = [("glass, n = 1.5", 1.5, "tab:blue"), ("water, n = 1.333", 1.333, "tab:cyan")]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4))
    notes = []
    for name, n, colour in media:
        for inside, style in ((True, "-"), (False, "--")):
            d = gonio.fresnel(theta, eta=1 / n if inside else n)
            tt = np.where(d["tir"], np.nan, np.degrees(np.arccos(np.clip(d["cos_t"], 0, 1))))
            where = "from inside " if inside else "from outside "
            a.plot(theta, tt, style, color=colour, label=where + name)
            b.plot(theta, d["R"], style, color=colour, label=where + name)
        crit = math.degrees(math.asin(1 / n))
        for ax in (a, b):
            ax.axvline(crit, color=colour, lw=0.8, ls=":")
        a.annotate("critical %.1f°" % crit, (crit, 5), rotation=90, fontsize=8, color=colour, ha="right")
        notes.append("%s critical %.2f°" % (name.split(",")[0], crit))
    a.set_xlabel("angle of incidence θi (degrees)")
    a.set_ylabel("angle of refraction θt (degrees)")
    a.set_title("Snell's law: past the critical angle nothing is refracted", fontsize=9)
    b.set_xlabel("angle of incidence θi (degrees)")
    b.set_ylabel("reflectance R (unpolarised)")
    b.set_title("Fresnel: R = 1 (total internal reflection) from inside", fontsize=9)
    for ax in (a, b):
        ax.set_xlim(0, 90)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    b.set_ylim(0, 1.02)
    fig.suptitle("Fig. 7: total internal reflection, glass and water", fontsize=10)
    fig.tight_layout()
    return save(fig, out, "fig7-tir.png", dpi), ", ".join(notes)


def fig7_block(out, dpi, quick):
    """Light trapped in a glass block: scenes/glass-block.json, a lamp inside a glass cube.
    The note gives the share of the lamp's light that can never leave a perfect cube: a
    box's faces only flip the signs of a ray's direction cosines, so a ray leaves only if
    one of |dx|, |dy|, |dz| exceeds cos θc, i.e. if it meets some face within the critical
    angle. The Monte Carlo estimate asks gonio.fresnel whether each face reflects totally;
    the closed form is 1 - 6 · (1 - cos θc) / 2, six disjoint escape cones (θc < 45°)."""
    with open(os.path.join(ROOT, "scenes", "glass-block.json"), encoding="utf-8") as f:
        scene = json.load(f)
    if quick:
        scene["camera"]["width"] //= 8
        scene["camera"]["height"] //= 8
    spp = 2 if quick else scene["render"]["spp"]
    img = gonio.render(scene, spp=spp, seed=1)
    path = os.path.join(out, "fig7-glass-block.png")
    plt.imsave(path, srgb(img))
    n = scene["materials"]["glass"]["eta"]
    d = np.random.default_rng(1).normal(size=(20000 if quick else 2000000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    angles = np.degrees(np.arccos(np.abs(d)))  # the angle with each face's normal
    trapped = np.all(gonio.fresnel(angles.ravel(), eta=1 / n)["tir"].reshape(angles.shape), axis=1).mean()
    closed = 1 - 3 * (1 - math.sqrt(1 - 1 / n ** 2))
    return path, "%dx%d, %d spp; trapped for ever in a perfect cube: %.4f (Monte Carlo, %d directions), %.4f (closed form)" % (
        img.shape[1], img.shape[0], spp, trapped, len(d), closed)


# --- Fig. 8: Fresnel reflectance of dielectrics and metals --------------------------------


def fig8(out, dpi, quick):
    theta = np.linspace(0, 90, 91 if quick else 901)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    notes = []
    dielectrics = [("glass (BK7, 550 nm)", dict(material="BK7", wavelength=550), "tab:blue"),
                   ("water (n = 1.333)", dict(eta=1.333), "tab:cyan")]
    metals = [("gold", "Au", "goldenrod"), ("aluminium", "Al", "tab:gray"), ("copper", "Cu", "chocolate")]
    for name, kw, colour in dielectrics:
        d = gonio.fresnel(theta, **kw)
        a.plot(theta, d["R"], color=colour, lw=2, label=name + ": R")
        a.plot(theta, d["Rs"], "--", color=colour, label="s")
        a.plot(theta, d["Rp"], ":", color=colour, label="p")
        brewster = math.degrees(math.atan(d["eta"][0]))
        a.axvline(brewster, color=colour, lw=0.6)
        notes.append("%s R(0) %.4f, Brewster %.2f°" % (name.split(" ")[0], d["R"][0], brewster))
    for name, sym, colour in metals:
        d = gonio.fresnel(theta, material=sym, wavelength=550)
        b.plot(theta, d["R"], color=colour, lw=2, label="%s (%s, 550 nm): R" % (name, sym))
        b.plot(theta, d["Rs"], "--", color=colour, label="s")
        b.plot(theta, d["Rp"], ":", color=colour, label="p")
        notes.append("%s R(0) %.3f" % (sym, d["R"][0]))
    a.set_title("dielectrics: small at normal incidence, 1 at grazing", fontsize=9)
    b.set_title("metals: large at every angle, a dip in p before grazing", fontsize=9)
    for ax, where in ((a, "upper left"), (b, "lower left")):
        ax.set_xlim(0, 90)
        ax.set_ylim(0, 1.02)
        ax.set_xlabel("angle of incidence θ (degrees)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=1 if ax is a else 3, loc=where)
    a.set_ylabel("reflectance (fraction of the incident power)")
    fig.suptitle("Fig. 8: Fresnel reflectance, unpolarised (R) and for s and p polarisation", fontsize=10)
    fig.tight_layout()
    return save(fig, out, "fig8-fresnel.png", dpi), "; ".join(notes)


# --- renders --------------------------------------------------------------------------------


def srgb(img, exposure=0.0):
    """Linear RGB → 8-bit-ready sRGB in [0, 1]: scaled by 2^exposure, clamped, the sRGB
    transfer function of IEC 61966-2-1."""
    x = np.clip(img * 2.0 ** exposure, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def default_scene(quick):
    with open(os.path.join(ROOT, "scenes", "default.json"), encoding="utf-8") as f:
        scene = json.load(f)
    if quick:
        scene["camera"]["width"] //= 8
        scene["camera"]["height"] //= 8
    return scene


def fig9(out, dpi, quick):
    scene = default_scene(quick)
    img = gonio.render(scene, spp=2 if quick else 256, seed=1)
    path = os.path.join(out, "fig9-varnished-floor.png")
    plt.imsave(path, srgb(img))
    return path, "the default scene, %dx%d, %d spp" % (img.shape[1], img.shape[0], 2 if quick else 256)


def sec34(out, dpi, quick):
    """Lecture §3.4, reflection is linear: three renders with one light each, their sum,
    and the render with all three."""
    scene = default_scene(quick)
    scene["environment"] = {"radiance": 0}
    scene["lights"] = [
        {"type": "quad", "corner": [-4.5, 3.5, -1.0], "edge1": [1.5, 0, 0], "edge2": [0, 0, 1.5], "radiance": [30, 6, 4]},
        {"type": "quad", "corner": [-0.75, 4.5, -1.0], "edge1": [1.5, 0, 0], "edge2": [0, 0, 1.5], "radiance": [5, 28, 6]},
        {"type": "quad", "corner": [3.0, 3.5, -1.0], "edge1": [1.5, 0, 0], "edge2": [0, 0, 1.5], "radiance": [4, 8, 32]},
    ]
    spp = 2 if quick else 128
    singles = []
    for k in range(3):
        s = copy.deepcopy(scene)
        s["lights"] = [scene["lights"][k]]
        singles.append(gonio.render(s, spp=spp, seed=1 + k))
    everything = gonio.render(scene, spp=spp, seed=7)
    total = singles[0] + singles[1] + singles[2]
    fig, axes = plt.subplots(1, 5, figsize=(16, 2.6))
    panels = [("light 1 alone", singles[0]), ("light 2 alone", singles[1]), ("light 3 alone", singles[2]),
              ("the sum of the three", total), ("all three lights at once", everything)]
    for ax, (name, img) in zip(axes, panels):
        ax.imshow(srgb(img))
        ax.set_title(name, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    mean_sum, mean_all = total.mean(axis=(0, 1)), everything.mean(axis=(0, 1))
    rel = float(np.abs(mean_sum - mean_all).max() / mean_all.max())
    fig.suptitle("§3.4: reflection is linear. Image means (R, G, B): sum %s, all %s (largest difference %.2f%%)"
                 % (np.array2string(mean_sum, precision=4), np.array2string(mean_all, precision=4), 100 * rel),
                 fontsize=9)
    fig.tight_layout()
    return save(fig, out, "sec34-linearity.png", dpi), "mean of the sum %s, of all lights %s (%.2f%%)" % (
        np.array2string(mean_sum, precision=5), np.array2string(mean_all, precision=5), 100 * rel)


FIGURES = {"fig1": fig1, "fig7": fig7, "fig7block": fig7_block, "fig8": fig8, "fig9": fig9, "sec34": sec34}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", help="directory for the PNG files")
    p.add_argument("--quick", action="store_true", help="low resolution and few samples (the test)")
    p.add_argument("--only", nargs="*", choices=sorted(FIGURES), help="just these figures")
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    dpi = 50 if a.quick else 110
    for name in a.only or FIGURES:
        path, note = FIGURES[name](a.out, dpi, a.quick)
        print("%s: %s" % (path, note))
    return 0


if __name__ == "__main__":
    sys.exit(main())
