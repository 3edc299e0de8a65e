r"""The Laplacian of Gaussian (LoG, Luhmann 5.42): the function, the filter, the zero crossings.

:func:`laplacian_of_gaussian` is ∇²G as a function of the radius (the errata's corrected
5.42); :func:`log_kernel_1d` samples the two 1-D kernels of the separable LoG (half width
:func:`gaussian_radius`, ``ceil(4σ)``), :func:`log_filter` filters an image with them and
:func:`zero_crossings` marks the edges where its response changes sign.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, as_scalar, check_finite
from photolib.measurement._image import _image2d


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
