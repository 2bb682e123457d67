"""gonio: physically based reflection models (BSDFs) on numpy arrays.

The C++ core (the extension gonio._gonio) evaluates, samples and validates the
materials of SPEC §2 over whole arrays, with the GIL released and every core busy::

    import numpy as np
    import gonio

    m = gonio.Material({"type": "roughconductor", "material": "Au", "alpha": 0.2})
    wo = np.array([[0.0, 0.0, 1.0]])
    wi = np.array([[0.3, 0.0, 0.95]])
    f, pdf = m.eval(wo, wi)          # f: (N, 3) float32 in 1/sr, pdf: (N,)

Directions are in the local shading frame (z = the surface normal), pointing away
from the surface. Bad input raises ValueError with the message the CLI prints.
Plots: ``python3 -m gonio.plot KIND ...`` (gonio.plot). See docs/python.md.
"""

import numpy as _np

from ._gonio import (  # noqa: F401  (the public surface)
    LOBE_NONE,
    LOBE_REFLECTION,
    LOBE_TRANSMISSION,
    Material,
    __version__,
    fresnel,
    fresnel_conductor,
    fresnel_dielectric,
    fresnel_schlick,
    half_diff_directions,
    material_types,
    named_index,
    read_material_file,
    subsurface,
    thin_film,
)
from . import _gonio

if hasattr(_gonio, "render"):
    from ._gonio import Scene, measure, render, write_image  # noqa: F401
if hasattr(_gonio, "fit"):
    from ._gonio import fit  # noqa: F401


def _require_finite(a, name, what):
    """ValueError naming the first element of a that is not finite (as the C++ calls do)."""
    bad = _np.flatnonzero(~_np.isfinite(a))
    if bad.size:
        i = int(bad[0])
        where = name if a.ndim == 0 else "%s[%s]" % (name, ", ".join(str(int(k)) for k in _np.unravel_index(i, a.shape)))
        raise ValueError("%s must be %s, got %r" % (where, what, float(a.flat[i])))


def direction(theta_deg, phi_deg=0.0):
    """Unit directions (N, 3) at polar angles theta and azimuths phi, in degrees.

    theta 0 is the normal (z); theta > 90 is below the surface. Scalars give (3,).
    """
    t, p = _np.broadcast_arrays(_np.asarray(theta_deg, dtype=float), _np.asarray(phi_deg, dtype=float))
    for name, a in (("theta", t), ("phi", p)):
        _require_finite(a, name, "a finite angle in degrees")
    t, p = _np.radians(t), _np.radians(p)
    return _np.stack([_np.sin(t) * _np.cos(p), _np.sin(t) * _np.sin(p), _np.cos(t)], axis=-1)


def spherical(w):
    """(theta, phi) in degrees of directions w of shape (N, 3) or (3,), of any length."""
    w = _np.asarray(w, dtype=float)
    if w.ndim not in (1, 2) or w.shape[-1] != 3:
        raise ValueError("w must have shape (N, 3) or (3,), got %s" % (w.shape,))
    rows = w.reshape(-1, 3)
    finite = _np.isfinite(rows).all(axis=1)
    bad = _np.flatnonzero(~finite | ~(rows != 0).any(axis=1))
    if bad.size:
        i = int(bad[0])
        where = "w" if w.ndim == 1 else "w[%d]" % i
        raise ValueError("%s %s" % (where, "is a zero vector" if finite[i] else "is not a finite vector"))
    # Scaled by the largest component first, so that no square overflows or vanishes.
    u = rows / _np.abs(rows).max(axis=1, keepdims=True)
    theta = _np.degrees(_np.arccos(_np.clip(u[:, 2] / _np.linalg.norm(u, axis=1), -1, 1)))
    phi = _np.degrees(_np.arctan2(u[:, 1], u[:, 0]))
    if w.ndim == 1:
        return theta[0], phi[0]
    return theta, phi


__all__ = [
    "Material",
    "LOBE_NONE",
    "LOBE_REFLECTION",
    "LOBE_TRANSMISSION",
    "direction",
    "fresnel",
    "fresnel_conductor",
    "fresnel_dielectric",
    "fresnel_schlick",
    "half_diff_directions",
    "material_types",
    "named_index",
    "read_material_file",
    "spherical",
    "subsurface",
    "thin_film",
] + [n for n in ("render", "measure", "fit") if hasattr(_gonio, n)]
