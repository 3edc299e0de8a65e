r"""Orientation of a stereo pair: dependent relative orientation and absolute orientation.

* :func:`relative_orientation` (Folgebildanschluss): image 1 fixed (X01 = 0, R1 = I), image 2
  at ``b = (bx, by, bz)`` with ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``; bx is fixed and sets the
  model scale. Gauss–Newton on the coplanarity condition scaled to a y-parallax,
  ``v = det[b, x*1, R2·x*2]/(bx·c)``, for the five unknowns (by, bz, ω2, φ2, κ2); the model
  points are the forward intersection of the oriented rays.
* :func:`independent_relative_orientation` (unabhängige Bildpaare): the base fixed along the
  model x axis, ``b = (bx, 0, 0)``; both images rotate, ``R1 = R_φ(φ1)·R_κ(κ1)`` (ω1 = 0: a
  rotation about the base changes nothing) and ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``; the unknowns
  (φ1, κ1, ω2, φ2, κ2), the same coplanarity condition ``det[b, R1·x*1, R2·x*2]/(bx·c)``. Both
  forms give the same model up to a similarity (a rotation about image 1 and the scale).
* :func:`absolute_orientation`: 3-D similarity (Helmert, 7 parameters) ``X = X0 + m·R·x``
  from model to object coordinates, in closed form (Horn 1987, Umeyama 1991).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._docs import shared_doc
from photolib._validate import (
    as_float_array,
    as_max_iter,
    as_point_pairs,
    as_points,
    as_scalar,
    as_tolerance,
)
from photolib.collinearity import PointBehindCameraError
from photolib.collinearity import project  # noqa: F401 - used by the examples (doctests)
from photolib.rotations import opk_from_rotation, rotation_opk
from photolib.stereo._intersection import forward_intersection
from photolib.stereo._rays import _image_vectors
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError


# -- relative orientation --------------------------------------------------------------------------

@dataclass(frozen=True)
class RelativeOrientation:
    """Dependent relative orientation from :func:`relative_orientation`."""

    base: np.ndarray  #: (3,) (bx, by, bz), model unit
    R2: np.ndarray  #: (3, 3) rotation of image 2 (image 1: R = I)
    omega: float  #: ω2, radians
    phi: float  #: φ2, radians
    kappa: float  #: κ2, radians
    model: np.ndarray  #: (N, 3) model coordinates (forward intersection, NaN if invalid)
    residuals: np.ndarray  #: (N,) coplanarity residual as y-parallax, image unit
    sigma0: float  #: image unit (NaN for 5 points)
    covariance: np.ndarray  #: (5, 5) of (by, bz, ω2, φ2, κ2)
    iterations: int
    converged: bool
    redundancy: int  #: N − 5

    @property
    def params(self) -> np.ndarray:
        """``(by, bz, ω2, φ2, κ2)``."""
        return np.r_[self.base[1:], self.omega, self.phi, self.kappa]


def _rotation_derivatives(w, p, k):
    cw, sw, cp, sp_, ck, sk = np.cos(w), np.sin(w), np.cos(p), np.sin(p), np.cos(k), np.sin(k)
    Rw = np.array([[1, 0, 0], [0, cw, -sw], [0, sw, cw]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    dRw = np.array([[0, 0, 0], [0, -sw, -cw], [0, cw, -sw]])
    dRp = np.array([[-sp_, 0, cp], [0, 0, 0], [-cp, 0, -sp_]])
    dRk = np.array([[-sk, -ck, 0], [ck, -sk, 0], [0, 0, 0]])
    return Rw @ Rp @ Rk, (dRw @ Rp @ Rk, Rw @ dRp @ Rk, Rw @ Rp @ dRk)

#: parameters shared by both relative orientations (see :func:`photolib._docs.shared_doc`)
_PAIR_POINTS = """xy1, xy2 : array_like, shape (N, 2)
    Corresponding image points (image unit), N ≥ 5.
c : float
    Camera constant > 0 of both images (image unit)."""
_PRINCIPAL_POINT = """x0, y0 : float
    Principal point of both images."""


def coplanarity_residuals(q, r1, x2, bx, c):
    """Coplanarity residuals ``det[b, r1, R2·x*2]/(bx·c)`` and their Jacobian (N, 5).

    ``q = (by, bz, ω2, φ2, κ2)``; ``r1`` (N, 3) rays of image 1 (R1 = I), ``x2`` (N, 3)
    image vectors of image 2. In the normal case the residual is the y-parallax y'2 − y'1.
    """
    b = np.array([bx, q[0], q[1]])
    R2, dR = _rotation_derivatives(*q[2:])
    r2 = x2 @ R2.T
    cross = np.cross(r1, r2)
    f = cross @ b / (bx * c)
    J = np.empty((len(r1), 5))
    J[:, 0] = cross[:, 1] / (bx * c)
    J[:, 1] = cross[:, 2] / (bx * c)
    for j, D in enumerate(dR):
        J[:, 2 + j] = np.cross(r1, x2 @ D.T) @ b / (bx * c)
    return f, J


@shared_doc(pair_points=_PAIR_POINTS, principal_point=_PRINCIPAL_POINT)
def relative_orientation(xy1, xy2, c, bx: float = 1.0, x0=0.0, y0=0.0, initial=None, *,
                         tol: float = 1e-12, max_iter: int = 30,
                         check: bool = True) -> RelativeOrientation:
    r"""Dependent relative orientation (Folgebildanschluss) of a stereo pair by least squares.

    Image 1 is fixed (X01 = 0, R1 = I); image 2 is at ``b = (bx, by, bz)`` with
    ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``; bx is fixed and sets the model scale. Five unknowns
    (by, bz, ω2, φ2, κ2), one coplanarity equation per point: at least 5 points.

    Parameters
    ----------
    {pair_points}
    bx : float
        Fixed base component (model unit), ≠ 0; its sign says on which side image 2 is.
    {principal_point}
    initial : array_like, shape (5,), optional
        Start (by, bz, ω2, φ2, κ2); default zeros (near the normal case).
    tol, max_iter, check
        Stop when the largest update is below ``tol`` (model units / radians). Not reaching
        it raises ``ConvergenceError`` unless ``check=False``.

    Returns
    -------
    RelativeOrientation

    Raises
    ------
    DegenerateGeometryError
        Zero parallax (identical images) or points that do not determine the five unknowns.
    PointBehindCameraError
        If the converged orientation puts every model point behind the cameras: the images
        are swapped, or bx has the wrong sign.
    ConvergenceError
        No convergence within ``max_iter`` (unless ``check=False``).

    Notes
    -----
    Gauss–Newton on the coplanarity condition, scaled to a y-parallax (image unit):

    .. math:: v_i = \frac{\det[\,b,\; x^*_{1i},\; R_2 x^*_{2i}\,]}{b_x\,c},\qquad
              σ_0 = \sqrt{\frac{v^Tv}{N-5}}

    The model coordinates are the forward intersection of the oriented rays.

    Examples
    --------
    >>> X = np.array([[0, 0, -10], [2, 1, -11], [-1, 2, -9], [1, -2, -10.5], [3, 3, -12],
    ...               [-2, -1, -10.0]])
    >>> R2 = rotation_opk(0.01, -0.02, 0.03)
    >>> xy1 = project(X, [0, 0, 0], np.eye(3), 50.0)
    >>> xy2 = project(X, [1.0, 0.1, -0.05], R2, 50.0)
    >>> ro = relative_orientation(xy1, xy2, 50.0, bx=1.0)
    >>> np.round(ro.params, 9).tolist(), ro.converged
    ([0.1, -0.05, 0.01, -0.02, 0.03], True)
    """
    q, _, R2, base, f, model, sigma0, cov, red, it, converged = _orient_pair(
        False, xy1, xy2, c, bx, x0, y0, initial, tol, max_iter, check)
    return RelativeOrientation(base=base, R2=R2, omega=float(q[2]), phi=float(q[3]),
                               kappa=float(q[4]), model=model, residuals=f,
                               sigma0=sigma0, covariance=cov, iterations=it,
                               converged=converged, redundancy=red)


def _pair_inputs(xy1, xy2, c, bx, x0, y0, initial, tol, max_iter, name, unknowns):
    """Checked arguments of a relative orientation and the image vectors of both images."""
    a, b2 = as_point_pairs(xy1, xy2, (2, 2), ("xy1", "xy2"), 5, name,
                           f"point pairs (5 unknowns: {unknowns})")
    c = as_scalar(c, "c", positive=True)
    bx = as_scalar(bx, "bx")
    if bx == 0:
        raise ValueError("bx must be ≠ 0: it fixes the scale of the model")
    x0, y0 = as_scalar(x0, "x0"), as_scalar(y0, "y0")
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    q = np.zeros(5) if initial is None else as_float_array(initial, "initial")
    if q.shape != (5,) or not np.all(np.isfinite(q)):
        raise ValueError(f"initial must be 5 finite values ({unknowns}), got {q.tolist()}")
    return (a, b2, c, bx, x0, y0, tol, max_iter, q, _image_vectors(a, c, x0, y0),
            _image_vectors(b2, c, x0, y0))


def _orient_pair(independent, xy1, xy2, c, bx, x0, y0, initial, tol, max_iter, check):
    """Both relative orientations: checked inputs, Gauss–Newton, model points and precision.

    ``independent=False``: dependent orientation, unknowns ``(by, bz, ω2, φ2, κ2)``, image 1
    fixed (``R1 = I``), base ``(bx, by, bz)``; the base components converge to ``tol·|bx|``.
    ``independent=True``: unknowns ``(φ1, κ1, ω2, φ2, κ2)``, ``R1 = R_φ(φ1)·R_κ(κ1)``, base
    ``(bx, 0, 0)``. Returns ``(q, R1, R2, base, f, model, sigma0, cov, redundancy,
    iterations, converged)`` with ``f`` the coplanarity residuals (image unit) at ``q``.
    """
    name = "independent relative orientation" if independent else "relative orientation"
    unknowns = "φ1, κ1, ω2, φ2, κ2" if independent else "by, bz, ω2, φ2, κ2"
    a, b2, c, bx, x0, y0, tol, max_iter, q, x1, x2 = _pair_inputs(
        xy1, xy2, c, bx, x0, y0, initial, tol, max_iter, name, unknowns)
    if independent:
        def residuals(q):
            return independent_coplanarity_residuals(q, x1, x2, c)

        def rays(q):
            return x1 @ rotation_opk(0.0, *q[:2]).T, x2 @ rotation_opk(*q[2:]).T
    else:
        def residuals(q):
            return coplanarity_residuals(q, x1, x2, bx, c)

        def rays(q):
            return x1, x2 @ rotation_opk(*q[2:]).T
    q, it, converged = _coplanarity_gauss_newton(
        residuals, rays, q, tol, max_iter, check, shifts=0 if independent else 2,
        scale=1.0 if independent else abs(bx), what=f"({unknowns})", name=name)
    f, J = residuals(q)
    R1 = rotation_opk(0.0, q[0], q[1]) if independent else np.eye(3)
    R2 = rotation_opk(*q[2:])
    base = np.array([bx, 0.0, 0.0]) if independent else np.array([bx, q[0], q[1]])
    model, sigma0, cov, red = _oriented_model(a, b2, f, J, R1, base, R2, c, x0, y0,
                                              converged, bx)
    return q, R1, R2, base, f, model, sigma0, cov, red, it, converged


def _coplanarity_gauss_newton(residuals, rays, q, tol, max_iter, check, *, shifts, scale,
                              what, name):
    """Gauss–Newton on coplanarity residuals: ``q`` updated until the largest step is below tol.

    ``residuals(q) -> (f, J)``; ``rays(q) -> (r1, r2)`` the rotated rays (for the diagnosis of
    a singular design); the first ``shifts`` unknowns are base components (tolerance scaled by
    ``scale``), the rest angles. Returns ``(q, iterations, converged)``.
    """
    converged, it, dq = False, 0, np.zeros_like(q)
    for it in range(1, max_iter + 1):
        f, J = residuals(q)
        sv = np.linalg.svd(J, compute_uv=False)
        if sv[-1] <= 1e-10 * sv[0] or not sv[0] > 0:
            r1, r2 = rays(q)
            sin = np.linalg.norm(np.cross(r1, r2), axis=1) / (
                np.linalg.norm(r1, axis=1) * np.linalg.norm(r2, axis=1))
            if np.max(sin) <= 1e-9:
                raise DegenerateGeometryError(
                    "zero parallax: every pair of rays is parallel (largest angle "
                    f"{np.max(sin):.3g} rad), so xy1 and xy2 are the same image up to a rotation "
                    "and there is no base to orient (identical images, or the two exposures "
                    f"from one point); the {name} needs x-parallaxes")
            raise DegenerateGeometryError(
                f"the coplanarity equations do not determine {what}: the points are badly "
                f"distributed or lie on a critical surface (condition "
                f"{sv[0] / max(sv[-1], 1e-300):.3g}); use ≥ 5 points spread over the overlap, "
                "not on one line, and not on a circular cylinder with its axis parallel to the "
                "base through both projection centres (the critical surface)")
        dq = np.linalg.lstsq(J, -f, rcond=None)[0]
        if not np.all(np.isfinite(dq)):
            raise ConvergenceError(f"{name} diverged in iteration {it}")
        q = q + dq
        if (np.max(np.abs(dq[:shifts]), initial=0.0) <= tol * scale
                and np.max(np.abs(dq[shifts:])) <= tol):
            converged = True
            break
    if not converged and check:
        raise ConvergenceError(f"{name} did not converge in {max_iter} "
                               f"iterations (last update {np.max(np.abs(dq)):.3g})")
    return q, it, converged


def _oriented_model(a, b2, f, J, R1, base, R2, c, x0, y0, converged, bx):
    """σ0, covariance and the model points (forward intersection) of an oriented pair.

    Raises ``PointBehindCameraError`` for the mirror solution: a converged orientation with
    every intersecting pair of rays behind the cameras (λ ≤ 0; not the parallel ones). The
    last iterate of ``check=False`` is kept.
    """
    red = len(a) - J.shape[1]
    sigma0 = float(np.sqrt(f @ f / red)) if red > 0 else float("nan")
    cov = (sigma0**2 * np.linalg.inv(J.T @ J)) if red > 0 else np.full((J.shape[1],) * 2, np.nan)
    inter = forward_intersection(np.stack([a, b2]), np.stack([np.zeros(3), base]),
                                 np.stack([R1, R2]), c, x0, y0, return_valid=True)
    behind = ~inter.valid & (inter.angle >= 1e-6)
    if converged and behind.any() and not inter.valid.any():
        raise PointBehindCameraError(
            f"the relative orientation fits the coplanarity condition (σ0 = {sigma0:.3g}), but "
            f"all {int(behind.sum())} model points with intersecting rays lie behind the cameras: "
            f"image 2 is on the other side of image 1 than bx = {bx:g} says. Flip the sign of "
            "bx, or swap the images (xy1 must be the left image for bx > 0)")
    return inter.points, sigma0, cov, red


# -- independent relative orientation --------------------------------------------------------------

@dataclass(frozen=True)
class IndependentRelativeOrientation:
    """Independent relative orientation from :func:`independent_relative_orientation`."""

    base: np.ndarray  #: (3,) (bx, 0, 0), model unit
    R1: np.ndarray  #: (3, 3) rotation of image 1, R_φ(φ1)·R_κ(κ1)
    R2: np.ndarray  #: (3, 3) rotation of image 2, R_ω(ω2)·R_φ(φ2)·R_κ(κ2)
    phi1: float  #: φ1, radians
    kappa1: float  #: κ1, radians
    omega2: float  #: ω2, radians
    phi2: float  #: φ2, radians
    kappa2: float  #: κ2, radians
    model: np.ndarray  #: (N, 3) model coordinates (forward intersection, NaN if invalid)
    residuals: np.ndarray  #: (N,) coplanarity residual as y-parallax, image unit
    sigma0: float  #: image unit (NaN for 5 points)
    covariance: np.ndarray  #: (5, 5) of (φ1, κ1, ω2, φ2, κ2)
    iterations: int
    converged: bool
    redundancy: int  #: N − 5

    @property
    def params(self) -> np.ndarray:
        """``(φ1, κ1, ω2, φ2, κ2)``."""
        return np.array([self.phi1, self.kappa1, self.omega2, self.phi2, self.kappa2])


def independent_coplanarity_residuals(q, x1, x2, c):
    """Residuals ``det[b, R1·x*1, R2·x*2]/(bx·c)`` with b = (bx, 0, 0), and the Jacobian (N, 5).

    ``q = (φ1, κ1, ω2, φ2, κ2)``; ``x1``, ``x2`` (N, 3) image vectors. With b along x the
    determinant over bx is the x component of ``R1·x*1 × R2·x*2``, so bx drops out.
    """
    R1, dR1 = _rotation_derivatives(0.0, q[0], q[1])
    R2, dR2 = _rotation_derivatives(*q[2:])
    r1, r2 = x1 @ R1.T, x2 @ R2.T
    f = np.cross(r1, r2)[:, 0] / c
    J = np.empty((len(x1), 5))
    J[:, 0] = np.cross(x1 @ dR1[1].T, r2)[:, 0] / c
    J[:, 1] = np.cross(x1 @ dR1[2].T, r2)[:, 0] / c
    for j, D in enumerate(dR2):
        J[:, 2 + j] = np.cross(r1, x2 @ D.T)[:, 0] / c
    return f, J


@shared_doc(pair_points=_PAIR_POINTS, principal_point=_PRINCIPAL_POINT)
def independent_relative_orientation(xy1, xy2, c, bx: float = 1.0, x0=0.0, y0=0.0,
                                     initial=None, *, tol: float = 1e-12, max_iter: int = 30,
                                     check: bool = True) -> IndependentRelativeOrientation:
    r"""Independent relative orientation (unabhängige Bildpaare) of a stereo pair.

    The base is fixed along the model x axis, ``b = (bx, 0, 0)``, image 1 at the origin; both
    images rotate: ``R1 = R_φ(φ1)·R_κ(κ1)`` (ω1 = 0, a rotation about the base changes no ray
    plane) and ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``. Five unknowns (φ1, κ1, ω2, φ2, κ2), one
    coplanarity equation per point: at least 5 points.

    Parameters
    ----------
    {pair_points}
    bx : float
        Base length (model unit), ≠ 0; it sets the model scale and its sign the side of image 2.
    {principal_point}
    initial : array_like, shape (5,), optional
        Start (φ1, κ1, ω2, φ2, κ2); default zeros (near the normal case).
    tol, max_iter, check
        Stop when the largest update is below ``tol`` (radians). Not reaching it raises
        ``ConvergenceError`` unless ``check=False``.

    Returns
    -------
    IndependentRelativeOrientation

    Raises
    ------
    DegenerateGeometryError
        Zero parallax, or points that do not determine the five angles (on one line, or on the
        critical cylinder: axis parallel to the base, through both projection centres).
    PointBehindCameraError
        The mirror solution: every model point behind the cameras (swap the images or flip bx).
    ConvergenceError
        No convergence within ``max_iter`` (unless ``check=False``).

    Notes
    -----
    Gauss–Newton on the coplanarity condition (derived in
    :func:`photolib.derive.stereo.independent_coplanarity`), scaled to a y-parallax:

    .. math:: v_i = rac{\det[\,b,\; R_1 x^*_{1i},\; R_2 x^*_{2i}\,]}{b_x\,c}
              = rac{(R_1 x^*_{1i} 	imes R_2 x^*_{2i})_x}{c}

    The dependent form (:func:`relative_orientation`) sees the same pair: its model is this one
    rotated by R1ᵀ about image 1 and scaled by its base length over bx.

    Examples
    --------
    >>> X = np.array([[0, 0, -10], [2, 1, -11], [-1, 2, -9], [1, -2, -10.5], [3, 3, -12],
    ...               [-2, -1, -10.0]])
    >>> R1, R2 = rotation_opk(0.0, 0.02, -0.01), rotation_opk(0.01, -0.02, 0.03)
    >>> xy1 = project(X, [0, 0, 0], R1, 50.0)
    >>> xy2 = project(X, [1.0, 0.0, 0.0], R2, 50.0)
    >>> ro = independent_relative_orientation(xy1, xy2, 50.0, bx=1.0)
    >>> np.round(ro.params, 9).tolist(), ro.converged
    ([0.02, -0.01, 0.01, -0.02, 0.03], True)
    """
    q, R1, R2, base, f, model, sigma0, cov, red, it, converged = _orient_pair(
        True, xy1, xy2, c, bx, x0, y0, initial, tol, max_iter, check)
    return IndependentRelativeOrientation(
        base=base, R1=R1, R2=R2, phi1=float(q[0]), kappa1=float(q[1]), omega2=float(q[2]),
        phi2=float(q[3]), kappa2=float(q[4]), model=model, residuals=f, sigma0=sigma0,
        covariance=cov, iterations=it, converged=converged, redundancy=red)


# -- absolute orientation --------------------------------------------------------------------------

@dataclass(frozen=True)
class AbsoluteOrientation:
    """3-D similarity ``X = X0 + m·R·x`` from :func:`absolute_orientation`."""

    m: float  #: scale (object unit per model unit)
    R: np.ndarray  #: (3, 3) rotation model → object, R_ω·R_φ·R_κ
    X0: np.ndarray  #: (3,) translation (object unit)
    residuals: np.ndarray  #: (N, 3) X_control − X(model), object unit
    sigma0: float  #: sqrt(vᵀv/(3N − 7)), NaN without redundancy
    redundancy: int  #: 3N − 7

    @property
    def angles(self) -> tuple[float, float, float]:
        """``(ω, φ, κ)`` of R, radians."""
        return opk_from_rotation(self.R)

    def __call__(self, x) -> np.ndarray:
        """Object coordinates of model points (N, 3) or (3,)."""
        pts, single = as_points(x, 3, "x")
        out = self.X0 + self.m * pts @ self.R.T
        return out[0] if single else out


def absolute_orientation(model, control) -> AbsoluteOrientation:
    r"""Absolute orientation: 7-parameter 3-D similarity (Helmert) from model to object.

    Parameters
    ----------
    model : array_like, shape (N, 3)
        Model coordinates of control points (model unit), N ≥ 3, not collinear.
    control : array_like, shape (N, 3)
        Their object coordinates (object unit).

    Returns
    -------
    AbsoluteOrientation

    Notes
    -----
    Least squares of :math:`\sum_i |X_i - (X_0 + m\,R\,x_i)|^2` in closed form (Horn 1987,
    Umeyama 1991): with centred points :math:`\bar x_i, \bar X_i` and the SVD
    :math:`\sum_i \bar X_i \bar x_i^T = U S V^T`,

    .. math:: R = U\,\mathrm{diag}(1, 1, \det UV^T)\,V^T,\quad
              m = \frac{\mathrm{tr}(S\,\mathrm{diag}(1,1,\det UV^T))}{\sum_i|\bar x_i|^2},\quad
              X_0 = \bar X - m R \bar x

    Seven unknowns (3 translations, 3 angles, 1 scale): two full control points and one
    height, or ≥ 3 non-collinear full points.

    Examples
    --------
    >>> x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> T = absolute_orientation(x, 10 + 2 * x @ rotation_opk(0.1, 0.2, 0.3).T)
    >>> round(T.m, 12), np.round(T.angles, 12).tolist(), np.round(T.X0, 9).tolist()
    (2.0, [0.1, 0.2, 0.3], [10.0, 10.0, 10.0])
    """
    x, X = as_point_pairs(model, control, (3, 3), ("model", "control"), 3,
                          "absolute orientation", "control points (7 unknowns)")
    xm, Xm = x.mean(axis=0), X.mean(axis=0)
    xc, Xc = x - xm, X - Xm
    for pts, name in ((xc, "model"), (Xc, "control")):
        sv = np.linalg.svd(pts, compute_uv=False)
        if sv[0] == 0 or sv[1] <= 1e-9 * sv[0]:
            raise DegenerateGeometryError(
                f"the {name} points are collinear (singular values {np.round(sv, 12).tolist()}): "
                "the rotation about their line is not determined; add a point off the line")
    U, S, Vt = np.linalg.svd(Xc.T @ xc)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    R = U @ D @ Vt
    m = float(np.trace(np.diag(S) @ D) / np.sum(xc**2))
    X0 = Xm - m * R @ xm
    v = X - (X0 + m * x @ R.T)
    red = 3 * len(x) - 7
    sigma0 = float(np.sqrt(np.sum(v**2) / red)) if red > 0 else float("nan")
    return AbsoluteOrientation(m=m, R=R, X0=X0, residuals=v, sigma0=sigma0, redundancy=red)
