"""Stereoscopic vision: the smallest depth difference the eyes (or cameras) can resolve.

The parallactic angle of a point at distance Z with base b is ``γ = 2·arctan(b/(2Z))``; a
depth step ΔZ is seen when γ drops by the stereoscopic acuity ε (radians):
``Z + ΔZ = b/(2·tan((γ − ε)/2)) ≈ Z + Z²ε/b``. Z, b and ΔZ share one unit.
"""

from __future__ import annotations

import numpy as np

from photolib.optics._checks import _array, _finite, _out


# -- stereoscopic vision --------------------------------------------------------------------------

def stereo_depth_acuity(distance, base, acuity):
    """Smallest depth difference seen stereoscopically (Tiefenauflösung), exact and small-angle.

    Parameters
    ----------
    distance : float or array_like
        Distance Z of the object from the eyes (or cameras), > 0.
    base : float or array_like
        Eye base b (Augenbasis, about 65 mm), > 0, same unit.
    acuity : float or array_like
        Stereoscopic acuity ε (smallest perceivable difference of the parallactic angle),
        radians, > 0 (5''–10'' for the eye).

    Returns
    -------
    float or ndarray
        ΔZ such that the parallactic angle γ = 2·arctan(b/(2Z)) drops by ε from Z to Z + ΔZ;
        ``inf`` where γ ≤ ε (beyond the range of stereo vision).

    Notes
    -----
    .. math:: Z + \\Delta Z = \\frac{b}{2\\tan\\frac{\\gamma - \\varepsilon}{2}}
              \\qquad\\approx\\qquad \\Delta Z \\approx \\frac{Z^2\\varepsilon}{b}

    Examples
    --------
    >>> eps = np.radians(10.0 / 3600.0)
    >>> round(stereo_depth_acuity(1000.0, 65.0, eps), 3)   # mm at 1 m
    0.747
    """
    Z = _finite(_array(distance, "distance", positive=True), "distance")
    b = _finite(_array(base, "base b", positive=True), "base b")
    eps = _finite(_array(acuity, "acuity", positive=True), "acuity")
    gamma = 2.0 * np.arctan(b / (2.0 * Z))
    with np.errstate(divide="ignore"):
        half = np.tan((gamma - eps) / 2.0)
        far = np.where(gamma > eps, b / (2.0 * np.where(gamma > eps, half, 1.0)), np.inf)
    return _out(far - Z)
