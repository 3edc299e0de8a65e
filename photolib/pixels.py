"""Pixel ↔ image coordinates.

Pixels are (col, row) with (0, 0) at the centre of the top-left pixel, row downwards; image
coordinates (x', y') have their origin at the image centre, x' right, y' up:

.. math:: x' = (col - (W-1)/2)\\,s_x,\\qquad y' = ((H-1)/2 - row)\\,s_y
"""

from __future__ import annotations

import numpy as np

from photolib._docs import shared_doc
from photolib._validate import as_float_array, as_points, as_scalar

__all__ = ["image_from_pixel", "pixel_from_image"]


def _pixel_size(pixel_size):
    s = as_float_array(pixel_size, "pixel_size", " (a scalar or (x, y))")
    if s.shape not in ((), (1,), (2,)):
        raise ValueError(f"pixel_size has shape {s.shape}; expected a scalar or (2,) = (x, y)")
    s = np.broadcast_to(s, (2,))
    for v, n in zip(s, ("pixel_size x", "pixel_size y")):
        as_scalar(v, n, positive=True)
    return s


#: the parameters ``width, height, pixel_size`` of both conversions
_IMAGE_SIZE = """width, height : int
    Image size W × H in pixels.
pixel_size : float or array_like, shape (2,)
    Pixel spacing / Pixelabstand ``(s_x, s_y)`` in mm per pixel, > 0; a scalar for square
    pixels."""


def _size(width, height):
    W, H = as_scalar(width, "width", positive=True), as_scalar(height, "height", positive=True)
    return W, H


@shared_doc(image_size=_IMAGE_SIZE)
def image_from_pixel(colrow, width, height, pixel_size):
    """Image coordinates (mm) of pixel positions.

    Parameters
    ----------
    colrow : array_like, shape (N, 2) or (2,)
        (col, row) in pixels, sub-pixel allowed.
    {image_size}

    Returns
    -------
    xy : ndarray, shape (N, 2) or (2,)
        Image coordinates (x', y') in mm, origin at the image centre, x' right, y' up; the
        same rank as ``colrow``.

    Notes
    -----
    .. math:: x' = (col - (W-1)/2)\\,s_x,\\qquad y' = ((H-1)/2 - row)\\,s_y

    Examples
    --------
    >>> image_from_pixel([0.0, 0.0], 3, 3, 0.01).round(12).tolist()
    [-0.01, 0.01]
    """
    pts, single = as_points(colrow, 2, "colrow")
    W, H = _size(width, height)
    s = _pixel_size(pixel_size)
    out = np.column_stack([(pts[:, 0] - (W - 1) / 2) * s[0], ((H - 1) / 2 - pts[:, 1]) * s[1]])
    return out[0] if single else out


@shared_doc(image_size=_IMAGE_SIZE)
def pixel_from_image(xy, width, height, pixel_size):
    """Pixel positions (col, row) of image coordinates (mm); inverse of :func:`image_from_pixel`.

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Image coordinates (x', y') in mm, origin at the image centre, x' right, y' up.
    {image_size}

    Returns
    -------
    colrow : ndarray, shape (N, 2) or (2,)
        (col, row) in pixels (sub-pixel), (0, 0) at the centre of the top-left pixel, row
        downwards; the same rank as ``xy``.

    Notes
    -----
    .. math:: col = x'/s_x + (W-1)/2,\\qquad row = (H-1)/2 - y'/s_y

    Examples
    --------
    >>> pixel_from_image([-0.01, 0.01], 3, 3, 0.01).round(12).tolist()
    [0.0, 0.0]
    """
    pts, single = as_points(xy, 2, "xy")
    W, H = _size(width, height)
    s = _pixel_size(pixel_size)
    out = np.column_stack([pts[:, 0] / s[0] + (W - 1) / 2, (H - 1) / 2 - pts[:, 1] / s[1]])
    return out[0] if single else out
