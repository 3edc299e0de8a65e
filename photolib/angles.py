"""Angle units. Every function of photolib takes radians; these helpers convert.

400 gon = 360° = 2π rad (gon, also grad / Neugrad, is the unit of German surveying).
"""

from __future__ import annotations

import numpy as np

__all__ = ["deg2rad", "rad2deg", "gon2rad", "rad2gon", "deg2gon", "gon2deg", "wrap_angle"]


def deg2rad(a):
    """Degrees → radians, ``a·π/180``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in degrees (°, 360° per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in radians; a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{rad}} = a_{\\mathrm{deg}}\\,π/180

    Examples
    --------
    >>> float(deg2rad(180.0))
    3.141592653589793
    """
    return np.asarray(a, dtype=float) / 180.0 * np.pi


def rad2deg(a):
    """Radians → degrees, ``a·180/π``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in degrees (°, 360° per turn); a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{deg}} = a_{\\mathrm{rad}}\\,180/π

    Examples
    --------
    >>> float(rad2deg(np.pi / 2))
    90.0
    """
    return np.asarray(a, dtype=float) / np.pi * 180.0


def gon2rad(a):
    """Gon → radians, ``a·π/200``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in gon (Neugrad, 400 gon per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in radians; a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{rad}} = a_{\\mathrm{gon}}\\,π/200

    Examples
    --------
    >>> float(gon2rad(100.0)) == np.pi / 2
    True
    """
    return np.asarray(a, dtype=float) / 200.0 * np.pi


def rad2gon(a):
    """Radians → gon, ``a·200/π``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians.

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in gon (Neugrad, 400 gon per turn); a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{gon}} = a_{\\mathrm{rad}}\\,200/π

    Examples
    --------
    >>> float(rad2gon(np.pi))
    200.0
    """
    return np.asarray(a, dtype=float) / np.pi * 200.0


def deg2gon(a):
    """Degrees → gon, ``a·400/360``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in degrees (°, 360° per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in gon (Neugrad, 400 gon per turn); a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{gon}} = a_{\\mathrm{deg}}\\,400/360

    Examples
    --------
    >>> float(deg2gon(90.0))
    100.0
    """
    return np.asarray(a, dtype=float) * (400.0 / 360.0)


def gon2deg(a):
    """Gon → degrees, ``a·360/400``.

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in gon (Neugrad, 400 gon per turn).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The angle in degrees (°, 360° per turn); a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{deg}} = a_{\\mathrm{gon}}\\,360/400

    Examples
    --------
    >>> float(gon2deg(50.0))
    45.0
    """
    return np.asarray(a, dtype=float) * (360.0 / 400.0)


def wrap_angle(a):
    """Wrap radians into [−π, π).

    Parameters
    ----------
    a : float or array_like, any shape
        Angle in radians, any value (e.g. a difference of two directions).

    Returns
    -------
    ndarray of float, same shape as ``a``
        The same direction in radians, in [−π, π); a 0-d array for a scalar input.

    Notes
    -----
    .. math:: a_{\\mathrm{wrapped}} = ((a + π) \\bmod 2π) - π

    Examples
    --------
    >>> float(wrap_angle(3 * np.pi / 2))
    -1.5707963267948966
    >>> float(wrap_angle(np.pi))   # +π maps to −π
    -3.141592653589793
    """
    a = np.asarray(a, dtype=float)
    return (a + np.pi) % (2 * np.pi) - np.pi
