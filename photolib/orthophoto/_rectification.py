r"""Indirect differential rectification (differentielle Entzerrung): the orthophoto.

For every ortho pixel its plan position (X, Y), the height from the terrain model, the
image point by the collinearity equations and the grey value there:
:func:`ortho_pixel_positions` gives the source pixel positions (the rectification maps) and
:func:`differential_rectification` resamples the image, in blocks of ``BLOCK_ROWS`` rows.
"""

from __future__ import annotations

import numpy as np

from photolib.collinearity import PointBehindCameraError
from photolib.orthophoto._camera import FrameCamera
from photolib.orthophoto._dtm import DTM
from photolib.rectify import _origin, _pixel_size, _shape, output_grid, sample_image

#: output rows per block of :func:`differential_rectification`
BLOCK_ROWS = 256


def _grid_args(out_shape, origin, pixel_size):
    return _shape(out_shape), _origin(origin), _pixel_size(pixel_size)


def ortho_pixel_positions(camera: FrameCamera, model: DTM, out_shape, origin, pixel_size,
                          *, rows=None):
    r"""Source-image pixel positions of the orthophoto's pixels (the rectification maps).

    For each ortho pixel: ``(X, Y)`` of its centre, ``Z = model.height(X, Y)``, then
    ``(col', row') = pixel_from_image(project((X, Y, Z)))``.

    Parameters
    ----------
    camera : FrameCamera
    model : DTM
        Terrain (DTM) or surface (DSM) model; must cover every ortho pixel.
    out_shape, origin, pixel_size
        Orthophoto grid as in :func:`photolib.rectify.rectify_image` (object units).
    rows : slice, optional
        Only these output rows (for blockwise processing).

    Returns
    -------
    colrow : ndarray, shape (rows, cols, 2)
        Source pixel positions, usable as ``cv2.remap`` maps.
    XYZ : ndarray, shape (rows, cols, 3)
        Object points of the ortho pixels.

    Raises
    ------
    OutsideModelError
        If an ortho pixel lies outside the height model.
    PointBehindCameraError
        If a ground point is not in front of the camera.

    Examples
    --------
    >>> cam = FrameCamera([0.0, 0.0, 100.0], np.eye(3), 50.0, 201, 201, 0.01)
    >>> dtm = DTM(np.zeros((3, 3)), (-1.0, 1.0), 1.0)
    >>> ortho_pixel_positions(cam, dtm, (1, 1), (1.0, 0.0), 1.0)[0].round(6).tolist()
    [[[150.0, 100.0]]]
    """
    (nr, nc), o, d = _grid_args(out_shape, origin, pixel_size)
    if not isinstance(model, DTM):
        raise TypeError(f"model must be a photolib.orthophoto.DTM, got {type(model).__name__}")
    grid = output_grid((nr, nc), o, d)
    if rows is not None:
        grid = grid[rows]
    Z = model.height(grid)
    XYZ = np.concatenate([grid, Z[..., None]], axis=-1)
    flat = XYZ.reshape(-1, 3)
    try:
        cr = camera.pixel(flat)
    except PointBehindCameraError as exc:
        raise PointBehindCameraError(f"ortho ground point behind the camera: {exc}") from None
    return cr.reshape(grid.shape[:2] + (2,)), XYZ


def differential_rectification(image, camera: FrameCamera, model: DTM, out_shape, origin,
                               pixel_size, *, order: int = 1, fill: float = 0.0,
                               block_rows: int = BLOCK_ROWS, progress: bool = False):
    r"""Orthophoto by indirect differential rectification (differentielle Entzerrung).

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
        The source image; its size must be ``camera.height × camera.width``.
    camera : FrameCamera
    model : DTM
        DTM for an orthophoto, DSM for the grey values of a true orthophoto.
    out_shape : tuple of int
        ``(rows, cols)`` of the orthophoto.
    origin : array_like, shape (2,)
        Object coordinates (X0, Y0) of the centre of the top-left ortho pixel (object unit).
    pixel_size : float
        Ortho pixel size Δ / ground sampling distance (Bodenpixelgröße), object unit per pixel,
        > 0: ``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``.
    order : {0, 1}
        Resampling: nearest neighbour or bilinear.
    fill : float
        Value where the ground point falls outside the image.
    block_rows : int
        Output rows computed at once: memory stays bounded for large orthophotos.
    progress : bool
        Show a ``tqdm`` progress bar over the blocks.

    Returns
    -------
    ndarray, shape out_shape (+ (C,))
        Float grey values of the orthophoto (unit of ``image``); ``fill`` where the ground
        point falls outside the source image.

    Notes
    -----
    .. math:: g_{ortho}(X, Y) = g\bigl(\mathrm{pixel}(x'(X, Y, Z(X, Y)),\ y'(X, Y, Z(X, Y)))\bigr)

    Examples
    --------
    >>> cam = FrameCamera([0.0, 0.0, 100.0], np.eye(3), 50.0, 3, 3, 0.5)
    >>> img = np.arange(9.0).reshape(3, 3)
    >>> dtm = DTM(np.zeros((3, 3)), (-1.0, 1.0), 1.0)
    >>> differential_rectification(img, cam, dtm, (3, 3), (-1.0, 1.0), 1.0).tolist()
    [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0], [6.0, 7.0, 8.0]]
    """
    img = np.asarray(image)
    if img.ndim not in (2, 3) or img.shape[:2] != (camera.height, camera.width):
        raise ValueError(f"image has shape {img.shape}; the camera expects "
                         f"({camera.height}, {camera.width}) (rows, cols)")
    (nr, nc), o, d = _grid_args(out_shape, origin, pixel_size)
    if int(block_rows) != block_rows or block_rows < 1:
        raise ValueError(f"block_rows must be a positive integer, got {block_rows!r}")
    out = np.empty((nr, nc) + img.shape[2:])
    starts = range(0, nr, int(block_rows))
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, desc="orthophoto", unit="block")
    for s in starts:
        rows = slice(s, min(s + int(block_rows), nr))
        cr, _ = ortho_pixel_positions(camera, model, (nr, nc), o, d, rows=rows)
        out[rows] = sample_image(img, cr, order=order, fill=fill)
    return out
