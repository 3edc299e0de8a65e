"""Plane transformations ``(x, y) → (X, Y)`` and the cross ratio.

One small surface for every class, as in scikit-image: ``from_estimate(src, dst)``
(least squares on Hartley-normalised points, with ``residuals``, ``sigma0`` and
``redundancy``), ``__call__(points)``, ``inverse``, ``params`` and ``a @ b`` ("b first,
then a"). Helmert, affine and projective transforms have closed-form inverses and are
closed under composition (the result takes the more general class); bilinear and
polynomial transforms invert by Newton iteration and compose to a
:class:`ComposedTransform`.

Examples
--------
>>> from photolib.transforms import HelmertTransform, ProjectiveTransform
>>> t = ProjectiveTransform(c1=0.1) @ HelmertTransform(a0=1.0)
>>> type(t).__name__, t([0.0, 0.0]).tolist()
('ProjectiveTransform', [0.9090909090909091, 0.0])
"""

from photolib.transforms._base import (
    ComposedTransform,
    ConvergenceError,
    DegenerateGeometryError,
    NewtonInverse,
    PlaneTransform,
)
from photolib.transforms._cross_ratio import cross_ratio
from photolib.transforms._matrix import AffineTransform, HelmertTransform, ProjectiveTransform
from photolib.transforms._poly import BilinearTransform, PolynomialTransform

__all__ = [
    "AffineTransform",
    "BilinearTransform",
    "ComposedTransform",
    "ConvergenceError",
    "DegenerateGeometryError",
    "HelmertTransform",
    "NewtonInverse",
    "PlaneTransform",
    "PolynomialTransform",
    "ProjectiveTransform",
    "cross_ratio",
]
