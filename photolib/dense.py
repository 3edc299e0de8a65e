r"""Dense matching of a rectified pair / dichte Bildzuordnung: block matching and its errors.

For a rectified (epipolar) pair a left pixel (col, row) matches the right pixel
(col − d, row) of the same row; :func:`block_matching` finds the disparity d of every pixel
as the minimum over ``d = d_min … d_max`` of the sum of absolute differences (SAD) of a
(2h + 1)² window, all pixels and disparities at once with box sums (integral images),
refined to subpixel by the parabola through the cost minimum and its two neighbours,

.. math:: δ = \frac{C_{-} - C_{+}}{2(C_{-} - 2C_0 + C_{+})}

(the vertex of the parabola through (−1, C₋), (0, C₀), (1, C₊): derived in
:mod:`photolib.derive.matching`). A pixel is refused (NaN) when its best cost is not unique
(``uniqueness``: the second best, one or more disparities away, must be worse by that
ratio), when the window is flat, or when d reaches the search range's end.
:func:`disparity_errors` compares a disparity map with a ground truth.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_int, check_finite

__all__ = ["DisparityErrors", "block_matching", "disparity_errors", "parabola_vertex"]


def parabola_vertex(c_minus, c0, c_plus):
    """Offset δ of the vertex of the parabola through (−1, c₋), (0, c₀), (1, c₊).

    ``δ = (c₋ − c₊)/(2(c₋ − 2c₀ + c₊))``; NaN where the three values are collinear.

    >>> float(parabola_vertex(4.0, 1.0, 2.0))
    0.25
    """
    cm, c0, cp = (np.asarray(v, float) for v in (c_minus, c0, c_plus))
    den = cm - 2.0 * c0 + cp
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den != 0, 0.5 * (cm - cp) / np.where(den != 0, den, 1.0), np.nan)


def _grey(a, name):
    g = as_float_array(a, name)
    if g.ndim == 3:
        g = g[..., :3] @ np.array([0.299, 0.587, 0.114])
    if g.ndim != 2:
        raise ValueError(f"{name} must be a grey (H, W) or RGB (H, W, 3) image, got {g.shape}")
    check_finite(g, name)
    return g


def block_matching(left, right, d_min: int, d_max: int, half: int = 3,
                   uniqueness: float = 0.05) -> np.ndarray:
    """Disparity map of the left image (px, NaN where refused) by SAD block matching.

    Parameters
    ----------
    left, right : array_like, shape (H, W) or (H, W, 3)
        The rectified pair (RGB is converted to grey, 0.299R + 0.587G + 0.114B).
    d_min, d_max : int
        Search range of the disparity, px, ``0 ≤ d_min < d_max - 1``.
    half : int
        Half width h of the (2h + 1) × (2h + 1) window.
    uniqueness : float
        The best cost must be below ``(1 − uniqueness)`` times every cost at least two
        disparities away.

    Returns
    -------
    ndarray, shape (H, W), float: d with subpixel refinement; NaN at refused pixels, in the
    ``d_max`` left columns and within ``half`` of the border.

    Raises
    ------
    ValueError
        Different image sizes, a bad search range, or a window wider than the image.
    """
    L, R = _grey(left, "left"), _grey(right, "right")
    if L.shape != R.shape:
        raise ValueError(f"left {L.shape} and right {R.shape} must have the same size")
    d_min = as_int(d_min, "d_min", minimum=0)
    d_max = as_int(d_max, "d_max", minimum=0)
    h = as_int(half, "half", minimum=1)
    if d_max < d_min + 2:
        raise ValueError(f"the search range d_min = {d_min} … d_max = {d_max} needs at least "
                         "three disparities (the subpixel parabola needs both neighbours)")
    H, W = L.shape
    if W <= d_max + 2 * h + 1 or H <= 2 * h + 1:
        raise ValueError(f"the image ({W} × {H} px) is too small for d_max = {d_max} and a "
                         f"{2 * h + 1}-pixel window")
    k = 2 * h + 1
    ds = np.arange(d_min, d_max + 1)
    cost = np.full((len(ds), H, W), np.inf)
    for i, d in enumerate(ds):
        ad = np.abs(L[:, d:] - R[:, :W - d])                 # left col c ↔ right col c − d
        s = np.zeros((H + 1, W - d + 1))
        s[1:, 1:] = ad.cumsum(0).cumsum(1)
        box = s[k:, k:] - s[:-k, k:] - s[k:, :-k] + s[:-k, :-k]
        cost[i, h:H - h, d + h:W - h] = box
    best = np.argmin(cost, axis=0)
    rr, cc = np.indices((H, W))
    c0 = cost[best, rr, cc]
    valid = np.isfinite(c0) & (best > 0) & (best < len(ds) - 1)
    bm, bp = np.clip(best - 1, 0, len(ds) - 1), np.clip(best + 1, 0, len(ds) - 1)
    cm, cp = cost[bm, rr, cc], cost[bp, rr, cc]
    near = np.abs(np.arange(len(ds))[:, None, None] - best) <= 1
    second = np.where(near, np.inf, cost).min(axis=0)
    valid &= c0 < (1.0 - uniqueness) * second
    with np.errstate(invalid="ignore"):
        delta = parabola_vertex(cm, c0, cp)
    valid &= np.isfinite(delta) & (np.abs(delta) <= 1.0)
    disp = ds[best] + np.where(valid, delta, 0.0)
    disp = np.where(valid, disp, np.nan)
    disp[:, :d_max + h] = np.nan
    return disp


class DisparityErrors(NamedTuple):
    """Statistics of :func:`disparity_errors` (px, on pixels where both maps are finite)."""

    n: int               #: pixels compared
    coverage: float      #: share of the ground-truth pixels that the estimate covers
    mean: float          #: mean error (estimate − truth)
    median_abs: float    #: median |error|
    rms: float           #: root mean square error
    nmad: float          #: 1.4826 · median |error − median error| (robust σ)
    bad1: float          #: share with |error| > 1 px
    bad2: float          #: share with |error| > 2 px


def disparity_errors(estimate, truth, mask=None) -> DisparityErrors:
    """Compare a disparity map with the ground truth (Middlebury's bad-pixel rates).

    >>> e = disparity_errors([[1.0, 2.5, np.nan]], [[1.0, 2.0, 3.0]])
    >>> e.n, round(e.coverage, 3), e.bad1
    (2, 0.667, 0.0)
    """
    est = np.asarray(estimate, float)
    gt = np.asarray(truth, float)
    if est.shape != gt.shape:
        raise ValueError(f"estimate {est.shape} and truth {gt.shape} differ in shape")
    known = np.isfinite(gt) if mask is None else (np.isfinite(gt) & np.asarray(mask, bool))
    both = known & np.isfinite(est)
    if not both.any():
        raise ValueError("no pixel has both an estimate and a ground truth")
    e = est[both] - gt[both]
    med = float(np.median(e))
    return DisparityErrors(int(both.sum()), float(both.sum() / known.sum()), float(e.mean()),
                           float(np.median(np.abs(e))), float(np.sqrt(np.mean(e * e))),
                           float(1.4826 * np.median(np.abs(e - med))),
                           float(np.mean(np.abs(e) > 1.0)), float(np.mean(np.abs(e) > 2.0)))
