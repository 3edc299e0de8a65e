"""Ground coverage: image scale, ground sampling distance, footprint, flight block, line rate.

Lengths in the image (pixel pitch, camera constant c) share one image unit (mm in the
course); flying heights, object distances and ground sizes share the object unit (m).

* Image scale number ``m_b = H/c`` and ground sampling distance ``GSD = p·H/c = p·m_b``.
* The footprint intersects the four outer image corners with a ground plane (tilted
  cameras give the true trapezoid).
* A block flight (Bildflug) with forward overlap p and side lap q has the air base
  ``B = S_along·(1 − p)`` and the strip spacing ``A = S_across·(1 − q)``, ``S = n·GSD``.
* A line sensor needs ``v/GSD`` lines per second for square ground pixels.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from photolib._validate import as_int, as_rotation, as_scalar, as_vector3
from photolib._validate import as_array as _array


# -- ground sampling distance, footprint, flight block -------------------------------------------

def image_scale_number(c, distance) -> np.ndarray | float:
    """Image scale number (Bildmaßstabszahl) :math:`m_b = H/c` of a nadir or normal image.

    ``c`` and ``distance`` in one unit (convert c from mm to m first): the scale is 1 : m_b.
    The camera constant is the image distance here; :func:`photolib.optics.image_scale_number`
    is the thin-lens form a/a' with a' from the imaging equation.

    Parameters
    ----------
    c : float
        Camera constant c (Kamerakonstante), > 0, in the unit of ``distance`` (m).
    distance : float or array_like
        Flying height above ground H, or object distance, > 0 (m).

    Returns
    -------
    float or ndarray
        Image scale number m_b, dimensionless; shape of ``distance`` (a float for a scalar).

    Notes
    -----
    .. math:: m_b = \\frac{H}{c}

    Examples
    --------
    >>> image_scale_number(0.15, 1500.0)
    10000.0
    >>> image_scale_number(0.05, np.array([500.0, 1000.0])).tolist()   # c = 50 mm
    [10000.0, 20000.0]
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
        Flying height above ground H, object unit, > 0.
    c, pixel_size : float
        Camera constant and pixel pitch, image unit (mm), > 0.
    n_along, n_across : int
        Sensor pixels along and across the flight direction, integers ≥ 1 (an integral
        float such as ``8000.0`` is accepted).
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
    n_along = as_int(n_along, "n_along", minimum=1)
    n_across = as_int(n_across, "n_across", minimum=1)
    H = as_scalar(height, "height", positive=True)     # checked here: the GSD calls it distance
    gsd = ground_sampling_distance(as_scalar(pixel_size, "pixel_size", positive=True),
                                   as_scalar(c, "c", positive=True), H)
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

    Parameters
    ----------
    speed : float
        Ground speed v of the platform, object unit per second (m/s), > 0.
    gsd : float
        Ground sampling distance along the track, object unit (m), > 0
        (:func:`ground_sampling_distance`).

    Returns
    -------
    float
        Line rate in lines per second (Hz).

    Notes
    -----
    .. math:: f_{line} = \\frac{v}{GSD}

    Examples
    --------
    >>> line_rate(70.0, 0.1)
    700.0
    >>> round(line_rate(250.0 / 3.6, 0.05), 3)   # 250 km/h at a 5 cm GSD
    1388.889
    """
    return as_scalar(speed, "speed", positive=True) / as_scalar(gsd, "gsd", positive=True)
