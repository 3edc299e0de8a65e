"""Collinearity equations with principal point, and their partial derivatives.

Derivation (docs/conventions.md):

* The image vector of an ideal point is ``x* = (x' − x'0, y' − y'0, −c)`` in the camera
  frame; R (``R = R_ω·R_φ·R_κ``, :mod:`photolib.derive.rotation`) turns it into the object
  frame, and the projection centre X0, the image point and the object point X are collinear:
  ``X − X0 = m·R·x*`` for a scale ``m > 0``.
* Multiplying by ``Rᵀ`` gives ``(kx, ky, N) = Rᵀ·(X − X0) = m·x*``; the third row fixes
  ``m = −N/c`` and the first two rows give

  ``x' = x'0 − c·kx/N``,   ``y' = y'0 − c·ky/N``.

  A point in front of the camera has ``N < 0`` (the camera looks along its −z axis).
* The partial derivatives with respect to the nine unknowns of a bundle
  (X0, Y0, Z0, ω, φ, κ, X, Y, Z) are taken by SymPy's ``diff`` of these expressions;
  :func:`luhmann_418` rewrites them in Luhmann's kx, ky, N form (with ``z' = −c``) so
  that the printed 4.18 can be compared.
"""

from __future__ import annotations

import functools

import sympy as sp

from photolib.derive._spec import GeneratedFunction
from photolib.derive.rotation import kappa, omega, phi, rotation_opk

X, Y, Z, X0, Y0, Z0 = sp.symbols("X Y Z X0 Y0 Z0", real=True)
c = sp.symbols("c", positive=True)
x0, y0 = sp.symbols("x0 y0", real=True)
#: general rotation-matrix elements r11..r33 (row-major), for code that takes R, not angles
r = sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33", real=True)

#: order of the unknowns in :func:`jacobian` and in ``collinearity_jacobian`` (last axis)
PARAMETERS = ("X0", "Y0", "Z0", "omega", "phi", "kappa", "X", "Y", "Z")
_SYMBOL = {"X0": X0, "Y0": Y0, "Z0": Z0, "omega": omega, "phi": phi, "kappa": kappa,
           "X": X, "Y": Y, "Z": Z}


def rotation_symbols() -> sp.Matrix:
    """A general 3×3 matrix of symbols r11..r33 (row-major)."""
    return sp.Matrix(3, 3, r)


def k_vector(R: sp.Matrix | None = None) -> sp.Matrix:
    """``(kx, ky, N) = Rᵀ·(X − X0)``; R defaults to ``R_ω·R_φ·R_κ`` in the angles."""
    R = rotation_opk() if R is None else R
    return R.T * sp.Matrix([X - X0, Y - Y0, Z - Z0])


def image_coordinates(R: sp.Matrix | None = None) -> tuple[sp.Expr, sp.Expr]:
    """``(x', y') = (x'0 − c·kx/N, y'0 − c·ky/N)`` without distortion."""
    kx, ky, N = k_vector(R)
    return x0 - c * kx / N, y0 - c * ky / N


def collinear_check() -> sp.Matrix:
    """``R·x* − (X − X0)/m`` with ``m = −N/c``: identically zero (a self-check of the derivation)."""
    R = rotation_symbols()
    kx, ky, N = k_vector(R)
    xs, ys = image_coordinates(R)
    xstar = sp.Matrix([xs - x0, ys - y0, -c])
    m = -N / c
    return (R.T * sp.Matrix([X - X0, Y - Y0, Z - Z0]) - m * xstar).applyfunc(sp.cancel)


def jacobian() -> dict[str, tuple[sp.Expr, sp.Expr]]:
    """``{name: (∂x'/∂name, ∂y'/∂name)}`` for the names in :data:`PARAMETERS`."""
    xs, ys = image_coordinates()
    return {name: (sp.diff(xs, _SYMBOL[name]), sp.diff(ys, _SYMBOL[name])) for name in PARAMETERS}


def luhmann_418() -> dict[str, tuple[sp.Expr, sp.Expr]]:
    """The derivatives in Luhmann's notation: functions of kx, ky, N, z', the angles and r_ij.

    Derived, not transcribed: with ``z' = −c``, ``∂k/∂ω = Rᵀ·[e_x]×ᵀ·(X − X0)``,
    ``∂k/∂φ = k × (sin κ, cos κ, 0)`` and ``∂k/∂κ = k × e_z``; the quotient rule on
    ``x' = x'0 + z'·kx/N`` gives each entry. The test suite proves every entry equal to
    :func:`jacobian` after substituting kx, ky, N.
    """
    kx, ky, N, zp = sp.symbols("k_x k_y N z'", real=True)
    k = sp.Matrix([kx, ky, N])
    R = rotation_opk()
    d = sp.Matrix([X - X0, Y - Y0, Z - Z0])
    dk = {
        "omega": R.T * sp.Matrix([[0, 0, 0], [0, 0, 1], [0, -1, 0]]) * d,
        "phi": k.cross(sp.Matrix([sp.sin(kappa), sp.cos(kappa), 0])),
        "kappa": k.cross(sp.Matrix([0, 0, 1])),
    }
    for i, name in enumerate(("X0", "Y0", "Z0")):
        dk[name] = -R.T[:, i]
    for i, name in enumerate(("X", "Y", "Z")):
        dk[name] = R.T[:, i]
    out = {}
    for name in PARAMETERS:
        dkx, dky, dN = dk[name]
        out[name] = (zp * (dkx * N - kx * dN) / N**2, zp * (dky * N - ky * dN) / N**2)
    return out


def luhmann_symbols():
    """The symbols ``(k_x, k_y, N, z')`` used by :func:`luhmann_418`."""
    return sp.symbols("k_x k_y N z'", real=True)


def _projection_outputs():
    R = rotation_symbols()
    kx, ky, N = k_vector(R)
    xs, ys = image_coordinates(R)
    return (("x", xs), ("y", ys), ("N", N))


def _jacobian_outputs():
    J = jacobian()
    return tuple((f"d{axis}_d{name}", J[name][i]) for name in PARAMETERS
                 for i, axis in enumerate(("x", "y")))


#: the interior orientation's parameters in the ideal model, in the order of
#: ``collinearity_jacobian_interior``'s outputs
INTERIOR = ("c", "x0", "y0")


def _interior_outputs():
    """``∂x'/∂q``, ``∂y'/∂q`` for q in (c, x'0, y'0) of the ideal model (general R): the
    self-calibration columns of the bundle adjustment (distortion's part is added there)."""
    R = rotation_symbols()
    xs, ys = image_coordinates(R)
    sym = {"c": c, "x0": x0, "y0": y0}
    return tuple((f"d{axis}_d{name}", sp.diff(e, sym[name])) for name in INTERIOR
                 for axis, e in (("x", xs), ("y", ys)))


@functools.cache
def codegen_functions() -> tuple:
    """The functions to generate (built on first use: the Jacobians take a second to derive)."""
    return (
        GeneratedFunction(
            name="project_r",
            args=(X, Y, Z, X0, Y0, Z0, *r, c, x0, y0),
            outputs=_projection_outputs(),
            doc="Ideal image coordinates x', y' (image unit, e.g. mm) and the depth N = r13·ΔX + "
                "r23·ΔY + r33·ΔZ (object unit; N < 0 in front) for a general R given by its "
                "elements r11..r33.",
        ),
        GeneratedFunction(
            name="collinearity_jacobian_opk",
            args=(X, Y, Z, X0, Y0, Z0, omega, phi, kappa, c),
            outputs=_jacobian_outputs(),
            doc="∂x'/∂p and ∂y'/∂p for p in (X0, Y0, Z0, ω, φ, κ, X, Y, Z), R = R_ω·R_φ·R_κ; "
                "image unit per object unit for lengths, image unit per radian for angles.",
        ),
        GeneratedFunction(
            name="collinearity_jacobian_interior",
            args=(X, Y, Z, X0, Y0, Z0, *r, c),
            outputs=_interior_outputs(),
            doc="∂x'/∂q and ∂y'/∂q for the interior orientation q in (c, x'0, y'0) of the ideal "
                "model x' = x'0 − c·kx/N, y' = y'0 − c·ky/N, for a general R given by its "
                "elements r11..r33 (dimensionless): the bundle adjustment's self-calibration "
                "columns before the distortion's share.",
        ),
    )


def __getattr__(name):
    # ``CODEGEN`` is computed lazily so that importing this module (e.g. in a chapter
    # notebook) does not pay for deriving every Jacobian
    if name == "CODEGEN":
        return codegen_functions()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
