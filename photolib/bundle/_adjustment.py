r"""The bundle adjustment itself: Gauss–Newton on the reduced normal equations.

:func:`bundle_adjustment` runs named stages: the checks of its arguments (:func:`_prepare`),
the layout of the unknowns (:func:`~photolib.bundle._blocks.make_layout`), the linearisation
of the collinearity equations of all observations with self-calibration of interior
orientation and distortion (:func:`linearise`), the normal equations in blocks with the
points eliminated (:func:`~photolib.bundle._blocks.normals`), the solution of the reduced
camera system (:class:`~photolib.bundle._blocks.ReducedSystem`), the iteration
(:func:`_iterate`) and, once after convergence, the statistics (:func:`_statistics`): σ0,
the covariance blocks, ``Q_vv`` and the redundancy numbers of the image and control
observations, from the block structure (no matrix over all unknowns or observations) and
from the normal equations and factor of the last iteration, which was linearised at the
estimate (the iteration stops when the update computed there is below ``tol``, extent =
the largest coordinate range of the start points; the update is not applied, as Ceres does
at its parameter tolerance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._generated.collinearity import (
    collinearity_jacobian_interior,
    collinearity_jacobian_opk,
    project_r,
)
from photolib._validate import as_max_iter, as_scalar, as_tolerance
from photolib.bundle._blocks import (
    Layout,
    Normals,
    ReducedSystem,
    back_substitute,
    covariances,
    make_layout,
    normals,
)
from photolib.bundle._datum import DatumError, _check_geometry  # noqa: F401  (Raises)
from photolib.bundle._inputs import _check_inputs, _control_sigma
from photolib.bundle._result import _DIST, INTERIOR_PARAMETERS, BundleResult, IterationRecord
from photolib.collinearity import PointBehindCameraError, project  # noqa: F401  (doctest)
from photolib.distortion import Distortion
from photolib.rotations import rotation_opk
from photolib.transforms._base import ConvergenceError

#: observations linearised at a time (the generated code's temporaries: 8192 × 8 B = 64 KiB)
LIN_CHUNK = 1 << 13


def bundle_adjustment(xy, image_index, point_index, exterior, points, c, x0=0.0, y0=0.0,
                      distortion=None, *, control=None, datum: str = "control",
                      control_sigma=None, sigma_image=None,
                      calibrate=(), tol: float = 1e-10, max_iter: int = 30,
                      check: bool = True, callback=None) -> BundleResult:
    r"""Bundle adjustment of a block by Gauss–Newton on the reduced normal equations.

    Parameters
    ----------
    xy : array_like, shape (N, 2)
        Measured image coordinates (image unit, e.g. mm), all of equal precision.
    image_index, point_index : array_like of int, shape (N,)
        Image j and object point i of each measurement.
    exterior : array_like, shape (M, 6)
        Approximate ``(X0, Y0, Z0, ω, φ, κ)`` per image (object unit, radians).
    points : array_like, shape (P, 3)
        Approximate object points; the rows of control points hold their control coordinates
        (fixed or observed), and approximate values for their unknown coordinates.
    c, x0, y0 : float
        Camera constant (> 0) and principal point (image unit), common to all images.
    distortion : Distortion, optional
        Starting (or fixed) distortion, evaluated at the measured points; ``r0`` is kept.
    control : array_like of int or bool mask (P,), optional
        Control points (Passpunkte), held fixed: their indices (0 … P − 1, each once) or a
        bool mask of length P.
    datum : {'control', 'free'}
        ``'control'``: datum by the control points (≥ 3, not on a line; with partial control
        the known coordinates must fix all seven similarity parameters); ``'free'``: free
        network with the seven inner constraints on all object points (``control`` and
        ``control_sigma`` ignored).
    control_sigma : array_like, optional
        Control per coordinate (Passpunkte als Beobachtungen, Lage- und Höhenpasspunkte),
        object unit: ``0`` the coordinate is fixed (error-free), ``inf`` unknown, ``σ > 0``
        observed with standard deviation σ (a pseudo-observation ``X_i,e = points[i, e]``
        with weight ``p = (σ_image/σ)²``, image observations having weight 1). Shape (P, 3)
        for all points when ``control`` is None; with ``control`` a scalar, (3,) or (K, 3)
        for its K points in its order (the other points unknown). Default: ``control``
        points fixed. E.g. a height control point (Höhenpasspunkt) is ``(inf, inf, 0)``, a
        plan control point (Lagepasspunkt) ``(0, 0, inf)``, a GNSS point ``(0.02,) * 3``.
    sigma_image : float, optional
        A-priori σ of an image coordinate (image unit, e.g. 0.003 mm), > 0: sets the weights
        of the control observations. Needed only when ``control_sigma`` has a value
        0 < σ < ∞; it changes no result of an adjustment without such observations (σ0 is
        always the a-posteriori σ of an image coordinate, the weight-1 observation).
    calibrate : iterable of str
        Interior parameters to estimate (self-calibration), from ``INTERIOR_PARAMETERS``.
    tol : float
        Stop at the iterate whose update is below ``tol`` (angles, rad) and ``tol·extent``
        (lengths); that iterate, the update not applied, is the estimate (see the module).
    max_iter : int
        Iteration limit; reaching it raises ``ConvergenceError`` unless ``check=False``.
    check : bool
        If True (default) no convergence within ``max_iter`` raises ``ConvergenceError``;
        False returns the last iterate with ``converged=False`` (its σ0 and covariances
        are those of that iterate, not of an adjusted block).
    callback : callable, optional
        ``callback(record)`` with an :class:`IterationRecord` after each iteration.

    Returns
    -------
    BundleResult

    Notes
    -----
    With control observations the model is ``v = A dx − l`` with weights
    ``P = diag(1 (image), p_c = σ_image²/σ_c² (control))``; they add ``p_c`` to the diagonal
    of the point's 3 × 3 block ``N_ii`` and ``−p_c·v_c`` to ``b_i``, so the Schur complement
    keeps its shape. A fixed coordinate of a partially known point has no unknown (its column
    of A is dropped). Then ``σ̂0² = (vᵀv + Σ p_c v_c²)/r``, ``r = n + n_c − u + d`` and the
    control redundancy numbers ``r_c = 1 − p_c (Q_xx)_cc`` with
    ``Σ_k r_k + Σ_c r_c = r``.

    Raises
    ------
    ValueError
        Shapes, NaN, indices out of range (``control`` too: integer indices, each once, or a
        bool mask of length P), unknown parameters, ``max_iter < 1``, ``tol ≤ 0``;
        ``control_sigma`` of the wrong shape, negative or NaN; ``sigma_image`` missing or
        not > 0 when it is needed.
    DatumError
        Datum not fixed, image with < 3 points, a new point seen once, a new point whose rays
        are parallel (zero base), singular normal matrix.
    ConvergenceError
        Divergence (points behind a camera, non-finite steps) or no convergence.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 3.0]])
    >>> ext = np.array([[3.0, 5, 30, 0, 0, 0], [7.0, 5, 30, 0, 0, 0]])
    >>> obs = [project(X, e[:3], rotation_opk(*e[3:]), 20.0) for e in ext]
    >>> res = bundle_adjustment(np.vstack(obs), np.repeat([0, 1], 5), np.tile(np.arange(5), 2),
    ...                         ext + 0.01, X, 20.0, control=[0, 1, 2, 3])
    >>> res.redundancy, bool(np.allclose(res.exterior, ext)), bool(np.allclose(res.points, X))
    (5, True, True)

    Point 4 as a height control point (Z fixed), points 0–3 observed with σ = 1 cm
    (σ_image = 1 µm): r = n + n_c − u = 20 + 12 − (12 + 12 + 2) = 6:

    >>> sig = np.array([[0.01] * 3] * 4 + [[np.inf, np.inf, 0.0]])
    >>> res = bundle_adjustment(np.vstack(obs), np.repeat([0, 1], 5), np.tile(np.arange(5), 2),
    ...                         ext + 0.01, X, 20.0, control_sigma=sig, sigma_image=0.001)
    >>> res.n_control_observations, res.n_unknowns, res.redundancy
    (12, 26, 6)
    >>> round(float(res.redundancy_numbers.sum() + res.control_redundancy_numbers.sum()), 9)
    6.0
    """
    prob = _prepare(xy, image_index, point_index, exterior, points, c, x0, y0, distortion,
                    control, datum, control_sigma, sigma_image, calibrate, tol, max_iter)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    ext, pts, interior, history, converged, lin = _iterate(prob, lay, check, callback)
    stats = _statistics(prob, lay, ext, pts, interior, lin)
    return BundleResult(
        exterior=ext, points=pts, c=float(interior["c"]), x0=float(interior["x0"]),
        y0=float(interior["y0"]),
        distortion=Distortion(r0=prob.r0, **{n: interior[n] for n in _DIST}),
        calibrate=prob.calib, n_observations=lay.n_obs, n_unknowns=lay.u, datum_defect=lay.d,
        redundancy=lay.r, iterations=len(history), converged=converged, history=tuple(history),
        n_control_observations=lay.n_c, control_sigma=prob.sig, sigma_image=prob.sigma_image,
        **stats)


@dataclass(frozen=True)
class _Problem:
    """The checked arguments of :func:`bundle_adjustment`."""

    xy: np.ndarray
    j: np.ndarray
    i: np.ndarray
    ext: np.ndarray
    pts: np.ndarray
    sig: np.ndarray  #: (P, 3) σ per control coordinate: 0 fixed, inf unknown
    weighted: np.ndarray  #: (P, 3) 0 < σ < inf
    sigma_image: float | None
    tol: float
    max_iter: int
    calib: tuple
    interior: dict
    r0: float
    datum: str


def _prepare(xy, image_index, point_index, exterior, points, c, x0, y0, distortion, control,
             datum, control_sigma, sigma_image, calibrate, tol, max_iter) -> _Problem:
    """Check the arguments of :func:`bundle_adjustment` (its Raises) and the geometry."""
    xy, j, i, ext, pts, ctrl = _check_inputs(xy, image_index, point_index, exterior, points,
                                             control)
    if datum not in ("control", "free"):
        raise ValueError(f"datum must be 'control' or 'free', got {datum!r}")
    sig = _control_sigma(control_sigma, control, ctrl, len(pts))
    if datum == "free":
        sig[:] = np.inf
    weighted = np.isfinite(sig) & (sig > 0)
    if weighted.any() and sigma_image is None:
        raise ValueError("sigma_image (the a-priori σ of an image coordinate, image unit) is "
                         "needed to weight control coordinates observed with 0 < σ < inf")
    if sigma_image is not None:
        sigma_image = as_scalar(sigma_image, "sigma_image", positive=True)
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    calib = (calibrate,) if isinstance(calibrate, str) else tuple(calibrate)
    unknown = [n for n in calib if n not in INTERIOR_PARAMETERS]
    if unknown or len(set(calib)) != len(calib):
        raise ValueError(f"calibrate {calib!r}: each name once, from {INTERIOR_PARAMETERS}")
    calib = tuple(n for n in INTERIOR_PARAMETERS if n in calib)
    if distortion is not None and not isinstance(distortion, Distortion):
        raise TypeError(f"distortion must be a photolib.Distortion or None, got "
                        f"{type(distortion).__name__}")
    interior = {"c": as_scalar(c, "c", positive=True), "x0": as_scalar(x0, "x0"),
                "y0": as_scalar(y0, "y0")}
    r0 = 0.0 if distortion is None else distortion.params["r0"]
    interior |= {k: (0.0 if distortion is None else distortion.params[k]) for k in _DIST}
    _check_geometry(j, i, ext, pts, sig, datum)
    return _Problem(xy, j, i, ext, pts, sig, weighted, sigma_image, tol, max_iter, calib,
                    interior, r0, datum)


def linearise(prob: _Problem, lay: Layout, ext, pts, interior):
    """Residuals and Jacobian blocks of the collinearity equations at (ext, pts, interior).

    Returns ``v`` (N, 2) = computed − observed (image unit), ``A`` (N, 2, 6 + k) = ∂v/∂(own
    image X0, Y0, Z0, ω, φ, κ; interior parameters) and ``Ap`` (N, 2, 3) = ∂v/∂(X, Y, Z)
    (columns of fixed coordinates zero). The model is ``x' = x'0 − c·kx/N + Δx'(x'_obs − x'0)``.
    The generated code runs on ``LIN_CHUNK`` observations at a time, so that its temporaries
    stay in the cache (the same arithmetic; the Jacobian code runs 1.9× faster per
    observation at 230,000 observations than in one pass).
    Raises ``PointBehindCameraError`` for a point with depth ``N ≥ 0``."""
    xy, j, i, calib, k = prob.xy, prob.j, prob.i, lay.calib, lay.k
    dist = Distortion(r0=prob.r0, **{n: interior[n] for n in _DIST})
    pp = np.array([interior["x0"], interior["y0"]])
    red = xy - pp
    Rm = rotation_opk(*ext[:, 3:].T).reshape(lay.M, 9)
    n_obs = len(xy)
    v, J = np.empty((n_obs, 2)), np.empty((n_obs, 2, 9))
    ideal = np.empty((n_obs, 3, 2)) if k else None
    for s in range(0, n_obs, LIN_CHUNK):
        c = slice(s, s + LIN_CHUNK)
        E, X, R = ext[j[c]].T, pts[i[c]].T, Rm[j[c]].T
        x, y, depth = project_r(*X, *E[:3], *R, interior["c"], *pp)
        if not np.all(depth < 0):
            q = s + int(np.argmin(depth < 0))
            raise PointBehindCameraError(f"object point {i[q]} is not in front of image "
                                         f"{j[q]}: N = {depth[q - s]:.6g} ≥ 0")
        v[c, 0], v[c, 1] = x, y
        dJ = collinearity_jacobian_opk(*X, *E, interior["c"])
        J[c] = np.stack(np.broadcast_arrays(*dJ), axis=-1).reshape(-1, 9, 2).transpose(0, 2, 1)
        if k:
            # the ideal model's columns for c, x'0, y'0 (generated from derive/collinearity.py)
            dI = collinearity_jacobian_interior(*X, *E[:3], *R, interior["c"])
            ideal[c] = np.stack(np.broadcast_arrays(*dI), axis=-1).reshape(-1, 3, 2)
    v -= xy
    A = np.concatenate([J[:, :, :6], np.zeros((n_obs, 2, k))], axis=2)
    if not dist.is_zero:
        v += dist.delta(red)
    if k:
        # the distortion's share: Δ(x'_obs − x'0) adds −∂Δ/∂x' to x'0, y'0
        Jxy, Jpar = dist.jacobian_xy(red), dist.jacobian_params(red)
        for n, name in enumerate(calib):
            if name in ("c", "x0", "y0"):
                A[:, :, 6 + n] = ideal[:, ("c", "x0", "y0").index(name), :]
                if name != "c":
                    A[:, :, 6 + n] -= Jxy[:, :, 0 if name == "x0" else 1]
            else:
                A[:, :, 6 + n] = Jpar[:, :, _DIST.index(name)]
    Ap = np.ascontiguousarray(J[:, :, 6:])
    if lay.partial:
        Ap *= lay.colmask[i][:, None, :]
    return v, A, Ap


def _vtpv_control(lay: Layout, pts) -> float:
    """Σ p_c v_c² of the control observations (object unit² × weight), 0 without any."""
    return float(np.sum(lay.wts * (pts[lay.free] - lay.control_obs) ** 2)) if lay.observed \
        else 0.0


@dataclass(frozen=True)
class _Linearisation:
    """The residuals, Jacobian blocks, normal equations and factorised reduced system of one
    iterate (what an iteration computes before its step)."""

    v: np.ndarray
    A: np.ndarray
    Ap: np.ndarray
    nrm: Normals
    system: ReducedSystem


def _linearise_solve(prob: _Problem, lay: Layout, ext, pts, interior) -> _Linearisation:
    """Linearisation, normal equations and factorised reduced system at (ext, pts, interior)."""
    v, A, Ap = linearise(prob, lay, ext, pts, interior)
    nrm = normals(lay, v, A, Ap, pts)
    return _Linearisation(v, A, Ap, nrm, ReducedSystem(lay, nrm))


def _iterate(prob: _Problem, lay: Layout, check: bool, callback):
    """Gauss–Newton: linearise, normal equations, reduced solve, back-substitution, until the
    update computed at the current iterate is below ``tol`` (rad) and ``tol·extent`` (object
    unit). That iterate is the estimate (its update is not applied): the statistics use the
    normal equations it was tested with. Returns ``(ext, pts, interior, history, converged,
    lin)``; ``lin`` is the :class:`_Linearisation` of the estimate, ``None`` if the
    iteration stopped at ``max_iter`` (its last update applied)."""
    ext, pts, interior = prob.ext, prob.pts, dict(prob.interior)
    M, tol, history = lay.M, prob.tol, []
    dl = da = float("nan")
    for it in range(1, prob.max_iter + 1):
        lin = None  # the previous iterate's arrays go before this one's are built
        try:
            lin = _linearise_solve(prob, lay, ext, pts, interior)
        except PointBehindCameraError as exc:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: {exc}") from None
        dy = lin.system.solve(lin.nrm.rhs)
        dp = back_substitute(lay, lin.nrm, dy)
        if not (np.all(np.isfinite(dy)) and np.all(np.isfinite(dp))):
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: non-finite step")
        de = dy[:6 * M].reshape(M, 6)
        dl = max(float(np.max(np.abs(de[:, :3]))), float(np.max(np.abs(dp), initial=0.0)))
        da = float(np.max(np.abs(de[:, 3:])))
        rec = IterationRecord(it, float(np.sum(lin.v**2)) + _vtpv_control(lay, pts), dl, da)
        history.append(rec)
        if callback is not None:
            callback(rec)
        if dl <= tol * lay.extent and da <= tol:
            return ext, pts, interior, history, True, lin
        if dl > 1e6 * lay.extent:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: an update of "
                                   f"{dl:.3g} object units")
        ext = ext + de
        pts = pts.copy()
        pts[lay.free] += dp
        for n, name in enumerate(lay.calib):
            interior[name] += dy[6 * M + n]
    if check:
        raise ConvergenceError(f"bundle adjustment did not converge to tol={tol:g} in "
                               f"{prob.max_iter} iterations (last length update {dl:.3g}, angle "
                               f"update {da:.3g}); pass check=False to get the last iterate")
    return ext, pts, interior, history, False, None


def _statistics(prob: _Problem, lay: Layout, ext, pts, interior,
                lin: _Linearisation | None = None) -> dict:
    r"""σ0, covariances (scaled by σ0²), residuals, q_vv and redundancy numbers at the
    estimate, from the block structure (:func:`~photolib.bundle._blocks.covariances`) and
    the normal equations ``lin`` of the estimate (linearised here if ``None``):

    ``σ̂0² = (vᵀv + Σ p_c v_c²)/r``, ``r_k = q_vv,k = 1 − (A Q_xx Aᵀ)_kk`` (P = I) and for a
    control coordinate ``q_vv,c = 1/p_c − (Q_xx)_cc``, ``r_c = p_c·q_vv,c``."""
    if lin is None:
        try:
            lin = _linearise_solve(prob, lay, ext, pts, interior)
        except PointBehindCameraError as exc:
            raise ConvergenceError(f"bundle adjustment ended with {exc}") from None
    v, A, Ap, nrm = lin.v, lin.A, lin.Ap, lin.nrm
    inv = lin.system.inverse_blocks()  # the covariance: once, after convergence
    cov = covariances(lay, nrm, inv, A, Ap, prob.j)
    qvv = np.clip(1.0 - cov.qhat, 0.0, 1.0)
    r = lay.r
    sigma0 = float(np.sqrt((np.sum(v**2) + _vtpv_control(lay, pts)) / r)) if r > 0 else \
        float("nan")
    s2 = sigma0**2 if r > 0 else float("nan")
    free, P, sig = lay.free, lay.P, prob.sig
    pcov = np.zeros((P, 3, 3))
    Qpp = cov.Qpp
    if lay.partial:
        Qpp = Qpp * lay.colmask[free][:, :, None] * lay.colmask[free][:, None, :]
    pcov[free] = s2 * Qpp
    cres, cqvv, crn = np.zeros((P, 3)), np.zeros((P, 3)), np.zeros((P, 3))
    weighted = prob.weighted
    if weighted.any():
        ctrl = np.ones(P, bool)
        ctrl[free] = False
        unseen = ctrl & weighted.any(axis=1)  # known, in no image: a priori σ², no redundancy
        pcov[unseen] = s2 * np.einsum("pi,ij->pij", np.where(weighted[unseen], (
            sig[unseen] / prob.sigma_image) ** 2, 0.0), np.eye(3))
        w = lay.wts > 0
        with np.errstate(divide="ignore"):
            q = np.where(w, 1.0 / np.where(w, lay.wts, 1.0) - np.einsum("pii->pi", Qpp), 0.0)
        cqvv[free] = np.maximum(q, 0.0)
        crn[free] = np.clip(lay.wts * q, 0.0, 1.0)
        cres[free] = np.where(w, pts[free] - lay.control_obs, 0.0)
    return dict(sigma0=sigma0, residuals=v, qvv=qvv, redundancy_numbers=qvv.copy(),
                exterior_covariance=s2 * cov.Qcam, point_covariance=pcov,
                interior_covariance=s2 * cov.Qint, control_residuals=cres, control_qvv=cqvv,
                control_redundancy_numbers=crn)
