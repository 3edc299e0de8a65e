"""Area-based matching by normalised cross-correlation / Kreuzkorrelation (NCC), and RANSAC.

* :func:`normalised_cross_correlation`: the correlation coefficient of a template f with every
  window of a search image g of the same size,

      ρ(u, v) = Σ (f − f̄)(g_uv − ḡ_uv) / √(Σ (f − f̄)² · Σ (g_uv − ḡ_uv)²),

  computed with box sums (integral images), so the cost does not grow with the template size
  for the sums of g. −1 ≤ ρ ≤ 1; a flat window (no texture) gives NaN, not a false peak.
* :func:`ncc_match`: the best window and its subpixel position, from a parabola through the
  peak and its two neighbours in each axis, ``δ = (ρ₋ − ρ₊)/(2(ρ₋ − 2ρ₀ + ρ₊))``; the start
  for least-squares matching (:func:`photolib.least_squares_matching`), which refines it.
* :func:`ransac`: random sample consensus with any estimator inside the loop (photolib's
  ``ProjectiveTransform.from_estimate``, a relative orientation, …) and the number of trials
  from the outlier rate, ``N = log(1 − p)/log(1 − (1 − ε)^s)`` (:func:`ransac_trials`),
  updated from the best inlier ratio found so far.
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_int, as_scalar, check_finite
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError

__all__ = ["NCCMatch", "RansacResult", "ncc_match", "normalised_cross_correlation", "ransac",
           "ransac_trials"]


def _image(a, name):
    arr = as_float_array(a, name)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D grey-value image, got shape {arr.shape}")
    check_finite(arr, name)
    return arr


def _box_sums(a, h, w):
    """Sums of every h×w window of ``a`` (valid positions), by an integral image."""
    s = np.zeros((a.shape[0] + 1, a.shape[1] + 1))
    s[1:, 1:] = a.cumsum(0).cumsum(1)
    return s[h:, w:] - s[:-h, w:] - s[h:, :-w] + s[:-h, :-w]


def normalised_cross_correlation(template, search):
    """Correlation coefficient ρ of ``template`` with every window of ``search``.

    Parameters
    ----------
    template : array_like, shape (h, w)
        Template f (Muster), grey values; not constant.
    search : array_like, shape (H, W)
        Search image g (Suchbild), H ≥ h, W ≥ w.

    Returns
    -------
    ndarray, shape (H − h + 1, W − w + 1)
        ρ[row, col] for the window whose top-left pixel is (col, row); NaN where the window is
        flat (zero variance: no texture to correlate).

    Examples
    --------
    >>> g = np.arange(25.0).reshape(5, 5) ** 1.5
    >>> rho = normalised_cross_correlation(g[1:4, 2:5], g)
    >>> np.unravel_index(np.nanargmax(rho), rho.shape), round(float(np.nanmax(rho)), 12)
    ((np.int64(1), np.int64(2)), 1.0)
    """
    f = _image(template, "template")
    g = _image(search, "search")
    h, w = f.shape
    if g.shape[0] < h or g.shape[1] < w:
        raise ValueError(f"search image {g.shape} is smaller than the template {f.shape}")
    fz = f - f.mean()
    f_norm = math.sqrt(float(np.sum(fz * fz)))
    if not f_norm > 0:
        raise ValueError("template is constant: it has no texture to correlate")
    windows = np.lib.stride_tricks.sliding_window_view(g, (h, w))
    cross = np.einsum("ijkl,kl->ij", windows, fz)        # Σ (f − f̄)·g = Σ (f − f̄)(g − ḡ)
    n = h * w
    sum_g = _box_sums(g, h, w)
    var_g = _box_sums(g * g, h, w) - sum_g**2 / n
    scale = np.sqrt(np.maximum(var_g, 0.0)) * f_norm
    flat = var_g <= 1e-12 * max(float(np.max(np.abs(var_g))), 1e-300)
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(flat, np.nan, cross / np.where(flat, 1.0, scale))
    return np.clip(rho, -1.0, 1.0)


class NCCMatch(NamedTuple):
    """Best window of :func:`ncc_match`."""

    position: np.ndarray  #: (2,) (col, row) of the template centre in the search image, subpixel
    integer: tuple  #: (col, row) of the best window's top-left pixel
    rho: float  #: peak correlation coefficient
    surface: np.ndarray  #: the whole correlation surface


def ncc_match(template, search, *, min_rho: float = 0.5) -> NCCMatch:
    """Find ``template`` in ``search`` by NCC, with the subpixel peak.

    Parameters
    ----------
    template, search : array_like
        As in :func:`normalised_cross_correlation`.
    min_rho : float
        The peak must reach this correlation, else the match is refused.

    Returns
    -------
    NCCMatch
        ``position`` is the template centre, ``((w − 1)/2, (h − 1)/2)`` added to the window's
        top-left corner plus the parabola offsets (pixel convention of the course: (0, 0) is
        the centre of the top-left pixel).

    Raises
    ------
    ValueError
        No peak above ``min_rho`` (no match), or the peak on the border of the surface (the
        subpixel parabola needs both neighbours: enlarge the search image).

    Examples
    --------
    >>> yy, xx = np.mgrid[0:40, 0:40]
    >>> blob = lambda cx, cy: np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / 18.0)
    >>> m = ncc_match(blob(20.0, 20.0)[12:29, 12:29], blob(17.3, 22.6))
    >>> np.round(m.position, 1).tolist()
    [17.3, 22.6]
    """
    rho = normalised_cross_correlation(template, search)
    min_rho = as_scalar(min_rho, "min_rho")
    if np.all(np.isnan(rho)):
        raise ValueError("the search image is flat everywhere: nothing to match")
    r, c = np.unravel_index(np.nanargmax(rho), rho.shape)
    peak = float(rho[r, c])
    if peak < min_rho:
        raise ValueError(f"no match: the best correlation is {peak:.3f} < min_rho = {min_rho}")
    if not (0 < r < rho.shape[0] - 1 and 0 < c < rho.shape[1] - 1):
        raise ValueError(f"the correlation peak lies on the border of the search area (window "
                         f"at col {c}, row {r}): enlarge the search image by a pixel on each side")

    def offset(m, z, p):
        den = m - 2.0 * z + p
        return 0.5 * (m - p) / den if den < 0 else 0.0

    dc = offset(rho[r, c - 1], peak, rho[r, c + 1])
    dr = offset(rho[r - 1, c], peak, rho[r + 1, c])
    h, w = np.shape(template)
    pos = np.array([c + dc + (w - 1) / 2.0, r + dr + (h - 1) / 2.0])
    return NCCMatch(pos, (int(c), int(r)), peak, rho)


# -- RANSAC ---------------------------------------------------------------------------------------

def ransac_trials(confidence, outlier_ratio, sample_size):
    """Number of random samples N that contain one outlier-free sample with probability p.

    Parameters
    ----------
    confidence : float
        p, in (0, 1).
    outlier_ratio : float
        ε, the share of outliers, in [0, 1).
    sample_size : int
        s, the minimal number of points of the estimator (4 for a homography).

    Returns
    -------
    int
        ``N = ⌈log(1 − p)/log(1 − (1 − ε)^s)⌉``: a sample is clean with probability
        ``(1 − ε)^s``, all N samples are contaminated with ``(1 − (1 − ε)^s)^N ≤ 1 − p``.

    Examples
    --------
    >>> ransac_trials(0.99, 0.3, 4), ransac_trials(0.99, 0.5, 4), ransac_trials(0.99, 0.5, 8)
    (17, 72, 1177)
    """
    p = as_scalar(confidence, "confidence")
    eps = as_scalar(outlier_ratio, "outlier_ratio")
    s = as_int(sample_size, "sample_size", minimum=1)
    if not 0 < p < 1:
        raise ValueError(f"confidence must lie in (0, 1), got {p}")
    if not 0 <= eps < 1:
        raise ValueError(f"outlier_ratio must lie in [0, 1), got {eps}")
    clean = (1.0 - eps) ** s
    if clean >= 1.0:
        return 1
    if clean <= 0.0:
        raise ValueError("with this outlier ratio no sample is ever clean")
    return max(1, math.ceil(math.log(1.0 - p) / math.log1p(-clean)))


class RansacResult(NamedTuple):
    """Result of :func:`ransac`."""

    model: object  #: the estimator refitted on the inliers (repeated until they are stable)
    inliers: np.ndarray  #: (N,) bool
    trials: int  #: samples drawn
    required_trials: int  #: N from the final inlier ratio


def ransac(n, sample_size, fit: Callable, residuals: Callable, threshold, *,
           confidence: float = 0.99, max_trials: int = 10_000, rng=None) -> RansacResult:
    """Random sample consensus: the model with most inliers, refitted on them.

    Parameters
    ----------
    n : int
        Number of observations (correspondences).
    sample_size : int
        Minimal sample s of the estimator.
    fit : callable
        ``fit(indices) -> model``: the estimator on the observations ``indices`` (an int
        array); it may raise ``DegenerateGeometryError``, ``ConvergenceError`` or
        ``ValueError`` for a degenerate sample, which is then skipped.
    residuals : callable
        ``residuals(model) -> (n,)`` absolute residual of every observation.
    threshold : float
        Inlier bound on the residual (e.g. 3σ of the measurements), > 0.
    confidence : float
        p of :func:`ransac_trials`; the number of trials is updated from the best inlier ratio.
    max_trials : int
        Upper bound on the samples drawn.
    rng : numpy.random.Generator or int, optional
        Random source (seeded for reproducible results).

    Returns
    -------
    RansacResult

    Raises
    ------
    DegenerateGeometryError
        No sample gave a model with more inliers than its own ``sample_size`` points.

    Examples
    --------
    >>> import photolib as pl
    >>> rng = np.random.default_rng(0)
    >>> src = rng.uniform(0, 100, (40, 2))
    >>> dst = pl.ProjectiveTransform(2, 1.1, 0.1, 3, -0.1, 0.9, 1e-3, 2e-3)(src)
    >>> dst[:8] += rng.uniform(20, 40, (8, 2))                      # 8 gross errors
    >>> res = ransac(40, 4, lambda i: pl.ProjectiveTransform.from_estimate(src[i], dst[i]),
    ...              lambda T: np.linalg.norm(T(src) - dst, axis=1), 0.5, rng=1)
    >>> int(res.inliers.sum()), bool(res.inliers[:8].any())
    (32, False)
    """
    n = as_int(n, "n", minimum=1)
    s = as_int(sample_size, "sample_size", minimum=1)
    if n < s:
        raise ValueError(f"{n} observations are fewer than the sample size {s}")
    threshold = as_scalar(threshold, "threshold", positive=True)
    max_trials = as_int(max_trials, "max_trials", minimum=1)
    rng = np.random.default_rng(rng)
    best, best_count, required, trials = None, 0, max_trials, 0
    while trials < min(required, max_trials):
        trials += 1
        idx = rng.choice(n, s, replace=False)
        try:
            model = fit(idx)
        except (DegenerateGeometryError, ConvergenceError, ValueError, np.linalg.LinAlgError):
            continue
        inliers = np.asarray(residuals(model), float) <= threshold
        count = int(inliers.sum())
        if count > best_count:
            best, best_count = inliers, count
            required = ransac_trials(confidence, 1.0 - count / n, s) if count < n else 1
    if best is None or best_count <= s:
        raise DegenerateGeometryError(
            f"RANSAC found no model supported by more than its own {s} sample points in "
            f"{trials} samples (threshold {threshold:g}): the threshold is too small or the "
            "data have no consensus")
    # refit on the consensus set until it no longer changes: the minimal sample's model may
    # miss good points near the threshold that the refitted model takes in
    inliers = best
    for _ in range(10):
        model = fit(np.flatnonzero(inliers))
        refitted = np.asarray(residuals(model), float) <= threshold
        if np.array_equal(refitted, inliers) or refitted.sum() <= s:
            break
        inliers = refitted
    return RansacResult(model, refitted, trials, required)
