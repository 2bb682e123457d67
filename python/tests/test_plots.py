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
    "thinfilm": [],
    "thinfilm_gold": ["--material", "Au", "--film-eta", "1.5", "--theta", "40"],
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


def test_albedo_plot_labels_the_light_side_and_does_not_clip(tmp_path):
    # A model that is not reciprocal: the light-side albedo (1.35 at 85° for this coat) is
    # drawn, labelled so, and the axis reaches it (it was clipped at 1.05).
    fig = plot.albedo('{"type":"openpbr","base_color":1,"coat_weight":1,"coat_roughness":0.2}', count=4, samples=4096)
    ax = fig.axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert any("light-side" in label for label in labels), labels
    light = [line for line in ax.get_lines() if "light-side" in line.get_label()][0]
    assert max(light.get_ydata()) > 1.1
    assert ax.get_ylim()[1] >= max(light.get_ydata())
    fig2 = plot.albedo('{"type":"roughconductor","alpha":0.3,"material":"Au"}', count=4, samples=1024)
    assert not any("light-side" in line.get_label() for line in fig2.axes[0].get_lines())


def test_lobe_3d_has_equal_axes():
    # An anisotropic lobe (α 0.05 along x, 0.5 along y) must look it: the three axes show
    # one scale (equal ranges, a cubic box).
    m = gonio.Material({"type": "roughconductor", "material": "Au", "alpha": [0.05, 0.5]})
    fig = plot.lobe(m, thetas=(30,), surface3d=True)
    ax = fig.axes[0]
    spans = [hi - lo for lo, hi in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())]
    assert spans[0] > 0 and np.allclose(spans, spans[0], rtol=1e-9), spans
    assert np.allclose(ax.get_box_aspect() / ax.get_box_aspect()[0], 1), ax.get_box_aspect()
    plot.plt.close(fig)


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


def test_thin_film_values_are_closed_forms():
    """gonio.thin_film against closed forms written here (Hecht, Optics, §9.7.1): a
    quarter-wave film (n_f d = λ/4) at normal incidence reflects ((n3 − n_f²)/(n3 + n_f²))²,
    a half-wave film is absent (the bare interface's ((n3 − 1)/(n3 + 1))²), and a free
    film's reflectance peaks at ((n_f² − 1)/(n_f² + 1))² (the soap film of `thinfilm`)."""
    r = gonio.thin_film(0, 550, 550 / (4 * 1.38), 1.38, eta=1.5)["R"][0]
    assert r == pytest.approx(((1.5 - 1.38**2) / (1.5 + 1.38**2)) ** 2, rel=1e-9)
    assert gonio.thin_film(0, 550, 99.6, 1.38, eta=1.5)["R"][0] == pytest.approx(0.0141, abs=5e-5)  # issue 34
    r = gonio.thin_film(0, 600, 600 / (2 * 2.0), 2.0, eta=1.5)["R"][0]
    assert r == pytest.approx((0.5 / 2.5) ** 2, rel=1e-9)
    d = np.linspace(0, 400, 4001)
    peak = gonio.thin_film(0, 500, d, 1.33, eta=1.0)["R"].max()
    assert peak == pytest.approx(((1.33**2 - 1) / (1.33**2 + 1)) ** 2, rel=1e-5)
    # Thickness 0 is the bare interface, at any angle.
    th = np.array([0.0, 30.0, 60.0, 85.0])
    assert np.allclose(gonio.thin_film(th, 550, 0, 1.7, eta=1.5)["R"], gonio.fresnel(th, eta=1.5)["R"], rtol=1e-12)
    with pytest.raises(ValueError, match="thickness must be in"):
        gonio.thin_film(0, 550, -1, 1.38)
    with pytest.raises(ValueError, match="film_eta must be in"):
        gonio.thin_film(0, 550, 100, 0.5)
