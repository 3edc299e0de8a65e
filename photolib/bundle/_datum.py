"""The datum (Datum) of a block and the geometry that fixes it, and :class:`DatumError`.

:func:`inner_constraints` gives the seven inner constraints ``Bᵀ dp = 0`` of a free network
(translation, rotation and scale of the object points). The checks of the adjustment raise
:class:`DatumError` when the datum is not fixed: too few points per image or rays per new
point, control points on a line or partial control that leaves a similarity parameter free,
and new points whose rays are parallel (a singular 3 × 3 normal block).
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_points
from photolib.bundle._inputs import _XYZ
from photolib.errors import DatumError  # noqa: F401 - raised here, defined in one hierarchy



def inner_constraints(points) -> np.ndarray:
    r"""Inner constraints B (3P, 7) of a free network: ``Bᵀ dp = 0`` fixes the datum.

    Columns: three translations, three rotations and the scale of the object points
    (coordinates reduced to their centroid): for a point ``X``
    :math:`B_i = [I_3 \mid [X]_\times^T \mid X]`. ``N·G = 0`` for the full similarity G.

    Parameters
    ----------
    points : array_like, shape (P, 3)
        Approximate object points (object unit, e.g. m); reduced to their centroid here.

    Returns
    -------
    B : ndarray, shape (3P, 7)
        Rows ``3i … 3i + 2`` belong to point i (X, Y, Z); columns: translations in X, Y, Z
        (dimensionless), rotations about X, Y, Z and the scale (object unit, the reduced
        coordinates).

    Notes
    -----
    .. math:: B_i = \begin{pmatrix} 1 & 0 & 0 & 0 & \bar Z_i & -\bar Y_i & \bar X_i \\
              0 & 1 & 0 & -\bar Z_i & 0 & \bar X_i & \bar Y_i \\
              0 & 0 & 1 & \bar Y_i & -\bar X_i & 0 & \bar Z_i \end{pmatrix},\qquad
              \bar X_i = X_i - \tfrac1P \sum_j X_j

    Raises
    ------
    DatumError
        For fewer than 3 points, or points on a straight line (their singular values
        σ2 ≤ 10⁻⁹·σ1 about the centroid): a rotation about that line moves none of them, so
        B has rank < 7 and fixes no datum.

    Examples
    --------
    >>> B = inner_constraints([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, -1.0, 0]])
    >>> B.shape, int(np.linalg.matrix_rank(B))
    ((12, 7), 7)
    >>> (B[:3, 5] + 0.0).tolist()   # point (1, 0, 0): a rotation about Z moves it along +Y
    [0.0, 1.0, 0.0]
    >>> (B[:3, 6] + 0.0).tolist()   # the scale moves it away from the centroid
    [1.0, 0.0, 0.0]
    """
    P, single = as_points(points, 3, "points")  # finite: NaN would spread into every row
    if single:
        raise ValueError(f"points has shape {np.shape(points)}; expected (P, 3)")
    if len(P) < 3:
        raise DatumError(f"inner constraints need at least 3 points, got {len(P)}: fewer do not "
                         "fix the 7 datum parameters (translation, rotation, scale)")
    sv = np.linalg.svd(P - P.mean(axis=0), compute_uv=False)
    if sv[1] <= 1e-9 * max(sv[0], 1e-300):
        raise DatumError("the points of the inner constraints lie on a straight line (or "
                         "coincide): the rotation about it is not fixed (B has rank < 7)")
    return _inner_constraints(P)


def _inner_constraints(P: np.ndarray) -> np.ndarray:
    """:func:`inner_constraints` of validated points (P, 3), P ≥ 1, without the datum checks
    (the bundle's own rank test reports a defect in its own words)."""
    Xc = P - P.mean(axis=0)
    x, y, z = Xc.T
    o, one = np.zeros(len(P)), np.ones(len(P))
    cols = [(one, o, o), (o, one, o), (o, o, one), (o, -z, y), (z, o, -x), (-y, x, o), (x, y, z)]
    return np.column_stack([np.column_stack(cc).ravel() for cc in cols])


def _check_geometry(j, i, ext, pts, sig, datum):
    per_image = np.bincount(j, minlength=len(ext))
    if per_image.min() < 3:
        k = int(np.argmin(per_image))
        raise DatumError(f"image {k} has {per_image[k]} observed points; at least 3 are needed "
                         "for its six orientation unknowns")
    rays = np.bincount(i, minlength=len(pts))
    known = np.isfinite(sig)
    ctrl = known.all(axis=1)
    lonely = np.flatnonzero((rays < 2) & ~known.any(axis=1))
    if len(lonely):
        k = int(lonely[0])
        raise DatumError(f"point {k} is observed in {rays[k]} image(s) and is not a control "
                         "point: a new point needs at least two rays")
    unseen = np.flatnonzero((rays == 0) & ~ctrl)
    if len(unseen):
        k = int(unseen[0])
        raise DatumError(f"point {k} is observed in no image and its coordinate(s) "
                         f"{''.join(_XYZ[e] for e in np.flatnonzero(~known[k]))} are unknown")
    if datum == "control" and np.any(known.any(axis=1) & ~ctrl & (rays > 0)):
        # partial control (e.g. heights only): the known coordinates must fix the 7 parameters
        # of a spatial similarity, i.e. their rows of the inner constraints B have rank 7
        use = known & (rays > 0)[:, None]
        rows = np.flatnonzero(use.any(axis=1))
        X = pts[rows]
        scale = float(np.max(np.ptp(X, axis=0))) or 1.0
        B = _inner_constraints(X).reshape(-1, 3, 7) * np.r_[1, 1, 1, [1 / scale] * 4]
        B = B[use[rows]]
        sv = np.linalg.svd(B, compute_uv=False)
        rank = int(np.sum(sv > 1e-9 * sv[0])) if len(sv) else 0
        if rank < 7:
            n = use.sum(axis=0)
            raise DatumError(f"the known control coordinates ({n[0]} X, {n[1]} Y, {n[2]} Z) fix "
                             f"only {rank} of the 7 datum parameters (e.g. heights alone leave "
                             "the plan shift, the rotation about Z and the scale free): add plan "
                             "control or use datum='free'")
        return
    if datum == "control":
        used = np.flatnonzero(ctrl & (rays > 0))
        if len(used) < 3:
            raise DatumError(f"{len(used)} observed control point(s): the datum (7 parameters) "
                             "needs at least 3 not on a line, or datum='free'")
        C = pts[used] - pts[used].mean(axis=0)
        sv = np.linalg.svd(C, compute_uv=False)
        if sv[1] <= 1e-9 * max(sv[0], 1e-300):
            raise DatumError("the control points lie on a straight line: rotation about it is "
                             "not fixed (datum defect)")


#: a new point's 3 × 3 normal block with λmin/λmax below this counts as singular: its rays
#: meet at less than about 1e-6 rad (the default ``min_angle`` of forward_intersection)
POINT_BLOCK_RCOND = 1e-12


def _check_point_blocks(Npp, free):
    """``DatumError`` naming the new points whose rays are (nearly) parallel: their 3 × 3
    normal blocks ``N_ii = Σ A_iᵀA_i`` are singular, so they cannot be intersected."""
    lam = np.linalg.eigvalsh(Npp)  # ascending, the blocks are symmetric positive semi-definite
    bad = ~(lam[:, 0] > POINT_BLOCK_RCOND * lam[:, 2])  # NaN counts as bad
    if bad.any():
        names = free[bad]
        shown = ", ".join(str(int(k)) for k in names[:10]) + (" …" if len(names) > 10 else "")
        raise DatumError(
            f"object point{'s' if len(names) > 1 else ''} {shown} cannot be intersected: "
            f"{'their' if len(names) > 1 else 'its'} rays are parallel (3 × 3 normal block with "
            f"λmin/λmax = {float(np.nan_to_num(lam[bad][0, 0] / lam[bad][0, 2])):.3g}): zero "
            "base, e.g. images taken from the same projection centre X0, or a point at infinity")
