r"""The stereo normal case (Normalfall): heights from x-parallaxes and their accuracy.

Camera 1 at the origin, camera 2 at ``(B, 0, 0)``, both with R = I and the same interior
orientation (c > 0, principal point x'0, y'0). The x-parallax ``px' = x'1 − x'2`` is > 0 for
points in front of the cameras and gives (derived in :mod:`photolib.derive.stereo`)

    ``X = B·(x'1 − x'0)/px'``, ``Y = B·(y'1 − y'0)/px'``, ``Z = −c·B/px'`` (Z < 0).

Accuracy (Luhmann example 3.7): ``σ_Z = (h/B)·m·σ_px'`` and ``σ_XY = m·σ_x'`` with the image
scale number ``m = h/c``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_float_array, as_points, as_scalar
from photolib.collinearity import PointBehindCameraError
from photolib.transforms._base import DegenerateGeometryError


# -- normal case -----------------------------------------------------------------------------------

def _parallax(px, name="px"):
    px = as_float_array(px, name)
    if not np.all(np.isfinite(px)):
        raise ValueError(f"{name} contains a non-finite value: {px.ravel().tolist()[:5]}")
    if np.any(px == 0):
        i = int(np.flatnonzero(px.ravel() == 0)[0])
        raise DegenerateGeometryError(f"{name}[{i}] = 0: zero parallax means parallel rays "
                                      "(a point at infinity); Z = −c·B/px' is undefined")
    if np.any(px < 0):
        i = int(np.flatnonzero(px.ravel() < 0)[0])
        raise PointBehindCameraError(
            f"{name}[{i}] = {float(px.ravel()[i])!r} < 0: with camera 2 at (+B, 0, 0) a point in front "
            "has px' = x'1 − x'2 > 0 (negative parallax gives Z > 0, behind the cameras; "
            "are the images swapped?)")
    return px


def height_from_parallax(px, c, B):
    r"""Z of the stereo normal case from the x-parallax / Höhe aus der x-Parallaxe.

    Parameters
    ----------
    px : float or array_like
        x-parallax ``px' = x'1 − x'2`` (image unit, mm), > 0 for points in front.
    c : float
        Camera constant, > 0 (image unit).
    B : float
        Base (Basis): camera 2 at ``(B, 0, 0)`` (object unit), > 0.

    Returns
    -------
    float or ndarray
        Z (object unit), negative: the cameras look down −Z.

    Raises
    ------
    DegenerateGeometryError
        For zero parallax (parallel rays).
    PointBehindCameraError
        For negative parallax.

    Notes
    -----
    .. math:: Z = -\frac{c\,B}{p_x'}

    Examples
    --------
    >>> float(height_from_parallax(2.0, c=100.0, B=20.0))
    -1000.0
    """
    c = as_scalar(c, "c", positive=True)
    B = as_scalar(B, "B", positive=True)
    px = _parallax(px)
    with np.errstate(over="ignore"):
        Z = -c * B / px
    _check_overflow(Z, px, "px")
    return float(Z) if Z.ndim == 0 else Z


def _check_overflow(values, px, name):
    """A parallax so small (e.g. 5e-324) that −c·B/px' overflows is a point at infinity."""
    if not np.all(np.isfinite(values)):
        rows = np.asarray(values).reshape(np.size(px), -1)  # one row per parallax
        i = int(np.flatnonzero(~np.isfinite(rows).all(axis=1))[0])
        raise DegenerateGeometryError(
            f"{name}[{i}] = {float(np.ravel(px)[i])!r} is so small that Z = −c·B/px' overflows: "
            "practically zero parallax, a point at infinity")


def normal_case_points(xy1, xy2, c, B, x0=0.0, y0=0.0):
    r"""Object points of the stereo normal case from both images' coordinates.

    Camera 1 at the origin, camera 2 at ``(B, 0, 0)``, both with R = I and the same interior
    orientation. X and Y come from image 1.

    Parameters
    ----------
    xy1, xy2 : array_like, shape (N, 2) or (2,)
        Image coordinates in image 1 and 2 (image unit).
    c : float
        Camera constant > 0 (image unit).
    B : float
        Base > 0 (object unit).
    x0, y0 : float
        Principal point (image unit).

    Returns
    -------
    ndarray, shape (N, 3) or (3,)

    Notes
    -----
    .. math:: p_x' = x_1' - x_2',\quad X = \frac{B\,(x_1'-x_0')}{p_x'},\quad
              Y = \frac{B\,(y_1'-y_0')}{p_x'},\quad Z = -\frac{c\,B}{p_x'}

    Examples
    --------
    >>> normal_case_points([1.0, 0.5], [-1.0, 0.5], c=100.0, B=20.0).tolist()
    [10.0, 5.0, -1000.0]
    """
    a, single = as_points(xy1, 2, "xy1")
    b, _ = as_points(xy2, 2, "xy2")
    if len(a) != len(b):
        raise ValueError(f"xy1 has {len(a)} points but xy2 has {len(b)}; they must pair up")
    c = as_scalar(c, "c", positive=True)
    B = as_scalar(B, "B", positive=True)
    x0, y0 = as_scalar(x0, "x0"), as_scalar(y0, "y0")
    px = _parallax(a[:, 0] - b[:, 0], "px' = x'1 − x'2")
    with np.errstate(over="ignore"):
        out = np.column_stack([B * (a[:, 0] - x0) / px, B * (a[:, 1] - y0) / px, -c * B / px])
    _check_overflow(out, px, "px' = x'1 − x'2")
    return out[0] if single else out


@dataclass(frozen=True)
class StereoAccuracy:
    """Accuracy of the stereo normal case from :func:`normal_case_accuracy`."""

    m: float  #: image scale number (Bildmaßstabszahl) m = h/c
    base_ratio: float  #: height-to-base ratio h/B (the inverse of the base ratio B/h)
    sigma_XY: float  #: σ_X = σ_Y = m·σ_x', object unit
    sigma_Z: float  #: σ_Z = (h/B)·m·σ_px', object unit


def normal_case_accuracy(h, B, c, sigma_px, sigma_xy) -> StereoAccuracy:
    r"""Standard deviations of X, Y and Z in the normal case (Luhmann example 3.7).

    Parameters
    ----------
    h : float
        Object distance ``h = −Z`` > 0 (object unit).
    B : float
        Base > 0 (object unit).
    c : float
        Camera constant > 0 (image unit).
    sigma_px : float
        σ of the x-parallax (object unit; give c, σ in the same unit, e.g. m, or mm and mm).
    sigma_xy : float
        σ of one image coordinate (same unit as ``sigma_px``). If x'1, x'2 are measured
        independently, ``σ_px' = √2·σ_x'`` by error propagation; stereoscopic measurement of
        the parallax is often assumed better, ``σ_px' = σ_x'/√2`` (errata record
        ``luhmann:example-3.7``). Which one holds is a statement about the measurement.

    Returns
    -------
    StereoAccuracy
        σ in the unit of ``sigma_px`` times ``h/c`` (e.g. mm of image σ → mm·m/mm).

    Notes
    -----
    From :math:`Z = -cB/p_x'`: :math:`|\partial Z/\partial p_x'| = Z^2/(cB)`, so

    .. math:: σ_Z = \frac{h}{B}\,\frac{h}{c}\,σ_{p_x'} = \frac{h}{B}\,m\,σ_{p_x'},\qquad
              σ_{X} = σ_Y = m\,σ_{x'},\quad m = \frac{h}{c}

    (σ_X is the leading term; the part from σ_Z, ``(X/h)·σ_Z``, is left out as in Luhmann.)

    Examples
    --------
    Example 3.7: m = 125, h = 5 m, b = 1.2 m, s_px' = 4 µm (σ in mm; c = h/m = 40 mm):

    >>> acc = normal_case_accuracy(5000.0, 1200.0, 40.0, 0.004, 0.004 * 2**0.5)
    >>> round(acc.m, 6), round(acc.sigma_Z, 4), round(acc.sigma_XY, 4)
    (125.0, 2.0833, 0.7071)
    """
    h = as_scalar(h, "h", positive=True)
    B = as_scalar(B, "B", positive=True)
    c = as_scalar(c, "c", positive=True)
    sigma_px = as_scalar(sigma_px, "sigma_px", positive=True)
    sigma_xy = as_scalar(sigma_xy, "sigma_xy", positive=True)
    m = h / c
    return StereoAccuracy(m=m, base_ratio=h / B, sigma_XY=m * sigma_xy,
                          sigma_Z=(h / B) * m * sigma_px)
