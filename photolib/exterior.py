r"""One camera, one type: the exterior orientation (äußere Orientierung) of an image.

:class:`ExteriorOrientation` holds the projection centre ``X0`` and the rotation ``R``
(``R = R_ω·R_φ·R_κ``, the conventions' order) and is accepted wherever photolib takes an
exterior orientation, while plain arrays stay accepted too:

* where a function takes ``X0, R`` (:func:`~photolib.project`, :func:`~photolib.monoplot`,
  :func:`~photolib.collinearity_jacobian`, the pose conversions): pass ``*eo``, it unpacks as
  ``X0, R``;
* where it takes the six parameters ``(X0, Y0, Z0, ω, φ, κ)`` or an ``(M, 6)`` array
  (:func:`~photolib.bundle_adjustment`'s ``exterior``, a resection's ``initial``): pass ``eo``
  or a list of them, NumPy reads each as its (6,) ``params``;
* results give one back: ``ResectionResult.orientation``, ``BundleResult.orientations``.

Units: ``X0`` in the object unit, angles in radians.

>>> import numpy as np
>>> eo = ExteriorOrientation.from_opk([10.0, 20.0, 500.0], 0.01, -0.02, 0.3)
>>> X0, R = eo
>>> np.round(np.asarray(eo), 6).tolist()
[10.0, 20.0, 500.0, 0.01, -0.02, 0.3]
>>> np.asarray([eo, eo]).shape
(2, 6)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_float_array, as_rotation, as_vector3, check_finite

__all__ = ["ExteriorOrientation"]


@dataclass(frozen=True, eq=False)
class ExteriorOrientation:
    """Projection centre ``X0`` (3,) [object unit] and rotation ``R`` (3, 3), ``R_ω·R_φ·R_κ``.

    Iterates as ``X0, R``; as an array it is ``params`` = ``(X0, Y0, Z0, ω, φ, κ)``.
    """

    X0: np.ndarray
    R: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "X0", as_vector3(self.X0, "X0"))
        object.__setattr__(self, "R", as_rotation(self.R, "R"))

    @classmethod
    def from_opk(cls, X0, omega: float, phi: float, kappa: float) -> ExteriorOrientation:
        """From the projection centre and ω, φ, κ in radians."""
        from photolib.rotations import rotation_opk
        return cls(X0, rotation_opk(float(omega), float(phi), float(kappa)))

    @classmethod
    def from_params(cls, params) -> ExteriorOrientation:
        """From ``(X0, Y0, Z0, ω, φ, κ)`` (angles in radians)."""
        p = as_float_array(params, "params", " with shape (6,)")
        if p.shape != (6,):
            raise ValueError(f"params has shape {p.shape}; expected (6,) = X0, Y0, Z0, ω, φ, κ")
        check_finite(p, "params")
        return cls.from_opk(p[:3], *p[3:])

    @property
    def angles(self) -> np.ndarray:
        """``(ω, φ, κ)`` in radians from ``R`` (:func:`photolib.opk_from_rotation`; raises
        :class:`photolib.GimbalLockError` at φ = ±π/2, where they are not separable)."""
        from photolib.rotations import opk_from_rotation
        return np.asarray(opk_from_rotation(self.R), dtype=float)

    @property
    def params(self) -> np.ndarray:
        """``(X0, Y0, Z0, ω, φ, κ)`` as one (6,) array (object unit, radians)."""
        return np.r_[self.X0, self.angles]

    def __iter__(self):
        return iter((self.X0, self.R))

    def __array__(self, dtype=None, copy=None):
        p = self.params
        return p if dtype is None else p.astype(dtype)

    def __repr__(self) -> str:
        w, p, k = self.angles
        return (f"ExteriorOrientation(X0={np.round(self.X0, 6).tolist()}, ω={w:.6g}, φ={p:.6g}, "
                f"κ={k:.6g} rad)")
