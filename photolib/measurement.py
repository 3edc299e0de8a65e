"""Image measurement / Bildmessung: Laplacian of Gaussian, moment-preserving threshold, circle fit.

The formulas are derived here (and checked with SymPy in the tests), not copied: Luhmann's
5.42 as corrected in the errata is right; the corrected 5.50 as printed in the errata list
(``p1 = ½[1 + s̄·sqrt(4 + s̄²)]``) is not — the square root belongs in the denominator.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_points, as_scalar, check_finite
from photolib.transforms._base import ConvergenceError, collinearity_ratio

__all__ = ["CircleFit", "MomentThreshold", "fit_circle", "laplacian_of_gaussian", "moment_threshold"]


def laplacian_of_gaussian(r, sigma):
    r"""Laplacian of the normalised 2-D Gaussian as a function of the radius (Luhmann 5.42).

    For :math:`G(x, y) = \frac{1}{2πσ^2} \exp\left(-\frac{r^2}{2σ^2}\right)`,
    :math:`r^2 = x^2 + y^2`:

    .. math::
        ∇^2 G = \frac{∂^2 G}{∂x^2} + \frac{∂^2 G}{∂y^2}
              = -\frac{1}{πσ^4}\left(1 - \frac{r^2}{2σ^2}\right) \exp\left(-\frac{r^2}{2σ^2}\right)

    (from :math:`∂^2G/∂x^2 = (x^2/σ^4 - 1/σ^2)\,G`). This is the errata's corrected 5.42;
    the original print :math:`-(1 - r/σ^2)\exp(-r^2/2σ^2)` has ``r`` for ``r²``, a wrong
    factor 2 and no normalisation. The zero crossing is at :math:`r = \sqrt 2\,σ` and the
    integral over the plane is 0.

    Parameters
    ----------
    r : float or array_like
        Distance from the centre (pixel or any length unit).
    sigma : float
        Standard deviation of the Gaussian, > 0 (same unit as r).

    Returns
    -------
    ndarray or float
        ∇²G, shape of ``r`` (unit⁻⁴).

    Examples
    --------
    >>> round(float(laplacian_of_gaussian(0.0, 1.0) * np.pi), 12)
    -1.0
    >>> abs(laplacian_of_gaussian(np.sqrt(2.0) * 3.0, 3.0)) < 1e-17  # zero crossing at √2·σ
    True
    """
    sigma = as_scalar(sigma, "sigma", positive=True)
    r = np.asarray(r, dtype=float)
    check_finite(np.atleast_1d(r), "r")
    q = r**2 / (2.0 * sigma**2)
    out = -(1.0 - q) * np.exp(-q) / (np.pi * sigma**4)
    return out if out.ndim else float(out)


class MomentThreshold(NamedTuple):
    """Result of :func:`moment_threshold` (grey values in the unit of the image)."""

    threshold: float  #: pixels ≤ threshold belong to the dark class h1
    p1: float  #: fraction of the dark class
    h1: float  #: dark representative grey value
    h2: float  #: bright representative grey value


def moment_threshold(image) -> MomentThreshold:
    r"""Moment-preserving threshold (Tsai 1985; Luhmann 5.49/5.50, derived anew).

    The grey values are replaced by two levels :math:`h_1 < h_2` with fractions
    :math:`p_1, p_2 = 1 - p_1` such that the first three moments are kept,

    .. math:: m_i = \frac{1}{n}\sum g^i = p_1 h_1^i + p_2 h_2^i, \qquad i = 1, 2, 3.

    With :math:`σ^2 = m_2 - m_1^2` and the skewness
    :math:`s = (m_3 - 3 m_1 m_2 + 2 m_1^3)/σ^3` the solution is

    .. math::
        p_1 = \frac{1}{2}\left(1 + \frac{s}{\sqrt{4 + s^2}}\right), \quad
        h_1 = m_1 - σ\sqrt{p_2/p_1}, \quad h_2 = m_1 + σ\sqrt{p_1/p_2}

    (a two-point distribution has skewness :math:`(p_1 - p_2)/\sqrt{p_1 p_2}`; solving for
    :math:`p_1` gives the root in the **denominator** — the errata's printed
    :math:`\tfrac12[1 + \bar s\sqrt{4 + \bar s^2}]` can exceed 1). The threshold is the
    :math:`p_1`-tile: the grey value whose cumulative fraction ``P(g ≤ t)`` is closest to
    :math:`p_1`.

    Parameters
    ----------
    image : array_like
        Grey values, any shape (at least two distinct finite values).

    Returns
    -------
    MomentThreshold
        ``(threshold, p1, h1, h2)``.

    Examples
    --------
    >>> img = np.array([10] * 30 + [200] * 70)
    >>> t = moment_threshold(img)
    >>> t.threshold, round(t.p1, 12), round(t.h1, 9), round(t.h2, 9)
    (10.0, 0.3, 10.0, 200.0)
    """
    g = np.asarray(image, dtype=float).ravel()
    if g.size == 0:
        raise ValueError("image is empty")
    check_finite(g, "image")
    m1 = g.mean()
    c = g - m1
    var = float(np.mean(c**2))
    if var <= (1e-12 * max(1.0, abs(m1))) ** 2:
        raise ValueError(f"image is constant (all grey values {m1:g}); there is no threshold")
    sd = np.sqrt(var)
    s = float(np.mean(c**3)) / sd**3
    p1 = 0.5 * (1.0 + s / np.sqrt(4.0 + s * s))
    p2 = 1.0 - p1
    h1 = m1 - sd * np.sqrt(p2 / p1)
    h2 = m1 + sd * np.sqrt(p1 / p2)
    values, counts = np.unique(g, return_counts=True)
    cdf = np.cumsum(counts) / g.size
    threshold = float(values[np.argmin(np.abs(cdf - p1))])
    return MomentThreshold(threshold, float(p1), float(h1), float(h2))


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
    if len(pts) < 3:
        raise ValueError(f"fit_circle needs at least 3 points, got {len(pts)}")
    if collinearity_ratio(pts) < 1e-9:
        raise ValueError("the points are collinear (or coincide); no circle is determined")
    centroid = pts.mean(axis=0)
    scale = np.sqrt(2.0) / np.mean(np.linalg.norm(pts - centroid, axis=1))
    u = scale * (pts - centroid)
    M = np.column_stack([np.sum(u**2, axis=1), 2 * u, np.ones(len(u))])
    A, D, E, F = np.linalg.svd(M)[2][-1]
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
