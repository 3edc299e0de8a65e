r"""The fundamental matrix estimated from point correspondences (normalised 8-point algorithm).

Luhmann's order as in :func:`photolib.stereo.fundamental_matrix`: ``h1ᵀ·F·h2 = 0`` for
corresponding homogeneous image points ``h_i = (x_i, y_i, 1)`` (image 1 left). Each pair gives
one linear equation in the nine elements of F, ``kron(h1, h2)·vec(F) = 0``; with the points
normalised (Hartley 1997: centroid at 0, mean distance √2) the least-squares solution is the
last right singular vector, and the rank 2 of F is enforced by zeroing its smallest singular
value. :func:`estimate_fundamental_ransac` wraps it in :func:`photolib.correlation.ransac`
with the symmetric epipolar distance as the residual.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_points, as_scalar
from photolib.transforms._base import DegenerateGeometryError


def _normaliser(pts, *, rms, min_spread, coincide):
    """Hartley's normalising similarity ``T`` of 2-D points (N, 2): centroid to 0, spread √2.

    The spread ``d`` is the mean distance from the centroid, or with ``rms`` the root mean
    square distance; ``T = [[k, 0, −k·m_x], [0, k, −k·m_y], [0, 0, 1]]``, ``k = √2/d``.
    ``d ≤ min_spread`` (and a NaN ``d``) raises ``DegenerateGeometryError(coincide)``.
    """
    m = pts.mean(axis=0)
    if rms:
        d = np.sqrt(np.mean(np.sum((pts - m) ** 2, axis=1)))
    else:
        d = np.mean(np.hypot(*(pts - m).T))
    if not d > min_spread:
        raise DegenerateGeometryError(coincide)
    k = np.sqrt(2.0) / d
    return np.array([[k, 0.0, -k * m[0]], [0.0, k, -k * m[1]], [0.0, 0.0, 1.0]])


def _normalised_eight_point(p1, p2, *, rms, min_spread, coincide, rtol, degenerate, rank2):
    r"""The normalised 8-point algorithm (Hartley 1997): ``M`` with ``h1ᵀ·M·h2 ≈ 0``.

    The one implementation behind :func:`estimate_fundamental`,
    :func:`photolib.fundamental_8point` (called with the images swapped, for OpenCV's
    ``x2ᵀ F x1 = 0``) and :func:`photolib.essential_eight_point` (reduced image vectors).

    ``p1, p2``: corresponding points (N, 2), N ≥ 8, checked by the caller;
    ``h_i = T_i·(x_i, y_i, 1)`` with :func:`_normaliser` (``rms``, ``min_spread``,
    ``coincide`` passed on). Each pair gives one row ``kron(ĥ1, ĥ2)`` of ``A``; ``M̂`` is the
    last right singular vector of ``A`` (minimises ``|A·vec M̂|`` with ``|M̂| = 1``). A
    relative singular value ``σ8/σ1 ≤ rtol`` (more than one solution) raises
    ``DegenerateGeometryError(degenerate.format(ratio=σ8/σ1))``. With ``rank2`` the
    smallest singular value of ``M̂`` is set to 0. Returns ``M = T1ᵀ·M̂·T2``, not rescaled.
    """
    T1 = _normaliser(p1, rms=rms, min_spread=min_spread, coincide=coincide)
    T2 = _normaliser(p2, rms=rms, min_spread=min_spread, coincide=coincide)
    h1 = np.column_stack([p1, np.ones(len(p1))]) @ T1.T
    h2 = np.column_stack([p2, np.ones(len(p2))]) @ T2.T
    A = (h1[:, :, None] * h2[:, None, :]).reshape(len(p1), 9)   # row: kron(h1, h2)
    _, sv, Vt = np.linalg.svd(A)                 # full V: its last row spans the null space
    if sv[7] <= rtol * sv[0]:                    # rank < 8: more than one solution
        raise DegenerateGeometryError(degenerate.format(ratio=sv[7] / sv[0]))
    Mn = Vt[-1].reshape(3, 3)
    if rank2:
        U, s, Vt3 = np.linalg.svd(Mn)
        Mn = U @ np.diag([s[0], s[1], 0.0]) @ Vt3
    return T1.T @ Mn @ T2


def estimate_fundamental(xy1, xy2) -> np.ndarray:
    r"""Fundamental matrix of ≥ 8 correspondences (normalised 8-point algorithm).

    Parameters
    ----------
    xy1, xy2 : array_like, shape (N, 2)
        Corresponding points in image 1 and 2 (any image unit, e.g. px), N ≥ 8.

    Returns
    -------
    ndarray, shape (3, 3)
        F with ``h1ᵀ·F·h2 = 0``, rank 2, scaled to ``|F|_Frobenius = 1``.

    Raises
    ------
    ValueError
        Fewer than 8 pairs or shapes that differ.
    DegenerateGeometryError
        The points do not determine F (the 9 × 9 system has a null space of dimension > 1:
        e.g. all points on one plane seen without parallax, or on a line).

    Notes
    -----
    With ``T_i`` the normalising similarities, ``ĥ_i = T_i·h_i``: minimise
    :math:`\sum_k (\hat h_{1k}^T \hat F \hat h_{2k})^2` subject to :math:`|\hat F| = 1`
    (SVD), set the smallest singular value of F̂ to 0, and ``F = T1ᵀ·F̂·T2``.

    Examples
    --------
    >>> import photolib as pl
    >>> X = np.random.default_rng(0).uniform([-5, -5, -30], [5, 5, -20], (12, 3))
    >>> R2 = pl.rotation_opk(0.02, -0.05, 0.01)
    >>> a, b = pl.project(X, [0, 0, 0], np.eye(3), 50.0), pl.project(X, [4.0, 0.5, 0], R2, 50.0)
    >>> F = estimate_fundamental(a, b)
    >>> E = pl.essential_matrix([0, 0, 0], np.eye(3), [4.0, 0.5, 0], R2)
    >>> F_true = pl.fundamental_matrix(E, 50.0, 50.0)
    >>> F_true /= np.linalg.norm(F_true)
    >>> bool(min(np.abs(F - F_true).max(), np.abs(F + F_true).max()) < 1e-9)
    True
    """
    p1, _ = as_points(xy1, 2, "xy1")
    p2, _ = as_points(xy2, 2, "xy2")
    if p1.shape != p2.shape:
        raise ValueError(f"xy1 and xy2 differ in shape: {p1.shape} and {p2.shape}")
    if len(p1) < 8:
        raise ValueError(f"the 8-point algorithm needs at least 8 correspondences, got {len(p1)}")
    F = _normalised_eight_point(
        p1, p2, rms=True, min_spread=0.0, coincide="all points coincide: no fundamental matrix",
        rtol=1e-10, rank2=True, degenerate=(
            "the correspondences do not determine F (the 9 linear equations have a null space "
            "of dimension > 1; relative singular value σ8/σ1 = {ratio:.3g}): points on a line "
            "or a plane without parallax?"))
    F /= np.linalg.norm(F)
    return F


def epipolar_distances(F, xy1, xy2) -> np.ndarray:
    r"""Symmetric epipolar distance of each pair: ``(|d(x1, F·h2)| + |d(x2, Fᵀ·h1)|)/2``.

    Parameters
    ----------
    F : array_like, shape (3, 3)
        ``h1ᵀ·F·h2 = 0``.
    xy1, xy2 : array_like, shape (N, 2)

    Returns
    -------
    ndarray, shape (N,)
        Mean of the distances (image unit) of x1 from the epipolar line of x2 and of x2 from
        that of x1.

    Examples
    --------
    >>> F = np.array([[0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])     # normal case: y1 = y2
    >>> epipolar_distances(F, [[1.0, 2.0]], [[5.0, 2.5]]).tolist()
    [0.5]
    """
    F = np.asarray(F, float)
    p1, _ = as_points(xy1, 2, "xy1")
    p2, _ = as_points(xy2, 2, "xy2")
    h1 = np.column_stack([p1, np.ones(len(p1))])
    h2 = np.column_stack([p2, np.ones(len(p2))])
    l1, l2 = h2 @ F.T, h1 @ F                      # lines in image 1 and in image 2
    r = np.sum(h1 * l1, axis=1)                    # = h1ᵀ F h2
    return 0.5 * np.abs(r) * (1 / np.hypot(l1[:, 0], l1[:, 1]) + 1 / np.hypot(l2[:, 0], l2[:, 1]))


def estimate_fundamental_ransac(xy1, xy2, threshold, *, rng=0):
    """:func:`estimate_fundamental` inside RANSAC (gross matching errors removed).

    Parameters
    ----------
    xy1, xy2 : array_like, shape (N, 2)
    threshold : float
        Inlier bound on :func:`epipolar_distances` (image unit), > 0.
    rng : int or numpy.random.Generator
        Seed of the samples (reproducible).

    Returns
    -------
    F, inliers : ndarray (3, 3), ndarray (N,) of bool
        F refitted on the inliers.

    Examples
    --------
    >>> import photolib as pl
    >>> rng = np.random.default_rng(1)
    >>> X = rng.uniform([-5, -5, -30], [5, 5, -20], (30, 3))
    >>> a = pl.project(X, [0, 0, 0], np.eye(3), 50.0)
    >>> b = pl.project(X, [4.0, 0.5, 0.0], pl.rotation_opk(0.02, -0.05, 0.01), 50.0)
    >>> b[:4] += [[0.0, 0.5]]                      # four gross mismatches (mm)
    >>> F, inl = estimate_fundamental_ransac(a, b, 1e-3, rng=0)
    >>> int(inl.sum()), bool(inl[:4].any())
    (26, False)
    """
    from photolib.correlation import ransac
    p1, _ = as_points(xy1, 2, "xy1")
    p2, _ = as_points(xy2, 2, "xy2")
    threshold = as_scalar(threshold, "threshold", positive=True)
    res = ransac(len(p1), 8, lambda i: estimate_fundamental(p1[i], p2[i]),
                 lambda F: epipolar_distances(F, p1, p2), threshold, rng=rng)
    return res.model, res.inliers
