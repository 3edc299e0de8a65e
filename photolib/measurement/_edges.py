r"""Gradient edges: the Sobel gradient and subpixel edge points along it.

:func:`sobel_gradient` gives ``(∂g/∂col, ∂g/∂row)`` in grey values per pixel (separable 1-D
passes, borders mirrored); :func:`edge_points` keeps the pixels whose gradient magnitude is
a maximum along the gradient direction and puts the edge between them by a parabola.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_scalar
from photolib.measurement._image import _image2d


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
