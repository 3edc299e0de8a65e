"""Natural vignetting (Lichtabfall): the cos⁴ law of the irradiance in the image plane.

For an image point at radius r' from the principal point, ``tan τ = r'/c`` and
``E(τ)/E(0) = cos⁴τ = c⁴/(c² + r'²)²`` (small aperture; mechanical vignetting comes on top).
"""

from __future__ import annotations

import numpy as np

from photolib.optics._checks import _array, _finite


# -- vignetting -----------------------------------------------------------------------------------

def natural_vignetting(xy, c):
    """Relative irradiance E(τ)/E(0) = cos⁴τ of natural vignetting (Lichtabfall).

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Image points reduced to the principal point, mm.
    c : float
        Camera constant, mm, > 0.

    Returns
    -------
    ndarray, shape (N,), or float
        cos⁴τ with tan τ = r'/c.

    Notes
    -----
    .. math:: \\frac{E(\\tau)}{E(0)} = \\cos^4\\tau = \\frac{c^4}{(c^2 + r'^2)^2}

    Right for a small aperture (record ``de-summary:vignetting-cos4``); mechanical
    vignetting comes on top.

    >>> natural_vignetting([0.0, 0.0], 50.0)
    1.0
    >>> natural_vignetting([[50.0, 0.0]], 50.0).round(6).tolist()   # τ = 45°
    [0.25]
    """
    from photolib._validate import as_points

    pts, single = as_points(xy, 2, "xy")
    c = _finite(_array(c, "camera constant c", positive=True), "camera constant c")
    r2 = np.sum(pts**2, axis=1)
    e = c**4 / (c**2 + r2) ** 2
    return float(e[0]) if single else e
