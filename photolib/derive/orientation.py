"""Interior and exterior orientation: image vector, parameter count, attitude axes, principal point.

* Image vector: the collinearity equations (:mod:`photolib.derive.collinearity`) say
  ``X − X0 = m·R·x*`` with the third component of ``x*`` equal to ``−c``; so
  ``x* = −c·k/N`` with ``k = Rᵀ(X − X0)``, and ``x' = x'0 − c·kx/N`` turns its first two
  components into ``x' − x'0``. A measured point carries the distortion
  (``x' = x'0 − c·kx/N + Δx'``, docs/conventions.md), hence
  ``x* = (ξ − ξ0 − Δξ, η − η0 − Δη, −c)`` in the measured coordinates ξ, η.
* Exterior orientation of one exposure: the rank of the Jacobian of the image coordinates
  of a few object points with respect to ``(X0, Y0, Z0, ω, φ, κ)`` is 6; a time (epoch)
  ``t`` does not enter the collinearity equations and adds a zero column.
* Attitude angles: ``∂R/∂angle`` at zero is the cross-product matrix of the axis the angle
  turns about (ω: X, φ: Y, κ: Z). The course's sequence ``R_ω·R_φ·R_κ`` and the yaw-pitch-roll
  sequence ``R_κ·R_φ·R_ω`` of an inertial system agree to first order only.
* Principal point: the image of the point on the camera axis is ``(x'0, y'0)`` whatever the
  distortion parameters; zero distortion does not put it at the origin (the image centre).

Examples
--------
>>> image_vector().T
Matrix([[-Delta_xi - x0 + xi, -Delta_eta + eta - y0, -c]])
>>> attitude_axes()["phi"].T
Matrix([[0, 1, 0]])
>>> axis_image_point()
(x0, y0)
"""

from __future__ import annotations

import mpmath
import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive.rotation import R_kappa, R_omega, R_phi, kappa, omega, phi, rotation_opk, skew

#: measured image coordinates ξ, η and their distortion corrections Δξ, Δη
xi, eta = sp.symbols("xi eta", real=True)
d_xi, d_eta = sp.symbols("Delta_xi Delta_eta", real=True)
#: the epoch of an exposure ("Zeit (t)")
t_epoch = sp.Symbol("t", real=True)
ANGLES = (omega, phi, kappa)


def image_vector() -> sp.Matrix:
    """``x* = (ξ − ξ0 − Δξ, η − η0 − Δη, −c)`` of a measured point (camera frame).

    Derived: ``x* = −c·k/N`` is the vector along ``Rᵀ(X − X0)`` with third component −c; it
    is checked to equal ``(x' − x'0, y' − y'0, −c)`` with x', y' from the collinearity
    equations, and the ideal x' is the measured ξ minus its distortion Δξ.
    """
    R = col.rotation_symbols()
    k = col.k_vector(R)
    xs, ys = col.image_coordinates(R)
    ray = -col.c * k / k[2]
    ideal = sp.Matrix([xs - col.x0, ys - col.y0, -col.c])
    if (ray - ideal).applyfunc(sp.cancel) != sp.zeros(3, 1):
        raise AssertionError("−c·k/N is not (x' − x'0, y' − y'0, −c)")
    return sp.Matrix([xi - d_xi - col.x0, eta - d_eta - col.y0, -col.c])


#: a generic pose and four object points for :func:`exterior_orientation_rank`
POSE = {col.X0: sp.Rational(1, 2), col.Y0: sp.Rational(-1, 3), col.Z0: 10,
        omega: sp.Rational(1, 10), phi: sp.Rational(-1, 5), kappa: sp.Rational(3, 10),
        col.c: sp.Rational(3, 20), col.x0: 0, col.y0: 0}
POINTS = ((0, 0, 0), (3, 1, sp.Rational(1, 2)), (-2, 2, sp.Rational(-3, 10)),
          (1, -3, sp.Rational(1, 5)))


def exterior_orientation_rank(with_time: bool = True):
    """Rank of ``∂(x', y')/∂(X0, Y0, Z0, ω, φ, κ[, t])`` over :data:`POINTS` at :data:`POSE`.

    Returns ``(rank, number of parameters, singular values)``; the singular values are
    computed with mpmath at 30 digits and a value below 1e-20 counts as zero.
    """
    params = [col.X0, col.Y0, col.Z0, omega, phi, kappa] + ([t_epoch] if with_time else [])
    F = sp.Matrix(col.image_coordinates(rotation_opk()))
    J = F.jacobian(params)
    rows = []
    for P in POINTS:
        sub = {**POSE, col.X: P[0], col.Y: P[1], col.Z: P[2]}
        rows.append(J.subs(sub))
    M = sp.Matrix.vstack(*rows)
    with mpmath.workdps(30):
        A = mpmath.matrix([[mpmath.mpf(str(sp.N(e, 35))) for e in M.row(i)]
                           for i in range(M.rows)])
        sv = list(mpmath.svd_r(A, compute_uv=False))
    rank = sum(1 for s in sv if abs(s) > 1e-20)
    return rank, len(params), sv


def attitude_axes() -> dict:
    """``{"omega" | "phi" | "kappa": axis}``: ``∂R/∂angle`` at zero equals ``[axis]×``."""
    R = rotation_opk()
    zero = dict.fromkeys(ANGLES, 0)
    out = {}
    for name, s in zip(("omega", "phi", "kappa"), ANGLES):
        G = sp.diff(R, s).subs(zero)
        axis = sp.Matrix([G[2, 1], G[0, 2], G[1, 0]])
        if G != skew(axis):
            raise AssertionError(f"∂R/∂{name} at 0 is not skew-symmetric: {G}")
        out[name] = axis
    return out


def yaw_pitch_roll_difference() -> sp.Matrix:
    """``R_ω·R_φ·R_κ − R_κ·R_φ·R_ω``: the course's ω-φ-κ sequence minus yaw-pitch-roll.

    With ω = roll, φ = pitch, κ = yaw, an inertial system's ``R_z(yaw)·R_y(pitch)·R_x(roll)``
    is ``R_κ·R_φ·R_ω``; the difference vanishes to first order in the angles.
    """
    return rotation_opk() - R_kappa() * R_phi() * R_omega()


def axis_image_point(R: sp.Matrix | None = None, depth=10):
    """Image of the object point on the camera axis, ``X = X0 + R·(0, 0, −depth)``.

    ``R`` defaults to I; for a rotation in the angles the result is trigsimp'ed (about a
    second) and is again ``(x'0, y'0)``.
    """
    rotated = R is not None
    R = sp.eye(3) if R is None else R
    P = sp.Matrix([col.X0, col.Y0, col.Z0]) + R * sp.Matrix([0, 0, -depth])
    xs, ys = col.image_coordinates(R)
    sub = {col.X: P[0], col.Y: P[1], col.Z: P[2]}
    tidy = sp.trigsimp if rotated else sp.cancel
    return tuple(tidy(sp.cancel(e.subs(sub))) for e in (xs, ys))
