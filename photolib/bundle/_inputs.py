"""The checks of the arguments of :func:`~photolib.bundle.bundle_adjustment`.

Image coordinates, image and point indices, approximate exterior orientations and points
(shapes, integers, finite values, each point once per image), the control points (indices
or a bool mask) and the σ of every control coordinate (0 fixed, inf unknown, > 0 observed),
each refused with a message that names the argument and the value.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_indices, check_finite


def _check_inputs(xy, image_index, point_index, exterior, points, control):
    xy = np.asarray(xy, float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"xy has shape {xy.shape}; expected (N, 2)")
    check_finite(xy, "xy")
    idx = []
    for name, v in (("image_index", image_index), ("point_index", point_index)):
        a = np.asarray(v)
        if a.shape != (len(xy),):
            raise ValueError(f"{name} has shape {a.shape}; expected ({len(xy)},), one per row of xy")
        if not np.issubdtype(a.dtype, np.integer):
            raise ValueError(f"{name} must hold integers, got dtype {a.dtype}")
        idx.append(a.astype(int))
    ext = np.array(exterior, float)
    pts = np.array(points, float)
    if ext.ndim != 2 or ext.shape[1] != 6:
        raise ValueError(f"exterior has shape {ext.shape}; expected (M, 6) = X0, Y0, Z0, ω, φ, κ")
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points has shape {pts.shape}; expected (P, 3)")
    check_finite(ext, "exterior")
    check_finite(pts, "points")
    j = as_indices(idx[0], "image_index", len(ext))
    i = as_indices(idx[1], "point_index", len(pts))
    pairs = j * len(pts) + i
    if len(np.unique(pairs)) != len(pairs):
        k = int(np.flatnonzero(np.bincount(pairs) > 1)[0])
        raise ValueError(f"point {k % len(pts)} is observed twice in image {k // len(pts)}")
    return xy, j, i, ext, pts, _control_mask(control, len(pts))


def _control_mask(control, P):
    """Bool mask (P,) of the control points from indices or a bool mask (P,)."""
    ctrl = np.zeros(P, bool)
    if control is None:
        return ctrl
    c_arr = np.asarray(control)
    if c_arr.dtype == bool:
        if c_arr.shape != (P,):
            raise ValueError(f"control mask has shape {c_arr.shape}; expected ({P},)")
        return c_arr.copy()
    if c_arr.size and c_arr.dtype.kind not in "iu":
        raise ValueError(f"control must hold integer point indices or be a bool mask of length "
                         f"{P}, got dtype {c_arr.dtype}: {c_arr.ravel()[:6].tolist()}")
    k = as_indices(c_arr, "control", P).ravel()
    counts = np.bincount(k, minlength=P)
    if np.any(counts > 1):
        twice = int(np.flatnonzero(counts > 1)[0])
        raise ValueError(f"control lists point {twice} {int(counts[twice])} times: pass each "
                         f"control point's index once, or a bool mask of length {P} (an integer "
                         "0/1 array is read as indices, not as a mask)")
    ctrl[k] = True
    return ctrl


_XYZ = "XYZ"


def _control_sigma(control_sigma, control, ctrl, P):
    """σ (P, 3) per control coordinate: 0 fixed, inf unknown, > 0 observed with that σ.

    Without ``control_sigma`` the ``control`` points are fixed. With ``control`` given,
    ``control_sigma`` is a scalar, (3,) or (K, 3) for the K control points (in the order of
    ``control``; a mask: ascending); without ``control`` it is (P, 3) for all points."""
    if control_sigma is None:
        return np.where(ctrl[:, None], 0.0, np.inf) * np.ones((1, 3))
    if isinstance(control_sigma, (str, bytes)) or getattr(
            getattr(control_sigma, "dtype", None), "kind", "") in ("c", "S", "U"):
        raise ValueError(f"control_sigma must be real numbers (0: fixed, inf: unknown, > 0: σ "
                         f"in object units), got {control_sigma!r}")
    try:
        s = np.array(control_sigma, float)
    except (TypeError, ValueError):
        raise ValueError(f"control_sigma must be real numbers (0: fixed, inf: unknown, > 0: σ in "
                         f"object units), got {control_sigma!r}") from None
    if control is not None:
        c_arr = np.asarray(control)
        order = np.flatnonzero(c_arr) if c_arr.dtype == bool else c_arr.astype(int).ravel()
        K = len(order)
        if s.ndim == 0 or s.shape == (3,):
            s = np.broadcast_to(s, (K, 3))
        elif s.shape != (K, 3):
            raise ValueError(f"control_sigma has shape {s.shape}; with control ({K} points) "
                             f"expected a scalar, (3,) or ({K}, 3) in the order of control — or "
                             f"leave out control and pass ({P}, 3) for all points")
        full = np.full((P, 3), np.inf)
        full[order] = s
    else:
        if s.shape != (P, 3):
            raise ValueError(f"control_sigma has shape {s.shape}; expected ({P}, 3) = σX, σY, σZ "
                             "per point (0: fixed, inf: unknown), or pass control= as well")
        full = s.copy()
    bad = np.argwhere(np.isnan(full) | (full < 0))
    if len(bad):
        p, e = (int(v) for v in bad[0])
        raise ValueError(f"control_sigma of point {p}, coordinate {_XYZ[e]} is "
                         f"{float(full[p, e])!r}: use 0 (fixed), inf (unknown) or a standard deviation > 0 (object unit)")
    return full
