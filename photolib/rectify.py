r"""Plane rectification of an image with resampling (Entzerrung, indirect method).

The rectified image is a regular grid in the object plane. For every output pixel the
*indirect* method (indirekte Entzerrung) computes the object coordinates of its centre, maps
them into the source image with ``transform`` and interpolates a grey value there, so every
output pixel gets exactly one value and no holes appear.

Pixel conventions (as :mod:`photolib.pixels`): pixels are (col, row) with (0, 0) at the
centre of the top-left pixel, row downwards. The output pixel (col, row) has the object
coordinates

.. math:: X = X_0 + col\,Δ, \qquad Y = Y_0 - row\,Δ,

with ``origin = (X0, Y0)`` the object coordinates of the centre of the top-left output
pixel and Δ the pixel size (object units), so that Y points up in the object plane and down
the rows of the image.
"""

from __future__ import annotations

import numpy as np

__all__ = ["output_grid", "rectify_image", "sample_image"]


def output_grid(out_shape, origin, pixel_size) -> np.ndarray:
    """Object coordinates of the centres of the output pixels.

    Parameters
    ----------
    out_shape : tuple of int
        ``(rows, cols)`` of the rectified image.
    origin : array_like, shape (2,)
        Object coordinates (X0, Y0) of the centre of the top-left output pixel.
    pixel_size : float
        Output pixel size Δ, object units (> 0).

    Returns
    -------
    ndarray, shape (rows, cols, 2)
        ``(X, Y)`` with ``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``.

    Examples
    --------
    >>> output_grid((2, 3), (10.0, 5.0), 0.5)[1, 2].tolist()
    [11.0, 4.5]
    """
    rows, cols = _shape(out_shape)
    X0, Y0 = _origin(origin)
    d = _pixel_size(pixel_size)
    col, row = np.meshgrid(np.arange(cols, dtype=float), np.arange(rows, dtype=float))
    return np.stack([X0 + col * d, Y0 - row * d], axis=-1)


def sample_image(image, colrow, *, order: int = 1, fill: float = 0.0) -> np.ndarray:
    r"""Grey values of ``image`` at sub-pixel positions, nearest neighbour or bilinear.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
        Source image; any numeric dtype (the result is float).
    colrow : array_like, shape (..., 2)
        Positions (col, row) in source pixels, (0, 0) = centre of the top-left pixel.
    order : {0, 1}
        0 nearest neighbour (Nächster Nachbar): the pixel whose centre is nearest, inside for
        ``−0.5 ≤ col < W − 0.5`` (rows alike). 1 bilinear (bilineare Interpolation) of the
        four surrounding pixel centres, inside for ``0 ≤ col ≤ W − 1``, ``0 ≤ row ≤ H − 1``:

        .. math:: g = (1-u)(1-v)\,g_{00} + u(1-v)\,g_{10} + (1-u)v\,g_{01} + uv\,g_{11},

        with u, v the fractional parts of col, row.
    fill : float
        Value of positions outside the image.

    Returns
    -------
    ndarray, shape (...) or (..., C)

    Examples
    --------
    >>> img = np.array([[0.0, 10.0], [20.0, 30.0]])
    >>> sample_image(img, [[0.5, 0.5], [0.25, 0.0], [2.0, 0.0]]).tolist()
    [15.0, 2.5, 0.0]
    >>> sample_image(img, [[0.6, 0.4]], order=0).tolist()
    [10.0]
    """
    img = _image(image)
    pos = np.asarray(colrow, dtype=float)
    if pos.ndim < 1 or pos.shape[-1] != 2:
        raise ValueError(f"colrow has shape {pos.shape}; expected (..., 2) positions (col, row)")
    if order not in (0, 1):
        raise ValueError(f"order must be 0 (nearest) or 1 (bilinear), got {order!r}")
    H, W = img.shape[:2]
    extra = img.shape[2:]
    flat = pos.reshape(-1, 2)
    col, row = flat[:, 0], flat[:, 1]
    finite = np.isfinite(col) & np.isfinite(row)
    col = np.where(finite, col, -1e9)
    row = np.where(finite, row, -1e9)
    if order == 0:
        out = np.full((len(flat),) + extra, float(fill))
        c = np.floor(col + 0.5)
        r = np.floor(row + 0.5)
        inside = finite & (c >= 0) & (c <= W - 1) & (r >= 0) & (r <= H - 1)
        out[inside] = img[r[inside].astype(np.intp), c[inside].astype(np.intp)]
    else:
        inside = finite & (col >= 0) & (col <= W - 1) & (row >= 0) & (row <= H - 1)
        everywhere = bool(inside.all())  # the usual case: no compaction, no scatter
        ci, ri = (col, row) if everywhere else (col[inside], row[inside])
        c0 = np.floor(ci).astype(np.intp)
        r0 = np.floor(ri).astype(np.intp)
        u, v = ci - c0, ri - r0
        if extra:
            u, v = u[:, None], v[:, None]
        # four gathers from the raveled image by one linear index; on the last column (row)
        # u = 0 (v = 0) and the neighbour is the pixel itself, so grid nodes are reproduced
        # exactly
        pixels = img.reshape((H * W,) + extra)
        step_c = (c0 < W - 1).view(np.int8)
        step_r = (r0 < H - 1) * W
        idx = r0 * W
        idx += c0
        g00 = pixels.take(idx, axis=0).astype(float, copy=False)
        top = pixels.take(idx + step_c, axis=0) - g00
        top *= u
        top += g00                                  # (1 − u)·g00 + u·g10
        idx += step_r
        g01 = pixels.take(idx, axis=0).astype(float, copy=False)
        bottom = pixels.take(idx + step_c, axis=0) - g01
        bottom *= u
        bottom += g01                               # (1 − u)·g01 + u·g11
        bottom -= top
        bottom *= v
        bottom += top                               # (1 − v)·top + v·bottom
        if everywhere:
            out = bottom
        else:
            out = np.full((len(flat),) + extra, float(fill))
            out[inside] = bottom
    return out.reshape(pos.shape[:-1] + extra)


def rectify_image(image, transform, out_shape, *, origin, pixel_size, order: int = 1,
                  fill: float = 0.0) -> np.ndarray:
    r"""Rectify an image onto the object plane (indirect method, with resampling).

    For each output pixel (col, row): object coordinates ``X = X0 + col·Δ``,
    ``Y = Y0 − row·Δ``; source position ``(col', row') = transform(X, Y)``; grey value by
    :func:`sample_image` (nearest neighbour or bilinear).

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
        Source image.
    transform : callable
        Maps object coordinates (N, 2) to **source pixel** coordinates (col, row), shape
        (N, 2) — the object → image direction, e.g. ``ProjectiveTransform.from_estimate(
        object_points, pixel_points)``, or the ``.inverse`` of an image → object transform.
    out_shape : tuple of int
        ``(rows, cols)`` of the rectified image.
    origin : array_like, shape (2,)
        Object coordinates (X0, Y0) of the centre of the top-left output pixel, object units.
    pixel_size : float
        Output pixel size Δ, object units per pixel (> 0).
    order : {0, 1}
        0 nearest neighbour, 1 bilinear.
    fill : float
        Value of output pixels that fall outside the source image.

    Returns
    -------
    ndarray, shape out_shape or out_shape + (C,)
        Float grey values.

    Examples
    --------
    A shift of the object plane by half a pixel, rectified bilinearly:

    >>> from photolib.transforms import AffineTransform
    >>> img = np.arange(12.0).reshape(3, 4)
    >>> to_pixel = AffineTransform(a0=0.5, a1=1.0, b0=0.0, b2=-1.0)   # col = X + ½, row = −Y
    >>> rectify_image(img, to_pixel, (2, 3), origin=(0.0, 0.0), pixel_size=1.0).tolist()
    [[0.5, 1.5, 2.5], [4.5, 5.5, 6.5]]
    """
    if not callable(transform):
        raise ValueError(f"transform must be callable (object → source pixel), got "
                         f"{type(transform).__name__}")
    img = _image(image)
    grid = output_grid(out_shape, origin, pixel_size)
    colrow = np.asarray(transform(grid.reshape(-1, 2)), dtype=float)
    if colrow.shape != (grid.shape[0] * grid.shape[1], 2):
        raise ValueError(f"transform returned shape {colrow.shape}; expected "
                         f"({grid.shape[0] * grid.shape[1]}, 2) source pixel positions")
    return sample_image(img, colrow.reshape(grid.shape), order=order, fill=fill)


def _image(image) -> np.ndarray:
    img = np.asarray(image)
    if img.ndim not in (2, 3) or img.shape[0] < 1 or img.shape[1] < 1:
        raise ValueError(f"image has shape {img.shape}; expected (H, W) or (H, W, C)")
    if not np.issubdtype(img.dtype, np.number) or np.issubdtype(img.dtype, np.complexfloating):
        raise ValueError(f"image must be real numeric, got dtype {img.dtype}")
    return img.astype(float, copy=False)


def _shape(out_shape):
    try:
        rows, cols = (int(v) for v in out_shape)
    except (TypeError, ValueError):
        raise ValueError(f"out_shape must be (rows, cols), got {out_shape!r}") from None
    if rows < 1 or cols < 1 or (rows, cols) != tuple(out_shape):
        raise ValueError(f"out_shape must be two positive integers (rows, cols), got {out_shape!r}")
    return rows, cols


def _origin(origin):
    o = np.asarray(origin, dtype=float)
    if o.shape != (2,) or not np.all(np.isfinite(o)):
        raise ValueError(f"origin must be two finite numbers (X0, Y0), got {origin!r}")
    return float(o[0]), float(o[1])


def _pixel_size(pixel_size):
    try:
        d = float(pixel_size)
    except (TypeError, ValueError):
        raise ValueError(f"pixel_size must be a positive number, got {pixel_size!r}") from None
    if not (np.isfinite(d) and d > 0):
        raise ValueError(f"pixel_size must be a positive number, got {pixel_size!r}")
    return d
