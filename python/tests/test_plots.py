"""Each plot kind writes a non-empty image whose pixels are not all one colour; `python3
-m gonio.plot` is the command SPEC §4 names."""

import os
import subprocess
import sys

import matplotlib.image
import numpy as np
import pytest

from gonio import plot

CASES = {
    "lobe": ["--theta", "0", "--theta", "45"],
    "lobe_delta": ["--bsdf", '{"type":"dielectric","eta":1.5}', "--theta", "30"],
    "lobe_3d": ["--3d", "--theta", "30"],
    "fresnel": ["--eta", "1.5"],
    "fresnel_metal": ["--material", "Au"],
    "albedo": ["--samples", "2048"],
    "slice": [],
    "sampling": ["--samples", "20000"],
}


def assert_not_blank(path):
    assert os.path.getsize(path) > 1000
    img = matplotlib.image.imread(path)
    assert img.ndim == 3
    flat = img.reshape(-1, img.shape[2])
    assert len(np.unique(flat, axis=0)) > 20, "the image is (nearly) one colour"


@pytest.mark.parametrize("case", sorted(CASES))
def test_each_kind_makes_an_image(case, tmp_path):
    kind = case.split("_")[0]
    out = str(tmp_path / (case + ".png"))
    assert plot.main([kind, "-o", out, "--dpi", "40"] + CASES[case]) == 0
    assert_not_blank(out)


def test_module_command_writes_svg(tmp_path):
    out = str(tmp_path / "fresnel.svg")
    p = subprocess.run([sys.executable, "-m", "gonio.plot", "fresnel", "--eta", "0.667", "-o", out],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    text = open(out, encoding="utf-8").read()
    assert text.lstrip().startswith("<?xml") and "<svg" in text and len(text) > 10000


def test_bad_input_exits_2(tmp_path):
    assert plot.main(["lobe", "--bsdf", '{"type":"nope"}', "-o", str(tmp_path / "x.png")]) == 2
    assert plot.main(["fresnel", "-o", str(tmp_path / "x.jpg")]) == 2
