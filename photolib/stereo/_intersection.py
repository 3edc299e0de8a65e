r"""Forward intersection (räumlicher Vorwärtsschnitt): the least-squares point of K ≥ 2 rays.

Ray k is ``X0k + λ·d_k`` with ``d_k = R_k·x*_k/|R_k·x*_k|`` (``R = R_ω·R_φ·R_κ`` camera →
object, ``x* = (x' − x'0, y' − y'0, −c)``). The point minimising the squared perpendicular
distances solves ``(Σ_k (I − d_k d_kᵀ))·X = Σ_k (I − d_k d_kᵀ)·X0k``; for two rays it is the
midpoint of their common perpendicular. It lies in front of camera k when
``λ_k = d_kᵀ(X − X0k) > 0`` (N < 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_float_array, as_points, as_rotation, as_scalar, as_vector3
from photolib.collinearity import PointBehindCameraError, project
from photolib.stereo._rays import _image_vectors
from photolib.transforms._base import DegenerateGeometryError


# -- forward intersection --------------------------------------------------------------------------

@dataclass(frozen=True)
class ForwardIntersection:
    """Result of :func:`forward_intersection` for N points seen in K images.

    For a single point (``xy`` of shape (K, 2)) the leading N axis is dropped, as for the
    other point functions: ``points`` (3,), ``distances`` (K,), ``residuals`` (K, 2), and
    ``miss``, ``angle`` (float) and ``valid`` (bool) are scalars.
    """

    points: np.ndarray  #: (N, 3) object points (NaN where not valid)
    distances: np.ndarray  #: (N, K) perpendicular distance of each point from each ray
    miss: np.ndarray  #: (N,) 2·RMS of ``distances``: for K = 2 the rays' common perpendicular
    residuals: np.ndarray  #: (N, K, 2) image residuals x'(point) − x'(observed), image unit
    angle: np.ndarray  #: (N,) largest intersection angle between two of the rays, radians
    valid: np.ndarray  #: (N,) False for parallel rays or points behind a camera


def _per_camera(value, K, name):
    arr = as_float_array(value, name)
    if arr.ndim == 0:
        arr = np.full(K, float(arr))
    if arr.shape != (K,):
        raise ValueError(f"{name} has shape {arr.shape}; expected a scalar or ({K},)")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains a non-finite value: {arr.tolist()}")
    return arr


def forward_intersection(xy, X0, R, c, x0=0.0, y0=0.0, *, min_angle: float = 1e-6,
                         return_valid: bool = False) -> ForwardIntersection:
    r"""Least-squares intersection of the rays of K ≥ 2 images / räumlicher Vorwärtsschnitt.

    Parameters
    ----------
    xy : array_like, shape (K, N, 2) or (K, 2)
        Image coordinates of N points in each of the K images (image unit); (K, 2) is one
        point, and its result has no N axis.
    X0 : array_like, shape (K, 3)
        Projection centres (object unit).
    R : array_like, shape (K, 3, 3)
        Rotations camera → object, ``R_ω·R_φ·R_κ``.
    c, x0, y0 : float or array_like of shape (K,)
        Interior orientation per image (image unit), c > 0.
    min_angle : float
        Rays meeting at less than this angle (radians) count as parallel (zero parallax).
    return_valid : bool
        If False (default) parallel rays raise ``DegenerateGeometryError`` and points behind
        a camera ``PointBehindCameraError``; if True such points get NaN and ``valid=False``.

    Returns
    -------
    ForwardIntersection
        Fields of shape (N, …), or without the N axis for a single point (K, 2).

    Notes
    -----
    Each ray is :math:`X_k + λ\,d_k` with :math:`d_k = R_k x^*_k/|R_k x^*_k|`. The point that
    minimises the sum of squared perpendicular distances solves

    .. math:: \Big(\sum_k (I - d_k d_k^T)\Big)\,X = \sum_k (I - d_k d_k^T)\,X_{0k}

    For two rays it is the midpoint of their common perpendicular. The point lies in front of
    camera k when :math:`λ_k = d_k^T(X - X_{0k}) > 0` (equivalently N < 0).

    Examples
    --------
    >>> I = np.eye(3)
    >>> res = forward_intersection([[1.0, 0.5], [-1.0, 0.5]], [[0, 0, 0], [20.0, 0, 0]],
    ...                            [I, I], c=100.0)
    >>> np.round(res.points, 9).tolist(), res.miss < 1e-9, res.valid
    ([10.0, 5.0, -1000.0], True, True)
    """
    min_angle = as_scalar(min_angle, "min_angle")
    if min_angle < 0:
        raise ValueError(f"min_angle must be ≥ 0 (radians), got {min_angle!r}")
    obs = as_float_array(xy, "xy")
    single = obs.ndim == 2 and obs.shape[-1] == 2      # (K, 2): one point, results of its rank
    if single:
        obs = obs[:, None, :]
    if obs.ndim != 3 or obs.shape[-1] != 2:
        raise ValueError(f"xy has shape {np.shape(xy)}; expected (K, N, 2) or (K, 2)")
    K, n = obs.shape[:2]
    if K < 2:
        raise ValueError(f"forward intersection needs at least 2 images, got {K}")
    obs = np.stack([as_points(obs[k], 2, f"xy[{k}]")[0] for k in range(K)])
    centres = as_float_array(X0, "X0")
    if centres.shape != (K, 3):
        raise ValueError(f"X0 has shape {centres.shape}; expected ({K}, 3) for {K} images")
    centres = np.stack([as_vector3(centres[k], f"X0[{k}]") for k in range(K)])
    rots = as_float_array(R, "R")
    if rots.shape != (K, 3, 3):
        raise ValueError(f"R has shape {rots.shape}; expected ({K}, 3, 3) for {K} images")
    rots = np.stack([as_rotation(rots[k], f"R[{k}]") for k in range(K)])
    cs = _per_camera(c, K, "c")
    if np.any(cs <= 0):
        raise ValueError(f"c must be > 0 for every image, got {cs.tolist()}")
    x0s, y0s = _per_camera(x0, K, "x0"), _per_camera(y0, K, "y0")
    # unit ray directions d (K, N, 3)
    # (N, 3) @ a transposed view drops NumPy to its slow non-BLAS loop: copy the 3 × 3 first
    d = np.stack([_image_vectors(obs[k], cs[k], x0s[k], y0s[k]) @ np.ascontiguousarray(rots[k].T)
                  for k in range(K)])
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    P = np.eye(3) - d[..., :, None] * d[..., None, :]          # (K, N, 3, 3) projectors
    A = P.sum(axis=0)                                            # (N, 3, 3)
    rhs = np.einsum("knij,kj->ni", P, centres)
    cosines = np.clip(np.einsum("anj,bnj->nab", d, d), -1.0, 1.0)
    angle = np.arccos(cosines.min(axis=(1, 2)))
    parallel = angle < min_angle
    points = np.full((n, 3), np.nan)
    ok = ~parallel
    if ok.any():
        points[ok] = np.linalg.solve(A[ok], rhs[ok][..., None])[..., 0]
    lam = np.einsum("knj,knj->kn", d, points[None] - centres[:, None])   # (K, N)
    behind = ok & np.any(~(lam > 0), axis=0)
    if not return_valid:
        if parallel.any():
            i = int(np.flatnonzero(parallel)[0])
            raise DegenerateGeometryError(
                f"the rays of point {i} are parallel (intersection angle {angle[i]:.3g} rad < "
                f"min_angle = {min_angle:g}): zero parallax, the point is at infinity")
        if behind.any():
            i = int(np.flatnonzero(behind)[0])
            k = int(np.flatnonzero(~(lam[:, i] > 0))[0])
            raise PointBehindCameraError(
                f"point {i} intersects at {points[i].tolist()}, behind camera {k} "
                f"(ray parameter λ = {lam[k, i]:.6g} ≤ 0, i.e. N ≥ 0): the rays diverge; "
                "check the orientation or pass return_valid=True")
    valid = ok & ~behind
    points[~valid] = np.nan
    foot = centres[:, None] + lam[..., None] * d
    dist = np.linalg.norm(points[None] - foot, axis=2).T          # (N, K)
    residuals = np.full((n, K, 2), np.nan)
    if valid.any():
        for k in range(K):
            residuals[valid, k] = project(points[valid], centres[k], rots[k], cs[k],
                                          x0s[k], y0s[k]) - obs[k][valid]
    miss = 2.0 * np.sqrt(np.mean(dist**2, axis=1))
    if single:
        return ForwardIntersection(points=points[0], distances=dist[0], miss=float(miss[0]),
                                   residuals=residuals[0], angle=float(angle[0]),
                                   valid=bool(valid[0]))
    return ForwardIntersection(points=points, distances=dist, miss=miss, residuals=residuals,
                               angle=angle, valid=valid)
