r"""The fundamental matrix from point correspondences / Fundamentalmatrix aus Punktzuordnungen.

:func:`fundamental_8point` is Hartley's normalised 8-point algorithm: each correspondence
gives one linear equation :math:`\tilde x_2^T F \tilde x_1 = 0` in the nine entries of F
(homogeneous pixel coordinates :math:`\tilde x = (col, row, 1)`, OpenCV's convention of
``cv2.findFundamentalMat(pts1, pts2)``); the points of each image are first moved to their
centroid and scaled to mean distance √2, the null vector of the stacked equations is taken
by SVD, the rank 2 is enforced by zeroing the smallest singular value, and the
normalisation is undone, :math:`F = T_2^T F_n T_1`. :func:`sampson_distance` is the
first-order geometric error used as the RANSAC residual,

.. math:: d = \frac{(\tilde x_2^T F \tilde x_1)^2}{(F\tilde x_1)_1^2 + (F\tilde x_1)_2^2
          + (F^T\tilde x_2)_1^2 + (F^T\tilde x_2)_2^2}\quad[\mathrm{px}^2].

:func:`ransac_fundamental` puts the estimator inside :func:`photolib.correlation.ransac`.
For calibrated cameras the essential matrix is :math:`E = K_2^T F K_1`.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, check_finite
from photolib.stereo._fundamental import _normalised_eight_point

__all__ = ["fundamental_8point", "ransac_fundamental", "sampson_distance"]


def _points(a, name):
    p = as_float_array(a, name)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{name} must be (N, 2) pixel coordinates (col, row), got {p.shape}")
    check_finite(p, name)
    return p


def fundamental_8point(x1, x2) -> np.ndarray:
    """Normalised 8-point fundamental matrix with ``x2ᵀ F x1 = 0``, scaled to ‖F‖ = 1, F[2,2] ≥ 0.

    Parameters
    ----------
    x1, x2 : array_like, shape (N, 2)
        Corresponding pixel coordinates (col, row) in image 1 and image 2, N ≥ 8.

    Returns
    -------
    ndarray, shape (3, 3), rank 2.

    Raises
    ------
    ValueError
        Fewer than 8 correspondences or different counts.
    DegenerateGeometryError
        The equations have more than one solution (e.g. all points on a plane seen as a
        homography with too few distinct points, or coincident points).
    """
    p1, p2 = _points(x1, "x1"), _points(x2, "x2")
    if len(p1) != len(p2):
        raise ValueError(f"x1 has {len(p1)} points, x2 has {len(p2)}: they must correspond")
    if len(p1) < 8:
        raise ValueError(f"the 8-point algorithm needs at least 8 correspondences, got {len(p1)}")
    # the shared estimator solves h1ᵀ·M·h2 = 0: image 2 first gives OpenCV's x2ᵀ F x1 = 0
    F = _normalised_eight_point(
        p2, p1, rms=False, min_spread=1e-12,
        coincide="the points of an image coincide: F is undetermined", rtol=1e-10, rank2=True,
        degenerate="the correspondences do not determine F (a second null vector): "
                   "degenerate configuration")
    F /= np.linalg.norm(F)
    return -F if F[2, 2] < 0 else F


def sampson_distance(F, x1, x2) -> np.ndarray:
    """Sampson (first-order geometric) distance of each correspondence to ``F``, px² (N,)."""
    F = as_float_array(F, "F")
    p1, p2 = _points(x1, "x1"), _points(x2, "x2")
    h1 = np.column_stack([p1, np.ones(len(p1))])
    h2 = np.column_stack([p2, np.ones(len(p2))])
    Fx1 = h1 @ F.T
    Ftx2 = h2 @ F
    e = np.sum(h2 * Fx1, axis=1)
    return e**2 / (Fx1[:, 0]**2 + Fx1[:, 1]**2 + Ftx2[:, 0]**2 + Ftx2[:, 1]**2)


def ransac_fundamental(x1, x2, threshold_px: float = 1.0, *, confidence: float = 0.99,
                       rng=None, max_trials: int = 10_000):
    """F by RANSAC with :func:`fundamental_8point` inside the loop (s = 8).

    An inlier has a Sampson distance ``√d ≤ threshold_px``. Returns the
    :class:`photolib.correlation.RansacResult` (``model`` is F refitted on the inliers).
    """
    from photolib.correlation import ransac

    p1, p2 = _points(x1, "x1"), _points(x2, "x2")
    thr = float(threshold_px)
    return ransac(len(p1), 8, lambda i: fundamental_8point(p1[i], p2[i]),
                  lambda F: np.sqrt(sampson_distance(F, p1, p2)), thr,
                  confidence=confidence, rng=rng, max_trials=max_trials)
