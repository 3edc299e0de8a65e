"""Camera calibration / Kamerakalibrierung: the plumb-line method (Lotlinien, Plumblines).

Lines that are straight in object space are imaged as straight lines by a distortion-free
central projection. Their curvature in a real image measures the lens distortion (the
lecture summary's "Plumblines": "Anhand der Wölbungen der Linien in der Aufnahme sind
Ausgleichungen möglich"). :func:`plumb_line` estimates the distortion parameters of the
course model (:class:`photolib.distortion.Distortion`) so that the corrected points of every
line are collinear.

Model (condition of the derivation in :mod:`photolib.derive.plumb_line`): each line ``i`` is
``n(θᵢ)·x = dᵢ`` with the unit normal ``n(θ) = (cos θ, sin θ)`` and the signed distance ``dᵢ``
from the principal point; every measured point ``x`` of line ``i``, reduced to the principal
point, satisfies after correction

.. math:: f = n(θ_i)\\cdot\\bigl(x - Δ(x; p)\\bigr) - d_i = 0 .

What the method cannot determine (the straightness of lines is invariant under every
projective map of the image plane, so every parameter whose effect is projective is lost):

* the camera constant c (a change of scale keeps lines straight);
* the linear radial term ``K0 = −(A1 r0² + A2 r0⁴ + A3 r0⁶)``: the balancing radius r0 is a
  datum chosen by the user, not a result — a fit with another r0 is the same fit scaled by
  ``1 − K0`` (and belongs to the camera constant ``c·(1 − K0)`` to first order);
* affinity and shear C1, C2 (affine maps keep lines straight);
* the principal point only weakly: it is held fixed here, and an error in it is partly
  absorbed by the tangential terms B1, B2 (part of whose effect is itself projective):
  exactly, to first order, for the A1 term (a shift (x'0, y'0) turns it into the tangential
  pattern B1 = −A1·x'0, B2 = −A1·y'0), not for A2 and A3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_float_array, as_max_iter, as_points, as_scalar, as_tolerance
from photolib.distortion import Distortion
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError

__all__ = ["PlumbLineResult", "plumb_line"]

#: parameters a plumb-line calibration can estimate, and their column in
#: :meth:`Distortion.jacobian_params`
_COLUMN = {"A1": 0, "A2": 1, "A3": 2, "B1": 3, "B2": 4}
#: a parameter's displacement grows with this power of the radius (for step sizes in mm)
_POWER = {"A1": 3, "A2": 5, "A3": 7, "B1": 2, "B2": 2}
#: lines closer than this fraction of the largest radius to the principal point count as
#: passing through it
_THROUGH_CENTRE = 0.01


@dataclass(frozen=True)
class PlumbLineResult:
    """Result of :func:`plumb_line`.

    Attributes
    ----------
    distortion : Distortion
        The estimated distortion (r0 as given; the other parameters 0).
    terms : tuple of str
        The estimated parameters, in the order of ``covariance``.
    sigma : dict
        Standard deviation of each estimated parameter (unit of the parameter), scaled by σ0.
    covariance : ndarray, shape (p, p)
        Covariance of the estimated parameters, scaled by σ0².
    sigma0 : float
        A-posteriori σ0 = √(vᵀv/r) of a measured image coordinate, mm.
    lines : ndarray, shape (L, 2)
        Adjusted lines ``(θ [rad], d [mm])``: ``cos θ·x + sin θ·y = d`` for corrected points
        reduced to the principal point.
    residuals_um : tuple of ndarray
        Per line, the residual v of each point (its distance from the distorted line), µm.
    iterations : int
        Gauss–Newton iterations used.
    converged : bool
        The last step moved no point by more than ``tol``.
    redundancy : int
        r = points − 2·lines − parameters.
    c : float
        The camera constant given (not estimated), mm.
    principal_point : ndarray, shape (2,)
        The principal point given (not estimated), mm.
    """

    distortion: Distortion
    terms: tuple
    sigma: dict
    covariance: np.ndarray
    sigma0: float
    lines: np.ndarray
    residuals_um: tuple
    iterations: int
    converged: bool
    redundancy: int
    c: float
    principal_point: np.ndarray

    @property
    def rms_um(self) -> np.ndarray:
        """RMS residual per line, µm, shape (L,)."""
        return np.array([float(np.sqrt(np.mean(v**2))) for v in self.residuals_um])

    @property
    def correlation(self) -> np.ndarray:
        """Correlation matrix of the estimated parameters, shape (p, p)."""
        s = np.sqrt(np.diag(self.covariance))
        return self.covariance / np.outer(s, s)

    def radial_sigma(self, r) -> np.ndarray:
        """Standard deviation of the radial distortion ``Δr′(r)`` at radii ``r`` (mm), mm.

        ``σ² = gᵀ C g`` with ``g = ∂Δr′/∂(A1, A2, A3) = r(r^{2k} − r0^{2k})`` over the
        estimated radial terms and C their part of ``covariance`` (tangential terms do not
        enter Δr′).
        """
        r = np.asarray(r, dtype=float)
        r0 = self.distortion.params["r0"]
        idx = [i for i, t in enumerate(self.terms) if t.startswith("A")]
        g = np.stack([r * (r ** (2 * int(self.terms[i][1])) - r0 ** (2 * int(self.terms[i][1])))
                      for i in idx], axis=-1)
        C = self.covariance[np.ix_(idx, idx)]
        return np.sqrt(np.einsum("...i,ij,...j->...", g, C, g))

    def image_vector(self, xy) -> np.ndarray:
        """Image vectors ``x* = (x' − x'0 − Δx', y' − y'0 − Δy', −c)`` of measured points, mm.

        ``xy`` has shape (N, 2) or (2,); the result (N, 3) or (3,).
        """
        pts, single = as_points(xy, 2, "xy")
        ideal = self.distortion.correct(pts - self.principal_point)
        out = np.column_stack([ideal, np.full(len(pts), -self.c)])
        return out[0] if single else out


def _check_terms(terms) -> tuple:
    if isinstance(terms, str):
        terms = (terms,)
    terms = tuple(terms)
    if not terms:
        raise ValueError("terms must name at least one parameter of A1, A2, A3, B1, B2")
    for t in terms:
        if t in ("C1", "C2"):
            raise ValueError(f"terms: {t} (affinity/shear) keeps straight lines straight; a "
                             "plumb-line calibration cannot determine it")
        if t in ("c", "x0", "y0", "r0"):
            raise ValueError(f"terms: {t!r} cannot be estimated from plumb lines (straight lines "
                             "stay straight under a change of scale or of the principal point; "
                             "r0 is a datum to choose)")
        if t not in _COLUMN:
            raise ValueError(f"terms: unknown parameter {t!r}; choose from {tuple(_COLUMN)}")
    if len(set(terms)) != len(terms):
        raise ValueError(f"terms must not repeat a parameter, got {terms!r}")
    return tuple(sorted(terms, key=_COLUMN.get))


def _check_lines(lines, pp) -> list:
    if isinstance(lines, np.ndarray) and lines.ndim == 3:
        lines = list(lines)
    try:
        lines = list(lines)
    except TypeError:
        raise ValueError("lines must be a sequence of (n_i, 2) point arrays, got "
                         f"{type(lines).__name__}") from None
    if len(lines) < 2:
        raise ValueError(f"plumb-line calibration needs at least 2 lines, got {len(lines)}: one "
                         "line shows the curvature at one distance from the principal point "
                         "only, and nothing tests that its object line was straight")
    out = []
    for i, line in enumerate(lines):
        pts, single = as_points(line, 2, f"lines[{i}]")
        if single or len(pts) < 3:
            raise ValueError(f"lines[{i}] has {1 if single else len(pts)} point(s); a line needs "
                             "at least 3 points (two points are always collinear)")
        centred = pts - pts.mean(axis=0)
        sv = np.linalg.svd(centred, compute_uv=False)
        if sv[0] <= 1e-12 * max(1.0, float(np.abs(pts).max())):
            raise DegenerateGeometryError(f"lines[{i}]: all its points coincide; its direction "
                                          "is not determined")
        out.append(pts - pp)
    return out


def _initial_line(pts) -> tuple[float, float]:
    """Total-least-squares line ``(θ, d)`` through points (N, 2): normal = least singular vector."""
    m = pts.mean(axis=0)
    _, _, vt = np.linalg.svd(pts - m)
    n = vt[-1]
    d = float(n @ m)
    if d < 0:
        n, d = -n, -d
    return float(np.arctan2(n[1], n[0])), d


def _design(xy, k, theta, dist, dist_model, terms):
    """Residuals and their Jacobian at the current unknowns.

    Returns ``(v, A)``: v (N,) the residuals ``w·f`` (mm) with the conditions
    ``f = n·(x − Δ) − d`` and ``w = 1/‖g‖``, ``g = nᵀ(I − ∂Δ/∂x)`` (so that v is referred to
    a measured coordinate); A (N, p + 2L) the Jacobian of v with respect to (parameters,
    θ₁, d₁, θ₂, d₂, …): ``∂v = w·∂f + f·∂w`` with ``∂w = −w³ g·∂g``, where
    ``∂g/∂p = −nᵀ ∂²Δ/∂x∂p`` (Δ is linear in p: the ∂Δ/∂x of the unit parameter) and
    ``∂g/∂θ = tᵀ(I − ∂Δ/∂x)``, ``t = ∂n/∂θ``.
    """
    n = np.column_stack([np.cos(theta[k]), np.sin(theta[k])])
    t = np.column_stack([-np.sin(theta[k]), np.cos(theta[k])])  # ∂n/∂θ
    corrected = xy - dist_model.delta(xy)
    f = np.sum(n * corrected, axis=1) - dist[k]
    J = dist_model.jacobian_xy(xy)
    g = n - np.einsum("ni,nij->nj", n, J)
    w = 1.0 / np.hypot(g[:, 0], g[:, 1])
    jp = dist_model.jacobian_params(xy)[:, :, [_COLUMN[name] for name in terms]]
    p, L, N = len(terms), len(theta), len(xy)
    r0 = dist_model.params["r0"]
    A = np.zeros((N, p + 2 * L))
    for j, name in enumerate(terms):
        unit = Distortion(r0=r0, **{name: 1.0})
        dg = -np.einsum("ni,nij->nj", n, unit.jacobian_xy(xy))
        dw = -w**3 * np.sum(g * dg, axis=1)
        A[:, j] = -w * np.einsum("ni,ni->n", n, jp[:, :, j]) + f * dw
    rows = np.arange(N)
    dg = t - np.einsum("ni,nij->nj", t, J)
    A[rows, p + 2 * k] = w * np.sum(t * corrected, axis=1) - f * w**3 * np.sum(g * dg, axis=1)
    A[rows, p + 2 * k + 1] = -w
    return w * f, A


def _undetermined(A_scaled, terms) -> str:
    """Names of the parameters in the null space of the scaled design matrix."""
    _, s, vt = np.linalg.svd(A_scaled, full_matrices=False)
    v = np.abs(vt[-1, :len(terms)])
    names = [t for t, x in zip(terms, v) if x > 0.1]
    return ", ".join(names) if names else "the line parameters"


def plumb_line(lines, *, c, r0=None, terms=("A1", "A2"), principal_point=(0.0, 0.0),
               tol: float = 1e-10, max_iter: int = 30, check: bool = True) -> PlumbLineResult:
    r"""Plumb-line calibration / Kalibrierung mit Lotlinien (Plumblines).

    Estimates distortion parameters so that the corrected points of every line are
    collinear. Unknowns: the parameters ``p`` named in ``terms`` and one line ``(θᵢ, dᵢ)``
    per line. Condition per measured point ``x`` of line ``i`` (reduced to the principal
    point):

    .. math:: f = \cos θ_i\,(x - Δx'(x; p)) + \sin θ_i\,(y - Δy'(x; p)) - d_i = 0

    with the Jacobian (:mod:`photolib.derive.plumb_line`)
    ``∂f/∂p = −n·∂Δ/∂p``, ``∂f/∂θᵢ = (−sin θᵢ, cos θᵢ)·(x − Δ)``, ``∂f/∂dᵢ = −1``.
    A measured coordinate error moves f by ``g = nᵀ(I − ∂Δ/∂x)`` times the error, so the
    residual is ``v = f/‖g‖``: the distance of the measured point from the distorted line,
    to first order (the Gauss–Helmert weights; ‖g‖ differs from 1 by about |∂Δ/∂x|).
    Gauss–Newton minimises ``vᵀv`` with the exact Jacobian of v, from ``p = 0`` and
    total-least-squares lines through the measured points. Weighting by ‖g‖ also makes the
    fit independent of the datum r0 (without it a smaller image scale would shrink vᵀv).

    Not determined by plumb lines (see the module text): c, the linear radial term (r0 is a
    datum), C1, C2, and — only weakly — the principal point, which is held fixed.

    Parameters
    ----------
    lines : sequence of array_like, each shape (n_i, 2)
        Measured image coordinates (mm, image frame: x' right, y' up) of the points of each
        line that is straight in object space; n_i ≥ 3, at least 2 lines.
    c : float
        Camera constant, mm, > 0. Not estimated; it scales the unknowns to dimensionless
        values for the solver and is kept for :meth:`PlumbLineResult.image_vector`.
    r0 : float or None
        Balancing radius of the radial model, mm (None: 0, Seidel's form).
    terms : sequence of str
        Parameters to estimate, from ``A1, A2, A3, B1, B2``.
    principal_point : array_like, shape (2,)
        ``(x'0, y'0)``, mm, held fixed.
    tol : float
        Convergence: no unknown's last step moves a point by more than ``tol`` mm at the
        largest radius of the data.
    max_iter : int
        Iteration limit.
    check : bool
        Raise :class:`ConvergenceError` when not converged (else return with
        ``converged=False``).

    Returns
    -------
    PlumbLineResult
        The distortion, σ0 (mm), σ of each parameter, covariance, adjusted lines, residuals
        per line (µm), iterations, convergence flag and redundancy.

    Raises
    ------
    ValueError
        Wrong shapes, NaN/inf, a line with fewer than 3 points, fewer than 2 lines,
        redundancy < 1, or terms that plumb lines cannot determine (C1, C2, c, x0, y0, r0).
    DegenerateGeometryError
        (a ValueError) All lines pass through the principal point while radial terms are
        asked for — radial distortion moves points along radial lines, so such lines stay
        straight — or the lines do not determine a parameter (named in the message).
    ConvergenceError
        No convergence within ``max_iter`` (with ``check=True``).

    Examples
    --------
    >>> import numpy as np
    >>> true = Distortion(A1=-3e-5)
    >>> t = np.linspace(-15.0, 15.0, 11)
    >>> ideal = [np.column_stack([t, np.full_like(t, v)]) for v in (-10.0, 5.0, 11.0)]
    >>> ideal += [np.column_stack([np.full_like(t, v), 0.8 * t]) for v in (-14.0, 7.0)]
    >>> fit = plumb_line([true.distort(p) for p in ideal], c=24.0, terms=("A1",))
    >>> fit.converged, f"{fit.distortion.params['A1']:.3e}", fit.sigma0 < 1e-9
    (True, '-3.000e-05', True)
    """
    c = as_scalar(c, "c", positive=True)
    r0 = 0.0 if r0 is None else as_scalar(r0, "r0")
    if r0 < 0:
        raise ValueError(f"r0 must be >= 0 (a radius) or None, got {r0!r}")
    terms = _check_terms(terms)
    pp = as_float_array(principal_point, "principal_point", " with shape (2,)")
    if pp.shape != (2,) or not np.all(np.isfinite(pp)):
        raise ValueError(f"principal_point must be 2 finite numbers (x'0, y'0) in mm, "
                         f"got {principal_point!r}")
    tol = as_tolerance(tol)
    max_iter = as_max_iter(max_iter)
    pts = _check_lines(lines, pp)
    L, p = len(pts), len(terms)
    n_obs = sum(len(q) for q in pts)
    redundancy = n_obs - 2 * L - p
    if redundancy < 1:
        raise ValueError(f"redundancy r = {n_obs} points − 2·{L} line unknowns − {p} parameters "
                         f"= {redundancy} < 1: measure more points or lines")
    xy = np.concatenate(pts)
    k = np.repeat(np.arange(L), [len(q) for q in pts])
    rmax = float(np.max(np.hypot(xy[:, 0], xy[:, 1])))
    start = np.array([_initial_line(q) for q in pts])
    theta, dist = start[:, 0].copy(), start[:, 1].copy()
    radial = [t for t in terms if t.startswith("A")]
    if radial and np.max(np.abs(dist)) < _THROUGH_CENTRE * rmax:
        raise DegenerateGeometryError(
            f"all {L} lines pass through the principal point (within {_THROUGH_CENTRE:.0%} of "
            f"the largest radius, {_THROUGH_CENTRE * rmax:.3g} mm): radial distortion moves "
            f"points along radial lines, so these stay straight and do not determine "
            f"{', '.join(radial)}")
    # dimensionless unknowns for the solver: A_k·c^(2k), B·c
    unit = np.array([c ** (_POWER[t] - 1) for t in terms])
    # step of each unknown → largest displacement it causes (mm)
    effect = np.concatenate([rmax ** np.array([_POWER[t] for t in terms]) / unit,
                             np.tile([rmax, 1.0], L)])
    q, theta, dist, it, converged = _plumb_line_iterate(xy, k, theta, dist, r0, terms, unit,
                                                        effect, tol, max_iter, check)
    return _plumb_line_result(xy, k, theta, dist, r0, terms, q / unit, pts, it, converged,
                              redundancy, c, pp)


def _plumb_line_iterate(xy, k, theta, dist, r0, terms, unit, effect, tol, max_iter, check):
    """Gauss–Newton of :func:`plumb_line`: minimise ``vᵀv`` over the distortion and the lines.

    Unknowns: the dimensionless parameters ``q = A_k·c^(2k), B·c`` (``q / unit`` in the model's
    units), from 0, and each line's normal angle ``theta`` (rad) and distance ``dist`` (mm),
    from the given start (updated in place). The columns of the design matrix are scaled to
    unit norm before the least-squares step; in the first iteration a smallest singular value
    below 1e-9 of the largest raises :class:`DegenerateGeometryError` naming the undetermined
    parameter. Converged when ``max |step| · effect < tol`` (mm: the largest displacement
    of a point each unknown's step causes). Returns ``(q, theta, dist, iterations,
    converged)``; not converged within ``max_iter`` raises :class:`ConvergenceError` when
    ``check``.
    """
    p = len(terms)
    q = np.zeros(p)
    converged, it = False, 0
    for it in range(1, max_iter + 1):
        model = Distortion(r0=r0, **dict(zip(terms, q / unit)))
        f, A = _design(xy, k, theta, dist, model, terms)  # f: the residuals v
        A[:, :p] /= unit
        scale = np.linalg.norm(A, axis=0)
        As = A / scale
        if it == 1:
            s = np.linalg.svd(As, compute_uv=False)
            if s[-1] < 1e-9 * s[0]:
                raise DegenerateGeometryError(
                    f"the lines do not determine {_undetermined(As, terms)} (condition number "
                    f"{s[0] / s[-1]:.3g}): use lines in several directions and at several "
                    "distances from the principal point, filling the format")
        step = np.linalg.lstsq(As, -f, rcond=None)[0] / scale
        if not np.all(np.isfinite(step)):
            raise ConvergenceError(f"plumb-line adjustment diverged in iteration {it}")
        q += step[:p]
        theta += step[p::2]
        dist += step[p + 1::2]
        if np.max(np.abs(step) * effect) < tol:
            converged = True
            break
    if not converged and check:
        raise ConvergenceError(f"plumb-line adjustment did not converge within max_iter="
                               f"{max_iter} (last step moves a point by "
                               f"{np.max(np.abs(step) * effect):.3g} mm > tol={tol:g})")
    return q, theta, dist, it, converged


def _plumb_line_result(xy, k, theta, dist, r0, terms, values, pts, it, converged, redundancy,
                       c, pp) -> PlumbLineResult:
    """The :class:`PlumbLineResult` at the solution of :func:`_plumb_line_iterate`.

    ``values``: the parameters in the model's units. Residuals ``v`` (mm) and design matrix at
    the solution; cofactor matrix ``Q = (AᵀA)⁻¹`` by the SVD of the column-scaled ``A``;
    ``σ0 = √(vᵀv / r)`` (mm); covariance ``σ0² Q`` of the distortion parameters; line angles
    wrapped to [−π, π); residuals split per line and given in µm.
    """
    p = len(terms)
    model = Distortion(r0=r0, **dict(zip(terms, values)))
    v, A = _design(xy, k, theta, dist, model, terms)
    scale = np.linalg.norm(A, axis=0)
    _, s, vt = np.linalg.svd(A / scale, full_matrices=False)
    Q = (vt.T / s**2) @ vt / np.outer(scale, scale)
    sigma0 = float(np.sqrt(v @ v / redundancy))
    cov = sigma0**2 * Q[:p, :p]
    sig = {t: float(np.sqrt(cov[i, i])) for i, t in enumerate(terms)}
    theta = (theta + np.pi) % (2 * np.pi) - np.pi
    residuals = tuple(np.split(v * 1000.0, np.cumsum([len(q_) for q_ in pts])[:-1]))
    return PlumbLineResult(model, terms, sig, cov, sigma0, np.column_stack([theta, dist]),
                           residuals, it, converged, redundancy, c, pp.copy())
