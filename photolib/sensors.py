"""Digital images and sensors: quantisation, noise, dynamic range, colour, sampling, coverage.

Conventions of this module (chapter 03, ``docs/conventions.md``):

* A sensor element collects *electrons* (e⁻); the analogue-to-digital converter maps them to
  *digital numbers* DN (Grauwerte) ``0 … 2^b − 1``. The gain K is in e⁻/DN; the full well
  saturates at the largest DN, so ``K = full_well / (2^b − 1)``.
* Quantisation rounds to the nearest level (midtread): ``DN = clip(round(s/Δ), 0, 2^b − 1)``
  with the step ``Δ = full_scale / (2^b − 1)``.
* Noise is given as a standard deviation in electrons; an SNR is a ratio of amplitudes and its
  decibel value ``20·log10``.
* Lengths in the image (pixel pitch, camera constant c) share one image unit (mm in the
  course); object distances and ground sizes share the object unit (m). Spatial frequencies
  are cycles per image unit.
* Bayer patterns are named by the colours of the top-left 2 × 2 block read row by row:
  ``"RGGB"``, ``"BGGR"``, ``"GRBG"``, ``"GBRG"``.

NumPy only.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from photolib._validate import as_rotation, as_scalar, as_vector3

__all__ = [
    "BAYER_PATTERNS", "DynamicRange", "FlightBlock", "alias_frequency", "bayer_masks",
    "bayer_mosaic", "bits_for_levels", "decibels", "demosaic_bilinear", "dequantise",
    "dynamic_range", "flight_block", "footprint", "gain_e_per_dn", "grey_levels",
    "ground_sampling_distance", "image_scale_number", "line_rate", "nyquist_frequency",
    "pixel_mtf", "quantisation_noise_variance", "quantisation_step", "quantise", "sample_sine",
    "snr",
]

#: the four Bayer patterns: colour index (0 R, 1 G, 2 B) of the top-left 2 × 2 block
BAYER_PATTERNS = {
    "RGGB": ((0, 1), (1, 2)),
    "BGGR": ((2, 1), (1, 0)),
    "GRBG": ((1, 0), (2, 1)),
    "GBRG": ((1, 2), (0, 1)),
}


# -- validation ----------------------------------------------------------------------------------

def _bits(bits) -> int:
    if isinstance(bits, bool) or not isinstance(bits, (int, np.integer)) or bits < 1 \
            or bits > 32:
        raise ValueError(f"bits must be a positive integer 1 … 32, got {bits!r}")
    return int(bits)


def _array(values, name: str, *, nonnegative: bool = False, positive: bool = False):
    arr = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {values!r}" if arr.size < 8
                         else f"{name} contains NaN or infinite values")
    if positive and np.any(arr <= 0):
        raise ValueError(f"{name} must be > 0, got {values!r}")
    if nonnegative and np.any(arr < 0):
        raise ValueError(f"{name} must be ≥ 0, got {values!r}")
    return arr


def _pattern(pattern: str) -> tuple:
    key = str(pattern).upper()
    if key not in BAYER_PATTERNS:
        raise ValueError(f"Bayer pattern {pattern!r} is not one of {sorted(BAYER_PATTERNS)}")
    return BAYER_PATTERNS[key]


# -- grey levels and quantisation ----------------------------------------------------------------

def grey_levels(bits) -> int:
    """Number of grey values (Grauwerte) of a b-bit image: :math:`2^b`.

    The German summary's "n bits give 2^n grey values" (errata record ``de-summary:bit-depth``,
    verdict right).

    >>> grey_levels(8), grey_levels(12)
    (256, 4096)
    """
    return 2 ** _bits(bits)


def bits_for_levels(levels) -> int:
    """Smallest bit depth b with :math:`2^b ≥` ``levels``: :math:`b = ⌈\\log_2 n⌉`.

    >>> bits_for_levels(256), bits_for_levels(257), bits_for_levels(2)
    (8, 9, 1)
    """
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or levels < 2:
        raise ValueError(f"levels must be an integer ≥ 2, got {levels!r}")
    return int(levels - 1).bit_length()


def quantisation_step(bits, full_scale: float = 1.0) -> float:
    """Step Δ between neighbouring levels: :math:`Δ = s_{max}/(2^b - 1)`.

    Parameters
    ----------
    bits : int
        Bit depth b ≥ 1.
    full_scale : float
        Signal that maps to the largest DN, :math:`2^b − 1` (any unit; > 0).

    >>> quantisation_step(8, 255.0)
    1.0
    """
    return as_scalar(full_scale, "full_scale", positive=True) / (grey_levels(bits) - 1)


def quantise(signal, bits, full_scale: float = 1.0) -> np.ndarray:
    """Digital numbers of an analogue signal: round to the nearest of :math:`2^b` levels.

    Parameters
    ----------
    signal : array_like, any shape
        Analogue values (same unit as ``full_scale``); values outside [0, full_scale] are
        clipped (under- and overexposure).
    bits : int
        Bit depth b.
    full_scale : float
        Signal of the largest DN.

    Returns
    -------
    ndarray of int64, same shape
        .. math:: DN = \\min(\\max(\\operatorname{round}(s/Δ), 0), 2^b - 1),\\quad Δ = s_{max}/(2^b-1)

    Examples
    --------
    >>> quantise([0.0, 0.26, 0.5, 1.2], 2).tolist()
    [0, 1, 2, 3]
    """
    step = quantisation_step(bits, full_scale)
    s = _array(signal, "signal")
    return np.clip(np.rint(s / step), 0, grey_levels(bits) - 1).astype(np.int64)


def dequantise(dn, bits, full_scale: float = 1.0) -> np.ndarray:
    """Signal values of digital numbers: :math:`s = DN·Δ` (inverse of :func:`quantise`).

    >>> dequantise([0, 1, 3], 2).round(6).tolist()
    [0.0, 0.333333, 1.0]
    """
    step = quantisation_step(bits, full_scale)
    d = _array(dn, "dn")
    if np.any(d < 0) or np.any(d > grey_levels(bits) - 1) or np.any(d != np.rint(d)):
        raise ValueError(f"dn must be integers 0 … {grey_levels(bits) - 1}")
    return d * step


def quantisation_noise_variance(step) -> np.ndarray | float:
    """Variance of the rounding error, uniform on [−Δ/2, Δ/2]: :math:`σ_q^2 = Δ^2/12`.

    .. math:: σ_q^2 = \\frac{1}{Δ}\\int_{-Δ/2}^{Δ/2} e^2\\,de = \\frac{Δ^2}{12}

    >>> quantisation_noise_variance(1.0) == 1 / 12
    True
    """
    d = _array(step, "step", positive=True)
    out = d**2 / 12.0
    return float(out) if out.ndim == 0 else out


# -- sensor: gain, dynamic range, SNR ------------------------------------------------------------

def gain_e_per_dn(full_well_e, bits) -> float:
    """System gain K in e⁻/DN when the full well fills the DN range: :math:`K = FW/(2^b − 1)`.

    The German summary's "Gain: number of photons (electrons) that define one grey level".

    >>> round(gain_e_per_dn(40950.0, 12), 6)
    10.0
    """
    fw = as_scalar(full_well_e, "full_well_e", positive=True)
    return fw / (grey_levels(bits) - 1)


class DynamicRange(NamedTuple):
    """Dynamic range (Dynamikumfang) as a ratio, in dB and in bits."""

    ratio: float
    db: float
    bits: float


def dynamic_range(full_well_e, read_noise_e) -> DynamicRange:
    """Dynamic range of a sensor: largest signal over the noise floor.

    Parameters
    ----------
    full_well_e : float
        Full-well capacity (Fassungsvermögen), electrons, > 0.
    read_noise_e : float
        Read noise (noise floor) σ_r, electrons, > 0.

    Returns
    -------
    DynamicRange
        .. math:: DR = FW/σ_r,\\quad DR_{dB} = 20\\log_{10} DR,\\quad DR_{bit} = \\log_2 DR

    Examples
    --------
    >>> dr = dynamic_range(20000.0, 5.0)
    >>> round(dr.ratio), round(dr.db, 2), round(dr.bits, 3)
    (4000, 72.04, 11.966)
    """
    fw = as_scalar(full_well_e, "full_well_e", positive=True)
    rn = as_scalar(read_noise_e, "read_noise_e", positive=True)
    ratio = fw / rn
    return DynamicRange(ratio, 20.0 * math.log10(ratio), math.log2(ratio))


def decibels(ratio) -> np.ndarray | float:
    """An amplitude ratio in decibels: :math:`20\\log_{10}(ratio)`.

    >>> decibels(100.0)
    40.0
    """
    r = _array(ratio, "ratio", positive=True)
    out = 20.0 * np.log10(r)
    return float(out) if out.ndim == 0 else out


def snr(signal_e, read_noise_e=0.0, gain=None, dark_e=0.0) -> np.ndarray | float:
    """Signal-to-noise ratio of a pixel: photon shot noise, dark, read and quantisation noise.

    Parameters
    ----------
    signal_e : float or array_like
        Mean signal S in electrons, ≥ 0 (Poisson: shot-noise variance S).
    read_noise_e : float
        Read noise σ_r, electrons.
    gain : float, optional
        Gain K in e⁻/DN; adds quantisation noise :math:`K^2/12` (electrons²). None: no ADC.
    dark_e : float
        Mean dark signal D in electrons (Poisson, variance D).

    Returns
    -------
    float or ndarray
        .. math:: SNR = \\frac{S}{\\sqrt{S + D + σ_r^2 + K^2/12}}

    Examples
    --------
    >>> snr(10000.0)
    100.0
    >>> round(snr(100.0, read_noise_e=10.0), 4)
    7.0711
    """
    S = _array(signal_e, "signal_e", nonnegative=True)
    rn = _array(read_noise_e, "read_noise_e", nonnegative=True)
    D = _array(dark_e, "dark_e", nonnegative=True)
    var = S + D + rn**2
    if gain is not None:
        var = var + quantisation_noise_variance(as_scalar(gain, "gain", positive=True))
    if np.any(var <= 0):
        raise ValueError("the noise variance is zero (no signal and no noise): SNR undefined")
    out = S / np.sqrt(var)
    return float(out) if np.ndim(out) == 0 else out


# -- ground sampling distance, footprint, flight block -------------------------------------------

def image_scale_number(c, distance) -> np.ndarray | float:
    """Image scale number (Bildmaßstabszahl) :math:`m_b = H/c` of a nadir or normal image.

    ``c`` and ``distance`` in one unit (convert c from mm to m first): the scale is 1 : m_b.
    The camera constant is the image distance here; :func:`photolib.optics.image_scale_number`
    is the thin-lens form a/a' with a' from the imaging equation.

    >>> image_scale_number(0.15, 1500.0)
    10000.0
    """
    c = as_scalar(c, "c", positive=True)
    h = _array(distance, "distance", positive=True)
    out = h / c
    return float(out) if out.ndim == 0 else out


def ground_sampling_distance(pixel_size, c, distance) -> np.ndarray | float:
    """Ground sampling distance (Bodenpixelgröße, pixel resolution): one pixel in object space.

    Parameters
    ----------
    pixel_size : float
        Pixel pitch, image unit (mm), > 0.
    c : float
        Camera constant, the same image unit, > 0.
    distance : float or array_like
        Flying height above ground H, or object distance, object unit (m), > 0.

    Returns
    -------
    float or ndarray
        GSD in the object unit.

        .. math:: GSD = p\\,\\frac{H}{c} = p\\,m_b

    Examples
    --------
    >>> round(ground_sampling_distance(0.006, 100.0, 1000.0), 9)   # 6 µm, c = 100 mm, 1000 m
    0.06
    """
    p = as_scalar(pixel_size, "pixel_size", positive=True)
    c = as_scalar(c, "c", positive=True)
    h = _array(distance, "distance", positive=True)
    out = p * h / c
    return float(out) if out.ndim == 0 else out


def footprint(width, height, pixel_size, c, X0, R=None, Z=0.0) -> np.ndarray:
    """Ground footprint of an image: its four outer corners intersected with the plane ``Z``.

    The corners of the pixel area (pixel edges, −0.5 and W − 0.5) are turned into image
    coordinates by :func:`photolib.image_from_pixel` and intersected with the plane by
    :func:`photolib.monoplot`, so a tilted camera gives the true trapezoid.

    Parameters
    ----------
    width, height : int
        Image size W × H in pixels.
    pixel_size : float
        Pixel pitch, image unit (mm).
    c : float
        Camera constant, image unit.
    X0 : array_like, shape (3,)
        Projection centre, object unit; Z0 > Z.
    R : array_like, shape (3, 3), optional
        Rotation (image → object); default the nadir view ``I``.
    Z : float
        Height of the ground plane.

    Returns
    -------
    ndarray, shape (4, 3)
        Top-left, top-right, bottom-right, bottom-left corner on the ground.

    Examples
    --------
    >>> F = footprint(1000, 800, 0.01, 50.0, [0.0, 0.0, 500.0])
    >>> round(float(F[1, 0] - F[0, 0]), 9), round(float(F[0, 1] - F[3, 1]), 9)
    (100.0, 80.0)
    """
    from photolib.collinearity import monoplot
    from photolib.pixels import image_from_pixel

    W = as_scalar(width, "width", positive=True)
    H = as_scalar(height, "height", positive=True)
    X0 = as_vector3(X0, "X0")
    R = np.eye(3) if R is None else as_rotation(R)
    corners = np.array([[-0.5, -0.5], [W - 0.5, -0.5], [W - 0.5, H - 0.5], [-0.5, H - 0.5]])
    xy = image_from_pixel(corners, W, H, pixel_size)
    return monoplot(xy, X0, R, c, Z)


class FlightBlock(NamedTuple):
    """An aerial photo flight over a rectangular block (Bildflug, Blockplanung)."""

    gsd: float                #: object unit
    coverage_along: float     #: ground length of the image along the flight, object unit
    coverage_across: float    #: ground width of the image across the flight
    base: float               #: air base B = along·(1 − p)
    strip_spacing: float      #: distance of neighbouring strips A = across·(1 − q)
    strips: int
    images_per_strip: int
    images: int


def flight_block(length, width, height, c, pixel_size, n_along, n_across,
                 overlap=0.6, sidelap=0.3) -> FlightBlock:
    """Images needed to cover a rectangular block in stereo with parallel strips.

    Parameters
    ----------
    length, width : float
        Block size along and across the flight direction, object unit (m).
    height : float
        Flying height above ground H, object unit.
    c, pixel_size : float
        Camera constant and pixel pitch, image unit (mm).
    n_along, n_across : int
        Sensor pixels along and across the flight direction.
    overlap : float
        Forward overlap p (Längsüberdeckung), in [0.5, 1): below 50 % neighbouring stereo
        models leave gaps.
    sidelap : float
        Side lap q (Querüberdeckung) of neighbouring strips, in [0, 1).

    Returns
    -------
    FlightBlock
        With the image's ground size :math:`S = n\\,GSD`, base :math:`B = S_{along}(1-p)` and
        strip spacing :math:`A = S_{across}(1-q)`: one stereo model (two neighbouring images)
        covers :math:`S_{along} - B = p\\,S_{along}`, k models in a row cover
        :math:`(k-1)B + pS_{along}`, so

        .. math:: k = \\max\\left(1, \\left\\lceil\\frac{L - pS_{along}}{B}\\right\\rceil + 1\\right),
                  \\quad n_{strip} = k + 1,\\quad
                  n_{strips} = \\max\\left(1, \\left\\lceil\\frac{W - S_{across}}{A}\\right\\rceil + 1\\right)

        with the block's start at the first model's start and the first strip's edge at the
        block's edge.

    Examples
    --------
    >>> fb = flight_block(3000.0, 2000.0, 1500.0, 100.0, 0.004, 10000, 15000)
    >>> fb.gsd, fb.base, fb.strips, fb.images_per_strip, fb.images
    (0.06, 240.0, 3, 13, 39)
    """
    L = as_scalar(length, "length", positive=True)
    Wd = as_scalar(width, "width", positive=True)
    p = as_scalar(overlap, "overlap")
    if not 0.5 <= p < 1.0:
        raise ValueError(f"overlap must be a fraction in [0.5, 1) for stereo cover, got {overlap!r}")
    q = as_scalar(sidelap, "sidelap")
    if not 0.0 <= q < 1.0:
        raise ValueError(f"sidelap must be a fraction in [0, 1), got {sidelap!r}")
    for value, name in ((n_along, "n_along"), (n_across, "n_across")):
        as_scalar(value, name, positive=True)
    gsd = ground_sampling_distance(pixel_size, c, height)
    along, across = n_along * gsd, n_across * gsd
    base = along * (1.0 - p)
    spacing = across * (1.0 - q)
    # 1e-9: a block of exactly k bases must not get a (k+1)-th from rounding noise
    models = max(1, math.ceil((L - p * along) / base - 1e-9) + 1)
    strips = max(1, math.ceil((Wd - across) / spacing - 1e-9) + 1)
    return FlightBlock(gsd, along, across, base, spacing, strips, models + 1,
                       strips * (models + 1))


def line_rate(speed, gsd) -> float:
    """Lines per second of a line sensor (Zeilensensor) for square ground pixels: v/GSD.

    A pushbroom scanner records one line per GSD of forward motion; slower reading stretches
    the ground pixels along the track.

    >>> line_rate(70.0, 0.1)
    700.0
    """
    return as_scalar(speed, "speed", positive=True) / as_scalar(gsd, "gsd", positive=True)


# -- colour: Bayer mosaic and bilinear demosaicing ------------------------------------------------

def bayer_masks(shape, pattern: str = "RGGB") -> np.ndarray:
    """Boolean masks (3, H, W): which pixel carries the R, G or B filter.

    >>> m = bayer_masks((4, 4))
    >>> m.sum(axis=(1, 2)).tolist()   # a quarter red, half green, a quarter blue
    [4, 8, 4]
    """
    cells = _pattern(pattern)
    if len(shape) != 2 or min(shape) < 2:
        raise ValueError(f"shape must be (H, W) with H, W ≥ 2, got {shape!r}")
    Hh, Ww = int(shape[0]), int(shape[1])
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


# -- sampling, aliasing, pixel MTF ---------------------------------------------------------------

def nyquist_frequency(pixel_pitch) -> float:
    """Highest frequency a pixel grid can represent: :math:`f_N = 1/(2p)` (cycles/unit).

    >>> nyquist_frequency(0.005)   # 5 µm pixels: 100 line pairs per mm
    100.0
    """
    return 0.5 / as_scalar(pixel_pitch, "pixel_pitch", positive=True)


def alias_frequency(frequency, pixel_pitch) -> np.ndarray | float:
    """Apparent frequency of a sampled sine (Alias): folded into [0, f_N].

    .. math:: f_a = \\left|f - f_s\\,\\operatorname{round}(f/f_s)\\right|,\\quad f_s = 1/p

    >>> alias_frequency([30.0, 80.0, 120.0, 200.0], 0.005).tolist()   # f_N = 100 /mm
    [30.0, 80.0, 80.0, 0.0]
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
    frequency : float or array_like
        Spatial frequency, cycles per image unit, ≥ 0.
    pixel_pitch : float
        Pixel pitch p, image unit.
    fill_factor : float
        Fill factor in (0, 1].

    Examples
    --------
    >>> round(pixel_mtf(100.0, 0.005), 4)    # at Nyquist, FF = 1: 2/π
    0.6366
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
