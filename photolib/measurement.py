"""Image measurement / Bildmessung: LoG, edges, moment-preserving threshold, centroid, circle fit.

* :func:`laplacian_of_gaussian` (5.42 as a function of r), :func:`log_filter` (separable LoG
  of an image, kernel half width ``ceil(4σ)``) and :func:`zero_crossings` (edges);
* :func:`sobel_gradient` and :func:`edge_points` (non-maximum suppression, subpixel position);
* :func:`moment_threshold` (Tsai, 5.49/5.50) and :func:`weighted_centroid` (with background
  threshold and precision);
* :func:`fit_circle`. Ellipse and plane fits are in :mod:`photolib.fitting`, least-squares
  matching in :mod:`photolib.matching`.

The formulas are derived here (and checked with SymPy in the tests), not copied: Luhmann's
5.42 as corrected in the errata is right; the corrected 5.50 as printed in the errata list
(``p1 = ½[1 + s̄·sqrt(4 + s̄²)]``) is not — the square root belongs in the denominator.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._linalg import svd_right
from photolib._validate import (
    as_float_array,
    as_max_iter,
    as_points,
    as_scalar,
    as_tolerance,
    check_finite,
)
from photolib.transforms._base import ConvergenceError, collinearity_ratio

__all__ = ["Centroid", "CircleFit", "EdgePoints", "MomentThreshold", "edge_points", "fit_circle",
           "gaussian_radius", "laplacian_of_gaussian", "log_filter", "log_kernel_1d",
           "moment_threshold", "sobel_gradient", "weighted_centroid", "zero_crossings"]


def laplacian_of_gaussian(r, sigma):
    r"""Laplacian of the normalised 2-D Gaussian as a function of the radius (Luhmann 5.42).

    For :math:`G(x, y) = \frac{1}{2πσ^2} \exp\left(-\frac{r^2}{2σ^2}\right)`,
    :math:`r^2 = x^2 + y^2`:

    .. math::
        ∇^2 G = \frac{∂^2 G}{∂x^2} + \frac{∂^2 G}{∂y^2}
              = -\frac{1}{πσ^4}\left(1 - \frac{r^2}{2σ^2}\right) \exp\left(-\frac{r^2}{2σ^2}\right)

    (from :math:`∂^2G/∂x^2 = (x^2/σ^4 - 1/σ^2)\,G`). This is the errata's corrected 5.42;
    the original print :math:`-(1 - r/σ^2)\exp(-r^2/2σ^2)` has ``r`` for ``r²``, a wrong
    factor 2 and no normalisation. The zero crossing is at :math:`r = \sqrt 2\,σ` and the
    integral over the plane is 0.

    Parameters
    ----------
    r : float or array_like
        Distance from the centre (pixel or any length unit).
    sigma : float
        Standard deviation of the Gaussian, > 0 (same unit as r).

    Returns
    -------
    ndarray or float
        ∇²G, shape of ``r`` (unit⁻⁴).

    Examples
    --------
    >>> round(float(laplacian_of_gaussian(0.0, 1.0) * np.pi), 12)
    -1.0
    >>> abs(laplacian_of_gaussian(np.sqrt(2.0) * 3.0, 3.0)) < 1e-17  # zero crossing at √2·σ
    True
    """
    sigma = as_scalar(sigma, "sigma", positive=True)
    r = as_float_array(r, "r")
    check_finite(np.atleast_1d(r), "r")
    q = r**2 / (2.0 * sigma**2)
    out = -(1.0 - q) * np.exp(-q) / (np.pi * sigma**4)
    return out if out.ndim else float(out)


class MomentThreshold(NamedTuple):
    """Result of :func:`moment_threshold` (grey values in the unit of the image)."""

    threshold: float  #: pixels ≤ threshold belong to the dark class h1
    p1: float  #: fraction of the dark class
    h1: float  #: dark representative grey value
    h2: float  #: bright representative grey value


def moment_threshold(image) -> MomentThreshold:
    r"""Moment-preserving threshold (Tsai 1985; Luhmann 5.49/5.50, derived anew).

    The grey values are replaced by two levels :math:`h_1 < h_2` with fractions
    :math:`p_1, p_2 = 1 - p_1` such that the first three moments are kept,

    .. math:: m_i = \frac{1}{n}\sum g^i = p_1 h_1^i + p_2 h_2^i, \qquad i = 1, 2, 3.

    With :math:`σ^2 = m_2 - m_1^2` and the skewness
    :math:`s = (m_3 - 3 m_1 m_2 + 2 m_1^3)/σ^3` the solution is

    .. math::
        p_1 = \frac{1}{2}\left(1 + \frac{s}{\sqrt{4 + s^2}}\right), \quad
        h_1 = m_1 - σ\sqrt{p_2/p_1}, \quad h_2 = m_1 + σ\sqrt{p_1/p_2}

    (a two-point distribution has skewness :math:`(p_1 - p_2)/\sqrt{p_1 p_2}`; solving for
    :math:`p_1` gives the root in the **denominator** — the errata's printed
    :math:`\tfrac12[1 + \bar s\sqrt{4 + \bar s^2}]` can exceed 1). The threshold is the
    :math:`p_1`-tile: the grey value whose cumulative fraction ``P(g ≤ t)`` is closest to
    :math:`p_1`.

    Parameters
    ----------
    image : array_like
        Grey values, any shape (at least two distinct finite values).

    Returns
    -------
    MomentThreshold
        ``(threshold, p1, h1, h2)``.

    Examples
    --------
    >>> img = np.array([10] * 30 + [200] * 70)
    >>> t = moment_threshold(img)
    >>> t.threshold, round(t.p1, 12), round(t.h1, 9), round(t.h2, 9)
    (10.0, 0.3, 10.0, 200.0)
    """
    g = as_float_array(image, "image").ravel()
    if g.size == 0:
        raise ValueError("image is empty")
    check_finite(g, "image")
    m1 = g.mean()
    c = g - m1
    var = float(np.mean(c**2))
    if var <= (1e-12 * max(1.0, abs(m1))) ** 2:
        raise ValueError(f"image is constant (all grey values {m1:g}); there is no threshold")
    sd = np.sqrt(var)
    s = float(np.mean(c**3)) / sd**3
    p1 = 0.5 * (1.0 + s / np.sqrt(4.0 + s * s))
    p2 = 1.0 - p1
    h1 = m1 - sd * np.sqrt(p2 / p1)
    h2 = m1 + sd * np.sqrt(p1 / p2)
    values, counts = np.unique(g, return_counts=True)
    cdf = np.cumsum(counts) / g.size
    threshold = float(values[np.argmin(np.abs(cdf - p1))])
    return MomentThreshold(threshold, float(p1), float(h1), float(h2))


class CircleFit(NamedTuple):
    """Result of :func:`fit_circle`."""

    centre: np.ndarray  #: (2,) centre (xc, yc), unit of the points
    radius: float  #: radius, unit of the points
    residuals: np.ndarray  #: (N,) radial residuals ``|p − centre| − radius``
    sigma0: float  #: sqrt(Σv²/(N − 3)); NaN for N = 3
    iterations: int  #: Gauss–Newton iterations of the geometric refinement (0 if none)


def fit_circle(xy, *, refine: bool = True, tol: float = 1e-12, max_iter: int = 50) -> CircleFit:
    r"""Circle through ≥ 3 points: algebraic fit, optionally refined geometrically.

    The algebraic fit solves the general circle equation (Luhmann 2.85/2.86)

    .. math::
        A(x^2 + y^2) + 2Dx + 2Ey + F = 0, \qquad
        x_c = -\frac{D}{A},\; y_c = -\frac{E}{A},\;
        r = \sqrt{\frac{D^2 + E^2 - AF}{A^2}}

    (the errata's corrected 2.86) in the least-squares sense with ``|(A, D, E, F)| = 1``
    on normalised points — unlike 2.88 with ``F = 1`` it also fits circles through the
    origin. The geometric refinement minimises :math:`\sum (|p_i - c| - r)^2` by
    Gauss–Newton.

    Parameters
    ----------
    xy : array_like, shape (N, 2)
        Points (any length unit), N ≥ 3, not collinear.
    refine : bool
        Geometric refinement after the algebraic fit.
    tol, max_iter
        Stop when the update is below ``tol·(1 + r)``; raise ``ConvergenceError`` after
        ``max_iter`` iterations.

    Returns
    -------
    CircleFit
        centre (2,), radius, residuals (N,), sigma0, iterations.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 7)[:-1]
    >>> fit = fit_circle(np.column_stack([3 + 2 * np.cos(t), -1 + 2 * np.sin(t)]))
    >>> np.round(fit.centre, 12).tolist(), round(fit.radius, 12)
    ([3.0, -1.0], 2.0)
    """
    pts, _ = as_points(xy, 2, "xy")
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    if len(pts) < 3:
        raise ValueError(f"fit_circle needs at least 3 points, got {len(pts)}")
    if collinearity_ratio(pts) < 1e-9:
        raise ValueError("the points are collinear (or coincide); no circle is determined")
    centroid = pts.mean(axis=0)
    scale = np.sqrt(2.0) / np.mean(np.linalg.norm(pts - centroid, axis=1))
    u = scale * (pts - centroid)
    M = np.column_stack([np.sum(u**2, axis=1), 2 * u, np.ones(len(u))])
    A, D, E, F = svd_right(M)[1][-1]
    if abs(A) < 1e-12:
        raise ValueError("the points lie (nearly) on a straight line; the circle radius is infinite")
    centre = np.array([-D / A, -E / A])
    radius = float(np.sqrt(max((D**2 + E**2 - A * F) / A**2, 0.0)))
    iterations = 0
    if refine and len(u) > 3:
        for iterations in range(1, max_iter + 1):  # noqa: B007 - reported after the loop
            d = u - centre
            dist = np.linalg.norm(d, axis=1)
            if np.any(dist == 0.0):
                raise ConvergenceError("a point coincides with the circle centre during refinement")
            J = np.column_stack([-d / dist[:, None], -np.ones(len(u))])
            step = np.linalg.lstsq(J, -(dist - radius), rcond=None)[0]
            centre, radius = centre + step[:2], radius + float(step[2])
            if np.linalg.norm(step) <= tol * (1.0 + abs(radius)):
                break
        else:
            raise ConvergenceError(f"fit_circle: geometric refinement did not converge in {max_iter} iterations")
    centre = centroid + centre / scale
    radius = float(abs(radius) / scale)
    residuals = np.linalg.norm(pts - centre, axis=1) - radius
    n = len(pts)
    sigma0 = float(np.sqrt(np.sum(residuals**2) / (n - 3))) if n > 3 else float("nan")
    return CircleFit(centre, radius, residuals, sigma0, iterations)


# -- LoG filtering of an image, zero crossings ---------------------------------------------------

def _image2d(image, name="image") -> np.ndarray:
    img = as_float_array(image, name)
    if img.ndim != 2 or min(img.shape) < 3:
        raise ValueError(f"{name} has shape {np.shape(image)}; expected a 2-D grey image of at "
                         "least 3 × 3 pixels")
    check_finite(img, name)
    return img


def _convolve1d(img: np.ndarray, kernel: np.ndarray, axis: int) -> np.ndarray:
    """Correlate along ``axis`` with a symmetric odd kernel, edges mirrored (d c b a | a b c d)."""
    h = len(kernel) // 2
    pad = [(0, 0), (0, 0)]
    pad[axis] = (h, h)
    p = np.pad(img, pad, mode="symmetric")
    n = img.shape[axis]
    out = np.zeros_like(img)
    for k, w in enumerate(kernel):
        if w != 0.0:
            out += w * (p[k:k + n] if axis == 0 else p[:, k:k + n])
    return out


def gaussian_radius(sigma, truncate: float = 4.0) -> int:
    """Half width of the sampled kernels: ``ceil(truncate·σ)`` pixels (at least 1).

    >>> gaussian_radius(1.5), gaussian_radius(0.1)
    (6, 1)
    """
    sigma = as_scalar(sigma, "sigma", positive=True)
    truncate = as_scalar(truncate, "truncate", positive=True)
    return max(1, int(np.ceil(truncate * sigma)))


def log_kernel_1d(sigma, truncate: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    r"""The two 1-D kernels of the separable LoG: ``(g, g'')``, length ``2·radius + 1``.

    .. math::
        g(x) = \frac{e^{-x^2/2σ^2}}{\sum_k e^{-k^2/2σ^2}}, \qquad
        g''(x) ∝ \left(\frac{x^2}{σ^4} - \frac{1}{σ^2}\right) g(x),

    so that :math:`∇^2G(x, y) = g''(x)\,g(y) + g(x)\,g''(y)` (the 2-D Gaussian is the
    product of two 1-D Gaussians). ``g`` sums to 1 (a flat image stays flat). The sampled
    ``g''`` meets neither of its two conditions exactly (the tails are cut), so it is taken
    from the same two-term family :math:`g'' = (α x^2 + β)\,g` with α, β fixed by

    .. math:: \sum_x g''(x) = 0 \quad\text{(a flat image gives LoG 0)}, \qquad
              \tfrac12 \sum_x x^2 g''(x) = 1 \quad\text{(the ramp } x^2
              \text{ has Laplacian 2)}.

    With the moments :math:`m_2 = \sum x^2 g` and :math:`\sum g = 1` the first condition
    gives :math:`β = -α m_2`, the second :math:`α \sum x^2(x^2 - m_2) g = 2`, and as
    :math:`\sum m_2 (x^2 - m_2) g = 0`,

    .. math:: g''(x) = \frac{2\,(x^2 - m_2)\,g(x)}{\sum_k (k^2 - m_2)^2\,g(k)}.

    Every term of the denominator is ≥ 0, so nothing cancels however small σ is (the former
    shift-then-scale construction cancelled the centre tap completely below σ ≈ 0.12 px and
    gave NaN below 0.03 px). With three taps (σ ≤ 0.25 px for ``truncate = 4``) the two
    conditions leave only the discrete Laplacian ``[1, −2, 1]``; that is also the limit
    σ → 0, returned once the outer taps of ``g`` underflow to 0 (σ ≲ 0.026 px). The radius
    is :func:`gaussian_radius`.

    Parameters
    ----------
    sigma : float
        σ of the Gaussian in pixels, > 0.
    truncate : float
        Kernel half width in units of σ, > 0 (at least one pixel).

    Returns
    -------
    g : ndarray, shape (2·radius + 1,)
        The sampled Gaussian, dimensionless, sum 1.
    g2 : ndarray, shape (2·radius + 1,)
        The second-derivative kernel, per pixel², sum 0 and ``½Σx²g'' = 1``.

    Examples
    --------
    >>> g, g2 = log_kernel_1d(1.0)
    >>> len(g), round(float(g.sum()), 12), abs(float(g2.sum())) < 1e-15
    (9, 1.0, True)
    >>> (log_kernel_1d(0.1)[1] + 0.0).round(12).tolist()   # three taps: the discrete Laplacian
    [1.0, -2.0, 1.0]
    """
    rad = gaussian_radius(sigma, truncate)
    sigma = as_scalar(sigma, "sigma", positive=True)
    x = np.arange(-rad, rad + 1, dtype=float)
    g = np.exp(-(x**2) / (2.0 * sigma**2))
    g /= g.sum()
    if g[rad + 1] == 0.0:       # σ → 0: g is the unit impulse, g'' the discrete Laplacian
        g2 = np.zeros_like(g)
        g2[rad - 1:rad + 2] = (1.0, -2.0, 1.0)
        return g, g2
    dev = x**2 - np.sum(x**2 * g)                  # x² − m2
    g2 = (2.0 / np.sum(dev**2 * g)) * dev * g
    return g, g2


def log_filter(image, sigma, truncate: float = 4.0) -> np.ndarray:
    r"""Laplacian-of-Gaussian filtered image (Luhmann 5.42) by separable convolution.

    .. math:: L = (g'' ⊗ g)\,*\,I + (g ⊗ g'')\,*\,I

    with the kernels of :func:`log_kernel_1d`: four 1-D passes of ``2·radius + 1``
    multiply-adds each instead of one 2-D convolution of size ``(2·radius + 1)²``. They run on
    blocks of rows small enough to stay in the cache (the two row passes read the same padded
    block), each tap after tap from left to right: the same operations in the same order, so
    the same values as the four passes run one after the other. Image borders are mirrored.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey values.
    sigma : float
        σ of the Gaussian in pixels, > 0. Edges appear where the response crosses zero,
        a blob of radius ≈ √2·σ gives the strongest response.
    truncate : float
        Kernel half width in units of σ.

    Returns
    -------
    ndarray, shape (H, W)
        ∇²(G * I) in grey values per pixel².

    Examples
    --------
    >>> yy, xx = np.mgrid[:15, :15]
    >>> L = log_filter((xx - 7.0) ** 2, 1.5)       # ∇²(x²) = 2 inside the image
    >>> round(float(L[7, 7]), 9)
    2.0
    """
    img = _image2d(image)
    g, g2 = log_kernel_1d(sigma, truncate)
    h = len(g) // 2
    H, W = img.shape
    p = np.pad(img, h, mode="symmetric")      # mirrored rows and columns (d c b a | a b c d)
    out = np.empty((H, W))
    block = max(2**17 // W, 4 * h)            # output rows per block (~1 MB buffers)
    a, b, t = (np.empty((min(block, H) + 2 * h, W)) for _ in range(3))
    out2 = np.empty((min(block, H), W))
    for r0 in range(0, H, block):
        n = min(block, H - r0)
        P, A, B, T = p[r0:r0 + n + 2 * h], a[:n + 2 * h], b[:n + 2 * h], t[:n + 2 * h]
        np.multiply(P[:, :W], g2[0], out=A)               # rows: A = g'' ⊛ I, B = g ⊛ I
        np.multiply(P[:, :W], g[0], out=B)
        for k in range(1, 2 * h + 1):
            A += np.multiply(P[:, k:k + W], g2[k], out=T)
            B += np.multiply(P[:, k:k + W], g[k], out=T)
        o, o2, T = out[r0:r0 + n], out2[:n], T[:n]        # columns: g ⊛ A + g'' ⊛ B
        np.multiply(A[:n], g[0], out=o)
        np.multiply(B[:n], g2[0], out=o2)
        for k in range(1, 2 * h + 1):
            o += np.multiply(A[k:k + n], g[k], out=T)
            o2 += np.multiply(B[k:k + n], g2[k], out=T)
        o += o2
    return out


def zero_crossings(response, threshold: float = 0.0) -> np.ndarray:
    """Edge pixels of a LoG response: sign changes to the right or lower neighbour.

    Of the two pixels of a sign change, the one with the smaller ``|response|`` (nearer to
    the zero) is marked; the jump ``|a − b|`` must exceed ``threshold`` (suppresses noise).

    Parameters
    ----------
    response : array_like, shape (H, W)
    threshold : float
        Minimum jump, ≥ 0, same unit as ``response``.

    Returns
    -------
    ndarray of bool, shape (H, W)

    Examples
    --------
    >>> zero_crossings([[-2.0, -1.0, 3.0, 4.0]] * 3)[0].tolist()
    [False, True, False, False]
    """
    L = as_float_array(response, "response")
    if L.ndim != 2:
        raise ValueError(f"response has shape {L.shape}; expected (H, W)")
    check_finite(L, "response")
    threshold = as_scalar(threshold, "threshold")
    if threshold < 0:
        raise ValueError(f"threshold must be ≥ 0, got {threshold!r}")
    out = np.zeros(L.shape, dtype=bool)
    for axis in (0, 1):
        a = L[:-1] if axis == 0 else L[:, :-1]
        b = L[1:] if axis == 0 else L[:, 1:]
        change = (np.sign(a) * np.sign(b) < 0) & (np.abs(a - b) > threshold)
        first = change & (np.abs(a) <= np.abs(b))
        second = change & ~first
        if axis == 0:
            out[:-1] |= first
            out[1:] |= second
        else:
            out[:, :-1] |= first
            out[:, 1:] |= second
    return out


# -- gradient edges -------------------------------------------------------------------------------

def sobel_gradient(image) -> tuple[np.ndarray, np.ndarray]:
    r"""Image gradient ``(∂g/∂col, ∂g/∂row)`` by the Sobel operator, scaled to grey/pixel.

    .. math::
        g_{col} = \frac{1}{8}\begin{bmatrix}-1&0&1\\-2&0&2\\-1&0&1\end{bmatrix} * g, \qquad
        g_{row} = \frac{1}{8}\begin{bmatrix}-1&-2&-1\\0&0&0\\1&2&1\end{bmatrix} * g

    (as correlations; smoothing [1, 2, 1]/4 across, central difference [−1, 0, 1]/2
    along). A ramp of slope 1 gives exactly 1. Borders are mirrored. ``row`` points down.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Grey values / Grauwerte g (any unit, e.g. DN), at least 3 × 3 pixels, finite.

    Returns
    -------
    g_col : ndarray, shape (H, W)
        ∂g/∂col, grey values per pixel, positive where the image gets brighter to the right.
    g_row : ndarray, shape (H, W)
        ∂g/∂row, grey values per pixel, positive where it gets brighter downwards.

    Raises
    ------
    ValueError
        If ``image`` is not a 2-D image of at least 3 × 3 pixels or holds NaN/inf.

    Examples
    --------
    >>> gc, gr = sobel_gradient(np.tile(np.arange(5.0), (4, 1)) * 3)
    >>> float(gc[1, 2]), float(gr[1, 2])
    (3.0, 0.0)
    """
    img = _image2d(image)
    smooth, diff = np.array([0.25, 0.5, 0.25]), np.array([-0.5, 0.0, 0.5])
    return (_convolve1d(_convolve1d(img, diff, 1), smooth, 0),
            _convolve1d(_convolve1d(img, smooth, 1), diff, 0))


class EdgePoints(NamedTuple):
    """Result of :func:`edge_points`."""

    colrow: np.ndarray      #: (N, 2) subpixel edge positions (col, row), pixels
    magnitude: np.ndarray   #: (N,) gradient magnitude there, grey/pixel
    direction: np.ndarray   #: (N, 2) unit gradient direction (dcol, drow), dark → bright
    mask: np.ndarray        #: (H, W) bool, pixels kept by the non-maximum suppression


def edge_points(image, threshold: float) -> EdgePoints:
    r"""Gradient edges: Sobel, non-maximum suppression, subpixel position along the gradient.

    A pixel is an edge pixel if its gradient magnitude ``m0`` exceeds ``threshold`` and is
    not smaller than the magnitudes ``m−, m+`` one pixel back and forward along the gradient
    direction (bilinearly interpolated with :func:`photolib.rectify.sample_image`). A
    parabola through the three values puts the edge at

    .. math:: t = \frac{m_- - m_+}{2(m_- - 2m_0 + m_+)}, \qquad |t| ≤ ½,

    pixels along the gradient direction from the pixel centre.

    Parameters
    ----------
    image : array_like, shape (H, W)
    threshold : float
        Minimum gradient magnitude (grey/pixel), > 0.

    Returns
    -------
    EdgePoints

    Examples
    --------
    >>> col = np.arange(12.0)
    >>> img = np.tile(100 / (1 + np.exp(-(col - 5.3) / 0.8)), (6, 1))   # edge at col 5.3
    >>> e = edge_points(img, 5.0)
    >>> bool(np.allclose(e.colrow[:, 0], 5.3, atol=0.05)), len(e.colrow)
    (True, 6)
    """
    from photolib.rectify import sample_image

    img = _image2d(image)
    threshold = as_scalar(threshold, "threshold", positive=True)
    gc, gr = sobel_gradient(img)
    mag = np.hypot(gc, gr)
    rows, cols = np.nonzero(mag > threshold)
    if len(rows) == 0:
        empty = np.zeros((0, 2))
        return EdgePoints(empty, np.zeros(0), empty, np.zeros(img.shape, bool))
    m0 = mag[rows, cols]
    d = np.column_stack([gc[rows, cols], gr[rows, cols]]) / m0[:, None]
    pos = np.column_stack([cols, rows]).astype(float)
    H, W = img.shape
    lim = np.array([W - 1.0, H - 1.0])
    m_minus = sample_image(mag, np.clip(pos - d, 0.0, lim))
    m_plus = sample_image(mag, np.clip(pos + d, 0.0, lim))
    keep = (m0 >= m_minus) & (m0 > m_plus)
    denom = m_minus - 2.0 * m0 + m_plus
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(denom < 0, (m_minus - m_plus) / (2.0 * denom), 0.0)
    t = np.clip(t, -0.5, 0.5)
    mask = np.zeros(img.shape, bool)
    mask[rows[keep], cols[keep]] = True
    return EdgePoints(pos[keep] + t[keep, None] * d[keep], m0[keep], d[keep], mask)


# -- centroid of a target -------------------------------------------------------------------------

class Centroid(NamedTuple):
    """Result of :func:`weighted_centroid`."""

    colrow: np.ndarray   #: (2,) centroid (col, row), pixels
    std: np.ndarray      #: (2,) standard deviations (σ_col, σ_row), pixels; NaN without sigma_g
    weight: float        #: Σw, grey values
    n_pixels: int        #: pixels with w > 0


def weighted_centroid(image, background: float = 0.0, sigma_g: float | None = None) -> Centroid:
    r"""Grey-value weighted centroid (Schwerpunkt) of a bright target on a dark background.

    Each pixel gets the weight :math:`w = \max(g - t, 0)` above the background threshold
    ``t``; then

    .. math::
        x_c = \frac{\sum x_i w_i}{\sum w_i}, \qquad y_c = \frac{\sum y_i w_i}{\sum w_i},
        \qquad σ_{x_c} = \frac{σ_g}{\sum w_i}\sqrt{\sum (x_i - x_c)^2}

    (x = col, y = row; the precision follows from :math:`∂x_c/∂w_i = (x_i - x_c)/\sum w`
    with independent grey-value noise ``σ_g`` on the pixels with w > 0). For a dark target
    on a bright background pass the inverted image.

    Parameters
    ----------
    image : array_like, shape (H, W)
    background : float
        Threshold t (grey values); pixels at or below it have no weight.
    sigma_g : float, optional
        Grey-value noise (grey values) for the precision.

    Returns
    -------
    Centroid
        ``colrow`` is (col, row) — SciPy's ``center_of_mass`` gives (row, col).

    Examples
    --------
    >>> img = np.zeros((5, 6)); img[1, 3] = 1.0; img[1, 4] = 3.0
    >>> c = weighted_centroid(img)
    >>> c.colrow.tolist(), c.n_pixels
    ([3.75, 1.0], 2)
    """
    img = _image2d(image)
    t = as_scalar(background, "background")
    w = np.maximum(img - t, 0.0)
    total = float(w.sum())
    n = int(np.count_nonzero(w))
    if n == 0 or total <= 0.0:
        raise ValueError(f"the target is empty: no pixel is above the background {t:g} "
                         f"(maximum grey value {float(img.max()):g})")
    rows, cols = np.indices(img.shape)
    c = np.array([np.sum(cols * w), np.sum(rows * w)]) / total
    if sigma_g is None:
        std = np.full(2, np.nan)
    else:
        s = as_scalar(sigma_g, "sigma_g")
        if s < 0:
            raise ValueError(f"sigma_g must be ≥ 0, got {s!r}")
        on = w > 0
        std = s / total * np.sqrt([np.sum((cols[on] - c[0]) ** 2), np.sum((rows[on] - c[1]) ** 2)])
    return Centroid(c, std, total, n)
