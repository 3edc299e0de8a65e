"""Hungarian Wikipedia article "Fotogrammetria" (001_*): collinearity and rotation matrix."""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive.rotation import kappa, omega, phi, rotation_opk, wolf_m
from photolib.errata._record import VersionSpec, formula

SRC = "001_a18d25e57ee77a17.txt (Hungarian Wikipedia, 'Matematikai alapok')"
co, so, cp, spp, ck, sk = (sp.cos(omega), sp.sin(omega), sp.cos(phi), sp.sin(phi),
                           sp.cos(kappa), sp.sin(kappa))


def printed_matrix():
    """R_ωφκ as printed (element (1,1) is cos ω cos κ)."""
    return sp.Matrix([[co * ck, co * sk + so * spp * ck, so * sk - co * spp * ck],
                      [-cp * sk, co * ck - so * spp * sk, so * ck + co * spp * sk],
                      [spp, -so * cp, co * cp]])


def _collinearity_printed(R=None):
    r = col.r if R is None else list(R)
    d = [col.X - col.X0, col.Y - col.Y0, col.Z - col.Z0]
    den = sum(r[3 * i + 2] * d[i] for i in range(3))
    return sp.Matrix([-col.c * sum(r[3 * i] * d[i] for i in range(3)) / den,
                      -col.c * sum(r[3 * i + 1] * d[i] for i in range(3)) / den])


def records():
    out = []
    out.append(formula(
        "hu-wiki:collinearity", SRC, "collinearity equations without principal point",
        {"printed": VersionSpec("right-under-condition: ξ, η reduced to the principal point "
                                "(x'0 = y'0 = 0); r_ij elements of R (image → object)",
                                expr=_collinearity_printed, condition={col.x0: 0, col.y0: 0},
                                condition_text="ξ, η reduced to the principal point "
                                               "(x'0 = y'0 = 0); r_ij elements of R (image → "
                                               "object)")},
        derivation=lambda: sp.Matrix(col.image_coordinates(col.rotation_symbols()))))
    out.append(formula(
        "hu-wiki:rotation-matrix", SRC, "rotation matrix R_ωφκ",
        {"printed": VersionSpec("wrong", expr=printed_matrix)},
        derivation=wolf_m,
        steps=("R = R_ω·R_φ·R_κ from the matrix exponentials of the axis generators",
               "the printed matrix is laid out as Wolf's M = Rᵀ (object → image)",
               "element (1,1) must be cos φ cos κ; the article prints cos ω cos κ"),
        note="With m11 = cos φ·cos κ the printed matrix equals Rᵀ of the course; as printed it "
             "is not even orthogonal (ω = 0.5, φ = κ = 0 gives m11 = cos 0.5)."))
    out.append(formula(
        "hu-wiki:collinearity-with-printed-matrix", SRC, "the article's collinearity equation "
        "evaluated with the article's own matrix",
        {"printed": VersionSpec("wrong", expr=lambda: _collinearity_printed(printed_matrix()))},
        derivation=lambda: sp.Matrix(col.image_coordinates(rotation_opk())).subs(
            {col.x0: 0, col.y0: 0}),
        note="The equation uses r11, r21, r31 (columns of R) but the matrix is laid out as "
             "M = Rᵀ: combining them transposes the rotation. With Rᵀ's elements the sums "
             "must run over rows."))
    return out
