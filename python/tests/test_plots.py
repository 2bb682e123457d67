"""Each plot kind writes a non-empty image whose pixels are not all one colour; `python3
-m gonio.plot` is the command SPEC §4 names."""

import os
import subprocess
import sys

import matplotlib.image
import numpy as np
import pytest

import gonio
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


def run_plot(args):
    return subprocess.run([sys.executable, "-m", "gonio.plot"] + args, capture_output=True, text=True, timeout=60)


def one_line_exit_2(p):
    assert p.returncode == 2, p.stderr
    assert p.stdout == ""
    assert p.stderr.startswith("gonio.plot: ") and p.stderr.count("\n") == 1, p.stderr
    return p.stderr


def test_usage_errors_are_one_line(tmp_path):
    """Issue 39: argparse's usage errors were five lines; docs/python.md promises one."""
    out = str(tmp_path / "x.png")
    assert "invalid choice" in one_line_exit_2(run_plot(["nosuchkind", "-o", out]))
    assert "-o/--output" in one_line_exit_2(run_plot(["lobe"]))
    assert "--theta" in one_line_exit_2(run_plot(["lobe", "--theta", "abc", "-o", out]))
    assert "unrecognized" in one_line_exit_2(run_plot(["lobe", "--nope", "-o", out]))


@pytest.mark.parametrize("args", [["lobe", "--theta", "1e9"], ["lobe", "--theta", "30", "--theta", "nan"],
                                  ["sampling", "--theta", "95"], ["sampling", "--theta", "-1"]])
def test_angles_out_of_range_are_refused(args, tmp_path):
    """Issue 39: lobe --theta 1e9 and sampling --theta 95 drew a picture."""
    out = tmp_path / "x.png"
    err = one_line_exit_2(run_plot(args + ["-o", str(out)]))
    assert "--theta must be in [0, 90] degrees" in err
    assert not out.exists()
    with pytest.raises(ValueError, match="theta must be in"):
        if args[0] == "lobe":
            plot.lobe('{"type":"diffuse"}', thetas=(30.0, float(args[-1])))
        else:
            plot.sampling('{"type":"diffuse"}', theta=float(args[-1]))


def test_bsdf_files_are_read_through_the_clis_bound(tmp_path):
    """Issue 39: @/dev/zero was read until memory ran out (a MemoryError traceback); the
    CLI's bounded reader refuses it at 16 MiB."""
    out = str(tmp_path / "x.png")
    err = one_line_exit_2(run_plot(["lobe", "--bsdf", "@/dev/zero", "-o", out]))
    assert "/dev/zero" in err and "too large" in err
    err = one_line_exit_2(run_plot(["lobe", "--bsdf", "@" + str(tmp_path / "missing.json"), "-o", out]))
    assert "missing.json" in err
    good = tmp_path / "m.json"
    good.write_text('{"type": "diffuse"}')
    assert gonio.read_material_file(str(good)) == b'{"type": "diffuse"}'
