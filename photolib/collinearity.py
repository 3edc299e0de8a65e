"""Collinearity equations / Kollinearitätsgleichungen: projection, Jacobian, monoplotting.

With ``(kx, ky, N) = Rᵀ·(X − X0)`` (derived in :mod:`photolib.derive.collinearity`):

.. math::
    x' = x'_0 - c\\,\\frac{k_x}{N} + Δx', \\qquad y' = y'_0 - c\\,\\frac{k_y}{N} + Δy'

A point in front of the camera has ``N < 0``. Object coordinates in any length unit (m),
image coordinates, c, x'0, y'0 and the distortion in one image unit (mm).
"""

from __future__ import annotations

import numpy as np

from photolib._generated.collinearity import collinearity_jacobian_opk, project_r
from photolib._validate import as_points, as_rotation, as_scalar, as_vector3, check_finite
from photolib.distortion import Distortion
from photolib.rotations import opk_from_rotation
from photolib.errors import PointBehindCameraError  # noqa: F401 - raised here, defined in one hierarchy

__all__ = ["project", "collinearity_jacobian", "monoplot", "monoplot_dtm", "PointBehindCameraError"]

#: points per block: temporaries stay in the CPU cache, memory stays bounded for N = 1e6+
BLOCK = 8192



def _behind_camera(pts, depth, valid, advice: str) -> PointBehindCameraError:
    """The error about the first point with ``N ≥ 0`` (``valid`` False), naming it and N."""
    i = int(np.argmin(valid))
    detail = (f"X[{i}] = {pts[i].tolist()} is not in front of the camera: N = {depth[i]:.6g} "
              "≥ 0 (N = r13·ΔX + r23·ΔY + r33·ΔZ must be negative)")
    err = PointBehindCameraError(f"{detail}. {advice}")
    err.index, err.detail = i, detail
    return err


def _interior(c, x0, y0, distortion):
    c = as_scalar(c, "c", positive=True)
    x0 = as_scalar(x0, "x0")
    y0 = as_scalar(y0, "y0")
    if distortion is not None and not isinstance(distortion, Distortion):
        raise TypeError(f"distortion must be a photolib.Distortion or None, got {type(distortion).__name__}")
    return c, x0, y0


def project(X, X0, R, c, x0=0.0, y0=0.0, distortion=None, *, return_valid=False):
    """Image coordinates of object points (collinearity equations with principal point).

    Parameters
    ----------
    X : array_like, shape (N, 3) or (3,)
        Object points (object unit, e.g. m).
    X0 : array_like, shape (3,)
        Projection centre (object unit).
    R : array_like, shape (3, 3)
        Rotation camera → object, ``R = R_ω·R_φ·R_κ`` (:func:`photolib.rotation_opk`).
    c : float
        Camera constant / Kamerakonstante, > 0 (image unit, e.g. mm).
    x0, y0 : float
        Principal point / Bildhauptpunkt (image unit).
    distortion : Distortion, optional
        Evaluated at the measured point, so the image point solves
        ``x' − x'0 − Δ(x' − x'0) = −c·kx/N`` by Newton's iteration (Luhmann p. 163/164).
    return_valid : bool
        If True return ``(xy, valid)`` with NaN rows where ``N ≥ 0`` instead of raising.

    Returns
    -------
    xy : ndarray, shape (N, 2) or (2,)
        Image coordinates (image unit).

    Raises
    ------
    PointBehindCameraError
        If a point has ``N ≥ 0`` and ``return_valid`` is False; the message names it.

    Notes
    -----
    .. math:: (k_x, k_y, N)^T = R^T (X - X_0),\\quad x' = x'_0 - c\\,k_x/N,\\quad y' = y'_0 - c\\,k_y/N

    Examples
    --------
    >>> project([1.0, 2.0, 0.0], [0.0, 0.0, 100.0], np.eye(3), c=50.0).round(12).tolist()
    [0.5, 1.0]
    """
    pts, single = as_points(X, 3, "X", finite=False)  # checked per block below
    X0 = as_vector3(X0, "X0")
    R = as_rotation(R)
    c, x0, y0 = _interior(c, x0, y0, distortion)
    n = len(pts)
    out = np.empty((n, 2))
    depth = np.empty(n)
    r = R.ravel()
    for s in range(0, n, BLOCK):
        b = pts[s:s + BLOCK].T
        if not np.isfinite(b).all():
            check_finite(pts, "X")  # raises, naming the first bad entry of the whole array
        x, y, N = project_r(b[0], b[1], b[2], X0[0], X0[1], X0[2], *r, c, x0, y0)
        out[s:s + BLOCK, 0] = x
        out[s:s + BLOCK, 1] = y
        depth[s:s + BLOCK] = N
    valid = depth < 0
    if not valid.all():
        if not return_valid:
            raise _behind_camera(pts, depth, valid, "Check X0, R, or pass return_valid=True to "
                                 "get NaN for such points.")
        out[~valid] = np.nan
    if distortion is not None and not distortion.is_zero and valid.any():
        ok = np.flatnonzero(valid)
        pp = np.array([x0, y0])
        out[ok] = distortion.distort(out[ok] - pp) + pp
    res = out[0] if single else out
    return (res, valid[0] if single else valid) if return_valid else res


def collinearity_jacobian(X, X0, R, c, *, angles=None):
    """Partial derivatives ∂(x', y')/∂(X0, Y0, Z0, ω, φ, κ, X, Y, Z) (no distortion).

    Parameters
    ----------
    X : array_like, shape (N, 3) or (3,)
    X0 : array_like, shape (3,)
    R : array_like, shape (3, 3)
        ``R = R_ω·R_φ·R_κ``; the angles are recovered with :func:`photolib.opk_from_rotation`.
    c : float
        Camera constant, > 0.
    angles : tuple of 3 floats, optional
        ``(omega, phi, kappa)`` in radians; required at gimbal lock, where R alone does not
        fix the angles (and so not the derivatives with respect to them). Must match R.

    Raises
    ------
    PointBehindCameraError
        If a point has ``N ≥ 0`` (on or behind the projection centre, where the
        collinearity equations and their derivatives do not describe an image point).

    Returns
    -------
    J : ndarray, shape (N, 2, 9) or (2, 9)
        Image unit per object unit for the lengths, image unit per radian for the angles.
        The entries are those of Luhmann (4.18) with ``z' = −c``, including the corrected 4.18b.

    Examples
    --------
    >>> J = collinearity_jacobian([0.0, 0.0, 0.0], [0.0, 0.0, 100.0], np.eye(3), c=50.0)
    >>> (J[0, :3].round(12) + 0.0).tolist()   # ∂x'/∂X0 = −c/|N| for a nadir image
    [-0.5, 0.0, 0.0]
    """
    pts, single = as_points(X, 3, "X")
    X0 = as_vector3(X0, "X0")
    R = as_rotation(R)
    c = as_scalar(c, "c", positive=True)
    depth = (pts - X0) @ R[:, 2]  # N of every point, as in project
    valid = depth < 0
    if not valid.all():
        raise _behind_camera(pts, depth, valid, "Check X0 and R: the image of such a point, "
                             "and so its derivatives, are not defined.")
    if angles is None:
        angles = opk_from_rotation(R)
    else:
        from photolib.rotations import rotation_opk

        try:
            count = None if isinstance(angles, (str, bytes)) else len(angles)
        except TypeError:
            count = None
        if count != 3:
            raise ValueError(f"angles must be the three angles (omega, phi, kappa), got "
                             f"{angles!r}")
        angles = tuple(as_scalar(a, n) for a, n in zip(angles, ("omega", "phi", "kappa")))
        if not np.allclose(rotation_opk(*angles), R, atol=1e-9):
            raise ValueError(f"angles {angles!r} do not give R (max deviation "
                             f"{np.max(np.abs(rotation_opk(*angles) - R)):.3g})")
    cols = collinearity_jacobian_opk(pts[:, 0], pts[:, 1], pts[:, 2], *X0, *angles, c)
    J = np.stack(np.broadcast_arrays(*cols), axis=-1).reshape(-1, 9, 2).transpose(0, 2, 1)
    return J[0].copy() if single else J.copy()


def monoplot(xy, X0, R, c, Z, x0=0.0, y0=0.0, distortion=None):
    """Intersect image rays with the horizontal plane ``Z = const`` (monoplotting).

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Measured image coordinates (image unit).
    X0, R, c, x0, y0, distortion
        As in :func:`project`; the distortion is removed directly (Δ at the measured point).
    Z : float
        Height of the plane (object unit).

    Returns
    -------
    X : ndarray, shape (N, 3) or (3,)

    Raises
    ------
    ValueError
        If a ray is parallel to the plane or meets it behind the camera.

    Notes
    -----
    .. math:: \\mathbf X = \\mathbf X_0 + λ\\,R\\,\\mathbf x^*,\\quad
              \\mathbf x^* = (x'-x'_0-Δx', y'-y'_0-Δy', -c)^T,\\quad λ = (Z - Z_0)/(R\\mathbf x^*)_3 > 0

    Examples
    --------
    >>> monoplot([0.5, 1.0], [0.0, 0.0, 100.0], np.eye(3), c=50.0, Z=0.0).round(12).tolist()
    [1.0, 2.0, 0.0]
    """
    pts, single = as_points(xy, 2, "xy")
    X0 = as_vector3(X0, "X0")
    R = as_rotation(R)
    c, x0, y0 = _interior(c, x0, y0, distortion)
    Z = as_scalar(Z, "Z")
    red = pts - [x0, y0]
    if distortion is not None:
        red = red - distortion.delta(red)
    rays = np.column_stack([red, np.full(len(red), -c)]) @ R.T
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = (Z - X0[2]) / rays[:, 2]
    bad = ~np.isfinite(lam) | (np.abs(rays[:, 2]) < 1e-12 * c) | (lam <= 0)
    if bad.any():
        i = int(np.argmax(bad))
        why = ("is parallel to the plane" if abs(rays[i, 2]) < 1e-12 * c
               else "meets the plane behind the camera")
        raise ValueError(f"the ray of xy[{i}] = {pts[i].tolist()} {why} Z = {Z} "
                         f"(Z0 = {X0[2]}, ray direction {rays[i].round(6).tolist()})")
    out = X0 + lam[:, None] * rays
    return out[0] if single else out


def monoplot_dtm(xy, X0, R, c, surface, x0=0.0, y0=0.0, distortion=None, *, Z_start=None,
                 tol=1e-4, max_iter=50, return_iterations=False):
    """Intersect image rays with a terrain surface Z = h(X, Y) (monoplotting on a DTM).

    The iteration of Kraus and Luhmann: start on the plane ``Z = Z_start``, intersect the ray
    with that plane (:func:`monoplot`), read the terrain height under the point, intersect
    again with the plane at that height, until the height changes by less than ``tol``::

        Z_(k+1) = h(X_k, Y_k),   (X_k, Y_k, Z_k) = X0 + λ_k·R·x*,  λ_k = (Z_k − Z0)/(R·x*)_3

    It converges where the terrain is less steep than the ray, ``|∇h|·tan ν < 1`` (ν the angle
    of the ray from the plumb line): the error shrinks by that factor per step.

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Measured image coordinates (image unit, mm).
    X0, R, c, x0, y0, distortion
        As in :func:`project`.
    surface : callable or photolib.DTM
        Terrain heights: ``surface(XY)`` with ``XY`` of shape (N, 2) returns N heights
        (object unit), or a :class:`photolib.DTM` (its ``height``).
    Z_start : float, optional
        Height of the first plane; default the terrain height under the projection centre.
    tol : float
        Stop when every point's height changes by less than ``tol`` (object unit).
    max_iter : int
        Iteration limit; not converging within it raises ``ValueError``.
    return_iterations : bool
        If True return ``(X, heights)`` with ``heights`` of shape (k + 1, N): the plane
        heights Z_0 … Z_k of the iteration.

    Returns
    -------
    X : ndarray, shape (N, 3) or (3,)
        Object points on the surface (to ``tol`` in height).

    Raises
    ------
    ValueError
        If a ray is parallel to a plane or meets it behind the camera, or the iteration does
        not converge (terrain steeper than the ray), naming the point.

    Examples
    --------
    >>> slope = lambda XY: 0.1 * XY[:, 0]              # a plane rising 10 % to the east
    >>> X = monoplot_dtm([10.0, 0.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0, slope, tol=1e-9)
    >>> np.round(X, 6).tolist()                        # X = 100 m·(1 − 0.01·X): 100/1.01
    [99.009901, 0.0, 9.90099]
    """
    pts, single = as_points(xy, 2, "xy")
    X0 = as_vector3(X0, "X0")
    height = surface.height if hasattr(surface, "height") else surface
    if not callable(height):
        raise TypeError(f"surface must be a callable h(XY) or a photolib.DTM, got "
                        f"{type(surface).__name__}")
    tol = as_scalar(tol, "tol", positive=True)
    if int(max_iter) < 1:
        raise ValueError(f"max_iter must be at least 1, got {max_iter!r}")

    def h(XY):
        Z = np.asarray(height(np.asarray(XY, float)), float).reshape(-1)
        if Z.shape != (len(XY),) or not np.isfinite(Z).all():
            raise ValueError(f"the surface gave {Z.tolist()[:5]} for plan positions "
                             f"{np.asarray(XY).tolist()[:5]}: expected {len(XY)} finite heights")
        return Z

    Z = (np.full(len(pts), h(X0[None, :2])[0]) if Z_start is None
         else np.full(len(pts), as_scalar(Z_start, "Z_start")))
    history = [Z.copy()]

    def on_planes(Z, k):
        try:
            return np.vstack([monoplot(p, X0, R, c, z, x0, y0, distortion)
                              for p, z in zip(pts, Z)])
        except ValueError as err:
            if k == 0:
                raise
            raise ValueError(f"monoplotting on the surface did not converge: at iteration {k} "
                             f"{err} (terrain steeper than the ray: |slope|·tan ν ≥ 1?)") from err

    for k in range(int(max_iter)):
        X = on_planes(Z, k)
        Z_new = h(X[:, :2])
        history.append(Z_new.copy())
        step = np.abs(Z_new - Z)
        Z = Z_new
        if (step < tol).all():
            X = on_planes(Z, k + 1)
            out = X[0] if single else X
            return (out, np.array(history)) if return_iterations else out
    i = int(np.argmax(step))
    raise ValueError(f"monoplotting on the surface did not converge in {max_iter} iterations "
                     f"for xy[{i}] = {pts[i].tolist()}: the height still changes by "
                     f"{step[i]:.3g} (terrain steeper than the ray: |slope|·tan ν ≥ 1?)")
