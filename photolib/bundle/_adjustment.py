r"""The bundle adjustment itself: Gauss–Newton on the reduced normal equations.

:func:`bundle_adjustment` linearises the collinearity equations of all observations (with
self-calibration of interior orientation and distortion), accumulates the normal equations
in blocks, eliminates the object points (Schur complement), solves the reduced system with a
condition check, and after convergence forms the covariances, ``Q_vv`` and the redundancy
numbers of the image and control observations once.
"""

from __future__ import annotations

import numpy as np

from photolib._generated.collinearity import collinearity_jacobian_opk, project_r
from photolib._validate import as_max_iter, as_scalar, as_tolerance
from photolib.bundle._datum import (
    DatumError,
    _check_geometry,
    _check_point_blocks,
    _inner_constraints,
)
from photolib.bundle._inputs import _check_inputs, _control_sigma
from photolib.bundle._result import _DIST, INTERIOR_PARAMETERS, BundleResult, IterationRecord
from photolib.collinearity import PointBehindCameraError, project  # noqa: F401  (doctest)
from photolib.distortion import Distortion
from photolib.rotations import rotation_opk
from photolib.transforms._base import ConvergenceError


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
        Stop when the update is below ``tol`` (angles, rad) and ``tol·extent`` (lengths).
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
    xy, j, i, ext, pts, ctrl = _check_inputs(xy, image_index, point_index, exterior, points,
                                             control)
    if datum not in ("control", "free"):
        raise ValueError(f"datum must be 'control' or 'free', got {datum!r}")
    sig = _control_sigma(control_sigma, control, ctrl, len(pts))
    if datum == "free":
        ctrl[:] = False
        sig[:] = np.inf
    weighted = np.isfinite(sig) & (sig > 0)
    if weighted.any():
        if sigma_image is None:
            raise ValueError("sigma_image (the a-priori σ of an image coordinate, image unit) is "
                             "needed to weight control coordinates observed with 0 < σ < inf")
        sigma_image = as_scalar(sigma_image, "sigma_image", positive=True)
    elif sigma_image is not None:
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

    M, P, k = len(ext), len(pts), len(calib)
    rays = np.bincount(i, minlength=P)
    # points without unknowns: all coordinates fixed, or known and in no image (nothing to adjust)
    ctrl = np.all(sig == 0, axis=1) | (np.all(np.isfinite(sig), axis=1) & (rays == 0))
    free = np.flatnonzero(~ctrl)
    slot = np.full(P, -1)
    slot[free] = np.arange(len(free))
    fixc = sig[free] == 0  # (Pf, 3) fixed coordinates of partially known points
    wts = np.zeros((len(free), 3))  # weights p_c of the control observations (0: none)
    wts[weighted[free]] = (sigma_image / sig[free][weighted[free]]) ** 2
    partial, observed = bool(fixc.any()), bool(np.any(wts > 0))
    colmask = (sig != 0).astype(float)  # (P, 3): 0 drops the column of a fixed coordinate
    diag_extra = wts + fixc  # added to the diagonal of N_ii
    control_obs = pts[free].copy()  # the observed control coordinates
    n_obs, n_c = 2 * len(xy), int(np.count_nonzero(wts))
    u = 6 * M + 3 * len(free) - int(fixc.sum()) + k
    d = 7 if datum == "free" else 0
    r = n_obs + n_c - u + d
    if r < 0:
        raise DatumError(f"more unknowns than observations: n = {n_obs} + {n_c} (control), "
                         f"u = {u}, d = {d}")
    extent = float(np.max(np.ptp(pts, axis=0))) or 1.0
    ny = 6 * M + k + d
    cols = np.column_stack([6 * np.arange(M)[:, None] + np.arange(6),  # of image a, interior
                            np.broadcast_to(6 * M + np.arange(k), (M, k))]).astype(int)
    # observations sorted by image and (new points only) by point: sums by np.add.reduceat
    by_image = np.argsort(j, kind="stable")
    image_start = np.searchsorted(j[by_image], np.arange(M))
    m = np.flatnonzero(~ctrl[i])
    s, jm = slot[i[m]], j[m]
    by_point = np.argsort(s, kind="stable")
    point_start = np.searchsorted(s[by_point], np.arange(len(free)))
    probe = np.random.default_rng(0).standard_normal((ny, 2))  # condition estimate, solve_reduced

    def linearise(ext, pts, interior):
        """v (N, 2); A (N, 2, 6 + k): ∂/∂ own image, ∂/∂ interior; Ap (N, 2, 3): ∂/∂ point."""
        dist = Distortion(r0=r0, **{n: interior[n] for n in _DIST})
        pp = np.array([interior["x0"], interior["y0"]])
        red = xy - pp
        E, X = ext[j].T, pts[i].T
        R = rotation_opk(*ext[:, 3:].T).reshape(M, 9)[j].T
        x, y, depth = project_r(*X, *E[:3], *R, interior["c"], *pp)
        if not np.all(depth < 0):
            q = int(np.argmin(depth < 0))
            raise PointBehindCameraError(f"object point {i[q]} is not in front of image {j[q]}: "
                                         f"N = {depth[q]:.6g} ≥ 0")
        proj = np.column_stack([x, y])
        v = proj - xy
        dJ = collinearity_jacobian_opk(*X, *E, interior["c"])
        J = np.stack(np.broadcast_arrays(*dJ), axis=-1).reshape(-1, 9, 2).transpose(0, 2, 1)
        A = np.concatenate([J[:, :, :6], np.zeros((len(xy), 2, k))], axis=2)
        if "c" in calib:
            A[:, :, 6 + calib.index("c")] = (proj - pp) / interior["c"]
        if not dist.is_zero:
            v += dist.delta(red)
        if k:
            Jxy, Jpar = dist.jacobian_xy(red), dist.jacobian_params(red)
            for n, name in enumerate(calib):
                if name in ("x0", "y0"):
                    e = 0 if name == "x0" else 1
                    A[:, :, 6 + n] = -Jxy[:, :, e]
                    A[:, e, 6 + n] += 1.0
                elif name != "c":
                    A[:, :, 6 + n] = Jpar[:, :, _DIST.index(name)]
        Ap = np.ascontiguousarray(J[:, :, 6:])
        if partial:
            Ap *= colmask[i][:, None, :]
        return v, A, Ap

    def normals(v, A, Ap, pts):
        """Reduced normal equations, accumulated in blocks: 6 × 6 (+ k) per image, 3 × 3 per
        point, 3 × 6 per observation of a new point (its image–point coupling)."""
        lv = -v[:, :, None]
        W = A.transpose(0, 2, 1) @ np.concatenate([A, lv], axis=2)
        W = np.add.reduceat(W[by_image], image_start, axis=0)  # (M, 6 + k, 7 + k)
        Nyy, by = np.zeros((ny, ny)), np.zeros(ny)
        np.add.at(Nyy, (cols[:, :, None], cols[:, None, :]), W[:, :, :-1])
        np.add.at(by, cols, W[:, :, -1])
        Wp = Ap[m].transpose(0, 2, 1) @ np.concatenate([Ap[m], A[m], lv[m]], axis=2)
        Sp = np.add.reduceat(Wp[by_point], point_start, axis=0)  # N_pp | N_p,interior | b_p
        Npy = np.zeros((len(free), 3, ny))
        Npy[s[:, None, None], np.arange(3)[:, None], cols[jm, None, :6]] = Wp[:, :, 3:9]
        Npy[:, :, 6 * M:6 * M + k] = Sp[:, :, 9:9 + k]
        if d:
            Npy[:, :, 6 * M + k:] = _inner_constraints(pts).reshape(P, 3, 7)[free]
        bp, Npp = Sp[:, :, -1], Sp[:, :, :3]
        if partial or observed:
            Npp = Npp + diag_extra[:, :, None] * np.eye(3)
            bp = bp - wts * (pts[free] - control_obs)
        _check_point_blocks(Npp, free)
        Ninv = np.linalg.inv(Npp)
        T = Ninv @ Npy  # (Pf, 3, ny)
        K = Nyy - Npy.reshape(-1, ny).T @ T.reshape(-1, ny)
        rhs = by - T.reshape(-1, ny).T @ bp.ravel()
        return K, rhs, Ninv, T, bp

    def solve_reduced(K, rhs=None):
        """K⁻¹·rhs by LU on the scaled K_s if two inverse iterations put its condition
        ‖K_s‖_F·‖K_s⁻¹‖ below 1e10; else (and for rhs None) the SVD check, then K⁻¹(·rhs)."""
        scale = 1.0 / np.sqrt(np.where(np.abs(np.diag(K)) > 0, np.abs(np.diag(K)), 1.0))
        Ks = K * scale[:, None] * scale[None, :]
        if rhs is not None:
            try:
                Z = np.linalg.solve(Ks, np.column_stack([scale * rhs, probe]))
                Z2 = np.linalg.solve(Ks, Z[:, 1:] / np.linalg.norm(Z[:, 1:], axis=0))
                if (np.linalg.norm(Ks) * np.max(np.linalg.norm(Z2, axis=0)) < 1e10
                        and np.all(np.isfinite(Z[:, 0]))):
                    return scale * Z[:, 0]
            except np.linalg.LinAlgError:
                pass
        sv = np.linalg.svd(Ks, compute_uv=False)
        if sv[-1] <= 1e-12 * sv[0]:
            what = ("the inner constraints do not remove the defect" if d else
                    "the control points do not fix the datum")
            raise DatumError(f"the reduced normal matrix is singular (condition "
                             f"{sv[0] / max(sv[-1], 1e-300):.3g}): {what}, or the geometry is "
                             "degenerate (e.g. self-calibration parameters not determined)")
        Kinv = scale[:, None] * np.linalg.inv(Ks) * scale[None, :]
        return Kinv if rhs is None else Kinv @ rhs

    def vtpv_control(pts):
        return float(np.sum(wts * (pts[free] - control_obs) ** 2)) if observed else 0.0

    history, converged, it = [], False, 0
    for it in range(1, max_iter + 1):
        try:
            v, A, Ap = linearise(ext, pts, interior)
        except PointBehindCameraError as exc:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: {exc}") from None
        K, rhs, Ninv, T, bp = normals(v, A, Ap, pts)
        dy = solve_reduced(K, rhs)
        dp = (Ninv @ bp[:, :, None])[:, :, 0] - T @ dy
        if not (np.all(np.isfinite(dy)) and np.all(np.isfinite(dp))):
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: non-finite step")
        de = dy[:6 * M].reshape(M, 6)
        ext = ext + de
        pts_before = pts
        pts = pts.copy()
        pts[free] += dp
        for n, name in enumerate(calib):
            interior[name] += dy[6 * M + n]
        dl = max(float(np.max(np.abs(de[:, :3]))), float(np.max(np.abs(dp), initial=0.0)))
        da = float(np.max(np.abs(de[:, 3:])))
        rec = IterationRecord(it, float(np.sum(v**2)) + vtpv_control(pts_before), dl, da)
        history.append(rec)
        if callback is not None:
            callback(rec)
        if dl <= tol * extent and da <= tol:
            converged = True
            break
        if dl > 1e6 * extent:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: an update of "
                                   f"{dl:.3g} object units")
    if not converged and check:
        raise ConvergenceError(f"bundle adjustment did not converge to tol={tol:g} in {max_iter} "
                               f"iterations (last length update {dl:.3g}, angle update {da:.3g}); "
                               "pass check=False to get the last iterate")
    try:
        v, A, Ap = linearise(ext, pts, interior)
    except PointBehindCameraError as exc:
        raise ConvergenceError(f"bundle adjustment ended with {exc}") from None
    K, rhs, Ninv, T, bp = normals(v, A, Ap, pts)
    Kinv = solve_reduced(K)  # the covariance: once, after convergence
    # diag(A Q A^T) per observation: g = a_y − a_p T_i, q = g K⁻¹ gᵀ + a_p N_ii⁻¹ a_pᵀ
    G = -(Ap @ np.concatenate([T, np.zeros((1, 3, ny))])[slot[i]])  # slot −1: control, 0
    G[np.arange(len(xy))[:, None, None], np.arange(2)[:, None], cols[j, None, :]] += A
    qhat = ((G.reshape(-1, ny) @ Kinv) * G.reshape(-1, ny)).sum(axis=1).reshape(-1, 2)
    qhat[m] += ((Ap[m] @ Ninv[s]) * Ap[m]).sum(axis=2)
    qvv = np.clip(1.0 - qhat, 0.0, 1.0)
    sigma0 = float(np.sqrt((np.sum(v**2) + vtpv_control(pts)) / r)) if r > 0 else float("nan")
    s2 = sigma0**2 if r > 0 else float("nan")
    ext_cov = s2 * np.stack([Kinv[6 * a:6 * a + 6, 6 * a:6 * a + 6] for a in range(M)])
    pcov = np.zeros((P, 3, 3))
    Qpp = Ninv + T @ Kinv @ T.transpose(0, 2, 1)
    if partial:
        Qpp *= colmask[free][:, :, None] * colmask[free][:, None, :]
    pcov[free] = s2 * Qpp
    icov = s2 * Kinv[6 * M:6 * M + k, 6 * M:6 * M + k]
    # control observations: v_c, q_vv,c = 1/p − Q_cc, r_c = p·q_vv,c
    cres, cqvv, crn = np.zeros((P, 3)), np.zeros((P, 3)), np.zeros((P, 3))
    if weighted.any():
        unseen = ctrl & weighted.any(axis=1)  # known, in no image: a priori σ², no redundancy
        pcov[unseen] = s2 * np.einsum("pi,ij->pij", np.where(weighted[unseen], (
            sig[unseen] / sigma_image) ** 2, 0.0), np.eye(3))
        w = wts > 0
        with np.errstate(divide="ignore"):
            q = np.where(w, 1.0 / np.where(w, wts, 1.0) - np.einsum("pii->pi", Qpp), 0.0)
        cqvv[free] = np.maximum(q, 0.0)
        crn[free] = np.clip(wts * q, 0.0, 1.0)
        cres[free] = np.where(w, pts[free] - control_obs, 0.0)
    dist = Distortion(r0=r0, **{n: interior[n] for n in _DIST})
    return BundleResult(ext, pts, float(interior["c"]), float(interior["x0"]),
                        float(interior["y0"]), dist, calib,
                        sigma0, n_obs, u, d, r, v, qvv, qvv.copy(), ext_cov, pcov, icov, it,
                        converged, tuple(history), n_control_observations=n_c,
                        control_sigma=sig, sigma_image=sigma_image, control_residuals=cres,
                        control_qvv=cqvv, control_redundancy_numbers=crn)
