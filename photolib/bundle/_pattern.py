"""The non-zero pattern of the normal matrix of a bundle adjustment, full or reduced.

:func:`normal_matrix_pattern` shows which blocks of ``N = AᵀA`` may be non-zero (images,
interior parameters, points) and, after the points are eliminated, where the reduced normal
matrix couples images that share a new point: the structure the reduced normal equations
exploit, to be shown with ``matplotlib``'s ``spy``.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_indices, as_int


def normal_matrix_pattern(image_index, point_index, n_images: int, n_points: int,
                          n_interior: int = 0, fixed=(), reduced: bool = False) -> np.ndarray:
    """Non-zero pattern (boolean u×u) of N, order: images (6 each), interior, points (3 each).

    ``fixed`` lists point indices with fixed coordinates (no columns). ``reduced``: the
    pattern of the reduced normal matrix (points eliminated), (6M + k) square: images are
    coupled where they share a new point. For ``matplotlib``'s ``spy``.

    Parameters
    ----------
    image_index, point_index : array_like of int, shape (N,)
        Image j and object point i of each measured image point, as in
        :func:`bundle_adjustment`.
    n_images : int
        Number of images M, ≥ 1.
    n_points : int
        Number of object points P, ≥ 0.
    n_interior : int
        Number k of interior (self-calibration) parameters common to all images, ≥ 0.
    fixed : sequence of int
        Indices of control points with fixed coordinates (no unknowns, no rows/columns).
    reduced : bool
        If True the pattern of the reduced normal matrix (points eliminated).

    Returns
    -------
    ndarray of bool, shape (u, u)
        True where N may be non-zero; ``u = 6M + k + 3·(P − len(fixed))``, or ``6M + k`` if
        ``reduced``.

    Notes
    -----
    .. math:: N = A^TA,\\qquad N_{ab} \\ne 0 \\iff \\text{the unknowns a and b occur in
              one observation (or, reduced, share a new point)}

    Examples
    --------
    >>> normal_matrix_pattern([0, 1], [0, 0], 2, 1).shape
    (15, 15)
    >>> P = normal_matrix_pattern([0, 1], [0, 0], 2, 1, reduced=True)
    >>> P.shape, bool(P[0, 6])       # images 0 and 1 share point 0: coupled
    ((12, 12), True)
    """
    n_images, n_points = as_int(n_images, "n_images", minimum=1), as_int(n_points, "n_points",
                                                                           minimum=0)
    j = as_indices(image_index, "image_index", n_images)
    i = as_indices(point_index, "point_index", n_points)
    if j.shape != i.shape:
        raise ValueError(f"image_index has shape {j.shape} but point_index {i.shape}; they must "
                         "pair up")
    free = np.setdiff1d(np.arange(n_points), as_indices(fixed, "fixed", n_points))
    inc = np.zeros((n_images, n_points), bool)  # incidence: image sees point
    inc[j, i] = True
    inc = inc[:, free]
    M, k = n_images, n_interior
    blocks = np.zeros((M + 1 + len(free),) * 2, bool)  # images, interior, points
    blocks[:M, :M] = np.eye(M, dtype=bool)
    blocks[:M, M] = blocks[M, :M] = k > 0
    blocks[M, M] = k > 0
    blocks[M, M + 1:] = blocks[M + 1:, M] = (k > 0) & inc.any(axis=0)
    blocks[:M, M + 1:] = inc
    blocks[M + 1:, :M] = inc.T
    blocks[M + 1:, M + 1:] = np.eye(len(free), dtype=bool)
    if reduced:
        blocks = blocks[:M + 1, :M + 1]
        blocks[:M, :M] |= (inc.astype(np.float32) @ inc.T.astype(np.float32)) > 0
    sizes = np.r_[np.full(M, 6), k, np.full(len(free), 3)][:len(blocks)]
    return np.repeat(np.repeat(blocks, sizes, axis=0), sizes, axis=1)
