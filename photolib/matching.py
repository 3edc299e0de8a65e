"""Least-squares matching / Kleinste-Quadrate-Zuordnung (LSM, Luhmann 5.72/5.73).

A template f (Muster) is found in a search image g (Suchbild) under an affine geometric and a
linear radiometric transformation,

    f(x, y) − e(x, y) = r0 + r1·g(x', y'),   x' = a0 + a1x + a2y,   y' = b0 + b1x + b2y,

by Gauss–Newton. The linearisation is the errata's corrected 5.72 (record ``luhmann:5.72``; the
old print drops r0 and the factor r1, right only in the first iteration with r0 = 0, r1 = 1),
with the gradients g_x' = ∂g/∂x', g_y' = ∂g/∂y' of the search image (5.73, record
``luhmann:5.73``). The template's coordinates (x, y) are (col, row) relative to its centre
pixel, so (a0, b0) is the position (col, row) of the template centre in the search image.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_max_iter, as_tolerance, check_finite
from photolib.transforms._base import ConvergenceError
from photolib.errors import StartOutsideImageError  # noqa: F401 - raised here, defined in one hierarchy

__all__ = ["PARAMETER_NAMES", "LSMResult", "StartOutsideImageError", "least_squares_matching",
           "lsm_design_matrix"]

#: order of the eight unknowns
PARAMETER_NAMES = ("a0", "a1", "a2", "b0", "b1", "b2", "r0", "r1")



class LSMResult(NamedTuple):
    """Result of :func:`least_squares_matching`."""

    params: np.ndarray     #: (8,) a0, a1, a2, b0, b1, b2, r0, r1
    std: np.ndarray        #: (8,) standard deviations σ0·sqrt(q_ii)
    sigma0: float          #: sqrt(vᵀv/(n − 8)), grey values
    covariance: np.ndarray  #: (8, 8) σ0²·(AᵀA)⁻¹
    residuals: np.ndarray  #: (h, w) v = f − (r0 + r1·g(x', y')) after the last iteration
    iterations: int        #: Gauss–Newton iterations
    converged: bool        #: True (a failure raises unless ``check=False``)
    history: np.ndarray    #: (iterations + 1, 8) parameters, start first

    @property
    def position(self) -> np.ndarray:
        """(col, row) of the template centre in the search image: (a0, b0)."""
        return self.params[[0, 3]].copy()


def _bilinear(planes, W, cols, rows):
    """Bilinear values of the stacked images ``planes`` (C, H·W) at (``cols``, ``rows``).

    The interpolation of :func:`photolib.rectify.sample_image` (the same operations in the same
    order, so the same values) without its checks: all positions must lie in
    ``0 ≤ col ≤ W − 1``, ``0 ≤ row ≤ H − 1``. Returns (C, n).
    """
    H = planes.shape[1] // W
    c0 = np.minimum(cols.astype(np.intp), W - 2)      # floor: the positions are ≥ 0
    r0 = np.minimum(rows.astype(np.intp), H - 2)
    u, v = cols - c0, rows - r0
    i = r0 * W + c0
    t = planes.take(np.concatenate([i, i + 1, i + W, i + W + 1]), axis=1)
    t = t.reshape(len(planes), 4, -1)                  # g00, g10, g01, g11 of each image
    u1, v1 = 1 - u, 1 - v
    return u1 * v1 * t[:, 0] + u * v1 * t[:, 1] + u1 * v * t[:, 2] + u * v * t[:, 3]


def _design(r1, x, y, g, gx, gy):
    """:func:`lsm_design_matrix` for 1-D float arrays, without its conversions (the same values)."""
    A = np.empty((len(g), 8))
    np.multiply(r1, gx, out=A[:, 0])
    np.multiply(A[:, 0], x, out=A[:, 1])
    np.multiply(A[:, 0], y, out=A[:, 2])
    np.multiply(r1, gy, out=A[:, 3])
    np.multiply(A[:, 3], x, out=A[:, 4])
    np.multiply(A[:, 3], y, out=A[:, 5])
    A[:, 6] = 1.0
    A[:, 7] = g
    return A


def _template_coordinates(shape):
    """(x, y) = (col, row) of the template pixels from its centre, row by row, each (h·w,)."""
    h, w = shape
    return (np.tile(np.arange(w, dtype=float) - (w - 1) / 2.0, h),
            np.repeat(np.arange(h, dtype=float) - (h - 1) / 2.0, w))


def lsm_design_matrix(params, x, y, g, gx, gy) -> np.ndarray:
    r"""Rows of the linearised LSM model (Luhmann 5.72 corrected), one per template pixel.

    .. math::
        f - e - (r_0 + r_1 g) = r_1 g_{x'}\,da_0 + r_1 g_{x'} x\,da_1 + r_1 g_{x'} y\,da_2
        + r_1 g_{y'}\,db_0 + r_1 g_{y'} x\,db_1 + r_1 g_{y'} y\,db_2 + dr_0 + g\,dr_1

    Parameters
    ----------
    params : array_like, shape (8,)
        Current a0, a1, a2, b0, b1, b2, r0, r1 (only r1 enters).
    x, y : array_like, shape (n,)
        Template coordinates (pixels from the template centre).
    g, gx, gy : array_like, shape (n,)
        Search-image grey value and its gradient (∂g/∂x', ∂g/∂y') at (x', y').

    Returns
    -------
    ndarray, shape (n, 8)

    Examples
    --------
    >>> lsm_design_matrix([0, 1, 0, 0, 0, 1, 0, 2.0], [1.0], [2.0], [50.0], [3.0], [4.0]).tolist()
    [[6.0, 6.0, 12.0, 8.0, 8.0, 16.0, 1.0, 50.0]]
    """
    r1 = float(np.asarray(params, float)[7])
    x, y, g, gx, gy = (np.asarray(v, float).ravel() for v in (x, y, g, gx, gy))
    return np.column_stack([r1 * gx, r1 * gx * x, r1 * gx * y, r1 * gy, r1 * gy * x,
                            r1 * gy * y, np.ones_like(g), g])


def least_squares_matching(template, search, initial, *, tol: float = 1e-4, max_iter: int = 30,
                           check: bool = True) -> LSMResult:
    r"""Least-squares matching of ``template`` in ``search`` (affine + linear radiometric).

    Each iteration resamples the search image and its gradient at
    :math:`x' = a_0 + a_1x + a_2y`, :math:`y' = b_0 + b_1x + b_2y` (bilinear as
    :func:`photolib.rectify.sample_image`, the three images in one gather), solves the normal
    equations of :func:`lsm_design_matrix` for the increments and adds them. It stops when no
    template pixel moves by ``tol`` pixels or more in a step. The normal equations count as
    singular when the condition number of :math:`N` scaled to unit diagonal,
    :math:`λ_{max}/λ_{min}` (symmetric eigenvalues), exceeds :math:`10^{12}`.
    The precision is :math:`σ_0 = \sqrt{v^Tv/(n - 8)}` and
    :math:`Σ = σ_0^2 (A^TA)^{-1}`.

    Parameters
    ----------
    template : array_like, shape (h, w)
        The pattern f, at least 3 × 3 pixels (more than the 8 unknowns), with texture.
    search : array_like, shape (H, W)
        The search image g.
    initial : array_like, shape (2,) or (8,)
        Start values: the approximate position (col, row) of the template centre in the
        search image (then a1 = b2 = r1 = 1, the rest 0), or all eight parameters.
    tol : float
        Convergence tolerance in pixels.
    max_iter : int
        Iteration limit.
    check : bool
        If False, return the last iterate with ``converged = False`` instead of raising when
        the iteration limit is reached.

    Returns
    -------
    LSMResult

    Raises
    ------
    ValueError
        If the template is flat (no grey-value gradient: the shifts are undetermined) or the
        normal equations are singular.
    StartOutsideImageError
        A ``ValueError`` (:class:`photolib.errors.InputError`) naming ``initial``
        when the patch at the start values does not lie inside the search image.
    ConvergenceError
        If the patch leaves the search image (divergence; the exception's ``history``
        attribute holds the iterates up to then) or the iteration limit is reached.
        (A rotationally symmetric target leaves its rotation undetermined: a1, a2, b1, b2
        wander and the iteration does not settle — match such targets by shift only.)

    Examples
    --------
    >>> yy, xx = np.mgrid[:40, :40].astype(float)
    >>> g = 100 + 40 * np.sin(xx / 3) * np.cos(yy / 4) + 0.5 * xx
    >>> f = 5 + 0.9 * g[12:25, 14:27]                # centre at col 20, row 18
    >>> res = least_squares_matching(f, g, (19.0, 19.0))
    >>> res.position.round(6).tolist(), res.params[6:].round(3).tolist(), res.converged
    ([20.0, 18.0], [5.0, 0.9], True)
    """
    f = as_float_array(template, "template")
    g_img = as_float_array(search, "search")
    for arr, name in ((f, "template"), (g_img, "search")):
        if arr.ndim != 2 or min(arr.shape) < 3:
            raise ValueError(f"{name} has shape {arr.shape}; expected a 2-D image of at least 3 × 3")
        check_finite(arr, name)
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    q = as_float_array(initial, "initial").ravel()
    if q.shape == (2,):
        q = np.array([q[0], 1.0, 0.0, q[1], 0.0, 1.0, 0.0, 1.0])
    if q.shape != (8,):
        raise ValueError(f"initial has shape {np.shape(initial)}; expected (2,) or (8,)")
    check_finite(q, "initial")
    fy, fx = np.gradient(f)
    texture = float(np.sqrt(np.mean(fx**2 + fy**2)))
    if texture <= 1e-9 * max(1.0, float(np.max(np.abs(f)))):
        raise ValueError("the template is flat (no grey-value gradient): its position cannot "
                         "be determined by matching")
    gy_img, gx_img = np.gradient(g_img)
    planes = np.stack([g_img.ravel(), gx_img.ravel(), gy_img.ravel()])  # sampled together
    x, y = _template_coordinates(f.shape)
    fv = f.ravel()
    hx, hy = float(np.max(np.abs(x))), float(np.max(np.abs(y)))
    H, W = g_img.shape
    history = [q.copy()]
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        a0, a1, a2, b0, b1, b2, r0, r1 = q.tolist()       # Python floats: cheaper, same values
        cols = a0 + a1 * x + a2 * y
        rows = b0 + b1 * x + b2 * y
        if not (cols.min() >= 0 and rows.min() >= 0 and cols.max() <= W - 1
                and rows.max() <= H - 1):                  # (NaN positions count as outside)
            raise _outside_error(it, initial, a0, b0, f.shape, W, H, history)
        g, gx, gy = _bilinear(planes, W, cols, rows)
        A = _design(r1, x, y, g, gx, gy)
        l = fv - (r0 + r1 * g)  # noqa: E741 - the usual name of the observation vector
        dq = _increment(A, l)
        q = q + dq
        history.append(q)
        if not np.isfinite(q).all():
            raise ConvergenceError(f"least-squares matching diverged at iteration {it}")
        d = np.abs(dq).tolist()
        move = max(d[0] + d[1] * hx + d[2] * hy, d[3] + d[4] * hx + d[5] * hy)
        if move < tol:
            converged = True
            break
    if not converged and check:
        raise ConvergenceError(f"least-squares matching did not converge in {max_iter} "
                               f"iterations (last shift step {np.hypot(dq[0], dq[3]):.3g} px)")
    return _lsm_result(q, planes, W, H, x, y, fv, f.shape, it, converged, history)


def _outside_error(it, initial, a0, b0, shape, W, H, history) -> ConvergenceError:
    """The error of :func:`least_squares_matching` when the patch leaves the search image.

    In iteration 1 the start itself does not fit (a :class:`StartOutsideImageError` naming
    ``initial``), later the iteration diverged (a :class:`ConvergenceError`). ``a0, b0``:
    the patch centre (col, row, pixels); ``shape``: the template's (h, w); ``W × H``: the
    search image. The iterates so far are attached as ``history``.
    """
    if it == 1:  # not a divergence: the start itself does not fit
        given = [float(v) for v in np.ravel(as_float_array(initial, "initial"))]
        start = f"({given[0]!r}, {given[1]!r})" if len(given) == 2 else repr(given)
        err = StartOutsideImageError(
            f"least-squares matching cannot start: the patch at the initial position "
            f"initial = {start} (centre col {a0:.2f}, row {b0:.2f}) does not lie inside "
            f"the search image of {W} × {H} pixels (the {shape[1]} × {shape[0]} "
            "template must fit into it); move the start away from the border")
    else:
        err = ConvergenceError(
            f"least-squares matching diverged: after {it - 1} iterations the patch "
            f"(centre col {a0:.2f}, row {b0:.2f}) leaves the search image of "
            f"{W} × {H} pixels")
    err.history = np.array(history)
    return err


def _increment(A, l) -> np.ndarray:  # noqa: E741 - the usual name of the observation vector
    """Increments ``dq = N⁻¹ Aᵀl`` of the eight LSM parameters, ``N = AᵀA``.

    Raises ``ValueError`` when ``N`` scaled to unit diagonal has condition number
    ``λmax/λmin`` above 1e12 (cond₂ of a symmetric positive semi-definite matrix; no SVD
    needed), i.e. the patch has no texture in one direction.
    """
    N = A.T @ A
    s = np.sqrt(N.diagonal())
    lam = np.linalg.eigvalsh(N / (s[:, None] * s)) if s.all() else (0.0, 1.0)
    if not lam[0] * 1e12 >= lam[-1]:
        raise ValueError("the normal equations of the matching are singular: the search "
                         "patch has no texture in one direction (flat or one-dimensional)")
    return np.linalg.solve(N, A.T @ l)


def _lsm_result(q, planes, W, H, x, y, fv, shape, it, converged, history) -> LSMResult:
    """The :class:`LSMResult` at the parameters ``q`` of :func:`least_squares_matching`.

    Resamples the search image at ``q`` (positions clipped to the image), residuals
    ``v = f − (r0 + r1·g)``, ``σ0 = √(vᵀv / (n − 8))`` (grey values) and
    ``Σ = σ0² (AᵀA)⁻¹``.
    """
    a0, a1, a2, b0, b1, b2, r0, r1 = q.tolist()
    cols = np.clip(a0 + a1 * x + a2 * y, 0, W - 1)
    rows = np.clip(b0 + b1 * x + b2 * y, 0, H - 1)
    g, gx, gy = _bilinear(planes, W, cols, rows)
    v = fv - (r0 + r1 * g)
    A = _design(r1, x, y, g, gx, gy)
    red = len(fv) - 8
    sigma0 = float(np.sqrt(v @ v / red))
    cov = sigma0**2 * np.linalg.inv(A.T @ A)
    return LSMResult(q, np.sqrt(np.diag(cov)), sigma0, cov, v.reshape(shape), it, converged,
                     np.array(history))
