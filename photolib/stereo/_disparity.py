r"""Depth from the disparity of a rectified pixel pair (Middlebury style calibration).

A rectified pair is the normal case (Normalfall) in pixels: camera 1 (left) at the origin,
camera 2 (right) at ``(B, 0, 0)``, R = I, focal length f in pixels, principal points
``(cx1, cy)`` and ``(cx2, cy)`` with ``doffs = cx2 − cx1``. The disparity of a point is
``d = u1 − u2`` (columns, px). With ``x' − x'0 = (u − cx)·p`` and ``y' − y'0 = −(v − cy)·p``
(pixel pitch p, the image y axis up, rows down), ``c = f·p`` and the normal-case parallax
``px' = (d + doffs)·p`` (derived in :func:`photolib.derive.stereo.depth_from_disparity`):

    ``Z = −f·B/(d + doffs)``, ``X = (u1 − cx1)·B/(d + doffs)``, ``Y = −(v − cy)·B/(d + doffs)``

(Z < 0: the camera looks down −Z; the distance is ``h = −Z``), and the pixel pitch cancels.
Error propagation gives ``σ_Z = Z²/(f·B)·σ_d``.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, as_scalar
from photolib.collinearity import PointBehindCameraError
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError


def _shifted(d, doffs):
    d = as_float_array(d, "d")
    if not np.all(np.isfinite(d)):
        raise ValueError(f"d contains a non-finite value: {d.ravel().tolist()[:5]}")
    s = d + as_scalar(doffs, "doffs")
    if np.any(s == 0):
        i = int(np.flatnonzero(s.ravel() == 0)[0])
        raise DegenerateGeometryError(
            f"d[{i}] + doffs = 0 (d = {float(d.ravel()[i])!r}, doffs = {float(doffs)!r}): "
            "zero parallax means parallel rays, the point is at infinity")
    if np.any(s < 0):
        i = int(np.flatnonzero(s.ravel() < 0)[0])
        raise PointBehindCameraError(
            f"d[{i}] + doffs = {float(s.ravel()[i])!r} < 0: the point would lie behind the "
            "cameras (are the images swapped? the disparity is d = u_left − u_right)")
    return s


def depth_from_disparity(d, f, B, doffs=0.0):
    r"""Z of a rectified pair from the disparity / Tiefe aus der Disparität.

    Parameters
    ----------
    d : float or array_like
        Disparity ``d = u1 − u2`` (px): column in the left image minus column in the right.
    f : float
        Focal length (camera constant / Kamerakonstante) in pixels, > 0.
    B : float
        Base (Basis), > 0 (object unit, e.g. mm).
    doffs : float
        Difference of the principal points ``cx2 − cx1`` (px).

    Returns
    -------
    float or ndarray
        ``Z = −f·B/(d + doffs)`` (unit of B), negative: the distance is ``−Z``.

    Raises
    ------
    DegenerateGeometryError
        ``d + doffs = 0`` (parallel rays).
    PointBehindCameraError
        ``d + doffs < 0`` (behind the cameras).

    Examples
    --------
    >>> depth_from_disparity(50.0, 1000.0, 200.0, doffs=30.0)
    -2500.0
    """
    f = as_scalar(f, "f", positive=True)
    B = as_scalar(B, "B", positive=True)
    Z = -f * B / _shifted(d, doffs)
    return float(Z) if np.ndim(Z) == 0 else Z


def points_from_disparity(u, v, d, f, B, cx, cy, doffs=0.0):
    r"""Object points ``(X, Y, Z)`` of left-image pixels ``(u, v)`` with disparity d.

    Parameters
    ----------
    u, v : float or array_like
        Column and row of the point in the left image (px; (0, 0) is the centre of the
        top-left pixel, rows down).
    d : float or array_like
        Disparity ``u1 − u2`` (px).
    f, B, doffs
        As in :func:`depth_from_disparity`.
    cx, cy : float
        Principal point of the left image (px).

    Returns
    -------
    ndarray, shape (..., 3)
        ``X = (u − cx)·B/(d + doffs)``, ``Y = −(v − cy)·B/(d + doffs)``,
        ``Z = −f·B/(d + doffs)`` (unit of B; course frame, y up, camera looking down −Z).

    Examples
    --------
    >>> points_from_disparity(110.0, 40.0, 50.0, 1000.0, 200.0, 100.0, 50.0, 30.0).tolist()
    [25.0, 25.0, -2500.0]
    """
    f = as_scalar(f, "f", positive=True)
    B = as_scalar(B, "B", positive=True)
    s = _shifted(d, doffs)
    u, v = as_float_array(u, "u"), as_float_array(v, "v")
    k = B / s
    return np.stack(np.broadcast_arrays((u - as_scalar(cx, "cx")) * k,
                                        -(v - as_scalar(cy, "cy")) * k, -f * k), axis=-1)


def depth_sigma(Z, f, B, sigma_d):
    r"""Standard deviation of the depth from that of the disparity.

    Parameters
    ----------
    Z : float or array_like
        Depth (unit of B).
    f : float
        Focal length (px), > 0.
    B : float
        Base (unit of Z), > 0.
    sigma_d : float or array_like
        σ of the disparity (px).

    Returns
    -------
    float or ndarray
        ``σ_Z = |∂Z/∂d|·σ_d = Z²/(f·B)·σ_d`` (unit of B).

    Examples
    --------
    >>> depth_sigma(-2500.0, 1000.0, 200.0, 0.1)
    3.125
    """
    f = as_scalar(f, "f", positive=True)
    B = as_scalar(B, "B", positive=True)
    Z, s = as_float_array(Z, "Z"), as_float_array(sigma_d, "sigma_d")
    if np.any(s < 0):
        raise ValueError(f"sigma_d must be ≥ 0 px, got {s.ravel().tolist()[:5]}")
    out = Z**2 / (f * B) * s
    return float(out) if np.ndim(out) == 0 else out


def _texture(gray, half):
    """Smallest eigenvalue of the structure tensor summed over (2·half + 1)² windows."""
    gy, gx = np.gradient(gray)
    from photolib.correlation import _box_sums
    w = 2 * half + 1
    sums = [_box_sums(a, w, w) for a in (gx * gx, gx * gy, gy * gy)]
    a, b, c = sums
    tr, det = a + c, a * c - b * b
    return tr / 2 - np.sqrt(np.maximum(tr**2 / 4 - det, 0.0))


def textured_points(gray, n, half=7, spacing=12, border=None, valid=None):
    """Up to ``n`` well-textured pixels (col, row) of ``gray`` on a grid, best first.

    Parameters
    ----------
    gray : array_like, shape (H, W)
        Grey-value image.
    n : int
        Number of points wanted (≥ 1).
    half : int
        Half size of the (2·half + 1)² window the texture is measured in.
    spacing : int
        Grid spacing of the candidates (px).
    border : int, optional
        Smallest distance of a candidate from the image edge (default ``half + 1``).
    valid : array_like of bool, shape (H, W), optional
        Candidates where it is False are dropped (e.g. no ground truth).

    Returns
    -------
    ndarray, shape (≤ n, 2)
        (col, row) as floats, ranked by the smallest eigenvalue of the structure tensor of
        their window (Förstner's / Shi–Tomasi's interest value: texture in every direction).

    Examples
    --------
    >>> img = np.zeros((40, 40)); img[20:, 20:] = 1.0          # one corner at (20, 20)
    >>> textured_points(img, 1, half=3, spacing=4).tolist()
    [[20.0, 20.0]]
    """
    gray = as_float_array(gray, "gray")
    if gray.ndim != 2:
        raise ValueError(f"gray has shape {gray.shape}; expected a 2-D image")
    n, half, spacing = int(n), int(half), int(spacing)
    if n < 1 or half < 1 or spacing < 1:
        raise ValueError(f"n, half and spacing must be ≥ 1, got {n}, {half}, {spacing}")
    border = half + 1 if border is None else int(border)
    lam = _texture(gray, half)              # (H − w + 1, W − w + 1), window top-left
    rows = np.arange(border, gray.shape[0] - border, spacing)
    cols = np.arange(border, gray.shape[1] - border, spacing)
    rr, cc = (a.ravel() for a in np.meshgrid(rows, cols, indexing="ij"))
    score = lam[rr - half, cc - half]
    if valid is not None:
        keep = np.asarray(valid, bool)[rr, cc]
        rr, cc, score = rr[keep], cc[keep], score[keep]
    order = np.argsort(-score, kind="stable")[:n]
    return np.column_stack([cc[order], rr[order]]).astype(float)


def match_disparities(left, right, points, d_range, half=7, lsm=True):
    r"""Disparities of left-image points in a rectified pair by NCC along the row, then LSM.

    Parameters
    ----------
    left, right : array_like, shape (H, W)
        Grey-value images of the rectified pair.
    points : array_like, shape (N, 2)
        Integer (col, row) of the points in the left image.
    d_range : (float, float)
        Smallest and largest disparity searched (px): the search window in the right image
        is the same row, columns ``u − d_max … u − d_min`` (the epipolar line is the row).
    half : int
        Half size of the (2·half + 1)² template.
    lsm : bool
        Refine the NCC peak (parabola subpixel) by least-squares matching
        (:func:`photolib.matching.least_squares_matching`).

    Returns
    -------
    d, sigma, rho : ndarray, shape (N,)
        Disparity ``u_left − u_right`` (px; NaN where no match), its σ (px: σ of the LSM
        shift a0, NaN without LSM) and the NCC peak.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> right = rng.uniform(0, 255, (30, 80))
    >>> left = np.roll(right, 12, axis=1)                    # every point 12 px further right
    >>> d, _, rho = match_disparities(left, right, [[40, 15]], (5, 20), half=4, lsm=False)
    >>> np.round(d, 1).tolist(), bool(rho[0] > 0.99)        # subpixel parabola: 12 ± 0.01
    ([12.0], True)
    """
    from photolib.correlation import ncc_match
    from photolib.matching import least_squares_matching
    L, Rg = as_float_array(left, "left"), as_float_array(right, "right")
    pts = np.asarray(points, int)
    dmin, dmax = (float(v) for v in d_range)
    if not 0 <= dmin < dmax:
        raise ValueError(f"d_range must satisfy 0 ≤ d_min < d_max, got {d_range!r}")
    n = len(pts)
    d, sig, rho = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    H, W = Rg.shape
    for i, (u, v) in enumerate(pts):
        tpl = L[v - half:v + half + 1, u - half:u + half + 1]
        lo = max(int(np.floor(u - dmax)) - half - 1, 0)
        hi = min(int(np.ceil(u - dmin)) + half + 2, W)
        if tpl.shape != (2 * half + 1,) * 2 or hi - lo < 2 * half + 4:
            continue
        strip = Rg[v - half - 1:v + half + 2, lo:hi]
        try:
            m = ncc_match(tpl, strip, min_rho=0.7)
        except ValueError:
            continue
        col = lo + m.position[0]
        rho[i] = m.rho
        if lsm:
            try:
                res = least_squares_matching(tpl, Rg, (col, float(v)), tol=1e-3, max_iter=20)
            except (ValueError, ConvergenceError):
                continue
            if abs(res.position[0] - col) > 1.0 or abs(res.position[1] - v) > 1.0:
                continue
            col, sig[i] = res.position[0], res.std[0]
        d[i] = u - col
    return d, sig, rho
