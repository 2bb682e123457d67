#!/usr/bin/env python3
"""The figure of docs/polarization.md: the retardance delta = phi_s - phi_p of the reflection
(from M22 = cos delta, M32 = sin delta of `gonio fresnel --mueller`) and the degree of
polarization of reflected unpolarized light, M01/M00, against the angle of incidence, for
glass from outside (eta = 1.5) and inside (eta = 1/1.5) and for gold at 600 nm.

Usage: tools/plot_fresnel_phase.py build/bin/gonio docs/fresnel-phase.png
Needs matplotlib (Debian: python3-matplotlib)."""
import json
import math
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def curve(gonio, index_args):
    out = subprocess.run([gonio, "fresnel", *index_args, "--theta-range", "0", "90", "361", "--mueller"],
                         check=True, capture_output=True, text=True).stdout
    th, delta, dop = [], [], []
    for line in out.splitlines():
        m = json.loads(line)["mueller_r"]
        th.append(len(th) * 0.25)
        delta.append(math.degrees(math.atan2(m[3][2], m[2][2])))
        dop.append(m[0][1] / m[0][0] if m[0][0] > 0 else 0.0)
    return th, delta, dop


def main():
    gonio, out = sys.argv[1], sys.argv[2]
    cases = [("glass, from outside (η = 1.5)", ["--eta", "1.5"]),
             ("glass, from inside (η = 1/1.5)", ["--eta", str(1 / 1.5)]),
             ("gold, 600 nm", ["--material", "Au", "--wavelength", "600"])]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for label, args in cases:
        th, delta, dop = curve(gonio, args)
        a.plot(th, delta, label=label)
        b.plot(th, dop, label=label)
    a.set(xlabel="angle of incidence θ (°)", ylabel="retardance δ = φs − φp (°)", xlim=(0, 90), ylim=(-5, 185))
    b.set(xlabel="angle of incidence θ (°)", ylabel="(Rs − Rp)/(Rs + Rp): Q/I of reflected light", xlim=(0, 90))
    for ax in (a, b):
        ax.grid(alpha=0.3)
    a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
