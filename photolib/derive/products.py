"""Products (chapter 12): relief displacement, orthophoto position errors, occlusion, GSD.

All from the collinearity equations of :mod:`photolib.derive.collinearity` for a vertical
(nadir) image: R = I, projection centre at ``(0, 0, H)`` above the reference plane Z = 0,
an object point at plan distance ``R_g`` from the nadir point and height ``h``. Its image
point lies on the x' axis at ``r = c·R_g/(H − h)`` (radial distance from the principal
point = nadir point).

* relief displacement (radiale Versetzung / Reliefversatz): the top of a vertical object of
  height h and its foot image at ``r_top = c·R_g/(H − h)`` and ``r_foot = c·R_g/H``, so
  ``Δr = r_top − r_foot = r_top·h/H = r_foot·h/(H − h)``: the familiar ``Δr = r·Δh/H`` is
  exact when r is the radial distance of the *displaced* point;
* on the ground, plane rectification puts the top at ``R_g·H/(H − h)``: the plan error is
  ``Δr·H/c = R_g·h/(H − h)``;
* a height error dZ of the DTM moves an ortho point by ``R_g·dZ/(H − h − dZ)``, to first
  order ``(r/c)·dZ`` (the tangent of the ray's nadir angle times dZ);
* the ground hidden behind a wall of height h at plan distance d from the nadir point
  (on the far side) has length ``d·h/(H − h)``;
* the ground sampling distance of a pixel of size p is ``p·(H − h)/c``.

Examples
--------
>>> import sympy as sp
>>> sp.cancel(relief_displacement() - r_top() * h / H)
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col

c = col.c
H, h, Rg, d, dZ, p = sp.symbols("H h R_g d dZ p", positive=True)


def radial_distance(height=None) -> sp.Expr:
    """Radial image distance r of a point at plan distance R_g and ``height`` (default h).

    From ``x' = x'0 − c·kx/N`` with R = I, X0 = (0, 0, H), X = (R_g, 0, height), x'0 = 0.
    """
    height = h if height is None else height
    xs, ys = col.image_coordinates(sp.eye(3))
    values = {col.X0: 0, col.Y0: 0, col.Z0: H, col.X: Rg, col.Y: 0, col.Z: height,
              col.x0: 0, col.y0: 0}
    assert ys.xreplace(values) == 0
    return sp.cancel(xs.xreplace(values))


def r_top() -> sp.Expr:
    """r of the top of the object (height h)."""
    return radial_distance(h)


def r_foot() -> sp.Expr:
    """r of the foot of the object (height 0)."""
    return radial_distance(sp.Integer(0))


def relief_displacement() -> sp.Expr:
    """``Δr = r_top − r_foot`` in c, R_g, H, h."""
    return sp.cancel(r_top() - r_foot())


def relief_displacement_forms() -> dict:
    """The two exact forms, each checked by ``cancel`` (no simplify): ``r_top·h/H``, ``r_foot·h/(H − h)``.

    >>> sorted(relief_displacement_forms())
    ['foot', 'top']
    """
    r = sp.Symbol("r", positive=True)
    dr = relief_displacement()
    top = r * h / H
    foot = r * h / (H - h)
    assert sp.cancel(dr - top.subs(r, r_top())) == 0
    assert sp.cancel(dr - foot.subs(r, r_foot())) == 0
    return {"top": top, "foot": foot}


def plane_rectification_error() -> sp.Expr:
    """Plan error of a point at height h after plane rectification onto Z = 0.

    Plane rectification maps the image point back with the scale of the plane, ``H/c``:
    the top lands at ``r_top·H/c``; it belongs at R_g.
    """
    return sp.cancel(r_top() * H / c - Rg)


def ortho_error_from_height_error() -> tuple[sp.Expr, sp.Expr]:
    """Plan error of an ortho pixel whose DTM height is wrong by dZ: exact and first order.

    The ortho pixel at R_g takes the grey value of the image point ``r(R_g, h + dZ)``; the
    ground point seen there lies at R' with ``r(R', h) = r(R_g, h + dZ)``.
    """
    Rp = sp.Symbol("R'", positive=True)
    sol = sp.solve(sp.Eq(radial_distance(h).subs(Rg, Rp), radial_distance(h + dZ)), Rp)[0]
    exact = sp.cancel(sol - Rg)
    first = sp.diff(exact, dZ).subs(dZ, 0) * dZ
    return exact, sp.cancel(first)


def occluded_length() -> sp.Expr:
    """Length of ground hidden behind a wall of height h at plan distance d (far side).

    The ray from X0 = (0, 0, H) over the roof edge (d, h) reaches Z = 0 at ``d·H/(H − h)``.
    """
    t = sp.Symbol("t", positive=True)
    ray_z = H + t * (h - H)             # X0 + t·((d, h) − X0)
    t0 = sp.solve(sp.Eq(ray_z, 0), t)[0]
    return sp.cancel(t0 * d - d)


def ground_sampling_distance() -> sp.Expr:
    """Ground size of an image pixel of size p at height h: ``p·(H − h)/c``."""
    return sp.cancel(p * sp.diff(Rg, Rg) / sp.diff(radial_distance(h), Rg))
