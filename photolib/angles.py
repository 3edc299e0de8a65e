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


def deg2rad(a):
    """Degrees → radians, ``a·π/180``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in degrees (°, 360° per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in radians; a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{rad}} = a_{\\mathrm{deg}}\\,π/180

    Examples
    --------
    >>> float(deg2rad(180.0))
    3.141592653589793
    """
    return _angle(a) / 180.0 * np.pi


def rad2deg(a):
    """Radians → degrees, ``a·180/π``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in degrees (°, 360° per turn); a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{deg}} = a_{\\mathrm{rad}}\\,180/π

    Examples
    --------
    >>> float(rad2deg(np.pi / 2))
    90.0
    """
    return _angle(a) / np.pi * 180.0


def gon2rad(a):
    """Gon → radians, ``a·π/200``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in gon (Neugrad, 400 gon per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in radians; a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{rad}} = a_{\\mathrm{gon}}\\,π/200

    Examples
    --------
    >>> float(gon2rad(100.0)) == np.pi / 2
    True
    """
    return _angle(a) / 200.0 * np.pi


def rad2gon(a):
    """Radians → gon, ``a·200/π``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in gon (Neugrad, 400 gon per turn); a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{gon}} = a_{\\mathrm{rad}}\\,200/π

    Examples
    --------
    >>> float(rad2gon(np.pi))
    200.0
    """
    return _angle(a) / np.pi * 200.0


def deg2gon(a):
    """Degrees → gon, ``a·400/360``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in degrees (°, 360° per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in gon (Neugrad, 400 gon per turn); a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{gon}} = a_{\\mathrm{deg}}\\,400/360

    Examples
    --------
    >>> float(deg2gon(90.0))
    100.0
    """
    return _angle(a) * (400.0 / 360.0)


def gon2deg(a):
    """Gon → degrees, ``a·360/400``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in gon (Neugrad, 400 gon per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in degrees (°, 360° per turn); a NumPy float (``np.float64``) for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{deg}} = a_{\\mathrm{gon}}\\,360/400

    Examples
    --------
    >>> float(gon2deg(50.0))
    45.0
    """
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
