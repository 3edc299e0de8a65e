r"""Structure from motion (SfM) in outline: pairwise orientation, chaining, bundle adjustment.

1. **Pairwise orientation** of consecutive images from tie points: the essential matrix of
   the coplanarity condition (course convention, :func:`photolib.essential_matrix`)

   .. math:: x^{*T}_1\,E\,x^*_2 = 0,\qquad E = R_1^T\,[b]_\times\,R_2

   with image vectors ``x* = (x' − x'0, y' − y'0, −c)``, estimated linearly from ≥ 8 points
   (:func:`essential_eight_point`, Hartley-normalised) or by photolib's coplanarity
   adjustment (:func:`photolib.relative_orientation`) inside RANSAC
   (:func:`photolib.ransac`) on the Sampson distance, and decomposed into
   ``R2`` and the base direction ``b/|b|`` of the dependent pair (image 1: R1 = I, X01 = 0)
   by the points in front of both cameras (:func:`decompose_essential`).
2. **Chaining** (Folgebildanschluss): ``R_{k+1} = R_k·R_rel``, ``X0_{k+1} = X0_k +
   s_k·R_k·b_rel``, the scale s_k of each new base from the points the pair shares with the
   previous model (:func:`chain_poses`).
3. **Bundle adjustment** (Bündelausgleichung) of all images and points together,
   :func:`photolib.bundle_adjustment`, free network (7 inner constraints): the datum and
   scale of an SfM block are arbitrary.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_scalar
from photolib.correlation import ransac
from photolib.stereo._fundamental import _normalised_eight_point

__all__ = ["PairOrientation", "chain_poses", "decompose_essential", "essential_eight_point",
           "image_vectors", "orient_pair", "sampson_distance", "triangulate_midpoint"]


def image_vectors(xy, c, x0=0.0, y0=0.0) -> np.ndarray:
    """Image vectors ``x* = (x' − x'0, y' − y'0, −c)`` of image points (N, 2) → (N, 3)."""
    xy = as_float_array(xy, "xy")
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"xy has shape {xy.shape}; expected (N, 2) image points")
    c = as_scalar(c, "c", positive=True)
    return np.column_stack([xy[:, 0] - x0, xy[:, 1] - y0, np.full(len(xy), -c)])


def essential_eight_point(xy1, xy2, c, x0=0.0, y0=0.0) -> np.ndarray:
    r"""Essential matrix of the course's coplanarity ``x*1ᵀ·E·x*2 = 0`` from ≥ 8 point pairs.

    Each pair gives one linear equation ``Σ_ij E_ij x*1_i x*2_j = 0`` in the nine entries
    (vectors divided by c, so all entries are of order 1); E is the singular vector of the
    smallest singular value, projected onto the essential matrices (singular values
    (1, 1, 0), ‖E‖_F = √2).

    Raises ``ValueError`` for fewer than 8 pairs or a configuration that does not determine
    E (two smallest singular values equal: all points on a plane through the base …).

    >>> import photolib as pl
    >>> rng = np.random.default_rng(0)
    >>> X = rng.uniform(-5, 5, (12, 3)) + [0, 0, -20]
    >>> R2 = pl.rotation_opk(0.05, -0.1, 0.2)
    >>> xy1 = pl.project(X, [0, 0, 0], np.eye(3), 1.0)
    >>> xy2 = pl.project(X, [1.0, 0.2, 0.1], R2, 1.0)
    >>> E = essential_eight_point(xy1, xy2, 1.0)
    >>> E0 = pl.essential_matrix([0, 0, 0], np.eye(3), [1.0, 0.2, 0.1], R2)
    >>> bool(np.allclose(E / np.linalg.norm(E), np.sign(E[0, 1] * E0[0, 1]) * E0 / np.linalg.norm(E0)))
    True
    """
    a = image_vectors(xy1, c, x0, y0)
    b = image_vectors(xy2, c, x0, y0)
    if len(a) != len(b) or len(a) < 8:
        raise ValueError(f"the eight-point algorithm needs ≥ 8 point pairs of equal number, got "
                         f"{len(a)} and {len(b)}")
    # homogeneous u = x*/(−c) = (−x/c, −y/c, 1), Hartley-normalised ũ = T·u (centroid 0,
    # mean distance √2); then x*1ᵀ·E·x*2 = c²·ũ1ᵀ·T1⁻ᵀ·E·T2⁻¹·ũ2, so E ∝ T1ᵀ·Ẽ·T2
    E = _normalised_eight_point(
        a[:, :2] / -c, b[:, :2] / -c, rms=False, min_spread=0.0,
        coincide="all image points coincide", rtol=1e-12, rank2=False,
        degenerate="the point pairs do not determine the essential matrix (a degenerate "
                   "configuration: too few distinct rays)")
    U, _, Wt = np.linalg.svd(E)
    return U @ np.diag([1.0, 1.0, 0.0]) @ Wt


def sampson_distance(E, xy1, xy2, c, x0=0.0, y0=0.0) -> np.ndarray:
    r"""First-order geometric distance (image unit) of each pair from ``x*1ᵀ·E·x*2 = 0``.

    .. math:: d = \frac{|x^{*T}_1 E x^*_2|}{\sqrt{(Ex^*_2)_1^2 + (Ex^*_2)_2^2
              + (E^Tx^*_1)_1^2 + (E^Tx^*_1)_2^2}}
    """
    a, b = image_vectors(xy1, c, x0, y0), image_vectors(xy2, c, x0, y0)
    f = np.einsum("ni,ij,nj->n", a, E, b)
    Eb, Ea = b @ E.T, a @ E
    return np.abs(f) / np.sqrt(Eb[:, 0]**2 + Eb[:, 1]**2 + Ea[:, 0]**2 + Ea[:, 1]**2)


def triangulate_midpoint(X01, d1, X02, d2):
    """Midpoints and ray parameters of the shortest segments between rays ``X0 + λ·d``.

    Returns ``(X, lam1, lam2)``: X (N, 3); λ > 0 means in front of that camera (d = R·x*).
    """
    d1, d2 = np.atleast_2d(d1), np.atleast_2d(d2)
    X01, X02 = np.asarray(X01, float), np.asarray(X02, float)
    w = X02 - X01
    a11, a12, a22 = np.sum(d1 * d1, 1), -np.sum(d1 * d2, 1), np.sum(d2 * d2, 1)
    r1, r2 = d1 @ w, -(d2 @ w)
    det = a11 * a22 - a12**2
    lam1 = (r1 * a22 - a12 * r2) / det
    lam2 = (a11 * r2 - a12 * r1) / det
    X = 0.5 * (X01 + lam1[:, None] * d1 + X02 + lam2[:, None] * d2)
    return X, lam1, lam2


def decompose_essential(E, xy1, xy2, c, x0=0.0, y0=0.0):
    r"""``(R2, b)`` of the dependent pair (R1 = I, X01 = 0, |b| = 1) from an essential matrix.

    ``E = U·diag(1, 1, 0)·Vᵀ`` gives ``R2 = U·W·Vᵀ`` or ``U·Wᵀ·Vᵀ`` (det +1) and
    ``b = ±u3``; of the four, the one with most points in front of both cameras
    (positive ray parameters λ of ``X = λ1·x*1 = b + λ2·R2·x*2``).
    """
    U, _, Vt = np.linalg.svd(E)
    if np.linalg.det(U) < 0:
        U = -U
    if np.linalg.det(Vt) < 0:
        Vt = -Vt
    W = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    a, b = image_vectors(xy1, c, x0, y0), image_vectors(xy2, c, x0, y0)
    best, best_count = None, -1
    for R2 in (U @ W @ Vt, U @ W.T @ Vt):
        for base in (U[:, 2], -U[:, 2]):
            _, l1, l2 = triangulate_midpoint(np.zeros(3), a, base, b @ R2.T)
            count = int(np.sum((l1 > 0) & (l2 > 0)))
            if count > best_count:
                best, best_count = (R2, base / np.linalg.norm(base)), count
    return best


class PairOrientation(NamedTuple):
    """Result of :func:`orient_pair`."""

    R2: np.ndarray  #: rotation of image 2 (image 1: R1 = I)
    base: np.ndarray  #: unit base vector X02 − X01
    E: np.ndarray  #: essential matrix (refitted on the inliers)
    inliers: np.ndarray  #: (N,) bool
    sampson: np.ndarray  #: (N,) Sampson distances of all pairs (image unit)
    trials: int


def orient_pair(xy1, xy2, c, x0=0.0, y0=0.0, *, threshold=1.0, method="coplanarity",
                rng=0) -> PairOrientation:
    r"""Relative orientation of two images from tie points, robust by RANSAC.

    ``method="coplanarity"`` (default): photolib's dependent relative orientation
    (:func:`photolib.relative_orientation`, Gauss–Newton on the coplanarity condition from
    the normal case, bx = 1) on minimal samples of 5 points; ``"eight-point"``: the linear
    :func:`essential_eight_point` on samples of 8 (sensitive to noise for short bases).
    ``threshold`` bounds the Sampson distance of an inlier (image unit, e.g. 3σ in px); the
    model refitted on the inliers gives ``R2`` and the unit base.
    """
    from photolib.stereo import relative_orientation
    xy1, xy2 = as_float_array(xy1, "xy1"), as_float_array(xy2, "xy2")
    if method not in ("coplanarity", "eight-point"):
        raise ValueError(f"method must be 'coplanarity' or 'eight-point', got {method!r}")

    def essential(R2, base):
        b = base / np.linalg.norm(base)
        Bx = np.array([[0.0, -b[2], b[1]], [b[2], 0.0, -b[0]], [-b[1], b[0], 0.0]])
        return Bx @ R2                       # E = R1ᵀ·[b]×·R2 with R1 = I

    if method == "coplanarity":
        def fit(i):
            ro = relative_orientation(xy1[i], xy2[i], c, 1.0, x0, y0, max_iter=20)
            return essential(ro.R2, ro.base)
        s = 5
    else:
        def fit(i):
            return essential_eight_point(xy1[i], xy2[i], c, x0, y0)
        s = 8
    res = ransac(len(xy1), s, fit, lambda E: sampson_distance(E, xy1, xy2, c, x0, y0),
                 threshold, rng=rng)
    E = res.model
    R2, base = decompose_essential(E, xy1[res.inliers], xy2[res.inliers], c, x0, y0)
    return PairOrientation(R2, base, E, res.inliers, sampson_distance(E, xy1, xy2, c, x0, y0),
                           res.trials)


def chain_poses(relative, shared_scales):
    r"""Poses of a chain of images from the relative orientations of consecutive pairs.

    ``relative[k] = (R_rel, b_rel)`` of pair (k, k + 1) in the frame of image k; image 0 is
    at the origin with R = I; ``shared_scales[k]`` is the length of base k (base 0 sets the
    scale, usually 1). ``R_{k+1} = R_k·R_rel``, ``X0_{k+1} = X0_k + s_k·R_k·b_rel``.

    >>> poses = chain_poses([(np.eye(3), np.array([1.0, 0, 0]))] * 2, [1.0, 2.0])
    >>> [X0.tolist() for X0, _ in poses]
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]]
    """
    poses = [(np.zeros(3), np.eye(3))]
    for (R_rel, b_rel), s in zip(relative, shared_scales):
        X0, R = poses[-1]
        poses.append((X0 + s * R @ np.asarray(b_rel, float), R @ R_rel))
    return poses
