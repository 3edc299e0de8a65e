"""The frame camera of an orthophoto: :class:`FrameCamera`, object point → image → pixel.

Exterior orientation (X0, R), interior orientation (c, x'0, y'0, distortion) and the pixel
grid of one image, frozen with read-only copies of its arrays; it projects object points
into image coordinates (:func:`photolib.project`) and pixel positions
(:func:`photolib.pixel_from_image`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_int, as_rotation, as_scalar, as_vector3
from photolib.collinearity import project
from photolib.distortion import Distortion
from photolib.pixels import pixel_from_image


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
