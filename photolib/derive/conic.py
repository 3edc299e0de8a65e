"""Circle from the general conic, and the plane through three points.

* A circle is the conic ``A(x² + y²) + 2Dx + 2Ey + F = 0`` (A ≠ 0; the factors 2 follow
  Luhmann 2.85). Completing the square gives the centre ``(−D/A, −E/A)`` and
  ``r² = (D² + E² − AF)/A²``; the radius is the square root. Dividing by F (F ≠ 0, i.e. the
  circle does not pass through the origin) normalises to F = 1.
* Plane ``z = a0 + a1x + a2y`` through three points: the 3×3 linear system is solved by
  SymPy; with the first point at the origin it reduces to Luhmann's 2.136 matrix.

Examples
--------
>>> circle_radius_squared()
-(A*F - D**2 - E**2)/A**2
"""

from __future__ import annotations

import sympy as sp

A, D, E, F = sp.symbols("A D E F", real=True)
xc, yc = sp.symbols("x y", real=True)
x1, y1, z1, x2, y2, z2, x3, y3, z3 = sp.symbols("x1 y1 z1 x2 y2 z2 x3 y3 z3", real=True)


def general_circle(x=xc, y=yc):
    """``A(x² + y²) + 2Dx + 2Ey + F``."""
    return A * (x**2 + y**2) + 2 * D * x + 2 * E * y + F


def circle_centre():
    """Centre from the zero of the gradient (completing the square)."""
    g = general_circle()
    sol = sp.solve([sp.diff(g, xc), sp.diff(g, yc)], [xc, yc], dict=True)[0]
    return sol[xc], sol[yc]


def circle_radius_squared():
    """``r²`` = squared distance from the centre to the circle: ``−g(centre)/A``."""
    cx, cy = circle_centre()
    # g(x) = A·|x − centre|² + g(centre) ⇒ on the circle |x − centre|² = −g(centre)/A
    return sp.factor(sp.cancel(-general_circle(cx, cy) / A))


def circle_radius():
    """``r = sqrt(r²)``."""
    return sp.sqrt(circle_radius_squared())


def circle_through_origin_F():
    """F of every circle through the origin: the conic at (0, 0) is F, so F = 0 there.

    Such circles cannot be normalised to F = 1 (Luhmann 2.88 assumes F = 1).
    """
    return general_circle(0, 0)


def plane_through_points():
    """``(a0, a1, a2)`` of ``z = a0 + a1x + a2y`` through the three points (solved)."""
    a0, a1, a2 = sp.symbols("a0 a1 a2", real=True)
    eqs = [a0 + a1 * xi + a2 * yi - zi for xi, yi, zi in ((x1, y1, z1), (x2, y2, z2), (x3, y3, z3))]
    sol = sp.solve(eqs, [a0, a1, a2], dict=True)[0]
    return sp.Matrix([sp.cancel(sol[a0]), sp.cancel(sol[a1]), sp.cancel(sol[a2])])


# -- general conic and ellipse (chapter 11) -------------------------------------------------------
ca, cb, cc, cd, ce, cf = sp.symbols("a b c d e f", real=True)
ex0, ey0 = sp.symbols("x_c y_c", real=True)
sa, sb, theta = sp.symbols("A_e B_e theta", positive=True)


def general_conic(x=xc, y=yc):
    """``a x² + b xy + c y² + d x + e y + f``."""
    return ca * x**2 + cb * x * y + cc * y**2 + cd * x + ce * y + cf


def conic_centre():
    """Centre of the general conic: the zero of its gradient, ``(x_c, y_c)``.

    Exists iff ``4ac − b² ≠ 0`` (the determinant of the linear system); for an ellipse
    ``4ac − b² > 0``.
    """
    g = general_conic()
    sol = sp.solve([sp.diff(g, xc), sp.diff(g, yc)], [xc, yc], dict=True)[0]
    return sp.factor(sol[xc]), sp.factor(sol[yc])


def ellipse_conic():
    """Coefficients ``(a, b, c, d, e, f)`` of the ellipse with centre (x_c, y_c), semi-axes
    A_e, B_e and the A_e-axis at angle θ: ``(u/A_e)² + (v/B_e)² − 1`` expanded, with
    ``u = (x − x_c)cos θ + (y − y_c)sin θ``, ``v = −(x − x_c)sin θ + (y − y_c)cos θ``.
    """
    u = (xc - ex0) * sp.cos(theta) + (yc - ey0) * sp.sin(theta)
    v = -(xc - ex0) * sp.sin(theta) + (yc - ey0) * sp.cos(theta)
    poly = sp.Poly(sp.expand((u / sa) ** 2 + (v / sb) ** 2 - 1), xc, yc)
    return tuple(poly.coeff_monomial(m) for m in (xc**2, xc * yc, yc**2, xc, yc, 1))
