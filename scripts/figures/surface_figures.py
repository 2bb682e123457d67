#!/usr/bin/env python3
"""Figures and tables of docs/gonioreflectometer.md, section "Surfaces".

Builds a small driver against the library of a Release build (default: build/, after
`cmake --build build --target gonio_measure`), which
  - writes the previews docs/gonioreflectometer-surface-{gaussian,anisotropic,vgroove}.png
    with gonio::measure::write_surface_preview (what `gonio measure --preview` writes;
    512 pixels a side here, 1024 there), and
  - prints, for Gaussian surfaces of alpha = 0.1, 0.3, 0.6, 1.0, the area-weighted histogram
    of the facet normals' θm against the integral of D(m) cos θm of gonio's Beckmann
    distribution over each bin (Simpson's rule).
Then prints the table of the docs and, when matplotlib is installed, draws
docs/gonioreflectometer-surface-histogram.png.

usage: scripts/figures/surface_figures.py [BUILD_DIR]
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

DRIVER = r"""
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>
#include "gonio/measure/gaussian_surface.h"
#include "gonio/measure/preview.h"
#include "gonio/measure/profiles.h"
#include "gonio/microfacet.h"

namespace gm = gonio::measure;

int main(int argc, char** argv) {
  const std::string docs = argv[1];
  gm::GaussianSurfaceParams p;  // correlation 8 cells (the default), seed 1
  p.alpha_x = p.alpha_y = 0.3;
  p.resolution = 128;  // 4 pixels per cell: the facets show
  gm::write_surface_preview(gm::gaussian_height_field(p), docs + "/gonioreflectometer-surface-gaussian.png", {true, 512});
  p.alpha_x = 0.15;
  p.alpha_y = 0.6;
  p.resolution = 256;
  gm::write_surface_preview(gm::gaussian_height_field(p), docs + "/gonioreflectometer-surface-anisotropic.png", {true, 512});
  gm::write_surface_preview(gm::vgroove_height_field(30, 8), docs + "/gonioreflectometer-surface-vgroove.png", {true, 512});

  const int nbins = 24;
  struct Config {
    double alpha;
    int n;
    double correlation;
  };
  // the four roughnesses at the defaults (n = 512, 64 correlation lengths per side), then
  // α = 0.3 with 32 lengths per side (16 cells per length) and at n = 2048 (256 lengths)
  for (const Config c : {Config{0.1, 512, 0}, Config{0.3, 512, 0}, Config{0.6, 512, 0}, Config{1.0, 512, 0},
                         Config{0.3, 512, 1.0 / 32}, Config{0.3, 2048, 0}}) {
    const double alpha = c.alpha;
    gm::GaussianSurfaceParams q;
    q.alpha_x = q.alpha_y = alpha;
    q.resolution = c.n;
    q.correlation = c.correlation;
    const gm::HeightField f = gm::gaussian_height_field(q);
    const double h = f.spacing();
    // bins uniform in θm up to atan(3α) (99.99% of the Beckmann facets), then the rest
    const double top = std::atan(3 * alpha);
    std::vector<double> count(nbins + 1, 0);
    double sx2 = 0, sy2 = 0;
    const auto add = [&](double sx, double sy) {
      sx2 += sx * sx;
      sy2 += sy * sy;
      const double th = std::atan(std::hypot(sx, sy));
      count[std::min(nbins, static_cast<int>(th / top * nbins))] += 1;
    };
    for (int j = 0; j < f.n; ++j)
      for (int i = 0; i < f.n; ++i) {
        const double z00 = f.at(i, j), z10 = f.at(i + 1, j), z01 = f.at(i, j + 1), z11 = f.at(i + 1, j + 1);
        add((z10 - z00) / h, (z01 - z00) / h);
        add((z11 - z01) / h, (z11 - z10) / h);
      }
    const double total = 2.0 * f.n * f.n;
    const gonio::MicrofacetDistribution d{gonio::MicrofacetType::Beckmann, float(alpha), float(alpha)};
    const auto density = [&](double th) {
      return 2 * 3.14159265358979323846 * d.D(gonio::Vec3(float(std::sin(th)), 0, float(std::cos(th)))) * std::cos(th) * std::sin(th);
    };
    std::printf("{\"alpha\": %.17g, \"n\": %d, \"correlation\": %.17g, \"rms_x\": %.9g, \"rms_y\": %.9g, \"top\": %.17g, \"bins\": [", alpha, f.n, c.correlation > 0 ? c.correlation : gm::default_gaussian_correlation(c.n, alpha, alpha),
                std::sqrt(sx2 / total), std::sqrt(sy2 / total), top);
    for (int b = 0; b <= nbins; ++b) {
      const double a = top * b / nbins, e = b < nbins ? top * (b + 1) / nbins : 1.5707963267948966;
      const int steps = 2000;
      const double w = (e - a) / steps;
      double s = density(a) + density(e);
      for (int i = 1; i < steps; ++i) s += (i % 2 ? 4 : 2) * density(a + i * w);
      std::printf("%s[%.17g, %.17g, %.9g, %.9g]", b ? ", " : "", a, e, count[b] / total, s * w / 3);
    }
    std::printf("]}\n");
  }
}
"""


def pkg_libs(*names):
    return subprocess.check_output(["pkg-config", "--libs", *names], text=True).split()


def main():
    build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
    docs = os.path.join(ROOT, "docs")
    with tempfile.TemporaryDirectory() as tmp:
        src, exe = os.path.join(tmp, "driver.cpp"), os.path.join(tmp, "driver")
        with open(src, "w") as f:
            f.write(DRIVER)
        libs = [os.path.join(build, n) for n in ("libgonio_measure.a", "libgonio_render.a", "libgonio.a")]
        subprocess.check_call(["g++", "-O2", "-std=c++20", "-I" + os.path.join(ROOT, "include"),
                               "-I" + os.path.join(build, "include"), "-I" + os.path.join(build, "generated"),
                               src, *libs, *pkg_libs("fftw3", "OpenEXR", "libpng"), "-o", exe])
        out = subprocess.check_output([exe, docs], text=True)
    rows = [json.loads(line) for line in out.splitlines()]

    print("| α | n, ℓ | RMS slope along x, y (want α/√2) | largest difference of a bin's fraction | beyond atan(3α): surface, theory |")
    print("|---|---|---|---|---|")
    for r in rows:
        diff = max(abs(o - e) for _, _, o, e in r["bins"])
        _, _, tail_o, tail_e = r["bins"][-1]
        # for the prose: the fullest bin, and χ² as if every facet were independent
        chi2 = sum(2 * r["n"] ** 2 * (o - e) ** 2 / e for _, _, o, e in r["bins"] if e > 0)
        print(f"alpha {r['alpha']:g}, n {r['n']}: fullest bin {max(e for *_, e in r['bins']):.3f}, "
              f"chi2/bins {chi2 / len(r['bins']):.1f}", file=sys.stderr)
        print(f"| {r['alpha']:g} | {r['n']}, 1/{1 / r['correlation']:g} | {r['rms_x']:.4f}, {r['rms_y']:.4f} ({r['alpha'] / 2 ** 0.5:.4f}) | "
              f"{diff:.4f} | {tail_o:.1e}, {tail_e:.1e} |")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no histogram figure", file=sys.stderr)
        return
    rows = rows[:4]  # the four roughnesses at the defaults
    fig, axes = plt.subplots(1, len(rows), figsize=(3.2 * len(rows), 3.0))
    for ax, r in zip(axes, rows):
        bins = r["bins"][:-1]  # the open tail bin is in the table
        mids = [(a + b) / 2 for a, b, _, _ in bins]
        widths = [b - a for a, b, _, _ in bins]
        ax.bar([m * 180 / 3.141592653589793 for m in mids], [o / w for (_, _, o, _), w in zip(bins, widths)],
               width=[w * 180 / 3.141592653589793 for w in widths], color="#9ab", label="surface facets")
        ax.plot([m * 180 / 3.141592653589793 for m in mids], [e / w for (_, _, _, e), w in zip(bins, widths)],
                "k.-", ms=3, lw=1, label="D(m) cos θm (Beckmann)")
        ax.set_title(f"α = {r['alpha']:g}")
        ax.set_xlabel("θm (degrees)")
    axes[0].set_ylabel("density per radian of θm")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(docs, "gonioreflectometer-surface-histogram.png")
    fig.savefig(path, dpi=110)
    print(path, file=sys.stderr)


if __name__ == "__main__":
    main()
