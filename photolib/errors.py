"""The errors photolib raises on purpose, in one hierarchy.

Every one is a :class:`PhotolibError`, and also the built-in class its kind has always been,
so ``except ValueError`` and ``except RuntimeError`` keep working::

    PhotolibError
    ├── InputError (ValueError)              bad input: a value, a shape, a start outside the image
    │   ├── StartOutsideImageError           least-squares matching: the start patch leaves the image
    │   └── GeometryError                    the geometry admits no (unique) answer
    │       ├── DegenerateGeometryError      collinear points, coincident points
    │       ├── GimbalLockError              secondary angle ±π/2
    │       ├── PointBehindCameraError       N ≥ 0 in the collinearity equations
    │       ├── DatumError                   the bundle's datum is not fixed
    │       ├── OutsideModelError            a plan position outside the terrain model
    │       ├── NoRealImageError             object inside the focal length of a thin lens
    │       └── TotalInternalReflectionError Snell's law has no solution
    └── ConvergenceError (RuntimeError)      an iteration did not reach its tolerance or diverged
        └── DistortionDivergenceError        the inversion of the distortion (photolib.distortion)

The classes are also importable from the modules that raise them (``photolib.rotations.
GimbalLockError`` is this module's class) and from ``photolib`` itself.

>>> issubclass(GimbalLockError, GeometryError) and issubclass(GimbalLockError, ValueError)
True
>>> issubclass(StartOutsideImageError, ConvergenceError)
False
"""

from __future__ import annotations

#: DistortionDivergenceError (photolib.distortion) is reached through this module too
__all__ = ["ConvergenceError", "DatumError", "DegenerateGeometryError", "GeometryError",
           "GimbalLockError", "InputError", "NoRealImageError", "OutsideModelError",
           "PhotolibError", "PointBehindCameraError", "StartOutsideImageError",
           "TotalInternalReflectionError"]


class PhotolibError(Exception):
    """Base of every error photolib raises on purpose."""


class InputError(PhotolibError, ValueError):
    """The input is not valid (a value, a shape, a start position); the message names it."""


class GeometryError(InputError):
    """The geometry of the input admits no answer, or no unique one."""


class ConvergenceError(PhotolibError, RuntimeError):
    """An iteration did not reach its tolerance within its iteration limit, or diverged."""


class DegenerateGeometryError(GeometryError):
    """The point configuration does not determine the parameters (e.g. collinear points)."""


class GimbalLockError(GeometryError):
    """The secondary angle is ±π/2: the primary and tertiary angles are not separable."""


class PointBehindCameraError(GeometryError):
    """A point has ``N ≥ 0``: on or behind the image plane's side of the projection centre.

    Raised by :func:`photolib.project` and :func:`photolib.collinearity_jacobian` with
    ``index`` (the first such point) and ``detail`` (the message without the advice, for
    callers that rephrase it).
    """

    index: int | None = None
    detail: str = ""


class DatumError(GeometryError):
    """The datum is not fixed or the normal equations are singular (names the reason)."""


class OutsideModelError(GeometryError):
    """A plan position lies outside the grid of a terrain or surface model."""


class NoRealImageError(GeometryError):
    """The object is at or inside the focal length: a thin lens forms no real image."""


class TotalInternalReflectionError(GeometryError):
    """Snell's law has no solution: n1·sin α > n2, the ray is totally reflected."""


class StartOutsideImageError(InputError):
    """The start values put the patch outside the search image: bad input, no iteration ran.

    Its ``history`` attribute holds the start parameters, shape (1, 8). (Until this
    hierarchy it was also a ``ConvergenceError``; no iteration ran, so it is not one.)
    """


def __getattr__(name: str):
    # DistortionDivergenceError carries the distortion's ConvergenceReport: defined there
    if name == "DistortionDivergenceError":
        from photolib.distortion import DistortionDivergenceError
        return DistortionDivergenceError
    raise AttributeError(f"module 'photolib.errors' has no attribute {name!r}")
