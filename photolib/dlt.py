r"""Direct linear transformation (DLT): estimation and decomposition (Luhmann 4.24–4.26).

.. math::
    x' = \frac{L_1 X + L_2 Y + L_3 Z + L_4}{L_9 X + L_{10} Y + L_{11} Z + 1}, \qquad
    y' = \frac{L_5 X + L_6 Y + L_7 Z + L_8}{L_9 X + L_{10} Y + L_{11} Z + 1}

Derivation of the decomposition (checked, not copied from 4.26). With
``A = [[L1, L2, L3], [L5, L6, L7], [L9, L10, L11]]`` and ``b = (L4, L8, 1)`` the
collinearity equations of CONVENTIONS give ``L·[A | b] = K·Rᵀ·[I | −X0]`` with

.. math::
    K = \begin{pmatrix} -c_x & s & x'_0 \\ 0 & -c_y & y'_0 \\ 0 & 0 & 1 \end{pmatrix},

so ``X0 = −A⁻¹·b``, the third column of R is ``r3 = L·(L9, L10, L11)`` and
``|L| = 1/sqrt(L9² + L10² + L11²)`` as printed. The sign is not free: ``det K = c_x·c_y > 0``
and ``det R = +1`` force ``sign L = sign det A``; equivalently **L equals the depth N of the
object-space origin**, negative when the origin lies in front of the camera. Luhmann's
``L = −1/sqrt(…)`` is therefore right exactly when the object origin is in front of the camera,
and the errata's rule "negate L if det R < 0" repairs the other case. Then (Gram–Schmidt from
the third row upwards)

.. math::
    y'_0 = L^2\,a_2·a_3,\quad c_y = |y'_0 r_3 - L a_2|,\quad r_2 = (y'_0 r_3 - L a_2)/c_y,\\
    x'_0 = L^2\,a_1·a_3,\quad s = L\,a_1·r_2,\quad c_x = |x'_0 r_3 + s r_2 - L a_1|,\quad
    r_1 = (x'_0 r_3 + s r_2 - L a_1)/c_x

with rows ``a1, a2, a3`` of A. The eleventh DLT parameter is the shear ``s``
(``x' = x'_0 − c_x k_x/N + s·k_y/N``); 4.26 ignores it, so its ``r11 = L(x'0·L9 − L1)/c_x``
and ``c_x`` agree with the above only for ``s = 0`` (4.26's c_x is ``sqrt(c_x² + s²)``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._linalg import svd_right
from photolib._validate import (
    as_float_array,
    as_point_pairs,
    as_rotation,
    as_scalar,
    as_vector3,
    check_finite,
)
from photolib.transforms._base import DegenerateGeometryError
from photolib.rotations import GimbalLockError, opk_from_rotation

__all__ = ["DLTDecomposition", "DLTEstimate", "dlt_decompose", "dlt_estimate", "dlt_from_camera"]


class DLTEstimate(NamedTuple):
    """Result of :func:`dlt_estimate`."""

    L: np.ndarray  #: (11,) L1…L11
    residuals: np.ndarray  #: (N, 2) reprojection residuals x'(L) − x' (image unit)
    sigma0: float  #: sqrt(vᵀv / r), image unit
    redundancy: int  #: r = 2N − 11


class DLTDecomposition(NamedTuple):
    """Result of :func:`dlt_decompose`; lengths in image / object units, angles in radians."""

    c_x: float
    c_y: float
    x0: float
    y0: float
    X0: np.ndarray
    R: np.ndarray
    omega: float
    phi: float
    kappa: float
    skew: float  #: the 11th parameter s: x' = x0 − c_x·kx/N + s·ky/N


def _as_L(L) -> np.ndarray:
    L = as_float_array(getattr(L, "L", L), "L", " with shape (11,)")
    if L.shape != (11,):
        raise ValueError(f"L has shape {L.shape}; expected (11,) (L1…L11)")
    check_finite(L, "L")
    return L


def _matrix(L: np.ndarray) -> np.ndarray:
    return np.append(L, 1.0).reshape(3, 4)


def _normaliser(P: np.ndarray) -> np.ndarray:
    d = P.shape[1]
    centroid = P.mean(axis=0)
    scale = np.sqrt(d) / np.mean(np.linalg.norm(P - centroid, axis=1))
    T = np.eye(d + 1) * scale
    T[:d, d] = -scale * centroid
    T[d, d] = 1.0
    return T


def _check_image_spread(xy: np.ndarray) -> None:
    """The image points of a DLT must span the image plane: coincident points (no spread,
    the normalisation would divide by 0) and collinear ones (the object points then lie in
    a plane through the projection centre) determine no camera."""
    sv = np.linalg.svd(xy - xy.mean(axis=0), compute_uv=False)
    size = float(np.max(np.abs(xy)))
    spread = float(sv[0] / np.sqrt(len(xy)))  # RMS along the widest direction
    if spread <= 1e-7 * max(size, 1e-300):
        raise DegenerateGeometryError(
            f"the image points (nearly) coincide: their spread {spread:.3g} is below 1e-7 of "
            f"their coordinates (up to {size:.3g}), so the 11 DLT parameters are not determined")
    if sv[1] <= 1e-9 * sv[0]:
        raise DegenerateGeometryError(
            "the image points are collinear (singular values of the centred points "
            f"{sv[0]:.3g}, {sv[1]:.3g}): the object points lie in a plane through the "
            "projection centre, and the 11 DLT parameters are not determined")


def _reproject(L: np.ndarray, X: np.ndarray) -> np.ndarray:
    h = np.column_stack([X, np.ones(len(X))]) @ _matrix(L).T
    if np.any(np.abs(h[:, 2]) < 1e-12):
        i = int(np.flatnonzero(np.abs(h[:, 2]) < 1e-12)[0])
        raise ValueError(f"object point {i} lies in the principal plane of the camera (denominator 0)")
    return h[:, :2] / h[:, 2:]


def dlt_estimate(X, xy) -> DLTEstimate:
    """The 11 DLT parameters from ≥ 6 non-coplanar object points by linear least squares.

    The object points and image points are normalised (centroid to 0, mean distance √3
    and √2), the homogeneous system ``x'·(L9X + L10Y + L11Z + L12) = L1X + …`` is solved
    by SVD (minimum algebraic error), then the result is denormalised and scaled to
    ``L12 = 1``.

    Parameters
    ----------
    X : array_like, shape (N, 3)
        Object points (object unit), N ≥ 6, not all in one plane.
    xy : array_like, shape (N, 2)
        Image points (image unit).

    Returns
    -------
    DLTEstimate
        ``(L, residuals, sigma0, redundancy)`` with ``L`` of shape (11,).

    Raises
    ------
    DegenerateGeometryError
        Coplanar (or collinear) object points, or image points that (nearly) coincide or
        lie on a line: then the 11 parameters are not determined.

    Examples
    --------
    >>> from photolib import project, rotation_opk
    >>> X = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [10, 10, 2], [5, 5, 5], [0, 10, 4], [3, 7, 1.0]])
    >>> xy = project(X, [5.0, 5.0, 40.0], rotation_opk(0.1, -0.05, 0.3), c=35.0)
    >>> est = dlt_estimate(X, xy)
    >>> bool(est.sigma0 < 1e-9), est.redundancy
    (True, 3)
    """
    X, xy = as_point_pairs(X, xy, (3, 2), ("X", "xy"), 6, "dlt_estimate")
    sv = np.linalg.svd(X - X.mean(axis=0), compute_uv=False)
    if sv[2] <= 1e-9 * sv[0]:
        raise DegenerateGeometryError(
            "the object points are coplanar (or collinear); the 11 DLT parameters are not "
            "determined — use the 8-parameter ProjectiveTransform for a plane")
    _check_image_spread(xy)
    TX, Tx = _normaliser(X), _normaliser(xy)
    Xn = np.column_stack([X, np.ones(len(X))]) @ TX.T
    xn = (np.column_stack([xy, np.ones(len(xy))]) @ Tx.T)[:, :2]
    n = len(X)
    A = np.zeros((2 * n, 12))
    A[0::2, 0:4] = Xn
    A[0::2, 8:12] = -xn[:, :1] * Xn
    A[1::2, 4:8] = Xn
    A[1::2, 8:12] = -xn[:, 1:] * Xn
    s, Vt = svd_right(A)
    if s[10] <= 1e-10 * s[0]:
        raise ValueError("degenerate configuration of object points; the DLT is not determined")
    P = np.linalg.inv(Tx) @ Vt[-1].reshape(3, 4) @ TX
    if abs(P[2, 3]) <= 1e-12 * np.abs(P[2, :3]).max() * (1.0 + np.abs(X).max()):
        raise ValueError("the object origin lies in the principal plane of the camera, so L12 = 0 "
                         "and the form with denominator L9·X + L10·Y + L11·Z + 1 does not exist; "
                         "shift the object coordinates")
    L = (P / P[2, 3]).reshape(-1)[:11]
    residuals = _reproject(L, X) - xy
    r = 2 * n - 11
    sigma0 = float(np.sqrt(np.sum(residuals**2) / r)) if r > 0 else float("nan")
    return DLTEstimate(L, residuals, sigma0, r)


def dlt_decompose(L) -> DLTDecomposition:
    """Interior and exterior orientation from the 11 DLT parameters (4.26, re-derived).

    See the module docstring for the derivation and what it says about 4.26.

    Parameters
    ----------
    L : array_like, shape (11,), or a :class:`DLTEstimate`

    Returns
    -------
    DLTDecomposition
        ``c_x, c_y > 0``, ``x0, y0`` (image unit), ``X0`` (3,) (object unit), ``R`` (3, 3)
        with ``R = R_ω·R_φ·R_κ``, ``omega, phi, kappa`` (radians; NaN at gimbal lock) and
        ``skew``.

    Examples
    --------
    >>> from photolib import rotation_opk
    >>> L = dlt_from_camera(50.0, 50.0, 0.1, -0.2, [1.0, 2.0, 30.0], rotation_opk(0.1, 0.2, 0.3))
    >>> d = dlt_decompose(L)
    >>> [round(float(v), 9) + 0.0 for v in (d.c_x, d.x0, d.y0, d.omega, d.phi, d.kappa, d.skew)]
    [50.0, 0.1, -0.2, 0.1, 0.2, 0.3, 0.0]
    >>> np.round(d.X0, 9).tolist()
    [1.0, 2.0, 30.0]
    """
    L = _as_L(L)
    P = _matrix(L)
    A, b = P[:, :3], P[:, 3]
    detA = np.linalg.det(A)
    if abs(detA) <= 1e-14 * np.linalg.norm(A) ** 3:
        raise ValueError("the 3×3 part of the DLT matrix is singular; L describes no central projection")
    a1, a2, a3 = A
    Ls = np.sign(detA) / np.linalg.norm(a3)  # = N of the object origin (see module docstring)
    X0 = -np.linalg.solve(A, b)
    r3 = Ls * a3
    y0 = Ls**2 * (a2 @ a3)
    v2 = y0 * r3 - Ls * a2
    c_y = float(np.linalg.norm(v2))
    r2 = v2 / c_y
    x0 = Ls**2 * (a1 @ a3)
    skew = Ls * (a1 @ r2)
    v1 = x0 * r3 + skew * r2 - Ls * a1
    c_x = float(np.linalg.norm(v1))
    R = np.column_stack([v1 / c_x, r2, r3])
    try:
        omega, phi, kappa = opk_from_rotation(R)
    except GimbalLockError:
        omega = phi = kappa = float("nan")
    return DLTDecomposition(c_x, c_y, float(x0), float(y0), X0, R, omega, phi, kappa, float(skew))


def dlt_from_camera(c_x, c_y, x0, y0, X0, R, skew=0.0) -> np.ndarray:
    """The 11 DLT parameters of a camera (inverse of :func:`dlt_decompose`).

    ``[A | b] = K·Rᵀ·[I | −X0] / N(origin)`` with K as in the module docstring and the
    scale chosen so that ``L12 = 1``.

    Parameters
    ----------
    c_x, c_y : float
        Camera constants / Kamerakonstanten in x' and y', > 0 (image unit, e.g. mm); equal for
        square pixels and no affinity.
    x0, y0 : float
        Principal point / Bildhauptpunkt (image unit).
    X0 : array_like, shape (3,)
        Projection centre / Projektionszentrum (object unit, e.g. m).
    R : array_like, shape (3, 3)
        Rotation camera → object, ``R = R_ω·R_φ·R_κ`` (:func:`photolib.rotation_opk`).
    skew : float
        The shear s, the eleventh DLT parameter (image unit):
        ``x' = x'0 − c_x·kx/N + s·ky/N``.

    Returns
    -------
    L : ndarray, shape (11,)
        L1…L11 (Luhmann 4.24), scaled so that the twelfth element is 1; L1–L8 in image unit
        per object unit (L4, L8 in image unit), L9–L11 per object unit.

    Raises
    ------
    ValueError
        If the object origin lies in the principal plane of the camera (N = 0), where no
        form with ``L12 = 1`` exists.

    Notes
    -----
    .. math::
        K = \\begin{pmatrix} -c_x & s & x'_0 \\\\ 0 & -c_y & y'_0 \\\\ 0 & 0 & 1
        \\end{pmatrix},\\qquad P = K\\,R^T\\,[I \\mid -X_0],\\qquad
        (L_1, …, L_{11}, 1) = \\operatorname{vec}(P)/P_{34}

    Examples
    --------
    >>> L = dlt_from_camera(35.0, 35.0, 0.0, 0.0, [0.0, 0.0, 10.0], np.eye(3))
    >>> (np.round(L, 12) + 0.0).tolist()
    [3.5, 0.0, 0.0, 0.0, 0.0, 3.5, 0.0, 0.0, 0.0, 0.0, -0.1]
    """
    c_x = as_scalar(c_x, "c_x", positive=True)
    c_y = as_scalar(c_y, "c_y", positive=True)
    x0, y0, skew = as_scalar(x0, "x0"), as_scalar(y0, "y0"), as_scalar(skew, "skew")
    X0, R = as_vector3(X0, "X0"), as_rotation(R)
    K = np.array([[-c_x, skew, x0], [0.0, -c_y, y0], [0.0, 0.0, 1.0]])
    P = K @ R.T @ np.column_stack([np.eye(3), -X0])
    if abs(P[2, 3]) <= 1e-12 * (1.0 + np.abs(X0).max()):
        raise ValueError("the object origin lies in the principal plane of the camera (N = 0); "
                         "the DLT form with L12 = 1 does not exist")
    return (P / P[2, 3]).reshape(-1)[:11]
