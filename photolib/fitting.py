"""Fitting of image features / Ausgleichung von Bildmerkmalen: ellipse, circle conic, plane.

* :func:`fit_ellipse` — direct algebraic least-squares ellipse (Fitzgibbon, Pilu & Fisher 1999
  in the numerically stable form of Halíř & Flusser 1998) on normalised points, and
  :func:`conic_to_ellipse`, the conversion of the conic to centre, semi-axes and orientation.
* :func:`circle_from_conic` — centre and radius of ``A(x² + y²) + 2Dx + 2Ey + F = 0``
  (Luhmann 2.86 as corrected: errata record ``luhmann:2.86``).
* :func:`plane_through_points` (three points, Luhmann 2.136 — record ``luhmann:2.136``: the
  printed matrix is the plane through (0, 0, z1), P2, P3, so it holds exactly when
  a1·x1 + a2·y1 = 0, e.g. with P1 at the origin) and :func:`fit_plane` (N points, SVD).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_points, as_scalar, as_vector3, check_finite
from photolib.transforms._base import DegenerateGeometryError, collinearity_ratio

__all__ = ["Ellipse", "EllipseFit", "Plane", "PlaneFit", "circle_from_conic", "conic_to_ellipse",
           "fit_ellipse", "fit_plane", "plane_through_points"]


class Ellipse(NamedTuple):
    """An ellipse: centre (2,), semi-axes ``(a, b)`` with a ≥ b, ``angle`` of the a-axis."""

    centre: np.ndarray  #: (2,) centre (x, y), unit of the points
    axes: np.ndarray    #: (2,) semi-axes (a, b), a ≥ b
    angle: float        #: direction of the a-axis from the +x axis towards +y, radians in [0, π)


def conic_to_ellipse(conic) -> Ellipse:
    r"""Centre, semi-axes and orientation of the conic ``a x² + b xy + c y² + d x + e y + f = 0``.

    With :math:`M = \begin{bmatrix} a & b/2 \\ b/2 & c\end{bmatrix}` the centre solves
    :math:`2M\,x_c = -(d, e)^T`; the conic at the centre is
    :math:`F_c = f + (d x_c + e y_c)/2`, and with the eigenvalues :math:`λ_i` and unit
    eigenvectors :math:`u_i` of M the conic is
    :math:`\sum λ_i ((x - x_c)\cdot u_i)^2 + F_c = 0`, so the semi-axes are

    .. math:: \sqrt{-F_c/λ_1},\; \sqrt{-F_c/λ_2}.

    Parameters
    ----------
    conic : array_like, shape (6,)
        ``(a, b, c, d, e, f)``, any scale and sign.

    Returns
    -------
    Ellipse

    Raises
    ------
    ValueError
        If the conic is not a real ellipse (b² − 4ac ≥ 0: parabola or hyperbola; or
        imaginary / a single point).

    Examples
    --------
    >>> e = conic_to_ellipse([1 / 9, 0, 1 / 4, -2 / 9, 0, 1 / 9 - 1])   # (x−1)²/9 + y²/4 = 1
    >>> e.centre.round(12).tolist(), e.axes.round(12).tolist(), round(e.angle, 12)
    ([1.0, 0.0], [3.0, 2.0], 0.0)
    """
    q = as_float_array(conic, "conic", " with shape (6,)")
    if q.shape != (6,):
        raise ValueError(f"conic has shape {q.shape}; expected (6,) = (a, b, c, d, e, f)")
    check_finite(q, "conic")
    a, b, c, d, e, f = q / np.max(np.abs(q)) if np.any(q) else q
    disc = b * b - 4.0 * a * c
    if disc >= -1e-14 * max(a * a + b * b + c * c, 1e-300):
        raise ValueError(f"the conic is not an ellipse: b² − 4ac = {disc:.3g} ≥ 0 "
                         "(parabola, hyperbola or degenerate)")
    M = np.array([[a, b / 2.0], [b / 2.0, c]])
    centre = np.linalg.solve(2.0 * M, -np.array([d, e])) + 0.0   # + 0.0: no −0.0
    Fc = f + 0.5 * (d * centre[0] + e * centre[1])
    lam, vec = np.linalg.eigh(M)
    sq = -Fc / lam
    if np.any(sq <= 0):
        raise ValueError("the conic is an imaginary ellipse or a single point "
                         f"(−F_c/λ = {sq[0]:.3g}, {sq[1]:.3g})")
    axes = np.sqrt(sq)
    major = int(np.argmax(axes))
    u = vec[:, major]
    angle = float(np.arctan2(u[1], u[0]) % np.pi)
    if np.isclose(angle, np.pi, rtol=0.0, atol=1e-15):
        angle = 0.0
    return Ellipse(centre, np.array([axes[major], axes[1 - major]]), angle)


class EllipseFit(NamedTuple):
    """Result of :func:`fit_ellipse`."""

    centre: np.ndarray     #: (2,) centre (x, y)
    axes: np.ndarray       #: (2,) semi-axes (a, b), a ≥ b
    angle: float           #: direction of the a-axis, radians in [0, π)
    conic: np.ndarray      #: (6,) (a, b, c, d, e, f) in the coordinates of the points, unit norm
    residuals: np.ndarray  #: (N,) Sampson distances F(p)/|∇F(p)| (≈ geometric distances)
    sigma0: float          #: sqrt(Σv²/(N − 5)); NaN for N = 5


def fit_ellipse(xy) -> EllipseFit:
    r"""Direct algebraic least-squares ellipse through ≥ 5 points (normalised).

    Minimises :math:`\sum (a x_i^2 + b x_i y_i + c y_i^2 + d x_i + e y_i + f)^2` subject to
    :math:`4ac - b^2 = 1`, which forces an ellipse (Fitzgibbon et al. 1999; Halíř & Flusser's
    block form, the algorithm of OpenCV's ``fitEllipseDirect``). The points are first moved to
    their centroid and scaled to mean distance √2 (Hartley), which keeps the normal
    equations well conditioned for image coordinates of any size; the conic is transformed
    back, :math:`C_x = T^T C_u T`, and converted by :func:`conic_to_ellipse`.

    Parameters
    ----------
    xy : array_like, shape (N, 2)
        Points, N ≥ 5, not collinear.

    Returns
    -------
    EllipseFit

    Raises
    ------
    DegenerateGeometryError
        Collinear points, fewer than 5 distinct ones, points through which more than one conic
        passes (e.g. four on a line), points exactly on a line pair, or no elliptic solution.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 9)[:-1]
    >>> p = np.column_stack([10 + 4 * np.cos(t), -3 + 2 * np.sin(t)])
    >>> fit = fit_ellipse(p)
    >>> fit.centre.round(9).tolist(), fit.axes.round(9).tolist(), round(fit.angle, 9)
    ([10.0, -3.0], [4.0, 2.0], 0.0)
    """
    pts, _ = as_points(xy, 2, "xy")
    if len(pts) < 5:
        raise ValueError(f"fit_ellipse needs at least 5 points, got {len(pts)}")
    if collinearity_ratio(pts) < 1e-9:
        raise DegenerateGeometryError("the points are collinear (or coincide); no ellipse is "
                                      "determined")
    m = pts.mean(axis=0)
    s = np.sqrt(2.0) / np.mean(np.linalg.norm(pts - m, axis=1))
    u, v = (s * (pts - m)).T
    D1 = np.column_stack([u * u, u * v, v * v])
    D2 = np.column_stack([u, v, np.ones_like(u)])
    S1, S2, S3 = D1.T @ D1, D1.T @ D2, D2.T @ D2
    try:
        _check_conic_determined(np.block([[S1, S2], [S2.T, S3]]))
    except DegenerateGeometryError:
        distinct = len(np.unique(pts, axis=0))      # the clearer message, only when it fails
        if distinct < 5:
            raise DegenerateGeometryError(f"fit_ellipse needs at least 5 distinct points, got "
                                          f"{distinct} among the {len(pts)}: a conic through "
                                          "fewer is not determined") from None
        raise
    T = -np.linalg.solve(S3, S2.T)
    Mred = S1 + S2 @ T
    Mred = np.array([Mred[2] / 2.0, -Mred[1], Mred[0] / 2.0])   # C1⁻¹·M
    _, vecs = np.linalg.eig(Mred)
    vecs = np.real(vecs)
    cond = 4.0 * vecs[0] * vecs[2] - vecs[1] ** 2
    if not np.any(cond > 0):
        raise DegenerateGeometryError("no ellipse fits these points (the constrained problem "
                                      "has no elliptic solution)")
    a1 = vecs[:, int(np.argmax(cond))]
    qu = np.r_[a1, T @ a1]
    Cu = np.array([[qu[0], qu[1] / 2, qu[3] / 2], [qu[1] / 2, qu[2], qu[4] / 2],
                   [qu[3] / 2, qu[4] / 2, qu[5]]])
    Tn = np.array([[s, 0.0, -s * m[0]], [0.0, s, -s * m[1]], [0.0, 0.0, 1.0]])
    Cx = Tn.T @ Cu @ Tn
    conic = np.array([Cx[0, 0], 2 * Cx[0, 1], Cx[1, 1], 2 * Cx[0, 2], 2 * Cx[1, 2], Cx[2, 2]])
    conic /= np.linalg.norm(conic)
    if conic[0] + conic[2] < 0:
        conic = -conic
    ell = conic_to_ellipse(conic)
    a, b, c, d, e, _ = conic
    x, y = pts.T
    F = a * x * x + b * x * y + c * y * y + d * x + e * y + conic[5]
    grad = np.hypot(2 * a * x + b * y + d, b * x + 2 * c * y + e)
    res = F / grad
    n = len(pts)
    sigma0 = float(np.sqrt(np.sum(res**2) / (n - 5))) if n > 5 else float("nan")
    return EllipseFit(ell.centre, ell.axes, ell.angle, conic, res, sigma0)


def _check_conic_determined(scatter: np.ndarray) -> None:
    """Refuse point sets that do not fix one proper conic, from the scatter matrix ``DᵀD`` of
    the design matrix ``D`` (N, 6) of the normalised points (rows ``u², uv, v², u, v, 1``).

    Two (near) zero singular values: a family of conics passes through the points (e.g. four
    of them on a line), any "fit" is arbitrary. One: the points lie exactly on one conic; if it
    is degenerate (a pair of lines, det of its 3 × 3 matrix zero) there is no ellipse to fit.
    """
    # singular values of D from the scatter matrix DᵀD (6 × 6, formed by the fit anyway):
    # squaring halves the digits, so the threshold is 1e-7 of the largest
    w, V = np.linalg.eigh(scatter)
    sv, Vt, tol = np.sqrt(np.clip(w[::-1], 0.0, None)), V[:, ::-1].T, 1e-7
    if sv[4] <= tol * sv[0]:
        raise DegenerateGeometryError(
            "the points do not determine a conic: more than one passes through them (e.g. four "
            "of them on one line); no ellipse is determined")
    if sv[5] <= tol * sv[0]:
        a, b, c, d, e, f = Vt[5]
        C = np.array([[a, b / 2, d / 2], [b / 2, c, e / 2], [d / 2, e / 2, f]])
        lam = np.sort(np.abs(np.linalg.eigvalsh(C)))
        if lam[0] <= tol * lam[-1]:
            raise DegenerateGeometryError(
                "the points lie on a degenerate conic (a pair of straight lines): no ellipse "
                "is determined")


def circle_from_conic(A, D, E, F) -> tuple[np.ndarray, float]:
    r"""Centre and radius of the circle ``A(x² + y²) + 2Dx + 2Ey + F = 0`` (Luhmann 2.86).

    .. math:: x_c = -\frac{D}{A}, \quad y_c = -\frac{E}{A}, \quad
              r = \sqrt{\frac{D^2 + E^2 - AF}{A^2}}

    — the errata's corrected 2.86 (record ``luhmann:2.86``); the old print
    :math:`\sqrt{D^2 + E^2 - AF}` is right only for A = 1.

    Parameters
    ----------
    A : float
        Coefficient of ``x² + y²``, ≠ 0. The equation may have any scale and sign; with x, y
        in mm, A·mm², D·mm and F share one unit (A = 1: D, E in mm, F in mm²).
    D, E : float
        Half the coefficients of x and y.
    F : float
        Constant term.

    Returns
    -------
    centre : ndarray, shape (2,)
        Centre ``(x_c, y_c)``, unit of the coordinates of the conic (e.g. mm).
    radius : float
        Radius r > 0, same unit.

    Raises
    ------
    ValueError
        If A = 0 (a straight line) or D² + E² − AF ≤ 0 (no real circle).

    Examples
    --------
    >>> c, r = circle_from_conic(2.0, -2.0, 4.0, 2.0)    # 2(x² + y²) − 4x + 8y + 2 = 0
    >>> c.tolist(), r
    ([1.0, -2.0], 2.0)
    """
    A, D, E, F = (as_scalar(v, n) for v, n in zip((A, D, E, F), "ADEF"))
    if A == 0.0:
        raise ValueError("A = 0: the conic is a straight line, not a circle")
    r2 = (D * D + E * E - A * F) / (A * A)
    if r2 <= 0.0:
        raise ValueError(f"D² + E² − AF = {D * D + E * E - A * F:g} ≤ 0: no real circle")
    return np.array([-D / A, -E / A]), float(np.sqrt(r2))


class Plane(NamedTuple):
    """A plane ``normal · X = d`` with a unit normal."""

    normal: np.ndarray  #: (3,) unit normal
    d: float            #: signed distance of the plane from the origin along ``normal``

    def distance(self, points) -> np.ndarray:
        """Signed distances ``normal·X − d`` of points (N, 3) or (3,)."""
        P, single = as_points(points, 3, "points")
        out = P @ self.normal - self.d
        return out[0] if single else out


def plane_through_points(p1, p2, p3) -> Plane:
    r"""Plane through three points: :math:`n = (P_2 - P_1) × (P_3 - P_1)/|…|`, ``d = n·P1``.

    The normal follows the right-hand order P1 → P2 → P3. Luhmann 2.136 writes the same plane as
    :math:`z = a_0 + a_1x + a_2y`; its printed matrix is the plane through (0, 0, z1), P2 and
    P3, so it holds exactly when :math:`a_1x_1 + a_2y_1 = 0`, e.g. with P1 at the origin (errata
    record ``luhmann:2.136``): then :math:`a_0 = z_1`, and in general
    :math:`a_1 = -n_x/n_z`, :math:`a_2 = -n_y/n_z`, :math:`a_0 = d/n_z`.

    Parameters
    ----------
    p1, p2, p3 : array_like, shape (3,)
        Three points P1, P2, P3, not collinear (object unit, e.g. m).

    Returns
    -------
    Plane
        ``normal`` (3,), unit normal (dimensionless) in the right-hand order P1 → P2 → P3, and
        ``d``, the signed distance of the plane from the origin along ``normal`` (object unit);
        the plane is ``normal · X = d``.

    Raises
    ------
    DegenerateGeometryError
        If the three points are collinear or coincide.

    Examples
    --------
    >>> pl_ = plane_through_points([0, 0, 1], [1, 0, 1], [0, 1, 1])
    >>> pl_.normal.tolist(), pl_.d
    ([0.0, 0.0, 1.0], 1.0)
    """
    P = np.array([as_vector3(p, name) for p, name in ((p1, "p1"), (p2, "p2"), (p3, "p3"))])
    n = np.cross(P[1] - P[0], P[2] - P[0])
    size = np.linalg.norm(n)
    scale = max(np.linalg.norm(P[1] - P[0]) * np.linalg.norm(P[2] - P[0]), 1e-300)
    if size <= 1e-12 * scale:
        raise DegenerateGeometryError("the three points are collinear (or coincide); they do "
                                      "not determine a plane")
    n = n / size
    return Plane(n, float(n @ P[0]))


class PlaneFit(NamedTuple):
    """Result of :func:`fit_plane`."""

    normal: np.ndarray     #: (3,) unit normal, n_z ≥ 0
    d: float               #: ``normal · X = d``
    centroid: np.ndarray   #: (3,) centroid of the points (on the plane)
    distances: np.ndarray  #: (N,) signed orthogonal distances
    sigma0: float          #: sqrt(Σdist²/(N − 3)); NaN for N = 3

    @property
    def plane(self) -> Plane:
        """The fitted plane as a :class:`Plane`."""
        return Plane(self.normal, self.d)


def fit_plane(points) -> PlaneFit:
    r"""Best-fit plane through N ≥ 3 points: minimal sum of squared orthogonal distances.

    The plane passes through the centroid :math:`\bar X`; its normal is the right singular
    vector of the smallest singular value of the centred points :math:`X_i - \bar X`
    (total least squares: all three coordinates are treated alike). Distances
    :math:`v_i = n·(X_i - \bar X)`; :math:`σ_0 = \sqrt{\sum v_i^2/(N - 3)}`. The sign is
    chosen with :math:`n_z > 0` (for a vertical plane the first non-zero component > 0).

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Points X_i, N ≥ 3, not collinear (object unit, e.g. m).

    Returns
    -------
    PlaneFit
        ``normal`` (3,) unit normal (dimensionless, :math:`n_z ≥ 0`), ``d`` (object unit,
        the plane is ``normal · X = d``), ``centroid`` (3,) (object unit), ``distances`` (N,)
        signed orthogonal distances :math:`v_i` (object unit) and ``sigma0`` (object unit;
        NaN for N = 3).

    Raises
    ------
    ValueError
        If fewer than 3 points are given.
    DegenerateGeometryError
        If the points are collinear or coincide.

    Examples
    --------
    >>> f = fit_plane([[0, 0, 2.1], [1, 0, 1.9], [0, 1, 1.9], [1, 1, 2.1]])
    >>> f.normal.round(12).tolist(), round(f.d, 12), f.distances.round(12).tolist()
    ([0.0, 0.0, 1.0], 2.0, [0.1, -0.1, -0.1, 0.1])
    """
    P, _ = as_points(points, 3, "points")
    if len(P) < 3:
        raise ValueError(f"fit_plane needs at least 3 points, got {len(P)}")
    c = P.mean(axis=0)
    _, sv, Vt = np.linalg.svd(P - c, full_matrices=False)
    if sv[0] == 0.0 or sv[1] <= 1e-12 * sv[0]:
        raise DegenerateGeometryError("the points are collinear (or coincide); they do not "
                                      "determine a plane")
    n = Vt[-1]
    nz = n[np.flatnonzero(np.abs(n) > 1e-12)]
    if (n[2] < 0) if abs(n[2]) > 1e-12 else (nz[0] < 0):
        n = -n
    dist = (P - c) @ n
    k = len(P)
    sigma0 = float(np.sqrt(np.sum(dist**2) / (k - 3))) if k > 3 else float("nan")
    return PlaneFit(n, float(n @ c), c, dist, sigma0)
