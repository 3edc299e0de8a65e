r"""Orthophoto / Orthophoto by differential rectification (differentielle Entzerrung).

A map has one scale everywhere (parallel projection, Parallelprojektion); an image is a
central projection (Zentralprojektion) whose scale changes with the height of the ground.
The **indirect differential rectification** computes, for every pixel of the orthophoto,

1. the plan position (X, Y) of its centre (:func:`photolib.rectify.output_grid`),
2. the height Z(X, Y) from a digital terrain model (DTM, digitales Geländemodell) — or, for a
   *true* orthophoto, from a surface model (DSM, digitales Oberflächenmodell),
3. the image coordinates of (X, Y, Z) by the collinearity equations
   (:func:`photolib.project`, with distortion),
4. the pixel position (:func:`photolib.pixel_from_image`) and the grey value there
   (:func:`photolib.rectify.sample_image`, nearest neighbour or bilinear).

Grids (DTM, DSM, orthophoto) follow :mod:`photolib.rectify`: ``origin = (X0, Y0)`` is the
centre of the top-left cell, ``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``.

Relief displacement (radiale Versetzung) of a vertical image, derived in
:mod:`photolib.derive.products`:

.. math:: Δr = r\,\frac{Δh}{H}

with r the radial image distance of the *displaced* (top) point, Δh its height above the
reference plane and H the flying height above that plane. Plane rectification
(ebene Entzerrung, :class:`photolib.ProjectiveTransform`) ignores Δh and misplaces the point
by exactly Δr, i.e. by Δr·H/c on the ground.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import (as_float_array, as_int, as_rotation, as_scalar, as_vector3,
                                check_finite)
from photolib.collinearity import PointBehindCameraError, project
from photolib.distortion import Distortion
from photolib.pixels import pixel_from_image
from photolib.rectify import _origin, _pixel_size, _shape, output_grid, sample_image

__all__ = ["DTM", "FrameCamera", "OutsideModelError", "differential_rectification",
           "mosaic_nearest_nadir", "ortho_pixel_positions", "relief_displacement",
           "true_orthophoto", "visibility"]

#: output rows per block of :func:`differential_rectification`
BLOCK_ROWS = 256

#: most samples :func:`visibility` takes along one ray with a ``step``; a smaller step raises
MAX_RAY_STEPS = 1_000_000

#: ray samples :func:`visibility` evaluates at once (bounds the memory of the marching)
_MARCH_SAMPLES = 1 << 18


class OutsideModelError(ValueError):
    """A plan position lies outside the grid of a terrain or surface model."""


class DTM:
    r"""A height model on a regular grid (DTM / DGM, or a DSM / DOM): Z(X, Y).

    Parameters
    ----------
    heights : array_like, shape (rows, cols)
        Heights of the cell centres (object unit, m); finite (NaN is refused).
    origin : array_like, shape (2,)
        (X0, Y0) of the centre of the top-left cell.
    spacing : float
        Grid spacing Δ (> 0), object unit.
    order : {0, 1}
        1: bilinear height interpolation (a terrain model); 0: nearest cell (a surface model
        of blocks, e.g. buildings with vertical walls).

    Notes
    -----
    Cell (col, row) lies at ``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``; heights between the
    cell centres are interpolated by :func:`photolib.rectify.sample_image`:

    .. math:: Z = (1-u)(1-v)Z_{00} + u(1-v)Z_{10} + (1-u)vZ_{01} + uvZ_{11}

    Examples
    --------
    >>> dtm = DTM([[10.0, 20.0], [30.0, 40.0]], origin=(0.0, 1.0), spacing=1.0)
    >>> dtm.height([[0.5, 0.5], [0.0, 1.0]]).tolist()
    [25.0, 10.0]
    """

    def __init__(self, heights, origin, spacing, order: int = 1):
        # a copy: the model must not change when the caller later changes its array
        Z = np.array(as_float_array(heights, "heights"))
        if Z.ndim != 2 or min(Z.shape) < 1:
            raise ValueError(f"heights has shape {Z.shape}; expected (rows, cols)")
        if order == 1 and min(Z.shape) < 2:
            raise ValueError(f"bilinear interpolation needs at least 2 × 2 cells, got {Z.shape}")
        check_finite(Z, "heights")
        if order not in (0, 1):
            raise ValueError(f"order must be 0 (nearest) or 1 (bilinear), got {order!r}")
        self.heights = Z
        self.origin = np.array(_origin(origin))
        self.spacing = as_scalar(spacing, "spacing", positive=True)
        self.order = order

    @classmethod
    def from_function(cls, f, shape, origin, spacing, order: int = 1):
        """Sample ``f(X, Y)`` (vectorised, arrays of shape ``shape``) at the cell centres.

        >>> DTM.from_function(lambda X, Y: X + 0 * Y, (2, 3), (0.0, 0.0), 2.0).heights.tolist()
        [[0.0, 2.0, 4.0], [0.0, 2.0, 4.0]]
        """
        XY = output_grid(shape, origin, spacing)
        return cls(np.asarray(f(XY[..., 0], XY[..., 1]), dtype=float), origin, spacing, order)

    @property
    def shape(self) -> tuple:
        return self.heights.shape

    @property
    def extent(self) -> tuple:
        """``(Xmin, Xmax, Ymin, Ymax)`` of the cell centres."""
        rows, cols = self.shape
        X0, Y0 = self.origin
        d = self.spacing
        return (X0, X0 + (cols - 1) * d, Y0 - (rows - 1) * d, Y0)

    def grid_position(self, XY) -> np.ndarray:
        """(col, row) in cells of plan positions ``XY`` (..., 2)."""
        XY = np.asarray(XY, dtype=float)
        return np.stack([(XY[..., 0] - self.origin[0]) / self.spacing,
                         (self.origin[1] - XY[..., 1]) / self.spacing], axis=-1)

    def inside(self, XY) -> np.ndarray:
        """True where ``XY`` (..., 2) can be interpolated (nearest: within half a cell)."""
        cr = self.grid_position(XY)
        rows, cols = self.shape
        m = 0.5 if self.order == 0 else 1e-9
        return ((cr[..., 0] >= -m) & (cr[..., 0] <= cols - 1 + m)
                & (cr[..., 1] >= -m) & (cr[..., 1] <= rows - 1 + m))

    def _lookup(self, XY) -> np.ndarray:
        """Heights at finite plan positions (N, 2), −inf outside; no checks (ray marching)."""
        col = (XY[:, 0] - self.origin[0]) / self.spacing
        row = (self.origin[1] - XY[:, 1]) / self.spacing
        rows, cols = self.shape
        if self.order == 0:
            c, r = np.floor(col + 0.5).astype(np.intp), np.floor(row + 0.5).astype(np.intp)
            ok = (c >= 0) & (c < cols) & (r >= 0) & (r < rows)
            out = np.full(len(XY), -np.inf)
            out[ok] = self.heights[r[ok], c[ok]]
            return out
        ok = (col >= 0) & (col <= cols - 1) & (row >= 0) & (row <= rows - 1)
        Z = sample_image(self.heights, np.stack([col, row], axis=-1))
        return np.where(ok, Z, -np.inf)

    def height(self, XY, *, outside: str = "raise") -> np.ndarray:
        """Heights Z at plan positions ``XY``, shape (..., 2) → (...).

        ``outside="raise"`` raises :class:`OutsideModelError` naming the first point outside
        the grid; ``"nan"`` returns NaN there.
        """
        XY = np.asarray(XY, dtype=float)
        if XY.ndim < 1 or XY.shape[-1] != 2:
            raise ValueError(f"XY has shape {XY.shape}; expected (..., 2) plan positions (X, Y)")
        check_finite(XY, "XY")
        if outside not in ("raise", "nan"):
            raise ValueError(f"outside must be 'raise' or 'nan', got {outside!r}")
        cr = self.grid_position(XY)
        rows, cols = self.shape
        ok = self.inside(XY)
        if not ok.all() and outside == "raise":
            i = tuple(int(k) for k in np.unravel_index(int(np.argmin(ok)), ok.shape))
            Xmin, Xmax, Ymin, Ymax = self.extent
            raise OutsideModelError(
                f"XY{list(i)} = {XY[i].tolist()} is outside the height model "
                f"(X in [{Xmin:g}, {Xmax:g}], Y in [{Ymin:g}, {Ymax:g}])")
        cr = np.stack([np.clip(cr[..., 0], 0, cols - 1), np.clip(cr[..., 1], 0, rows - 1)], -1)
        Z = sample_image(self.heights, cr, order=self.order)
        return np.where(ok, Z, np.nan)


@dataclass(frozen=True)
class FrameCamera:
    """A frame image: exterior and interior orientation and the pixel grid.

    Parameters
    ----------
    X0 : (3,) projection centre (object unit); R : (3, 3) rotation camera → object
    (``R = R_ω·R_φ·R_κ``); c : camera constant (mm, > 0); width, height : image size in
    pixels; pixel_size : mm; x0, y0 : principal point (mm); distortion : Distortion or None.
    ``X0`` and ``R`` are stored as read-only copies: changing the arrays passed in does not
    move the camera (use :func:`dataclasses.replace` for a new pose).

    Examples
    --------
    >>> cam = FrameCamera([0.0, 0.0, 100.0], np.eye(3), 50.0, 101, 101, 0.01)
    >>> cam.pixel([[1.0, 0.0, 0.0]]).round(9).tolist()
    [[100.0, 50.0]]
    """

    X0: np.ndarray
    R: np.ndarray
    c: float
    width: int
    height: int
    pixel_size: float
    x0: float = 0.0
    y0: float = 0.0
    distortion: Distortion | None = None

    def __post_init__(self):
        # own read-only copies: a frozen camera must not change when the caller later reuses
        # its arrays (as DTM copies its heights)
        for name, arr in (("X0", as_vector3(self.X0, "X0")), ("R", as_rotation(self.R))):
            arr = arr.copy()
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "c", as_scalar(self.c, "c", positive=True))
        object.__setattr__(self, "x0", as_scalar(self.x0, "x0"))
        object.__setattr__(self, "y0", as_scalar(self.y0, "y0"))
        if self.distortion is not None and not isinstance(self.distortion, Distortion):
            raise TypeError("distortion must be a photolib.Distortion or None, "
                            f"got {type(self.distortion).__name__}")
        for name in ("width", "height"):
            v = getattr(self, name)
            try:
                as_int(v, name, minimum=1)
            except ValueError:
                raise ValueError(f"{name} must be a positive number of pixels, got {v!r}") from None
        as_scalar(self.pixel_size, "pixel_size", positive=True)

    @property
    def nadir(self) -> np.ndarray:
        """Plan position (X0, Y0) of the projection centre (the nadir point for a vertical image)."""
        return self.X0[:2].copy()

    def image(self, X, *, return_valid=False):
        """Image coordinates (mm) of object points: :func:`photolib.project`."""
        return project(X, self.X0, self.R, self.c, self.x0, self.y0, self.distortion,
                       return_valid=return_valid)

    def pixel(self, X, *, return_valid=False):
        """Pixel positions (col, row) of object points (N, 3)."""
        if return_valid:
            xy, valid = self.image(X, return_valid=True)
        else:
            xy = self.image(X)
        cr = pixel_from_image(np.nan_to_num(xy), self.width, self.height, self.pixel_size)
        if return_valid:
            cr[~np.atleast_1d(valid)] = np.nan
            return cr, valid
        return cr


def relief_displacement(r, dh, H):
    r"""Relief displacement / radiale Versetzung of a vertical image: ``Δr = r·Δh/H``.

    Parameters
    ----------
    r : float or array_like
        Radial distance (image unit, mm) of the *displaced* image point (the top of the
        object) from the nadir point (= principal point of a vertical image).
    dh : float or array_like
        Height of the point above the reference plane (object unit, m).
    H : float or array_like
        Flying height of the projection centre above the reference plane (object unit), > dh.

    Returns
    -------
    ndarray or float
        Δr in the unit of r, directed away from the nadir point.

    Notes
    -----
    .. math:: Δr = r_{top} - r_{foot} = \frac{cR}{H-Δh} - \frac{cR}{H} = r_{top}\,\frac{Δh}{H}
              = r_{foot}\,\frac{Δh}{H-Δh}

    Exact for a vertical (nadir) image; derived in :func:`photolib.derive.products.relief_displacement`.

    Examples
    --------
    >>> relief_displacement(80.0, 30.0, 1200.0)   # mm, m, m
    2.0
    """
    r = as_float_array(r, "r")
    dh = as_float_array(dh, "dh")
    H = as_float_array(H, "H")
    for v, n in ((r, "r"), (dh, "dh"), (H, "H")):
        check_finite(np.atleast_1d(v), n)
    if np.any(H <= 0):
        raise ValueError(f"H (flying height above the reference plane) must be > 0, got {H.tolist()}")
    if np.any(dh >= H):
        raise ValueError(f"dh = {dh.tolist()} reaches the flying height H = {H.tolist()}: "
                         "the point is not below the camera")
    out = r * dh / H
    return float(out) if out.ndim == 0 else out


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
    if longest / step > MAX_RAY_STEPS:
        raise ValueError(f"step = {step:g} would need {np.ceil(longest / step):.3g} samples along "
                         f"the longest ray (plan length {longest:.6g} below the highest cell), "
                         f"more than MAX_RAY_STEPS = {MAX_RAY_STEPS:,}; use a larger step (the "
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
