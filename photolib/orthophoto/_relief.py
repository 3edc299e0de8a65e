r"""Relief displacement (radiale Versetzung) of a vertical image: ``Δr = r·Δh/H``.

The radial shift of the image of a point Δh above the reference plane, the error a plane
rectification makes and a differential rectification removes; derived in
:mod:`photolib.derive.products`.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, check_finite


def relief_displacement(r, dh, H):
    r"""Relief displacement / radiale Versetzung of a vertical image: ``Δr = r·Δh/H``.

    Parameters
    ----------
    r : float or array_like
        Radial distance (image unit, mm) of the *displaced* image point (the top of the
        object) from the nadir point (= principal point of a vertical image).
    dh : float or array_like
        Height of the point above the reference plane (object unit, m).
    H : float or array_like
        Flying height of the projection centre above the reference plane (object unit), > dh.

    Returns
    -------
    ndarray or float
        Δr in the unit of r, directed away from the nadir point.

    Notes
    -----
    .. math:: Δr = r_{top} - r_{foot} = \frac{cR}{H-Δh} - \frac{cR}{H} = r_{top}\,\frac{Δh}{H}
              = r_{foot}\,\frac{Δh}{H-Δh}

    Exact for a vertical (nadir) image; derived in :func:`photolib.derive.products.relief_displacement`.

    Examples
    --------
    >>> relief_displacement(80.0, 30.0, 1200.0)   # mm, m, m
    2.0
    """
    r = as_float_array(r, "r")
    dh = as_float_array(dh, "dh")
    H = as_float_array(H, "H")
    for v, n in ((r, "r"), (dh, "dh"), (H, "H")):
        check_finite(np.atleast_1d(v), n)
    if np.any(H <= 0):
        raise ValueError(f"H (flying height above the reference plane) must be > 0, got {H.tolist()}")
    if np.any(dh >= H):
        raise ValueError(f"dh = {dh.tolist()} reaches the flying height H = {H.tolist()}: "
                         "the point is not below the camera")
    out = r * dh / H
    return float(out) if out.ndim == 0 else out
