"""docs/figures/lecture_figures.py makes every figure of docs/lecture.md, at low
resolution here (--quick), and none is blank."""

import os
import subprocess
import sys

import matplotlib.image
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIGURES = ["fig1-lobes.png", "fig7-tir.png", "fig7-glass-block.png", "fig8-fresnel.png", "fig9-varnished-floor.png", "sec34-linearity.png"]


def test_lecture_figures_are_made_and_not_blank(tmp_path):
    p = subprocess.run([sys.executable, os.path.join(ROOT, "docs", "figures", "lecture_figures.py"), str(tmp_path),
                        "--quick"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    for name in FIGURES:
        path = tmp_path / name
        assert path.is_file(), name
        img = matplotlib.image.imread(str(path))
        flat = img.reshape(-1, img.shape[2])
        assert len(np.unique(flat, axis=0)) > 20, name + " is (nearly) one colour"
        # Not black either: some pixel is bright.
        assert flat[:, :3].max() > 0.5, name
