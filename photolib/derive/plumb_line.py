"""Plumb-line calibration / Kalibrierung mit Lotlinien (Plumblines): condition and Jacobians.

A line straight in object space is imaged straight by the distortion-free central projection.
With the line ``n(θ)·x = d``, ``n = (cos θ, sin θ)``, and the course distortion Δ of
:mod:`photolib.derive.distortion` (evaluated at the measured point reduced to the principal
point), a measured point (x, y) of the line satisfies the condition

``f = cos θ·(x − Δx') + sin θ·(y − Δy') − d = 0``.

:func:`jacobian` differentiates f with respect to the unknowns (A1, A2, A3, B1, B2, θ, d);
:func:`jacobian_observations` with respect to the measured coordinates. A coordinate error
moves f by that gradient times the error, so the residual of a measured coordinate is
:func:`residual` ``v = f/‖∂f/∂(x, y)‖`` (the Gauss–Helmert weight), and
:func:`residual_jacobian` is the Jacobian of the adjustment. The invariances behind the method's limits are derived too:

* :func:`radial_line_invariance`: on a line through the principal point, radial distortion
  has no component normal to the line (such lines stay straight);
* :func:`r0_datum`: with another balancing radius r0 the corrected points are the Seidel
  ones (r0 = 0) scaled by ``1 − K0`` — straightness cannot fix r0;
* :func:`tangential_projective_part`: ``B1·(2x², 2xy)``, two thirds of the x²-part of B1's
  field, is the first-order displacement of a projective map (lines stay straight), so
  plumb lines see only the rest ``B1·(x² + y², 0)``.

Examples
--------
>>> sp.simplify(radial_line_invariance())
0
>>> sp.simplify(r0_datum())
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import distortion as dd

theta, d = sp.symbols("theta d", real=True)
t, phi, eps, g = sp.symbols("t phi epsilon g", real=True)
#: unknowns of a plumb-line calibration in the order of :func:`jacobian`
UNKNOWNS = (dd.A1, dd.A2, dd.A3, dd.B1, dd.B2, theta, d)


def _radial_tangential():
    """Δ with C1 = C2 = 0 (affinity and shear keep lines straight: not estimable)."""
    dx, dy = dd.delta()
    return dx.subs({dd.C1: 0, dd.C2: 0}), dy.subs({dd.C1: 0, dd.C2: 0})


def condition():
    """``f = cos θ·(x − Δx') + sin θ·(y − Δy') − d`` (mm)."""
    dx, dy = _radial_tangential()
    return sp.cos(theta) * (dd.x - dx) + sp.sin(theta) * (dd.y - dy) - d


def jacobian():
    """``∂f/∂(A1, A2, A3, B1, B2, θ, d)`` as a 1×7 matrix (r0 held fixed)."""
    return sp.Matrix([condition()]).jacobian(list(UNKNOWNS))


def jacobian_observations():
    """``∂f/∂(x, y) = nᵀ(I − ∂Δ/∂x)`` as a 1×2 matrix."""
    return sp.Matrix([condition()]).jacobian([dd.x, dd.y])


def residual():
    """``v = f/‖∂f/∂(x, y)‖``: the condition referred to a measured coordinate (mm)."""
    g = jacobian_observations()
    return condition() / sp.sqrt(g[0] ** 2 + g[1] ** 2)


def residual_jacobian():
    """``∂v/∂(A1, A2, A3, B1, B2, θ, d)`` as a 1×7 matrix: the Jacobian of the adjustment."""
    return sp.Matrix([residual()]).jacobian(list(UNKNOWNS))


def radial_line_invariance():
    """Normal component of the radial Δ on the line through the origin in direction φ (0)."""
    dx, dy = dd.delta_radial()
    on_line = {dd.x: t * sp.cos(phi), dd.y: t * sp.sin(phi)}
    return sp.expand(-sp.sin(phi) * dx.subs(on_line) + sp.cos(phi) * dy.subs(on_line))


def r0_datum():
    """Corrected x with r0 minus ``(1 − K0)`` times the Seidel-corrected x with ``A/(1 − K0)`` (0)."""
    dx, _ = dd.delta_radial()
    K0 = dd.conrady_from_seidel()[dd.K0]
    s = 1 - K0
    seidel = (dd.x - dx).subs({dd.r0: 0, dd.A1: dd.A1 / s, dd.A2: dd.A2 / s, dd.A3: dd.A3 / s},
                              simultaneous=True)
    return sp.expand(sp.cancel((dd.x - dx) - s * seidel))


def tangential_projective_part():
    """First-order displacement of ``x ↦ x/(1 − g x)`` minus ``B1·(2x², 2xy)`` at g = 2B1 (0, 0).

    The projective map divides both coordinates by ``1 − g x``; its displacement to first
    order in g is ``g·x·(x, y)``.
    """
    den = 1 - eps * g * dd.x
    moved = sp.Matrix([dd.x / den - dd.x, dd.y / den - dd.y])
    first = sp.diff(moved, eps).subs(eps, 0)
    return sp.simplify(first.subs(g, 2 * dd.B1) - sp.Matrix([2 * dd.B1 * dd.x**2,
                                                              2 * dd.B1 * dd.x * dd.y]))
