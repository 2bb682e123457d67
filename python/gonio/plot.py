"""Plots of gonio's materials (matplotlib, Agg): ``python3 -m gonio.plot KIND ... -o OUT``.

KIND is one of

  lobe      f·cos θo in the plane of incidence for several θi, a polar plot (the
            lecture's Fig. 1); ``--3d`` draws the lobe of the first θi as a surface
  fresnel   Rs, Rp and R against θ for --eta/--k or a named --material, Schlick
            overlaid, the Brewster and critical angles marked
  albedo    directional albedo ρ_hd(ωo) against the view's θ: reflectance, transmittance, sum
  slice     f over θh × θd at φd = 90° (Burley 2012's slice), log scale
  sampling  histogram of sample() against the pdf on a (cos θ, φ) grid: the χ² picture
  thinfilm  a thin film's reflectance against its thickness and the wavelength, an image
            (--film-eta on --eta/--k or a named --material; default: a soap film in air)

OUT ends in .png or .svg. Each kind is also a function (lobe(...), fresnel(...), ...)
returning the matplotlib Figure. See docs/python.md.
"""

import argparse
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import gonio  # noqa: E402

KINDS = ("lobe", "fresnel", "albedo", "slice", "sampling", "thinfilm")

# A material for each kind when --bsdf is not given.
DEFAULT_BSDF = {
    "lobe": '{"type": "roughconductor", "material": "Au", "alpha": 0.3}',
    "albedo": '{"type": "roughdielectric", "eta": 1.5, "alpha": 0.3}',
    "slice": '{"type": "roughconductor", "material": "Cu", "alpha": 0.2}',
    "sampling": '{"type": "plastic", "reflectance": 0.5, "eta": 1.5, "alpha": 0.2}',
}
CHANNEL_COLOURS = ("tab:red", "tab:green", "tab:blue")


def material_title(m):
    """The material's JSON, short enough for a title."""
    text = json.dumps(json.loads(m.json), separators=(", ", ": "))
    return text if len(text) <= 90 else text[:87] + "..."


def _material(bsdf):
    return bsdf if isinstance(bsdf, gonio.Material) else gonio.Material(bsdf)


def _check_theta(value, name):
    """value (degrees) if it is a direction on the outside, θ in [0, 90]; else ValueError
    naming `name` (NaN and infinities included)."""
    v = float(value)
    if not 0 <= v <= 90:
        raise ValueError("%s must be in [0, 90] degrees, got %s" % (name, value))
    return v


def _channel_labels(c):
    return ("",) if c == 1 else (" (R)", " (G)", " (B)")


# --- lobe --------------------------------------------------------------------------------


def lobe(bsdf, thetas=(0, 30, 60), samples=720, surface3d=False):
    """Polar plot of f(wo, wi)·|cos θo| in the plane of incidence (φ = 0 and 180°).

    wi is the direction towards the light at each θi (on the φ = 180° side); wo sweeps the
    whole circle, so a transmission lobe shows below the surface. The value is the mean
    over the colour channels. Delta lobes (f is a Dirac) are drawn as spikes along their
    sampled directions, as long as the fraction of the incident power each carries
    (sample weight times the lobe's probability, importance mode).
    """
    thetas = tuple(_check_theta(t, "theta") for t in thetas)
    m = _material(bsdf)
    if surface3d:
        return _lobe3d(m, thetas[0])
    fig = plt.figure(figsize=(7, 5.6))
    ax = fig.add_subplot(projection="polar")
    draw_lobe(ax, m, thetas, samples)
    ax.set_xlabel("θo (degrees from the normal; light from the left, dotted)")
    ax.set_ylabel("f · |cos θo|  (1/sr)", labelpad=28)
    ax.legend(loc="lower right", bbox_to_anchor=(1.2, -0.1), fontsize=8)
    ax.set_title("lobe, plane of incidence: " + material_title(m), fontsize=9)
    fig.tight_layout()
    return fig


def draw_lobe(ax, m, thetas=(0, 30, 60), samples=720):
    """lobe()'s curves, into a polar Axes `ax` (for figures of several panels)."""
    ax.set_theta_zero_location("N")  # the normal points up
    ax.set_theta_direction(-1)
    # Angles of wo from the normal: positive on the φ = 0 side.
    ang = np.linspace(-180, 180, samples, endpoint=False) + 180.0 / samples
    lights = []
    wo = np.stack([np.sin(np.radians(ang)), np.zeros_like(ang), np.cos(np.radians(ang))], axis=1)
    for n, ti in enumerate(thetas):
        colour = "C%d" % n
        wi = gonio.direction(ti, 180.0)
        f, _ = m.eval(wo, wi)
        r = f.mean(axis=1) * np.abs(wo[:, 2])
        label = "θi = %g°" % ti
        if np.any(r > 0):
            ax.plot(np.radians(np.append(ang, ang[0]) % 360), np.append(r, r[0]), color=colour, label=label)
            label = None
        # Delta lobes: sample from wi (importance mode: light arriving along wi).
        u = np.array([[(k + 0.5) / 64, 0.5, 0.5] for k in range(64)])
        wis, weight, prob, delta, _ = m.sample(np.broadcast_to(wi, (64, 3)), u, mode="importance")
        if np.any(delta):
            seen = set()
            # weight · (the lobe's probability) = the fraction of the power it carries.
            for w, wt in zip(wis[delta], weight[delta].mean(axis=1) * prob[delta]):
                key = tuple(np.round(w, 4))
                if key in seen:
                    continue
                seen.add(key)
                a = math.atan2(w[0], w[2]) % (2 * math.pi)
                ax.annotate("", xy=(a, float(wt)), xytext=(a, 0),
                            arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.8))
            ax.plot([], [], color=colour, lw=1.8, label=(label or "θi = %g°" % ti) + " (delta lobe: its share of the power)")
        # The light's direction, a dotted ray.
        lights.append((math.radians(-ti) % (2 * math.pi), colour))
    top = ax.get_ylim()[1] or 1
    for a, colour in lights:
        ax.plot([a, a], [0, top], ":", color=colour, lw=0.8)
    ax.plot(np.radians([90, 270]), [top, top], color="0.3", lw=1.2, label="the surface")
    ax.set_thetalim(0, 2 * np.pi)
    ax.set_thetagrids(range(0, 360, 30), ["%d°" % min(t, 360 - t) for t in range(0, 360, 30)])


def _lobe3d(m, ti):
    th = np.linspace(0, 90, 60)
    ph = np.linspace(-180, 180, 121)
    T, P = np.meshgrid(th, ph)
    wo = gonio.direction(T.ravel(), P.ravel())
    f, _ = m.eval(wo, gonio.direction(ti, 180.0))
    r = (f.mean(axis=1) * wo[:, 2]).reshape(T.shape)
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    x, y, z = (wo * r.reshape(-1, 1)).T
    surf = ax.plot_surface(x.reshape(T.shape), y.reshape(T.shape), z.reshape(T.shape),
                           facecolors=plt.cm.viridis(r / (r.max() or 1)), linewidth=0, antialiased=True)
    surf.set_label("f · cos θo at θi = %g°" % ti)
    # One scale on the three axes (a cube about the lobe's middle, drawn as a cube):
    # matplotlib's own limits fit each axis to its data, which stretches a narrow lobe
    # round (an anisotropic one no longer looks it).
    lo, hi = np.array([x.min(), y.min(), z.min()]), np.array([x.max(), y.max(), z.max()])
    mid, half = (lo + hi) / 2, max((hi - lo).max() / 2, 1e-12)
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x (1/sr)")
    ax.set_ylabel("y (1/sr)")
    ax.set_zlabel("z, the normal (1/sr)")
    ax.legend(handles=[matplotlib.patches.Patch(color=plt.cm.viridis(0.7), label="f · cos θo, θi = %g°" % ti)],
              loc="upper left", fontsize=8)
    ax.set_title("lobe: " + material_title(m), fontsize=9)
    return fig


# --- fresnel -----------------------------------------------------------------------------


def fresnel(eta=1.5, k=0.0, material=None, count=901):
    """Rs, Rp, R and Schlick against the angle of incidence θ from the outside.

    A dielectric's Brewster angle (Rp = 0, tan θB = η) and, for η < 1 (light inside the
    denser medium), its critical angle (sin θc = η) are marked.
    """
    theta = np.linspace(0, 90, count)
    d = gonio.fresnel(theta, eta=eta, k=k, material=material)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    rs, rp, r, sch = (np.atleast_2d(d[key].T).T for key in ("Rs", "Rp", "R", "schlick"))
    channels = r.shape[1]
    for c in range(channels):
        colour = CHANNEL_COLOURS[c] if channels == 3 else None
        suffix = _channel_labels(channels)[c]
        ax.plot(theta, r[:, c], color=colour or "k", lw=2, label="R (unpolarised)" + suffix)
        ax.plot(theta, rs[:, c], "--", color=colour or "tab:blue", label="Rs (s, TE)" + suffix)
        ax.plot(theta, rp[:, c], "-.", color=colour or "tab:orange", label="Rp (p, TM)" + suffix)
        ax.plot(theta, sch[:, c], ":", color=colour or "tab:gray", lw=1.5, label="Schlick" + suffix)
    for c, (e, kk) in enumerate(zip(d["eta"], d["k"])):
        if kk == 0:
            brewster = math.degrees(math.atan(e))
            ax.axvline(brewster, color="tab:purple", lw=0.8)
            ax.annotate("Brewster %.1f°" % brewster, (brewster, 0.92 - 0.07 * c), rotation=90, fontsize=8,
                        ha="right", color="tab:purple")
            if e < 1:
                crit = math.degrees(math.asin(e))
                ax.axvline(crit, color="tab:red", lw=0.8)
                ax.annotate("critical %.1f°" % crit, (crit, 0.5 - 0.07 * c), rotation=90, fontsize=8,
                            ha="right", color="tab:red")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("angle of incidence θ (degrees)")
    ax.set_ylabel("reflectance (fraction of the incident power)")
    ax.legend(fontsize=7, ncol=2 if channels == 3 else 1, loc="upper left")
    if material:
        name = material + " (RGB: 650, 550, 450 nm)"
    else:
        name = "η = %g" % eta + (" + %gi" % k if k > 0 else "")
    ax.set_title("Fresnel reflectance: " + name, fontsize=10)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


# --- albedo ------------------------------------------------------------------------------


def albedo(bsdf, count=19, samples=1 << 16):
    """The lecture's directional albedo ρ_hd(ωo) against the view's θo, with ±2σ bands:
    reflectance, transmittance and their sum, per channel (SPEC §3: radiance mode, the
    refraction scaling removed). For a material that is not reciprocal, the light-side
    albedo (light arriving along θ, importance mode) is drawn too, labelled so."""
    m = _material(bsdf)
    theta = np.linspace(0, 90, count)
    d = m.albedo(theta, samples=samples)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    channels = m.channels
    top = 1.0
    for c in range(channels):
        colour = CHANNEL_COLOURS[c] if channels == 3 else "k"
        suffix = _channel_labels(channels)[c]
        for key, style, se, name in (("reflectance", "-", "stderr_reflectance", "reflectance"),
                                     ("transmittance", "--", "stderr_transmittance", "transmittance"),
                                     ("albedo", ":", "stderr", "albedo ρhd(ωo) (sum)")):
            v, e = d[key][:, c], d[se][:, c]
            if key == "transmittance" and not np.any(v > 0):
                continue
            ax.plot(theta, v, style, color=colour, label=name + suffix)
            ax.fill_between(theta, v - 2 * e, v + 2 * e, color=colour, alpha=0.15, lw=0)
            top = max(top, float(np.max(v + 2 * e)))
        if "reflectance_light" in d:
            v = d["reflectance_light"][:, c] + d["transmittance_light"][:, c]
            ax.plot(theta, v, "-.", color=colour, lw=1,
                    label="light-side albedo, not reciprocal" + suffix)
            top = max(top, float(np.max(v)))
    ax.set_xlim(0, 90)
    # Never clipped: a light-side figure of a model that is not reciprocal may exceed 1.
    ax.set_ylim(0, 1.05 * top)
    ax.set_xlabel("θo of the view direction (degrees; 90: the limit)")
    ax.set_ylabel("directional albedo ρ (fraction of the power)")
    ax.legend(fontsize=7, ncol=2 if channels == 3 else 1)
    ax.set_title("albedo: " + material_title(m), fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


# --- slice -------------------------------------------------------------------------------


def slice_plot(bsdf, resolution=180, phi_d=90.0):
    """log10 f over θh (x) × θd (y) at φd, as Burley 2012's slices of MERL data."""
    m = _material(bsdf)
    th = (np.arange(resolution) + 0.5) * 90.0 / resolution
    TH, TD = np.meshgrid(th, th)
    wo, wi = gonio.half_diff_directions(TH.ravel(), TD.ravel(), phi_d)
    f, _ = m.eval(wo, wi)
    v = f.mean(axis=1).reshape(TH.shape)
    below = ((wo[:, 2] <= 0) | (wi[:, 2] <= 0)).reshape(TH.shape)
    positive = v > 0
    floor = np.log10(v[positive].min()) if positive.any() else -3.0
    img = np.where(positive, np.log10(np.where(positive, v, 1)), floor)
    img = np.ma.masked_where(below, img)
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    im = ax.imshow(img, origin="lower", extent=(0, 90, 0, 90), cmap="inferno", aspect="equal")
    fig.colorbar(im, ax=ax, label="log10 f  (f in 1/sr, mean of the channels)")
    ax.plot([], [], "s", color="white", markeredgecolor="gray", label="below the horizon")
    ax.legend(loc="upper right", fontsize=7)
    ax.set_xlabel("θh, half vector from the normal (degrees)")
    ax.set_ylabel("θd, difference angle (degrees)")
    ax.set_title("slice at φd = %g°: %s" % (phi_d, material_title(m)), fontsize=9)
    fig.tight_layout()
    return fig


# --- thinfilm ----------------------------------------------------------------------------


def thin_film(film_eta=1.33, eta=1.0, k=0.0, material=None, theta=0.0, max_thickness=1000.0, count=(300, 161)):
    """R of a film (index film_eta) on an interface (eta + i k, or a named material) against
    the film's thickness (x, nm) and the wavelength (y, nm) at incidence theta, computed by
    gonio.thin_film (the models' own Airy sum). eta = 1 is a free-standing film: the soap
    bubble of `thindielectric` with a `thin_film`."""
    d = np.linspace(0.0, max_thickness, count[0])
    nm = np.linspace(380.0, 780.0, count[1])
    D, L = np.meshgrid(d, nm)
    r = gonio.thin_film(theta, L.ravel(), D.ravel(), film_eta, eta=eta, k=k, material=material)["R"].reshape(D.shape)
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    im = ax.imshow(r, origin="lower", extent=(0, max_thickness, 380, 780), aspect="auto", cmap="magma")
    fig.colorbar(im, ax=ax, label="reflectance R (unpolarised)")
    ax.set_xlabel("film thickness d (nm)")
    ax.set_ylabel("wavelength λ (nm)")
    on = material or ("air" if eta == 1 and k == 0 else "η = %g" % eta + (" + %gi" % k if k > 0 else ""))
    ax.set_title("thin film n = %g on %s at θ = %g° (Airy sum, Belcour & Barla 2017)" % (film_eta, on, theta),
                 fontsize=9)
    fig.tight_layout()
    return fig


# --- sampling ----------------------------------------------------------------------------


def sampling(bsdf, theta=45.0, samples=200_000, cells=(40, 80), seed=1):
    """sample() from wo at θ against pdf(): counts per cell of a (cos θ, φ) grid of the
    sphere beside the counts the pdf predicts (its integral over each cell, by a 3×3
    midpoint rule, times the number of samples)."""
    theta = _check_theta(theta, "theta")
    m = _material(bsdf)
    rng = np.random.default_rng(seed)
    wo = gonio.direction(theta, 0.0)
    u = rng.random((samples, 3))
    wi, _, _, delta, lobe_ = m.sample(wo, u, mode="radiance")
    ok = (lobe_ != gonio.LOBE_NONE) & ~delta
    nc, nphi = cells
    cos_edges = np.linspace(-1, 1, nc + 1)
    phi_edges = np.linspace(0, 2 * np.pi, nphi + 1)
    w = wi[ok].astype(float)
    phi = np.mod(np.arctan2(w[:, 1], w[:, 0]), 2 * np.pi)
    hist, _, _ = np.histogram2d(np.clip(w[:, 2], -1, 1), phi, bins=(cos_edges, phi_edges))
    # Expected counts: pdf integrated over each cell (area dcos dφ) with 3×3 midpoints.
    q = (np.arange(3) + 0.5) / 3
    dc, dp = 2.0 / nc, 2 * np.pi / nphi
    cc = (cos_edges[:-1, None] + q[None, :] * dc).ravel()
    pp = (phi_edges[:-1, None] + q[None, :] * dp).ravel()
    C, P = np.meshgrid(cc, pp, indexing="ij")
    s = np.sqrt(np.clip(1 - C ** 2, 0, 1))
    dirs = np.stack([s * np.cos(P), s * np.sin(P), C], axis=-1).reshape(-1, 3)
    pdf = m.pdf(np.broadcast_to(wo, dirs.shape), dirs).reshape(nc, 3, nphi, 3).mean(axis=(1, 3))
    expected = pdf * dc * dp * samples
    vmax = max(hist.max(), expected.max(), 1)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), sharey=True)
    for ax, data, name in ((axes[0], hist, "sample(): counts"), (axes[1], expected, "pdf(): expected counts")):
        im = ax.imshow(data, origin="lower", extent=(0, 360, -1, 1), aspect="auto", cmap="viridis", vmin=0, vmax=vmax)
        ax.set_xlabel("φ of wi (degrees)")
        ax.set_title(name, fontsize=9)
        ax.axhline(0, color="white", lw=0.6, label="the surface (cos θ = 0)")
    axes[0].set_ylabel("cos θ of wi")
    axes[0].legend(loc="lower right", fontsize=7)
    fig.colorbar(im, ax=axes, label="samples per cell")
    mask = expected > 5
    chi2 = float(np.sum((hist[mask] - expected[mask]) ** 2 / expected[mask])) if mask.any() else 0.0
    fig.suptitle("sampling at θo = %g°, %d samples (χ² = %.0f over %d cells): %s"
                 % (theta, samples, chi2, int(mask.sum()), material_title(m)), fontsize=9)
    return fig


# --- command line ------------------------------------------------------------------------


class _OneLineParser(argparse.ArgumentParser):
    """argparse with its usage errors as one line, `gonio.plot: <message>`, exit 2
    (docs/python.md), instead of the usage text and the program's name."""

    def error(self, message):
        print("gonio.plot: %s" % _one_line(message), file=sys.stderr)
        sys.exit(2)


def _one_line(text):
    """text with its control characters escaped, so that a message stays one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


def _parser():
    p = _OneLineParser(prog="python3 -m gonio.plot", description=__doc__.split("\n\n")[0],
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("kind", choices=KINDS, help="what to plot")
    p.add_argument("--bsdf", help="material JSON text, or @path to a file holding it (lobe, albedo, slice, sampling)")
    p.add_argument("--eta", type=float, help="fresnel: relative index n_t / n_i (default 1.5)")
    p.add_argument("--k", type=float, default=0.0, help="fresnel: extinction coefficient (conductor)")
    p.add_argument("--material", help="fresnel: a named metal (Au, Ag, Cu, Al, CuZn) or glass (BK7, ...)")
    p.add_argument("--theta", type=float, action="append",
                   help="lobe: an incidence angle in degrees (repeat; default 0, 30, 60); sampling: θo (45)")
    p.add_argument("--film-eta", type=float, default=1.33, help="thinfilm: the film's index (default 1.33)")
    p.add_argument("--max-thickness", type=float, default=1000.0,
                   help="thinfilm: the largest thickness plotted, in nm (default 1000)")
    p.add_argument("--3d", dest="surface3d", action="store_true", help="lobe: a 3D surface at the first --theta")
    p.add_argument("--samples", type=int, help="albedo: samples per angle (65536); sampling: samples (200000)")
    p.add_argument("--dpi", type=float, default=120, help="resolution of a PNG in dots per inch (default 120)")
    p.add_argument("-o", "--output", required=True, help="the image to write: .png or .svg")
    return p


def _bsdf_text(arg, kind):
    if arg is None:
        return DEFAULT_BSDF[kind]
    if arg.startswith("@"):
        # The CLI's bounded reader (16 MiB, devices and pipes included): @/dev/zero is
        # refused, not read until memory runs out.
        try:
            return gonio.read_material_file(arg[1:]).decode("utf-8")
        except ValueError as e:
            raise ValueError("--bsdf: %s" % e) from None
    return arg


def main(argv=None):
    args = _parser().parse_args(argv)
    ext = os.path.splitext(args.output)[1].lower()
    if ext not in (".png", ".svg"):
        print("gonio.plot: -o %s: the output must end in .png or .svg" % args.output, file=sys.stderr)
        return 2
    try:
        if args.kind == "fresnel":
            if args.material and args.eta is not None:
                raise ValueError("--material excludes --eta")
            fig = fresnel(eta=1.5 if args.eta is None else args.eta, k=args.k, material=args.material)
        elif args.kind == "thinfilm":
            if args.material and args.eta is not None:
                raise ValueError("--material excludes --eta")
            for t in args.theta or ():
                _check_theta(t, "--theta")
            if not (0 < args.max_thickness <= 1e4):
                raise ValueError("--max-thickness must be in (0, 10000] nm, got %r" % args.max_thickness)
            fig = thin_film(film_eta=args.film_eta, eta=1.0 if args.eta is None else args.eta, k=args.k,
                            material=args.material, theta=(args.theta or [0.0])[0], max_thickness=args.max_thickness)
        else:
            m = gonio.Material(_bsdf_text(args.bsdf, args.kind))
            for t in args.theta or ():
                _check_theta(t, "--theta")
            if args.kind == "lobe":
                fig = lobe(m, thetas=tuple(args.theta or (0, 30, 60)), surface3d=args.surface3d)
            elif args.kind == "albedo":
                fig = albedo(m, samples=args.samples or (1 << 16))
            elif args.kind == "slice":
                fig = slice_plot(m)
            else:
                fig = sampling(m, theta=(args.theta or [45.0])[0], samples=args.samples or 200_000)
        fig.savefig(args.output, dpi=args.dpi)
        plt.close(fig)
    except (ValueError, OSError, MemoryError) as e:
        print("gonio.plot: %s" % _one_line(e), file=sys.stderr)
        return 2
    print(args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
