"""`cmake --install` puts the package into site-packages under the prefix, and it imports
from there (not from the build tree)."""

import os
import subprocess
import sys

import pytest

BUILD = os.environ.get("GONIO_BUILD_DIR")
SITE = os.environ.get("GONIO_PYTHON_INSTALL_DIR")


@pytest.mark.skipif(not BUILD or not SITE, reason="run by ctest, which names the build")
def test_imports_from_install_prefix(tmp_path):
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", BUILD, "--component", "python", "--prefix", str(prefix)],
                   check=True, capture_output=True)
    site = prefix / SITE
    assert (site / "gonio" / "__init__.py").is_file() and (site / "gonio" / "plot.py").is_file()
    assert any(p.name.startswith("_gonio") and p.suffix == ".so" for p in (site / "gonio").iterdir())
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    code = ("import gonio, numpy as np; print(gonio.__file__); "
            "f, p = gonio.Material({'type': 'diffuse', 'reflectance': 0.5}).eval([0, 0, 1], [0, 0, 1]); "
            "print(f[0, 0] * np.pi)")
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=str(tmp_path), check=True,
                         capture_output=True, text=True).stdout.split()
    assert out[0].startswith(str(site))
    assert abs(float(out[1]) - 0.5) < 1e-6
