"""Stereo normal case, height from parallax and its accuracy, from the collinearity equations.

Normal case (Normalfall): both cameras unrotated (ω = φ = κ = 0, so R = I), camera 1 at the
origin, camera 2 at ``(B, 0, 0)``. The collinearity equations of
:mod:`photolib.derive.collinearity` with R = I give the image coordinates; the x-parallax
``px' = x'1 − x'2`` is ``−c·B/Z`` and so ``Z = −c·B/px'`` (c > 0, points in front have
Z < 0). Error propagation of ``Z(px')`` and of ``X = m·x'`` gives the accuracy formulas.

Examples
--------
>>> import sympy as sp
>>> sp.simplify(height_from_parallax() - (-c*B/px))
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col

X, Y, Z, c, x0, y0 = col.X, col.Y, col.Z, col.c, col.x0, col.y0
B = sp.symbols("B", positive=True)
px = sp.symbols("p_x", real=True)
x1, x2, y1 = sp.symbols("x1 x2 y1", real=True)
s_x, s_px, h, b, m = sp.symbols("s_x s_px h b m", positive=True)


def image_coordinates_normal_case(camera: int):
    """``(x', y')`` of camera 1 (at the origin) or 2 (at (B, 0, 0)), R = I."""
    if camera not in (1, 2):
        raise ValueError(f"camera must be 1 or 2, got {camera!r}")
    base = 0 if camera == 1 else B
    xs, ys = col.image_coordinates(sp.eye(3))
    return tuple(sp.simplify(e.subs({col.X0: base, col.Y0: 0, col.Z0: 0})) for e in (xs, ys))


def parallax():
    """``px' = x'1 − x'2`` in the normal case."""
    return sp.simplify(image_coordinates_normal_case(1)[0] - image_coordinates_normal_case(2)[0])


def height_from_parallax():
    """Z solved from ``px' = x'1 − x'2``."""
    return sp.solve(sp.Eq(parallax(), px), Z)[0]


def object_from_image(camera: int):
    """``(X, Y)`` solved from the image coordinates (x', y') of one camera at known Z."""
    xs, ys = image_coordinates_normal_case(camera)
    xi, yi = sp.symbols("xi eta", real=True)
    sol = sp.solve([sp.Eq(xs, xi), sp.Eq(ys, yi)], [X, Y], dict=True)[0]
    return sol[X], sol[Y], (xi, yi)


def parallax_sigma_independent():
    """σ of ``px' = x'1 − x'2`` for independent x'1, x'2 of equal σ ``s_x`` (propagation)."""
    J = sp.Matrix([[sp.diff(x1 - x2, x1), sp.diff(x1 - x2, x2)]])
    return sp.sqrt((J * sp.diag(s_x**2, s_x**2) * J.T)[0])


def sigma_Z():
    """σ_Z from ``Z = −cB/px'`` at ``|Z| = h``, ``h/c = m`` (scale number), base b."""
    dZ = sp.diff(-c * B / px, px)
    # |dZ/dpx| = c·B/px² = Z²/(c·B) = h²/(c·b) = (h/b)·m
    val = sp.Abs(dZ).subs(px, c * B / h).subs({B: b, c: h / m})
    return sp.simplify(val * s_px)


def sigma_XY():
    """σ_X of ``X = m·x'`` for image σ ``s_x`` (scale number m)."""
    return m * s_x
