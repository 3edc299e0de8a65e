r"""Visibility over a surface model (DSM) and the true orthophoto (True-Orthophoto).

:func:`visibility` marches the ray from each ortho pixel's surface point to the projection
centre and marks the ground it finds occluded (sichttote Fläche): exactly, cell edge by cell
edge, over a DSM of constant cells, otherwise sampled every ``step``, at most
``MAX_RAY_STEPS`` samples per ray. :func:`true_orthophoto` rectifies on the DSM and fills
the occluded pixels.
"""

from __future__ import annotations

import numpy as np

import photolib.orthophoto as _package  # MAX_RAY_STEPS: read from the package at each call
from photolib._validate import as_scalar
from photolib.collinearity import PointBehindCameraError
from photolib.orthophoto._camera import FrameCamera
from photolib.orthophoto._dtm import DTM
from photolib.orthophoto._rectification import _grid_args, differential_rectification
from photolib.rectify import output_grid

#: ray samples :func:`visibility` evaluates at once (bounds the memory of the marching)
_MARCH_SAMPLES = 1 << 18


def visibility(camera: FrameCamera, dsm: DTM, out_shape, origin, pixel_size, *,
               step: float | None = None, tolerance: float = 1e-6) -> np.ndarray:
    r"""Which ortho pixels the camera sees, by ray marching over the surface model (DSM).

    For each ortho pixel the surface point ``P = (X, Y, Z_DSM(X, Y))`` is joined to the
    projection centre ``X0``; it is **occluded** (sichttote Fläche) if the ray
    ``P + t·(X0 − P)``, ``0 < t ≤ 1``, passes below the surface anywhere, i.e.
    ``Z_ray(t) < Z_DSM(X_ray(t), Y_ray(t)) − tolerance``. For a DSM of constant cells
    (``order=0``) and no ``step``, the ray is tested exactly where it enters each cell it
    crosses; otherwise it is sampled every ``step`` (default: a quarter of the DSM spacing)
    in plan until it rises above the highest cell, at most ``MAX_RAY_STEPS`` (10⁶) samples
    per ray: a ``step`` that would need more raises ``ValueError``.

    Parameters
    ----------
    camera : FrameCamera
        The image; only its projection centre ``X0`` (object unit) enters.
    dsm : DTM
        Surface model (DSM / digitales Oberflächenmodell), heights in object unit; must cover
        every ortho pixel. ``order=0`` for blocks with vertical walls (exact test).
    out_shape : tuple of int
        ``(rows, cols)`` of the orthophoto.
    origin : array_like, shape (2,)
        Object coordinates (X0, Y0) of the centre of the top-left ortho pixel (object unit).
    pixel_size : float
        Ortho pixel size Δ, object unit per pixel, > 0.
    step : float, optional
        Sampling interval along the ray in plan (object unit), > 0; default (None): exact cell
        crossings for ``order=0``, a quarter of the DSM spacing otherwise.
    tolerance : float
        Height margin (object unit): the ray is below the surface only if
        ``Z_ray < Z_DSM − tolerance``, so the surface point itself does not hide itself.

    Returns
    -------
    ndarray of bool, shape out_shape
        True where the ground is visible in the image.

    Raises
    ------
    PointBehindCameraError
        If a surface point is not below the projection centre.
    OutsideModelError
        If an ortho pixel lies outside the surface model.
    ValueError
        If ``step`` would need more than ``MAX_RAY_STEPS`` samples along a ray.

    Notes
    -----
    .. math:: P(t) = P + t\,(X_0 - P),\quad 0 < t ≤ 1;\qquad
              \text{occluded} \iff \exists t:\ Z_{P(t)} < Z_{DSM}(X_{P(t)}, Y_{P(t)}) - \text{tol}

    Examples
    --------
    A 10 m block in the middle of a 5 × 1 strip, camera above the left end:

    >>> dsm = DTM([[0.0, 0.0, 10.0, 0.0, 0.0]], (0.0, 0.0), 1.0, order=0)
    >>> cam = FrameCamera([0.0, 0.0, 20.0], np.eye(3), 20.0, 1000, 1000, 0.01)
    >>> visibility(cam, dsm, (1, 5), (0.0, 0.0), 1.0).tolist()
    [[True, True, True, False, False]]
    """
    (nr, nc), o, d = _grid_args(out_shape, origin, pixel_size)
    grid = output_grid((nr, nc), o, d).reshape(-1, 2)
    Z = dsm.height(grid)
    P = np.column_stack([grid, Z])
    ray = camera.X0 - P
    if np.any(ray[:, 2] <= 0):
        i = int(np.argmax(ray[:, 2] <= 0))
        raise PointBehindCameraError(f"surface point {P[i].tolist()} is not below the "
                                     f"projection centre {camera.X0.tolist()}")
    top = float(dsm.heights.max())
    t_top = np.clip((top - P[:, 2]) / ray[:, 2], 0.0, 1.0)     # above this the ray is free
    if dsm.order == 0 and step is None:
        visible = np.ones(len(P), dtype=bool)
        for s in range(0, len(P), 4096):
            b = slice(s, s + 4096)
            visible[b] = _visible_cells(dsm, P[b], ray[b], t_top[b], tolerance)
        return visible.reshape(nr, nc)
    step = dsm.spacing / 4.0 if step is None else as_scalar(step, "step", positive=True)
    plan = np.hypot(ray[:, 0], ray[:, 1]) * t_top
    longest = float(plan.max()) if len(plan) else 0.0
    if longest / step > _package.MAX_RAY_STEPS:
        raise ValueError(f"step = {step:g} would need {np.ceil(longest / step):.3g} samples along "
                         f"the longest ray (plan length {longest:.6g} below the highest cell), "
                         f"more than MAX_RAY_STEPS = {_package.MAX_RAY_STEPS:,}; use a larger step (the "
                         f"default is a quarter of the DSM spacing, {dsm.spacing / 4.0:g})")
    n_steps = int(np.ceil(longest / step)) if len(plan) else 0
    visible = np.ones(len(P), dtype=bool)
    active = np.flatnonzero(plan > 0)
    k0 = 1
    while k0 <= n_steps:  # steps k0 … k0 + m − 1 of all rays still below the top at once
        active = active[(k0 - 1) * step < plan[active]]
        if not len(active):
            break
        m = max(1, min(n_steps - k0 + 1, _MARCH_SAMPLES // len(active)))
        k = np.arange(k0, k0 + m, dtype=float)
        pa = plan[active][:, None]
        t = np.minimum(k * step / pa, 1.0) * t_top[active][:, None]
        q = P[active][:, None, :] + t[..., None] * ray[active][:, None, :]
        below = q[..., 2] < dsm._lookup(q[..., :2].reshape(-1, 2)).reshape(t.shape) - tolerance
        hidden = (below & ((k - 1) * step < pa)).any(axis=1)  # only steps the ray still takes
        visible[active[hidden]] = False
        active = active[~hidden]
        k0 += m
    return visible.reshape(nr, nc)


def _visible_cells(dsm: DTM, P, ray, t_top, tolerance):
    """Exact visibility over a DSM of constant cells: test the ray where it enters each cell.

    The ray rises towards the camera, so inside one cell its lowest point is where it
    enters; checking every crossing of a cell edge (x and y lines) up to ``t_top`` is exact.
    """
    d = dsm.spacing
    ts = []
    for k in (0, 1):
        edge0 = dsm.origin[k] - d / 2 if k == 0 else dsm.origin[k] + d / 2
        rk = ray[:, k]
        lo = np.minimum(P[:, k], P[:, k] + rk * t_top)
        hi = np.maximum(P[:, k], P[:, k] + rk * t_top)
        first = np.ceil((lo - edge0) / d)
        count = np.floor((hi - edge0) / d) - first + 1
        m = int(count.max()) if len(count) else 0
        if m <= 0:
            continue
        edges = edge0 + (first[:, None] + np.arange(m)) * d
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (edges - P[:, k:k + 1]) / rk[:, None]
        t[(np.arange(m)[None] >= count[:, None]) | ~np.isfinite(t)] = np.nan
        ts.append(t)
    if not ts:
        return np.ones(len(P), dtype=bool)
    t = np.concatenate(ts, axis=1)
    eps = 1e-9 * np.maximum(t_top, 1e-300)[:, None]
    valid = np.isfinite(t) & (t > eps) & (t <= t_top[:, None])  # not the edge P lies on
    t = t + eps                                                 # just inside the next cell
    t = np.where(valid, t, 0.0)
    q = P[:, None, :] + t[..., None] * ray[:, None, :]
    z = dsm._lookup(q[..., :2].reshape(-1, 2)).reshape(t.shape)
    hidden = valid & (q[..., 2] < z - tolerance)
    return ~hidden.any(axis=1)


def true_orthophoto(image, camera: FrameCamera, dsm: DTM, out_shape, origin, pixel_size, *,
                    order: int = 1, fill: float = np.nan, **kwargs):
    """True orthophoto (True-Orthophoto): rectified on the DSM, occluded ground marked.

    The grey values come from :func:`differential_rectification` on the DSM, so roofs stand
    on their footprints; pixels :func:`visibility` finds occluded get ``fill`` (NaN by
    default) instead of the grey value of the building in front of them.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
        The source image; its size must be ``camera.height × camera.width``.
    camera : FrameCamera
        Exterior and interior orientation of the image (c, x'0, y'0 in mm).
    dsm : DTM
        Surface model (DSM / digitales Oberflächenmodell), heights in object unit; must cover
        every ortho pixel.
    out_shape : tuple of int
        ``(rows, cols)`` of the orthophoto.
    origin : array_like, shape (2,)
        Object coordinates (X0, Y0) of the centre of the top-left ortho pixel (object unit).
    pixel_size : float
        Ortho pixel size Δ / ground sampling distance, object unit per pixel, > 0.
    order : {0, 1}
        Resampling: nearest neighbour or bilinear.
    fill : float
        Value of occluded ortho pixels and of those whose ground point falls outside the image.
    **kwargs
        ``step`` goes to :func:`visibility`; ``block_rows`` and ``progress`` to
        :func:`differential_rectification`.

    Returns
    -------
    ortho : ndarray, shape out_shape (+ (C,))
        Float grey values (unit of ``image``), ``fill`` where occluded.
    visible : ndarray of bool, shape out_shape
        True where the ground is visible in the image (:func:`visibility`).

    Notes
    -----
    .. math:: g_{true}(X, Y) = \\begin{cases} g_{ortho}(X, Y) & \\text{visible} \\\\
              \\text{fill} & \\text{occluded} \\end{cases}

    Examples
    --------
    >>> dsm = DTM([[0.0, 0.0, 10.0, 0.0, 0.0]], (0.0, 0.0), 1.0, order=0)
    >>> cam = FrameCamera([0.0, 0.0, 20.0], np.eye(3), 20.0, 1000, 1000, 0.01)
    >>> ortho, vis = true_orthophoto(np.ones((1000, 1000)), cam, dsm, (1, 5), (0.0, 0.0), 1.0)
    >>> ortho.tolist()
    [[1.0, 1.0, 1.0, nan, nan]]
    """
    step = kwargs.pop("step", None)
    ortho = differential_rectification(image, camera, dsm, out_shape, origin, pixel_size,
                                       order=order, fill=fill, **kwargs)
    visible = visibility(camera, dsm, out_shape, origin, pixel_size, step=step)
    ortho[~visible] = fill
    return ortho, visible
