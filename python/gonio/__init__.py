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
    subsurface,
)
from . import _gonio

if hasattr(_gonio, "render"):
    from ._gonio import measure, render  # noqa: F401
if hasattr(_gonio, "fit"):
    from ._gonio import fit  # noqa: F401


def direction(theta_deg, phi_deg=0.0):
    """Unit directions (N, 3) at polar angles theta and azimuths phi, in degrees.

    theta 0 is the normal (z); theta > 90 is below the surface. Scalars give (3,).
    """
    t = _np.radians(_np.asarray(theta_deg, dtype=float))
    p = _np.radians(_np.asarray(phi_deg, dtype=float))
    t, p = _np.broadcast_arrays(t, p)
    return _np.stack([_np.sin(t) * _np.cos(p), _np.sin(t) * _np.sin(p), _np.cos(t)], axis=-1)


def spherical(w):
    """(theta, phi) in degrees of directions w of shape (N, 3) or (3,)."""
    w = _np.asarray(w, dtype=float)
    r = _np.linalg.norm(w, axis=-1)
    theta = _np.degrees(_np.arccos(_np.clip(w[..., 2] / _np.where(r > 0, r, 1), -1, 1)))
    phi = _np.degrees(_np.arctan2(w[..., 1], w[..., 0]))
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
    "spherical",
    "subsurface",
] + [n for n in ("render", "measure", "fit") if hasattr(_gonio, n)]
