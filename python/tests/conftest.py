"""Shared fixtures of the Python module's tests (python/tests, run by ctest).

ctest sets PYTHONPATH to build/python, GONIO_BINARY to build/bin/gonio and
GONIO_BUILD_DIR; GONIO_TEST_SCALE (the sanitizer pass: 0.1) scales sample counts.
"""

import json
import os
import subprocess

import numpy as np
import pytest

GONIO = os.environ.get("GONIO_BINARY", "gonio")
SCALE = float(os.environ.get("GONIO_TEST_SCALE", "1"))


def run_gonio(args, stdin=""):
    """Runs the CLI; returns (status, stdout, stderr)."""
    p = subprocess.run([GONIO] + list(args), input=stdin, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def cli_lines(args, stdin=""):
    status, out, err = run_gonio(args, stdin)
    assert status == 0, err
    return [json.loads(line) for line in out.splitlines() if line.strip()]


def rows_text(a, b):
    """Lines of a and b's rows with every double written exactly (repr round-trips)."""
    return "".join(" ".join(repr(float(x)) for x in list(r) + list(s)) + "\n" for r, s in zip(a, b))


def write_merl(path):
    """A MERL table written byte by byte here (not by gonio): three int32 90 90 180, then
    the red, green, blue channels as doubles f/scale (Matusik et al. 2003; SPEC §2). The
    values vary with every index, so interpolation errors would show."""
    n = 90 * 90 * 180
    i = np.arange(n)
    th, td, pd = i // (90 * 180), (i // 180) % 90, i % 180
    base = 0.05 + 2.0 * np.exp(-th / 6.0) * (1 + 0.3 * np.cos(np.radians(pd))) + 0.001 * td
    scale = np.array([1.0 / 1500, 1.15 / 1500, 1.66 / 1500])
    with open(path, "wb") as f:
        f.write(np.array([90, 90, 180], dtype="<i4").tobytes())
        for c, mult in enumerate((1.0, 0.8, 0.6)):
            f.write((base * mult / scale[c]).astype("<f8").tobytes())


@pytest.fixture(scope="session")
def merl_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "table.binary"
    write_merl(path)
    return str(path)
