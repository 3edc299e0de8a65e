r"""Height models on a regular grid: :class:`DTM` (a DTM or a DSM) and :class:`OutsideModelError`.

A :class:`DTM` holds the heights of the cell centres (``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``)
and interpolates Z(X, Y) bilinearly (a terrain model) or takes the nearest cell (a surface
model of blocks with vertical walls); a plan position outside the grid raises
:class:`OutsideModelError` or gives NaN.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, as_scalar, check_finite
from photolib.rectify import _origin, output_grid, sample_image
from photolib.errors import OutsideModelError  # noqa: F401 - raised here, defined in one hierarchy



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
