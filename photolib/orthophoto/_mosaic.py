r"""Mosaic (Bildmosaik) of orthophotos on one grid with nearest-nadir seamlines.

Each pixel of :func:`mosaic_nearest_nadir` comes from the orthophoto whose nadir point is
nearest in plan (the least relief displacement) and that has a value there.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import check_finite
from photolib.rectify import output_grid


def mosaic_nearest_nadir(orthos, nadirs, origin, pixel_size):
    r"""Mosaic (Bildmosaik) of orthophotos on one grid with nearest-nadir seamlines.

    Each output pixel takes the orthophoto whose nadir point is nearest in plan (the least
    relief displacement, as :func:`relief_displacement` grows with r); where that one has no
    value (NaN), the next nearest with a value. For two images the seamline (Schnittkante)
    is the perpendicular bisector of the two nadir points.

    Parameters
    ----------
    orthos : sequence of array_like, each shape (rows, cols)
        Orthophotos on the same grid (NaN = no value).
    nadirs : array_like, shape (K, 2)
        Plan positions of the nadir points (X0, Y0 of the cameras).
    origin, pixel_size
        The common grid.

    Returns
    -------
    mosaic : ndarray, shape (rows, cols)
    source : ndarray of int, shape (rows, cols)
        Index of the orthophoto used (−1 where none has a value).

    Examples
    --------
    >>> a, b = np.zeros((1, 4)), np.ones((1, 4))
    >>> m, src = mosaic_nearest_nadir([a, b], [[0.0, 0.0], [3.0, 0.0]], (0.0, 0.0), 1.0)
    >>> m.tolist(), src.tolist()
    ([[0.0, 0.0, 1.0, 1.0]], [[0, 0, 1, 1]])
    """
    stack = np.stack([np.asarray(o, dtype=float) for o in orthos])
    if stack.ndim != 3:
        raise ValueError(f"orthos must be 2-D grids of one shape, got shape {stack.shape[1:]}")
    nad = np.asarray(nadirs, dtype=float)
    if nad.shape != (len(stack), 2):
        raise ValueError(f"nadirs has shape {nad.shape}; expected ({len(stack)}, 2), one per ortho")
    check_finite(nad, "nadirs")
    grid = output_grid(stack.shape[1:], origin, pixel_size)
    dist = np.linalg.norm(grid[None] - nad[:, None, None, :], axis=-1)
    dist = np.where(np.isfinite(stack), dist, np.inf)
    source = np.argmin(dist, axis=0)
    mosaic = np.take_along_axis(stack, source[None], axis=0)[0]
    none = ~np.isfinite(dist.min(axis=0))
    source[none] = -1
    mosaic[none] = np.nan
    return mosaic, source
