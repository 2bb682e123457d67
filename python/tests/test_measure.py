"""gonio.measure (the virtual gonioreflectometer) gives `gonio measure`'s numbers for the
same surface, rays and seed: the CLI prints the float readings with %.9g, which read back
to the same float32; the MERL table it writes is the same file byte for byte. Bad input
raises ValueError with the CLI's message. Also: gonio.render stops on Ctrl-C."""

import json
import os
import signal
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest

import gonio
from conftest import run_gonio

SURFACE = {"type": "gaussian", "alpha": 0.3, "resolution": 64, "material": {"type": "mirror"}}
GLASS = {"type": "gaussian", "alpha": 0.5, "resolution": 32, "material": {"type": "dielectric", "eta": 1.5}}
GANTRY = {"theta_i": [0, 40], "phi_i": [0, 30], "theta_o": [10, 30, 60, 150], "phi_o": [0, 180], "aperture": 5}


def cli_json(args):
    status, out, err = run_gonio(["measure"] + args)
    assert status == 0, err
    return json.loads(out)


def f32(x):
    return np.asarray(x, dtype=np.float32)


@pytest.mark.parametrize("surface", [SURFACE, GLASS], ids=["mirror", "glass"])
def test_gantry_equals_the_cli(surface):
    r = gonio.measure(surface, GANTRY, samples=40000, seed=5, threads=2)
    c = cli_json(["--surface", json.dumps(surface), "--gantry", json.dumps(GANTRY), "--samples", "40000",
                  "--seed", "5", "--threads", "1"])
    inc = c["incidences"]
    assert r["mode"] == "gantry" and r["aperture"] == c["aperture"] == 5
    assert r["rays_per_incidence"] == c["rays_per_incidence"] == 10000
    assert r["f"].shape == (4, 8, 3) and r["hits"].shape == (4, 8)
    np.testing.assert_array_equal(r["theta_i"], [i["theta_i"] for i in inc])
    np.testing.assert_array_equal(r["phi_i"], [i["phi_i"] for i in inc])
    for key in ("albedo", "stderr_albedo", "transmittance", "stderr_transmittance"):
        np.testing.assert_array_equal(f32(r[key]), f32([i[key] for i in inc]), err_msg=key)
    det = [[d for d in i["detectors"]] for i in inc]
    np.testing.assert_array_equal(f32(r["f"]), f32([[d["f"] for d in row] for row in det]))
    np.testing.assert_array_equal(f32(r["stderr"]), f32([[d["stderr"] for d in row] for row in det]))
    np.testing.assert_array_equal(r["hits"], [[d["hits"] for d in row] for row in det])
    np.testing.assert_array_equal(r["theta_o"], [d["theta_o"] for d in det[0]])
    np.testing.assert_array_equal(r["phi_o"], [d["phi_o"] for d in det[0]])
    np.testing.assert_allclose(r["solid_angle"], [d["solid_angle"] for d in det[0]], rtol=1e-15)
    assert r["rays"] == [i["rays"] for i in inc]
    # Light reached the detectors: the comparison is not one of zeros.
    assert (r["hits"] > 0).sum() >= 8 and r["f"].max() > 0.1
    if surface is GLASS:
        assert r["transmittance"].min() > 0.5 and r["f"][:, 6:, :].max() > 0  # θo = 150°: below


def test_the_result_does_not_depend_on_the_thread_count():
    a = gonio.measure(SURFACE, GANTRY, samples=30000, seed=2, threads=1)
    b = gonio.measure(SURFACE, GANTRY, samples=30000, seed=2, threads=2)
    for key in ("f", "stderr", "albedo", "hits"):
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    c = gonio.measure(SURFACE, GANTRY, samples=30000, seed=3, threads=2)
    assert not np.array_equal(a["f"], c["f"])  # the seed matters


def test_table_equals_the_cli_file(tmp_path):
    surface = dict(SURFACE, resolution=32)
    mine, theirs = tmp_path / "py.binary", tmp_path / "cli.binary"
    r = gonio.measure(surface, output=str(mine), samples=50000, seed=1, threads=2, min_rays=0)
    c = cli_json(["--surface", json.dumps(surface), "-o", str(theirs), "--samples", "50000", "--seed", "1",
                  "--threads", "1", "--min-rays", "0"])
    assert mine.read_bytes() == theirs.read_bytes()
    assert r["mode"] == "table" and r["file"] == str(mine)
    for key in ("entries", "filled", "pooled", "missing", "zero", "filled_by_pilot", "min_expected_rays", "pilot_rays",
                "relative_stderr_above"):
        assert r[key] == c[key], key
    assert r["filled"] > 0 and r["rays"] == c["rays"]
    bands = c["albedo"]
    assert r["theta_i"].shape == (90, 2) and r["albedo"].shape == (90, 3)
    np.testing.assert_array_equal(r["theta_i"], [b["theta_i"] for b in bands])
    np.testing.assert_array_equal(r["band_rays"], [b["rays"] for b in bands])
    np.testing.assert_array_equal(f32(r["albedo"]), f32([b["albedo"] for b in bands]))
    np.testing.assert_array_equal(f32(r["stderr_albedo"]), f32([b["stderr"] for b in bands]))
    # The file is a table gonio reads as a material.
    m = gonio.Material({"type": "measured", "file": str(mine)})
    f, _ = m.eval([0.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    assert np.isfinite(f).all()


BAD = [
    ({"type": "gaussian", "alpha": -1, "material": {"type": "mirror"}}, GANTRY, []),
    ({"type": "nosuchsurface", "material": {"type": "mirror"}}, GANTRY, []),
    ('{"type": "flat",', GANTRY, []),
    (SURFACE, {"theta_o": [90]}, []),
    (SURFACE, {"theta_i": [10]}, []),
    (SURFACE, GANTRY, ["--samples", "0"]),
    (SURFACE, GANTRY, ["--seed", "-1"]),
]


@pytest.mark.parametrize("surface, gantry, extra", BAD)
def test_bad_input_raises_the_clis_message(surface, gantry, extra):
    text = surface if isinstance(surface, str) else json.dumps(surface)
    status, out, err = run_gonio(["measure", "--surface", text, "--gantry", json.dumps(gantry)] + extra)
    assert status == 2 and out == "" and err.startswith("gonio: "), err
    kwargs = {}
    if extra:
        kwargs[extra[0].lstrip("-")] = int(extra[1])
    with pytest.raises(ValueError) as e:
        gonio.measure(surface, gantry, **kwargs)
    # CLI11 words its own range check of --samples/--seed differently; the rest are gonio's.
    if not extra:  # the source named as gonio.measure's argument, not the option --surface
        assert str(e.value) == err[len("gonio: "):].rstrip("\n").replace("--surface: ", "surface: ", 1)
    else:
        assert extra[0].lstrip("-") in str(e.value)


def test_gantry_and_output_are_separate_runs(tmp_path):
    with pytest.raises(ValueError, match="give gantry= .* or output="):
        gonio.measure(SURFACE)
    with pytest.raises(ValueError, match="separate runs"):
        gonio.measure(SURFACE, GANTRY, output=str(tmp_path / "t.binary"))
    with pytest.raises(ValueError, match="surface: expected JSON text"):
        gonio.measure(42, GANTRY)


def interrupt_after(call, seconds):
    """Runs `call` (Python source) in a fresh interpreter, sends it SIGINT `seconds` after
    it starts the call, and asserts that the call raised KeyboardInterrupt within 60 s."""
    code = ("import sys, gonio\n"
            "print('started', flush=True)\n"
            "try:\n"
            "    %s\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True)\n"
            "    sys.exit(3)\n") % call
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=os.environ.copy())
    assert p.stdout.readline() == "started\n"
    time.sleep(seconds)
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        pytest.fail("%s did not stop within 60 s of SIGINT" % call)
    assert p.returncode == 3 and out == "interrupted\n", (p.returncode, out, err)


def test_measure_stops_on_ctrl_c(tmp_path):
    """A table far too long to finish (10^12 rays) is interrupted by SIGINT within seconds,
    raising KeyboardInterrupt, and writes no table."""
    out = tmp_path / "t.binary"
    interrupt_after("gonio.measure(%r, output=%r, samples=10**12, threads=2)" % (json.dumps(SURFACE), str(out)), 1.5)
    assert not out.exists()


def test_render_stops_on_ctrl_c():
    """A render far too long to finish (the default scene at 2^20 spp) is interrupted by
    SIGINT within seconds, raising KeyboardInterrupt in the interpreter."""
    interrupt_after("gonio.render(spp=1 << 20, threads=2)", 1.0)


def test_a_table_with_holes_warns_once(tmp_path):
    """Issue 55: a table with missing entries above the horizon is read with a UserWarning
    giving the missing fraction (the model reads a hole with no measured neighbour as 0);
    a table `gonio measure` fills (every entry above the horizon) is read silently."""
    holes, full = tmp_path / "holes.binary", tmp_path / "full.binary"
    gonio.measure(dict(SURFACE, resolution=32), output=str(holes), samples=20000, seed=1, threads=2, min_rays=0)
    data = bytearray(holes.read_bytes())
    # Every θh slab from 45 on missing: the file is 3 int32 dimensions, then 3 channels of
    # 1,458,000 float64 entries each, θh-major (MERL's layout, merl.h).
    values = np.frombuffer(bytes(data[12:]), dtype="<f8").copy().reshape(3, 90, 90, 180)
    values[:, 45:] = -1
    holes.write_bytes(bytes(data[:12]) + values.tobytes())
    with pytest.warns(UserWarning, match=r"% of the table's entries above the horizon are missing"):
        gonio.Material({"type": "measured", "file": str(holes)})
    gonio.measure(dict(SURFACE, resolution=32), output=str(full), samples=20000, seed=1, threads=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gonio.Material({"type": "measured", "file": str(full)})
