r"""Targets in a real photograph / Zielmarken in einer realen Aufnahme.

:func:`yellowness` turns an RGB image into a grey-value image in which yellow targets are
bright (``min(R, G) − B``: grey surfaces have R ≈ G ≈ B and give ≈ 0); :func:`measure_targets`
segments it (threshold midway between the two levels of the moment-preserving threshold),
and measures each large blob three ways: the binary centroid, the grey-value weighted
centroid (:func:`~photolib.measurement.weighted_centroid`, with its precision from the noise
of the flat target interior) and, for a four-sided target, a straight line through the
subpixel edge points of each side (total least squares) whose intersections give the
corners and, as the intersection of the diagonals, the image of the rectangle's centre
(which a centroid is not under perspective). The side fits' residuals give their precision.

The centroid's σ from the interior noise assumes the noise independent from pixel to pixel.
A camera's demosaicing and JPEG compression correlate neighbouring pixels;
:func:`noise_autocorrelation` measures it in the interior and ``RealTarget.noise_factor``
is the factor by which σ of the centroid grows (see there).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, check_finite
from photolib.measurement._edges import edge_points
from photolib.measurement._targets import moment_threshold, weighted_centroid

__all__ = ["RealTarget", "fit_line_tls", "measure_targets", "noise_autocorrelation", "yellowness"]


def yellowness(rgb) -> np.ndarray:
    """``min(R, G) − B`` of an RGB image (H, W, 3), grey values as float: yellow is bright.

    >>> yellowness(np.array([[[250, 200, 40], [120, 120, 120]]], np.uint8)).tolist()
    [[160.0, 0.0]]
    """
    a = as_float_array(rgb, "rgb")
    if a.ndim != 3 or a.shape[2] < 3:
        raise ValueError(f"rgb must be an (H, W, 3) colour image, got shape {a.shape}")
    check_finite(a, "rgb")
    return np.minimum(a[..., 0], a[..., 1]) - a[..., 2]


def fit_line_tls(points):
    r"""Total-least-squares line ``n·p = d`` (unit normal n) through points (N, 2), N ≥ 3.

    Returns ``(n, d, sigma0)``: the line passes through the centroid, n is the singular
    vector of the centred points with the smallest singular value, and
    :math:`σ_0 = \sqrt{\sum r_i^2/(N - 2)}` of the orthogonal residuals :math:`r_i = n·p_i - d`.

    >>> n, d, s0 = fit_line_tls([[0, 1.0], [1, 1.0], [2, 1.0]])
    >>> np.round(np.abs(n), 12).tolist(), round(abs(d), 12), round(s0, 12)
    ([0.0, 1.0], 1.0, 0.0)
    """
    p = as_float_array(points, "points")
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3:
        raise ValueError(f"points must be (N, 2) with N ≥ 3, got shape {p.shape}")
    check_finite(p, "points")  # NaN/inf: a clear message, not SVD's "did not converge"
    m = p.mean(axis=0)
    _, sv, vt = np.linalg.svd(p - m, full_matrices=False)
    if sv[0] <= 1e-12:
        raise ValueError("the points coincide: no line is determined")
    n = vt[1]
    r = (p - m) @ n
    return n, float(n @ m), float(np.sqrt(r @ r / (len(p) - 2)))


def _intersect(l1, l2):
    A = np.array([l1[0], l2[0]])
    return np.linalg.solve(A, [l1[1], l2[1]])


def noise_autocorrelation(image, mask, max_lag: int = 1) -> np.ndarray:
    r"""Autocorrelation ρ(Δr, Δc) of the noise of ``image`` inside ``mask`` (bool, same
    shape), for |Δr|, |Δc| ≤ ``max_lag``: a (2L + 1, 2L + 1) array with ρ(0, 0) = 1 at
    the centre.

    The noise is the residual ``e`` of a quadratic trend surface fitted to the masked grey
    values (the illumination); ρ(Δ) = mean(e(p)·e(p + Δ)) / mean(e²) over the pairs with both
    pixels in the mask. For independent noise ρ = 0 off the centre.

    **Effect on a weighted centroid** :math:`x_c = \sum w_i x_i / \sum w_i`: its error
    from noise :math:`δw_i` is :math:`\sum (x_i - x_c)\,δw_i/\sum w`; with a coefficient
    :math:`x_i - x_c` that changes little over the correlation length,

    .. math:: σ_{x_c}^2 ≈ \frac{σ_g^2 \sum (x_i - x_c)^2}{(\sum w)^2}\;\sum_Δ ρ(Δ),

    so the σ of independent noise grows by :math:`\sqrt{\sum_Δ ρ(Δ)}`.

    >>> rng = np.random.default_rng(0)
    >>> white = rng.normal(size=(400, 400))
    >>> boxed = (white[:-1, :-1] + white[1:, :-1] + white[:-1, 1:] + white[1:, 1:]) / 2
    >>> rho = noise_autocorrelation(boxed, np.ones(boxed.shape, bool))
    >>> bool(np.allclose(rho, [[0.25, 0.5, 0.25], [0.5, 1, 0.5], [0.25, 0.5, 0.25]], atol=0.02))
    True
    >>> round(float(np.sqrt(rho.sum())), 1)   # a 2 × 2 box of white noise: σ of a centroid × 2
    2.0
    """
    g = as_float_array(image, "image")
    m = np.asarray(mask, dtype=bool)
    if g.ndim != 2 or m.shape != g.shape:
        raise ValueError(f"image must be 2-D and mask of its shape, got {g.shape} and {m.shape}")
    L = int(max_lag)
    if L < 0:
        raise ValueError(f"max_lag must be ≥ 0, got {max_lag!r}")
    rows, cols = np.nonzero(m)
    if len(rows) < 7:
        raise ValueError(f"the mask has {len(rows)} pixels; a quadratic trend needs at least 7")
    v = g[rows, cols]
    check_finite(v, "image")
    A = np.column_stack([np.ones(len(v)), cols, rows, cols**2.0, cols * rows * 1.0, rows**2.0])
    e = np.zeros(g.shape)
    e[rows, cols] = v - A @ np.linalg.lstsq(A, v, rcond=None)[0]
    var = float(np.mean(e[rows, cols] ** 2))
    if var <= (1e-12 * max(1.0, float(np.abs(v).max()))) ** 2:
        raise ValueError("the masked grey values follow the trend exactly: no noise to measure")
    H, W = g.shape
    rho = np.empty((2 * L + 1, 2 * L + 1))
    for dr in range(-L, L + 1):
        for dc in range(-L, L + 1):
            a = (slice(max(dr, 0), H + min(dr, 0)), slice(max(dc, 0), W + min(dc, 0)))
            b = (slice(max(-dr, 0), H + min(-dr, 0)), slice(max(-dc, 0), W + min(-dc, 0)))
            both = m[a] & m[b]
            rho[dr + L, dc + L] = float(np.mean(e[a][both] * e[b][both])) / var
    return rho


class RealTarget(NamedTuple):
    """One target of :func:`measure_targets`; positions (col, row) in the whole image, px."""

    bbox: tuple                #: (col0, row0, col1, row1), inclusive-exclusive window
    area: int                  #: pixels of the blob
    binary: np.ndarray         #: (2,) unweighted centroid of the blob's pixels
    weighted: np.ndarray       #: (2,) grey-value weighted centroid, weights g − t
    weighted_std: np.ndarray   #: (2,) its σ from the interior noise σ_g, px
    sigma_g: float             #: grey-value noise of the flat interior
    corners: np.ndarray        #: (4, 2) corners from the side fits (NaN if not 4-sided)
    centre: np.ndarray         #: (2,) intersection of the diagonals
    side_sigma: np.ndarray     #: (4,) σ0 of each side's line fit, px
    side_points: int           #: edge points used in the four side fits
    threshold: float           #: the segmentation threshold t
    #: √(Σ ρ) of the interior noise over lags ≤ 1 (:func:`noise_autocorrelation`): the factor
    #: by which ``weighted_std`` grows for the noise's correlation between neighbours
    noise_factor: float = float("nan")


def measure_targets(rgb, *, min_area: int = 1000, threshold: float | None = None,
                    edge_threshold: float = 20.0):
    """Find and measure the bright (yellow) targets of an RGB photograph.

    Parameters
    ----------
    rgb : array_like, shape (H, W, 3)
    min_area : int
        Blobs with fewer pixels are noise, not targets.
    threshold : float, optional
        Segmentation threshold on :func:`yellowness`; default ``(h1 + h2)/2`` of
        :func:`~photolib.measurement.moment_threshold`.
    edge_threshold : float
        Gradient magnitude (grey/px) for :func:`~photolib.measurement.edge_points`.

    Returns
    -------
    list of RealTarget, sorted by row then column of the weighted centroid.

    Raises
    ------
    ValueError
        No blob reaches ``min_area`` pixels.
    """
    from scipy import ndimage

    y = yellowness(rgb)
    if threshold is None:
        try:
            m = moment_threshold(y)
        except ValueError as exc:  # e.g. a grey photograph: yellowness 0 everywhere
            raise ValueError(f"no target: the yellowness min(R, G) − B has one value over the "
                             f"whole image, nothing is yellower than its surroundings ({exc})"
                             ) from None
        threshold = 0.5 * (m.h1 + m.h2)
    t = float(threshold)
    labels, n = ndimage.label(y > t)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    big = [k for k in range(1, n + 1) if sizes[k] >= min_area]
    if not big:
        raise ValueError(f"no target: no blob above the threshold {t:.1f} has min_area = "
                         f"{min_area} pixels (largest {int(sizes[1:].max()) if n else 0})")
    H, W = y.shape
    edges = edge_points(y, edge_threshold)
    out = []
    for k in big:
        mask = labels == k
        rows, cols = np.nonzero(mask)
        r0, r1 = max(rows.min() - 3, 0), min(rows.max() + 4, H)
        c0, c1 = max(cols.min() - 3, 0), min(cols.max() + 4, W)
        win = np.where(ndimage.binary_dilation(mask, iterations=2), y, t)[r0:r1, c0:c1]
        interior = ndimage.binary_erosion(mask, iterations=4)
        sigma_g = float(np.std(y[interior], ddof=1))
        rho = noise_autocorrelation(y[r0:r1, c0:c1], interior[r0:r1, c0:c1])
        wc = weighted_centroid(win, t, sigma_g)
        binary = np.array([cols.mean(), rows.mean()])
        corners, centre, side_sigma, used = _rectangle(mask, edges, binary)
        out.append(RealTarget((int(c0), int(r0), int(c1), int(r1)), int(sizes[k]), binary,
                              wc.colrow + [c0, r0], wc.std, sigma_g, corners, centre,
                              side_sigma, used, t, float(np.sqrt(max(rho.sum(), 0.0)))))
    out.sort(key=lambda tg: (round(tg.weighted[1] / 50.0), tg.weighted[0]))
    return out


def _rectangle(mask, edges, centre0):
    """Four TLS side lines from the edge points near the blob's rim (see the module doc)."""
    from scipy import ndimage

    rows, cols = np.nonzero(mask)
    P = np.column_stack([cols, rows]) - centre0
    _, _, vt = np.linalg.svd(P, full_matrices=False)
    u, v = P @ vt[0], P @ vt[1]
    a, b = np.percentile(np.abs(u), 99.5), np.percentile(np.abs(v), 99.5)
    rim = ndimage.binary_dilation(mask, iterations=3) & ~ndimage.binary_erosion(mask, iterations=3)
    pc = np.round(edges.colrow).astype(int)
    ok = rim[np.clip(pc[:, 1], 0, mask.shape[0] - 1), np.clip(pc[:, 0], 0, mask.shape[1] - 1)]
    E = edges.colrow[ok] - centre0
    eu, ev = E @ vt[0] / a, E @ vt[1] / b
    away = ~((np.abs(eu) > 0.75) & (np.abs(ev) > 0.75))       # leave out the rounded corners
    sides = [(eu > 0.75) & away, (ev > 0.75) & away, (eu < -0.75) & away, (ev < -0.75) & away]
    nan4 = np.full((4, 2), np.nan)
    if any(s.sum() < 5 for s in sides):
        return nan4, np.full(2, np.nan), np.full(4, np.nan), 0
    lines = [fit_line_tls(E[s] + centre0) for s in sides]
    corners = np.array([_intersect(lines[i], lines[(i + 1) % 4]) for i in range(4)])
    d1, d2 = corners[2] - corners[0], corners[3] - corners[1]
    st = np.linalg.solve(np.column_stack([d1, -d2]), corners[1] - corners[0])
    centre = corners[0] + st[0] * d1
    return corners, centre, np.array([s0 for *_, s0 in lines]), int(sum(s.sum() for s in sides))
