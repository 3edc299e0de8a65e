"""Colour sensors: the Bayer colour filter array and bilinear demosaicing (chapter 03).

Bayer patterns are named by the colours of the top-left 2 × 2 block read row by row:
``"RGGB"``, ``"BGGR"``, ``"GRBG"``, ``"GBRG"``; colour indices are 0 R, 1 G, 2 B. The mosaic
keeps one colour per pixel, ``M(r, c) = I_k(r, c)`` with ``k = pattern[r mod 2][c mod 2]``;
demosaicing convolves each masked channel with a 3 × 3 kernel (mirrored borders).
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_int
from photolib._validate import as_array as _array


#: the four Bayer patterns: colour index (0 R, 1 G, 2 B) of the top-left 2 × 2 block
BAYER_PATTERNS = {
    "RGGB": ((0, 1), (1, 2)),
    "BGGR": ((2, 1), (1, 0)),
    "GRBG": ((1, 0), (2, 1)),
    "GBRG": ((1, 2), (0, 1)),
}


def _pattern(pattern: str) -> tuple:
    key = str(pattern).upper()
    if key not in BAYER_PATTERNS:
        raise ValueError(f"Bayer pattern {pattern!r} is not one of {sorted(BAYER_PATTERNS)}")
    return BAYER_PATTERNS[key]


# -- colour: Bayer mosaic and bilinear demosaicing ------------------------------------------------

def bayer_masks(shape, pattern: str = "RGGB") -> np.ndarray:
    """Boolean masks (3, H, W): which pixel carries the R, G or B filter.

    Parameters
    ----------
    shape : tuple of int
        Image size (H, W) in pixels (rows, columns), integers ≥ 2; a fractional or
        non-finite entry raises ``ValueError`` naming it (``shape[0]``, ``shape[1]``).
    pattern : str
        Bayer pattern, the colours of the top-left 2 × 2 block row by row: ``"RGGB"``,
        ``"BGGR"``, ``"GRBG"`` or ``"GBRG"`` (case-insensitive).

    Returns
    -------
    ndarray of bool, shape (3, H, W)
        ``masks[k]`` is True where the pixel's filter has colour k (0 R, 1 G, 2 B); every
        pixel is in exactly one mask.

    Notes
    -----
    .. math:: m_k(r, c) = \\left[\\text{pattern}[r \\bmod 2][c \\bmod 2] = k\\right]

    Examples
    --------
    >>> m = bayer_masks((4, 4))
    >>> m.sum(axis=(1, 2)).tolist()   # a quarter red, half green, a quarter blue
    [4, 8, 4]
    >>> bayer_masks((2, 2), "GRBG").argmax(axis=0).tolist()   # colour index per pixel
    [[1, 0], [2, 1]]
    """
    cells = _pattern(pattern)
    try:
        entries = tuple(shape)
    except TypeError:
        entries = ()
    if len(entries) != 2:
        raise ValueError(f"shape must be (H, W) with H, W ≥ 2, got {shape!r}")
    Hh, Ww = (as_int(v, f"shape[{i}]", minimum=2) for i, v in enumerate(entries))
    rows, cols = np.mgrid[0:Hh, 0:Ww]
    colour = np.array(cells)[rows % 2, cols % 2]
    return np.stack([colour == k for k in range(3)])


def bayer_mosaic(rgb, pattern: str = "RGGB") -> np.ndarray:
    """What a Bayer sensor records of an RGB scene: one colour per pixel.

    Parameters
    ----------
    rgb : array_like, shape (H, W, 3)
        Scene radiance in R, G, B (any real unit).
    pattern : str
        ``"RGGB"``, ``"BGGR"``, ``"GRBG"`` or ``"GBRG"``.

    Returns
    -------
    ndarray, shape (H, W)
        .. math:: M(r, c) = I_{k(r, c)}(r, c),\\quad k = \\text{pattern}[r \\bmod 2][c \\bmod 2]

    Examples
    --------
    >>> rgb = np.zeros((2, 2, 3)); rgb[..., 0], rgb[..., 1], rgb[..., 2] = 1.0, 2.0, 3.0
    >>> bayer_mosaic(rgb).tolist()
    [[1.0, 2.0], [2.0, 3.0]]
    """
    img = _array(rgb, "rgb")
    if img.ndim != 3 or img.shape[2] != 3:
        raise ValueError(f"rgb has shape {img.shape}; expected (H, W, 3)")
    masks = bayer_masks(img.shape[:2], pattern)
    return np.einsum("khw,hwk->hw", masks.astype(float), img)


def _convolve3(a: np.ndarray, kernel: np.ndarray) -> np.ndarray:
    """3 × 3 correlation with mirrored borders (``reflect``: the edge pixel is not repeated)."""
    p = np.pad(a, 1, mode="reflect")
    Hh, Ww = a.shape
    out = np.zeros_like(a)
    for i in range(3):
        for j in range(3):
            if kernel[i, j]:
                out += kernel[i, j] * p[i:i + Hh, j:j + Ww]
    return out


_K_GREEN = np.array([[0.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 0.0]]) / 4.0
_K_RB = np.array([[1.0, 2.0, 1.0], [2.0, 4.0, 2.0], [1.0, 2.0, 1.0]]) / 4.0


def demosaic_bilinear(mosaic, pattern: str = "RGGB") -> np.ndarray:
    """Bilinear demosaicing (Farbinterpolation): the missing colours from their neighbours.

    Parameters
    ----------
    mosaic : array_like, shape (H, W)
        A Bayer image, H, W ≥ 2.
    pattern : str
        Its Bayer pattern.

    Returns
    -------
    ndarray, shape (H, W, 3)
        Each channel ``k`` is the masked mosaic ``M·m_k`` convolved with

        .. math:: K_G = \\tfrac14\\begin{pmatrix}0&1&0\\\\1&4&1\\\\0&1&0\\end{pmatrix},\\quad
                  K_{R,B} = \\tfrac14\\begin{pmatrix}1&2&1\\\\2&4&2\\\\1&2&1\\end{pmatrix}

        so a measured value is kept, a missing green is the mean of its 4 green neighbours,
        a missing red/blue the mean of its 2 or 4 neighbours of that colour. The border is
        mirrored.

    Examples
    --------
    >>> flat = np.full((4, 4, 3), [0.2, 0.5, 0.8])
    >>> bool(np.allclose(demosaic_bilinear(bayer_mosaic(flat)), flat))
    True
    """
    m = _array(mosaic, "mosaic")
    if m.ndim != 2 or min(m.shape) < 2:
        raise ValueError(f"mosaic has shape {m.shape}; expected (H, W) with H, W ≥ 2")
    masks = bayer_masks(m.shape, pattern)
    kernels = (_K_RB, _K_GREEN, _K_RB)
    return np.stack([_convolve3(m * masks[k], kernels[k]) for k in range(3)], axis=-1)
