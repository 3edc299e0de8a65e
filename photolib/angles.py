"""Angle units. Every function of photolib takes radians; these helpers convert.

400 gon = 360° = 2π rad (gon, also grad / Neugrad, is the unit of German surveying).
NaN, text and complex numbers raise ``ValueError`` naming the argument ``a``; the unit
conversions turn ±inf into ±inf, :func:`wrap_angle` refuses it (no direction).
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_array

__all__ = ["deg2rad", "rad2deg", "gon2rad", "rad2gon", "deg2gon", "gon2deg", "wrap_angle"]


def _angle(a):
    """``a`` as a float array; NaN, strings and complex numbers raise ``ValueError`` naming
    ``a`` (±inf passes: a unit conversion of inf is inf)."""
    return as_array(a, "a", finite=False)


#: unit → (its name in a sentence, its description as the input of a conversion)
_UNITS = {"rad": ("radians", "radians"),
          "deg": ("degrees", "degrees (°, 360° per turn)"),
          "gon": ("gon", "gon (Neugrad, 400 gon per turn)")}


def _conversion(src: str, dst: str, factor: str, example: str):
    """Decorator: the numpydoc docstring of the conversion ``src → dst``, ``a·factor``.

    ``src``, ``dst``: keys of ``_UNITS``; ``factor``: the factor as printed (``π/180``);
    ``example``: the doctest, its ``>>>`` line and its output. One text for all six
    conversions, so that their documentation cannot drift apart.
    """
    def decorate(func):
        func.__doc__ = f"""{_UNITS[src][0].capitalize()} → {_UNITS[dst][0]}, ``a·{factor}``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in {_UNITS[src][1]}.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in {_UNITS[dst][1]}; a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{{\\mathrm{{{dst}}}}} = a_{{\\mathrm{{{src}}}}}\\,{factor}

    Examples
    --------
    {example}
    """
        return func
    return decorate


@_conversion("deg", "rad", "π/180", ">>> float(deg2rad(180.0))\n    3.141592653589793")
def deg2rad(a):
    return _angle(a) / 180.0 * np.pi


@_conversion("rad", "deg", "180/π", ">>> float(rad2deg(np.pi / 2))\n    90.0")
def rad2deg(a):
    return _angle(a) / np.pi * 180.0


@_conversion("gon", "rad", "π/200", ">>> float(gon2rad(100.0)) == np.pi / 2\n    True")
def gon2rad(a):
    return _angle(a) / 200.0 * np.pi


@_conversion("rad", "gon", "200/π", ">>> float(rad2gon(np.pi))\n    200.0")
def rad2gon(a):
    return _angle(a) / np.pi * 200.0


@_conversion("deg", "gon", "400/360", ">>> float(deg2gon(90.0))\n    100.0")
def deg2gon(a):
    return _angle(a) * (400.0 / 360.0)


@_conversion("gon", "deg", "360/400", ">>> float(gon2deg(50.0))\n    45.0")
def gon2deg(a):
    return _angle(a) * (360.0 / 400.0)


def wrap_angle(a):
    """Wrap radians into [−π, π).

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians, any finite value (e.g. a difference of two directions); NaN and
        ±inf have no direction and raise ``ValueError``.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The same direction in radians, in [−π, π); a NumPy float (``np.float64``) for a
        scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{wrapped}} = ((a + π) \\bmod 2π) - π

    Just below an odd multiple of −π, ``a + π`` is a tiny negative number whose remainder
    rounds up to exactly 2π, which would give +π: such results are moved to −π.

    Examples
    --------
    >>> float(wrap_angle(3 * np.pi / 2))
    -1.5707963267948966
    >>> float(wrap_angle(np.pi))   # +π maps to −π
    -3.141592653589793
    >>> float(wrap_angle(np.nextafter(-np.pi, -4.0)))   # not +π
    -3.141592653589793
    """
    a = as_array(a, "a")
    w = np.mod(a + np.pi, 2 * np.pi) - np.pi
    return np.where(w >= np.pi, w - 2 * np.pi, w)[()]
