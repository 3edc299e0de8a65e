r"""Circle fit through ≥ 3 points: algebraic, then refined geometrically.

:func:`fit_circle` solves the general circle equation (Luhmann 2.85/2.86, the errata's
corrected 2.86) in the least-squares sense on normalised points, so that circles through
the origin fit too, and refines centre and radius by Gauss–Newton on the radial residuals.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._linalg import svd_right
from photolib._validate import as_max_iter, as_points, as_tolerance
from photolib.transforms._base import ConvergenceError, collinearity_ratio


class CircleFit(NamedTuple):
    """Result of :func:`fit_circle`."""

    centre: np.ndarray  #: (2,) centre (xc, yc), unit of the points
    radius: float  #: radius, unit of the points
    residuals: np.ndarray  #: (N,) radial residuals ``|p − centre| − radius``
    sigma0: float  #: sqrt(Σv²/(N − 3)); NaN for N = 3
    iterations: int  #: Gauss–Newton iterations of the geometric refinement (0 if none)


def fit_circle(xy, *, refine: bool = True, tol: float = 1e-12, max_iter: int = 50) -> CircleFit:
    r"""Circle through ≥ 3 points: algebraic fit, optionally refined geometrically.

    The algebraic fit solves the general circle equation (Luhmann 2.85/2.86)

    .. math::
        A(x^2 + y^2) + 2Dx + 2Ey + F = 0, \qquad
        x_c = -\frac{D}{A},\; y_c = -\frac{E}{A},\;
        r = \sqrt{\frac{D^2 + E^2 - AF}{A^2}}

    (the errata's corrected 2.86) in the least-squares sense with ``|(A, D, E, F)| = 1``
    on normalised points — unlike 2.88 with ``F = 1`` it also fits circles through the
    origin. The geometric refinement minimises :math:`\sum (|p_i - c| - r)^2` by
    Gauss–Newton.

    Parameters
    ----------
    xy : array_like, shape (N, 2)
        Points (any length unit), N ≥ 3, not collinear.
    refine : bool
        Geometric refinement after the algebraic fit.
    tol, max_iter
        Stop when the update is below ``tol·(1 + r)``; raise ``ConvergenceError`` after
        ``max_iter`` iterations.

    Returns
    -------
    CircleFit
        centre (2,), radius, residuals (N,), sigma0, iterations.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 7)[:-1]
    >>> fit = fit_circle(np.column_stack([3 + 2 * np.cos(t), -1 + 2 * np.sin(t)]))
    >>> np.round(fit.centre, 12).tolist(), round(fit.radius, 12)
    ([3.0, -1.0], 2.0)
    """
    pts, _ = as_points(xy, 2, "xy")
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    if len(pts) < 3:
        raise ValueError(f"fit_circle needs at least 3 points, got {len(pts)}")
    if collinearity_ratio(pts) < 1e-9:
        raise ValueError("the points are collinear (or coincide); no circle is determined")
    centroid = pts.mean(axis=0)
    scale = np.sqrt(2.0) / np.mean(np.linalg.norm(pts - centroid, axis=1))
    u = scale * (pts - centroid)
    M = np.column_stack([np.sum(u**2, axis=1), 2 * u, np.ones(len(u))])
    A, D, E, F = svd_right(M)[1][-1]
    if abs(A) < 1e-12:
        raise ValueError("the points lie (nearly) on a straight line; the circle radius is infinite")
    centre = np.array([-D / A, -E / A])
    radius = float(np.sqrt(max((D**2 + E**2 - A * F) / A**2, 0.0)))
    iterations = 0
    if refine and len(u) > 3:
        for iterations in range(1, max_iter + 1):  # noqa: B007 - reported after the loop
            d = u - centre
            dist = np.linalg.norm(d, axis=1)
            if np.any(dist == 0.0):
                raise ConvergenceError("a point coincides with the circle centre during refinement")
            J = np.column_stack([-d / dist[:, None], -np.ones(len(u))])
            step = np.linalg.lstsq(J, -(dist - radius), rcond=None)[0]
            centre, radius = centre + step[:2], radius + float(step[2])
            if np.linalg.norm(step) <= tol * (1.0 + abs(radius)):
                break
        else:
            raise ConvergenceError(f"fit_circle: geometric refinement did not converge in {max_iter} iterations")
    centre = centroid + centre / scale
    radius = float(abs(radius) / scale)
    residuals = np.linalg.norm(pts - centre, axis=1) - radius
    n = len(pts)
    sigma0 = float(np.sqrt(np.sum(residuals**2) / (n - 3))) if n > 3 else float("nan")
    return CircleFit(centre, radius, residuals, sigma0, iterations)
