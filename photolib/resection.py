r"""Space resection / räumlicher Rückwärtsschnitt: exterior orientation of one image.

Gauss–Newton least squares of the collinearity equations for the six unknowns
``(X0, Y0, Z0, ω, φ, κ)`` with the interior orientation (c, x'0, y'0, distortion) known:

.. math::
    v = x'(X_0, ω, φ, κ) - x'_{obs}, \qquad
    A\,\hat{dq} = -v,\quad \hat{dq} = (A^T A)^{-1} A^T (-v),\qquad
    σ_0 = \sqrt{\frac{v^T v}{2n - 6}},\quad Σ_{qq} = σ_0^2 (A^T A)^{-1}

with ``A`` the partial derivatives of :func:`photolib.collinearity_jacobian` (Luhmann 4.18).
Distortion is evaluated at the measured points (CONVENTIONS), so the observations are
corrected once, ``x_ideal = x_meas − Δ(x_meas − x'0)``, before the adjustment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import (
    as_float_array,
    as_max_iter,
    as_point_pairs,
    as_scalar,
    as_tolerance,
)
from photolib.collinearity import PointBehindCameraError, collinearity_jacobian, project
from photolib.distortion import Distortion
from photolib.dlt import dlt_decompose, dlt_estimate
from photolib.rotations import rotation_opk
from photolib.transforms._base import ConvergenceError

__all__ = ["ResectionResult", "space_resection"]


@dataclass(frozen=True)
class ResectionResult:
    """Exterior orientation from :func:`space_resection`."""

    X0: np.ndarray  #: (3,) projection centre, object unit
    R: np.ndarray  #: (3, 3) rotation R_ω·R_φ·R_κ
    omega: float  #: radians
    phi: float  #: radians
    kappa: float  #: radians
    sigma0: float  #: a-posteriori σ0, image unit (NaN for 3 points)
    covariance: np.ndarray  #: (6, 6) for (X0, Y0, Z0, ω, φ, κ): object units², rad²
    residuals: np.ndarray  #: (N, 2) v = x'(adjusted) − x'(observed, distortion-corrected), image unit
    iterations: int
    converged: bool
    redundancy: int  #: r = 2N − 6

    @property
    def params(self) -> np.ndarray:
        """``(X0, Y0, Z0, ω, φ, κ)`` as one (6,) array."""
        return np.r_[self.X0, self.omega, self.phi, self.kappa]

    @property
    def orientation(self):
        """The result as a :class:`photolib.ExteriorOrientation` (``X0``, ``R``)."""
        from photolib.exterior import ExteriorOrientation
        return ExteriorOrientation(self.X0, self.R)

    @property
    def std(self) -> np.ndarray:
        """Standard deviations of ``params`` (sqrt of the covariance diagonal)."""
        return np.sqrt(np.diag(self.covariance))


def _initial_from_dlt(X, xy):
    if len(X) < 6:
        raise ValueError(f"initial values are needed: the DLT start needs ≥ 6 points, got {len(X)}")
    sv = np.linalg.svd(X - X.mean(axis=0), compute_uv=False)
    if sv[2] <= 1e-9 * sv[0]:
        raise ValueError("initial values are needed: the object points are coplanar, so the DLT "
                         "cannot provide them; pass initial=(X0, Y0, Z0, omega, phi, kappa)")
    d = dlt_decompose(dlt_estimate(X, xy))
    if not np.isfinite(d.omega):
        raise ValueError("DLT start at gimbal lock (φ = ±90°); pass initial values")
    return np.r_[d.X0, d.omega, d.phi, d.kappa]


def space_resection(X, xy, c, x0=0.0, y0=0.0, distortion=None, initial=None, *,
                    tol: float = 1e-10, max_iter: int = 50, check: bool = True) -> ResectionResult:
    """Exterior orientation ``(X0, Y0, Z0, ω, φ, κ)`` of one image by iterative least squares.

    Parameters
    ----------
    X : array_like, shape (N, 3)
        Object points (object unit, e.g. m), N ≥ 3 (≥ 6 non-coplanar without ``initial``).
    xy : array_like, shape (N, 2)
        Measured image coordinates (image unit, e.g. mm).
    c : float
        Camera constant, > 0 (image unit).
    x0, y0 : float
        Principal point (image unit).
    distortion : Distortion, optional
        Distortion of the measured points (evaluated at the measured coordinates).
    initial : array_like, shape (6,), optional
        Start ``(X0, Y0, Z0, ω, φ, κ)``; default from :func:`photolib.dlt.dlt_estimate`.
    tol : float
        Stop when the update is below ``tol`` (angles, radians) and ``tol·extent`` (lengths).
    max_iter : int
        Iteration limit. Reaching it raises ``ConvergenceError`` unless ``check=False``, which
        returns the last iterate with ``converged=False`` (NaN residuals for points behind
        its camera, NaN σ0/covariance where they are not defined).
    check : bool
        If True (default) no convergence within ``max_iter`` raises ``ConvergenceError``;
        False returns the last iterate with ``converged=False`` instead.

    Returns
    -------
    ResectionResult

    Raises
    ------
    ValueError
        Shapes, NaN, ``max_iter < 1``, ``tol ≤ 0``; ``DegenerateGeometryError`` (a
        ValueError) from the DLT start for coplanar object or collinear image points.
    ConvergenceError
        Divergence (non-finite values, points ending behind the camera) or no convergence.

    Examples
    --------
    >>> from photolib import project
    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 4], [2, 8, 1.0]])
    >>> R = rotation_opk(0.05, -0.1, 0.2)
    >>> xy = project(X, [4.0, 6.0, 30.0], R, c=24.0)
    >>> res = space_resection(X, xy, c=24.0)
    >>> np.round(res.X0, 9).tolist(), round(res.kappa, 12), res.converged
    ([4.0, 6.0, 30.0], 0.2, True)
    """
    X, xy = as_point_pairs(X, xy, (3, 2), ("X", "xy"), 3, "space_resection")
    c = as_scalar(c, "c", positive=True)
    x0, y0 = as_scalar(x0, "x0"), as_scalar(y0, "y0")
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    if distortion is not None and not isinstance(distortion, Distortion):
        raise TypeError(f"distortion must be a photolib.Distortion or None, got {type(distortion).__name__}")
    pp = np.array([x0, y0])
    obs = xy if distortion is None else pp + distortion.correct(xy - pp)
    if initial is None:
        q = _initial_from_dlt(X, obs)
    else:
        q = as_float_array(initial, "initial")
        if q.shape != (6,):
            raise ValueError(f"initial has shape {q.shape}; expected (6,) = (X0, Y0, Z0, omega, phi, kappa)")
        if not np.all(np.isfinite(q)):
            raise ValueError(f"initial contains a non-finite value: {q.tolist()}")
    extent = float(np.max(np.ptp(X, axis=0))) or 1.0
    converged, it = False, 0
    for it in range(1, max_iter + 1):
        R = rotation_opk(*q[3:])
        try:
            v = project(X, q[:3], R, c, x0, y0) - obs
            A = collinearity_jacobian(X, q[:3], R, c, angles=tuple(q[3:]))[:, :, :6].reshape(-1, 6)
        except PointBehindCameraError as exc:  # its detail: without project's return_valid hint
            raise ConvergenceError(f"space resection diverged in iteration {it}: "
                                   f"{exc.detail or exc}; check the initial values") from None
        dq = np.linalg.lstsq(A, -v.reshape(-1), rcond=None)[0]
        if not np.all(np.isfinite(dq)):
            raise ConvergenceError(f"space resection diverged in iteration {it}: non-finite update")
        q = q + dq
        if np.max(np.abs(dq[:3])) <= tol * extent and np.max(np.abs(dq[3:])) <= tol:
            converged = True
            break
        if np.linalg.norm(q[:3] - X.mean(axis=0)) > 1e6 * extent:
            raise ConvergenceError(f"space resection diverged in iteration {it}: the projection "
                                   f"centre ran away to {q[:3].tolist()}")
    if not converged and check:
        raise ConvergenceError(f"space resection did not converge to tol={tol:g} in {max_iter} "
                               "iterations (last update "
                               f"{np.max(np.abs(dq)):.3g}); pass check=False to get the last iterate")
    R = rotation_opk(*q[3:])
    r = 2 * len(X) - 6
    # the last iterate of a run that did not converge (check=False) is returned as it is:
    # points behind the camera get NaN residuals, and no covariance is claimed for it
    xy_q, valid = project(X, q[:3], R, c, x0, y0, return_valid=True)
    if not converged and not valid.all():
        return ResectionResult(q[:3].copy(), R, float(q[3]), float(q[4]), float(q[5]),
                               float("nan"), np.full((6, 6), np.nan), xy_q - obs, it, False, r)
    if not valid.all():
        i = int(np.argmin(valid))
        raise ConvergenceError(f"space resection ended with point {i} ({X[i].tolist()}) behind "
                               "the camera")
    v = xy_q - obs
    A = collinearity_jacobian(X, q[:3], R, c, angles=tuple(q[3:]))[:, :, :6].reshape(-1, 6)
    sigma0 = float(np.sqrt(np.sum(v**2) / r)) if r > 0 else float("nan")
    N = A.T @ A
    singular = np.linalg.cond(N) > 1e14
    if singular and converged:
        raise ConvergenceError("normal equations are singular: the points do not determine the "
                               "exterior orientation (e.g. all on a line, or on the danger cylinder)")
    cov = (sigma0**2 * np.linalg.inv(N) if r > 0 and not singular
           else np.full((6, 6), np.nan))
    return ResectionResult(q[:3].copy(), R, float(q[3]), float(q[4]), float(q[5]), sigma0, cov,
                           v, it, converged, r)
