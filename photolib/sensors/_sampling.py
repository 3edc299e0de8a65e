"""Sampling by a pixel grid: Nyquist frequency, aliasing and the pixel MTF (chapter 03).

Spatial frequencies are cycles per image unit (line pairs per mm in the course), the pixel
pitch p is in the image unit and pixel k has its centre at ``x_k = k·p``.

* Nyquist frequency ``f_N = 1/(2p)``; a sine above it appears at the alias frequency
  ``f_a = |f − f_s·round(f/f_s)|``, ``f_s = 1/p``.
* A square sensitive area of side ``a = p·√FF`` (fill factor FF) has the
  ``MTF(f) = |sinc(f·a)|``.
"""

from __future__ import annotations

import math

import numpy as np

from photolib._validate import as_scalar
from photolib._validate import as_array as _array


# -- sampling, aliasing, pixel MTF ---------------------------------------------------------------

def nyquist_frequency(pixel_pitch) -> float:
    """Highest frequency a pixel grid can represent: :math:`f_N = 1/(2p)` (cycles/unit).

    Parameters
    ----------
    pixel_pitch : float
        Pixel pitch p (Pixelabstand), > 0, image unit (mm in the course: 0.005 for 5 µm).

    Returns
    -------
    float
        Nyquist frequency f_N, cycles per image unit (lp/mm for p in mm): one line pair
        per two pixels.

    Notes
    -----
    .. math:: f_N = \\frac{f_s}{2} = \\frac{1}{2p}

    Examples
    --------
    >>> nyquist_frequency(0.005)   # 5 µm pixels: 100 line pairs per mm
    100.0
    >>> round(nyquist_frequency(0.0035), 3)   # 3.5 µm pixels, lp/mm
    142.857
    """
    return 0.5 / as_scalar(pixel_pitch, "pixel_pitch", positive=True)


def alias_frequency(frequency, pixel_pitch) -> np.ndarray | float:
    """Apparent frequency of a sampled sine (Alias): folded into [0, f_N].

    Parameters
    ----------
    frequency : float or array_like, any shape
        Spatial frequency f of the pattern, ≥ 0, cycles per image unit (lp/mm).
    pixel_pitch : float
        Pixel pitch p, > 0, image unit (mm).

    Returns
    -------
    float or ndarray
        Alias frequency f_a in [0, f_N], cycles per image unit (lp/mm); f itself below the
        Nyquist frequency. Shape of ``frequency`` (a float for a scalar).

    Notes
    -----
    .. math:: f_a = \\left|f - f_s\\,\\operatorname{round}(f/f_s)\\right|,\\quad f_s = 1/p

    Examples
    --------
    >>> alias_frequency([30.0, 80.0, 120.0, 200.0], 0.005).tolist()   # f_N = 100 /mm
    [30.0, 80.0, 80.0, 0.0]
    >>> alias_frequency(150.0, 0.005)   # lp/mm: 150 /mm on 5 µm pixels looks like 50 /mm
    50.0
    """
    f = _array(frequency, "frequency", nonnegative=True)
    fs = 1.0 / as_scalar(pixel_pitch, "pixel_pitch", positive=True)
    out = np.abs(f - fs * np.rint(f / fs))
    return float(out) if out.ndim == 0 else out


def pixel_mtf(frequency, pixel_pitch, fill_factor: float = 1.0) -> np.ndarray | float:
    """MTF of a square pixel aperture (one axis) with fill factor FF.

    The light-sensitive part of a pixel is a square of side :math:`a = p\\sqrt{FF}`
    (FF = area fraction, raised by micro-lenses). Integrating the image over that box is a
    convolution with a box of width a; its Fourier transform is

    .. math:: MTF(f) = \\left|\\frac{\\sin(π f a)}{π f a}\\right| = |\\operatorname{sinc}(f a)|

    Parameters
    ----------
    frequency : float or array_like, any shape
        Spatial frequency f, cycles per image unit (lp/mm), ≥ 0.
    pixel_pitch : float
        Pixel pitch p, image unit (mm), > 0.
    fill_factor : float
        Fill factor FF (Füllfaktor), the light-sensitive fraction of the pixel area,
        dimensionless, in (0, 1].

    Returns
    -------
    float or ndarray
        Modulation transfer MTF(f), dimensionless in [0, 1]; shape of ``frequency``
        (a float for a scalar).

    Examples
    --------
    >>> round(pixel_mtf(100.0, 0.005), 4)    # at Nyquist, FF = 1: 2/π
    0.6366
    >>> round(pixel_mtf(100.0, 0.005, 0.5), 4)   # a smaller sensitive area: less blur
    0.8067
    >>> pixel_mtf([0.0, 200.0], 0.005).round(12).tolist()   # first zero at f = 1/a
    [1.0, 0.0]
    """
    f = _array(frequency, "frequency", nonnegative=True)
    p = as_scalar(pixel_pitch, "pixel_pitch", positive=True)
    ff = as_scalar(fill_factor, "fill_factor", positive=True)
    if ff > 1.0:
        raise ValueError(f"fill_factor must be in (0, 1], got {fill_factor!r}")
    out = np.abs(np.sinc(f * p * math.sqrt(ff)))
    return float(out) if out.ndim == 0 else out


def sample_sine(frequency, pixel_pitch, n, phase: float = 0.0, fill_factor=None):
    """Pixel values of the pattern :math:`\\cos(2πfx + φ)` sampled on ``n`` pixels.

    Parameters
    ----------
    frequency : float
        f, cycles per image unit.
    pixel_pitch : float
        p, image unit; pixel k has its centre at :math:`x_k = k\\,p`.
    n : int
        Number of pixels, ≥ 2.
    phase : float
        φ, radians.
    fill_factor : float, optional
        None: point samples. Otherwise each pixel averages the pattern over its sensitive
        width :math:`a = p\\sqrt{FF}`, which multiplies the amplitude by
        :math:`\\operatorname{sinc}(fa)` (:func:`pixel_mtf`, with its sign).

    Returns
    -------
    x : ndarray, shape (n,)
        Pixel centres.
    values : ndarray, shape (n,)
        .. math:: v_k = \\operatorname{sinc}(fa)\\cos(2πf x_k + φ)

    Examples
    --------
    >>> x, v = sample_sine(150.0, 0.005, 4)     # 150 /mm on 5 µm pixels looks like 50 /mm
    >>> bool(np.allclose(v, np.cos(2 * np.pi * 50.0 * x)))
    True
    """
    f = as_scalar(frequency, "frequency")
    if f < 0:
        raise ValueError(f"frequency must be ≥ 0, got {frequency!r}")
    p = as_scalar(pixel_pitch, "pixel_pitch", positive=True)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"n must be an integer ≥ 2, got {n!r}")
    ph = as_scalar(phase, "phase")
    x = np.arange(int(n)) * p
    amp = 1.0
    if fill_factor is not None:
        ff = as_scalar(fill_factor, "fill_factor", positive=True)
        if ff > 1.0:
            raise ValueError(f"fill_factor must be in (0, 1], got {fill_factor!r}")
        amp = float(np.sinc(f * p * math.sqrt(ff)))
    return x, amp * np.cos(2.0 * np.pi * f * x + ph)
