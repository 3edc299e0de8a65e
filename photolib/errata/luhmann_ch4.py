"""Luhmann errata of chapter 4 (without the DLT): 4.13, x'0 sign, 4.18b, 4.76, 4.8, table 4.1.

Symbols: ``z_p`` is Luhmann's z' (the image-space z of the image plane; the course has
``z' = −c``); ``X0s, Y0s, Z0s`` are the components of his vector X0* (4.11); ``k_x, k_y, N``
his auxiliary values; r11..r33 the elements of R.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive import dlt, stereo
from photolib.derive.rotation import kappa
from photolib.errata._record import Evidence, Record, VersionSpec, figure, formula, numbers_evidence

SRC = "002_b1d9e6507973e20d.txt (Luhmann errata list, 11.7.2017)"
zp = sp.Symbol("z_p", real=True)
X0s, Y0s, Z0s = sp.symbols("X0s Y0s Z0s", real=True)
kx, ky, N = sp.symbols("k_x k_y N", real=True)

#: example 4.8 as printed: (c in mm, Z1 in m, Z2 in m); b = 1.2 m
EX48 = {"old": (64.0, 3.88, 58.49), "corrected": (-60.2, -3.65, -55.02), "b": 1.2}
#: table 4.1, first column: (n, r) old and corrected; other columns unchanged
TABLE41 = {"old": ((110, 20), (384, 208), (304, 192)),
           "corrected": ((112, 22), (384, 208), (304, 192))}


def _f413(second):
    r = col.r
    Xv = (col.X, col.Y, col.Z)
    num = [sum(zp * r[3 * i + j] / Z0s * Xv[i] for i in range(3)) for j in (0, 1)]
    den = sum(r[3 * i + 2] / Z0s * Xv[i] for i in range(3)) + Z0s / Z0s
    tx, ty = second
    return sp.Matrix([(num[0] + zp / Z0s * tx) / den, (num[1] + zp / Z0s * ty) / den])


def _derived_413():
    xs, ys, _ = dlt.collinearity_413_form()
    return sp.Matrix([xs, ys])


def _cond_413():
    _, _, X0star = dlt.collinearity_413_form()
    return {zp: -col.c, X0s: X0star[0], Y0s: X0star[1], Z0s: X0star[2]}


def _dy_dphi(old: bool):
    inner = (kx * sp.cos(kappa) + ky * sp.sin(kappa)) if old else \
        (ky * sp.sin(kappa) - kx * sp.cos(kappa))
    return zp / N * (ky / N * inner + N * sp.sin(kappa))


def _ev48(which: str) -> Evidence:
    b = EX48["b"]
    c_old, z1_old, z2_old = EX48["old"]
    # course: Z = −c·B/px' with c > 0; Luhmann prints c < 0, so c_course = −c_printed
    Zf = stereo.height_from_parallax()
    pxs = [sp.solve(sp.Eq(Zf.subs({stereo.c: -c_old, stereo.B: b}), z), stereo.px)[0]
           for z in (z1_old, z2_old)]
    if which == "old":
        return Evidence("not-checkable: the image coordinates of example 4.8 are not printed "
                        "in the errata list; c = 64 mm versus 60.2 mm is a camera datum",
                        f"implied parallaxes px' = {float(pxs[0]):.4f}, {float(pxs[1]):.4f} mm")
    c_new, z1_new, z2_new = EX48["corrected"]
    rows = []
    for name, px, z_old, z_new in (("Z1", pxs[0], z1_old, z1_new), ("Z2", pxs[1], z2_old, z2_new)):
        z = float(Zf.subs({stereo.c: -c_new, stereo.B: b, stereo.px: px}))
        tol = 0.005 + abs(z_new) * 0.005 / abs(z_old)
        rows.append((name + " (m)", z_new, z, tol))
    return numbers_evidence(rows, "corrected Z recomputed from the parallaxes implied by the "
                            "old print", condition="Luhmann's negative c (z' = c): "
                            "Z = c·b/px' = −c_course·b/px'; image coordinates not printed, so "
                            "only old and corrected results are checked against each other")


def _ev41(which: str) -> Evidence:
    us = {w: [n - r for n, r in TABLE41[w]] for w in TABLE41}
    same = us["old"] == us["corrected"]
    rows = [(f"u column {i + 1}", us["corrected"][i], us[which][i], 0, us[which][i] ==
             us["corrected"][i]) for i in range(3)]
    return Evidence("not-checkable: the numbers of images, points and parameters of the "
                    "block are not printed; both versions satisfy r = n − u with the same u = "
                    f"{us[which][0]}" if same else "wrong",
                    f"u = n − r per column: {us[which]}", table=rows)


OLD_476 = ("right-under-condition: κ_i = κ (the left side R_i(ω, φ, κ) names κ, so A_i must "
           "take the same κ); the product is a rotation with either argument")


def _ev476(which: str) -> Evidence:
    """4.76: the product is a rotation; the arguments of A_i must match the left side."""
    if not dlt.composed_rotation_is_rotation():
        return Evidence("wrong", "R(ξ, η, ζ)·A(ω, φ, κ) is not a rotation")
    detail = "R(ξ, η, ζ)·A(ω, φ, κ) is orthonormal with det 1 (30 digits)"
    if which == "corrected":
        return Evidence("right", detail + "; A_i takes the κ of R_i(ω, φ, κ)")
    return Evidence(OLD_476, detail + "; A_i(ω, φ, κ_i) depends on κ_i, which the left side "
                    "does not name")


def records():
    r = []
    r.append(formula(
        "luhmann:4.13", SRC + ", p. 241, formula 4.13", "collinearity in reduced form "
        "(divided by Z0*)",
        {"old": VersionSpec("wrong", expr=lambda: _f413((col.X0, col.Y0)), condition=_cond_413,
                            claim="wrong"),
         "corrected": VersionSpec(
             "right-under-condition: X0* = −Rᵀ·X0 (so k = Rᵀ·X + X0*), z' = −c, "
             "principal point at the origin, Z0* ≠ 0",
             expr=lambda: _f413((X0s, Y0s)), condition=_cond_413, claim="right",
             condition_text="X0* = −Rᵀ·X0 (so k = Rᵀ·X + X0*), z' = −c, principal point at "
                            "the origin, Z0* ≠ 0")},
        derivation=_derived_413,
        steps=("x' = −c·kx/N with k = Rᵀ(X − X0) = Rᵀ·X + X0*, X0* := −Rᵀ·X0",
               "numerator and denominator divided by Z0* (third component of X0*)",
               "old print has X0, Y0 (object coordinates of the centre) where X0*, Y0* belong"),
        note="R is a general 3×3 matrix of symbols; the meaning of X0* (4.11) is not printed in "
             "the errata list and is derived here."))
    r.append(formula(
        "luhmann:4.18b", SRC + ", p. 245, formula 4.18b", "partial derivative ∂y'/∂φ",
        {"old": VersionSpec("wrong", expr=lambda: _dy_dphi(True), condition={zp: -col.c},
                            claim="wrong"),
         "corrected": VersionSpec(
             "right-under-condition: z' = −c, R = R_ω·R_φ·R_κ, (kx, ky, N) = Rᵀ(X − X0)",
             expr=lambda: _dy_dphi(False), condition={zp: -col.c}, claim="right",
             condition_text="z' = −c, R = R_ω·R_φ·R_κ, (kx, ky, N) = Rᵀ(X − X0)")},
        derivation=dlt.dy_dphi, given=dlt.k_substitution,
        symbols=lambda: {"k_x": kx, "k_y": ky, "N": N, "z_p": zp, "kappa": kappa},
        steps=("y' = y'0 − c·ky/N with (kx, ky, N) = Rᵀ(X − X0), R = R_ω R_φ R_κ",
               "∂y'/∂φ by SymPy diff of the full expression in X, X0, ω, φ, κ",
               "printed form in kx, ky, N, z' compared after substituting kx, ky, N and z' = −c",
               "(by hand: ∂k/∂φ = k × (sin κ, cos κ, 0) = (−N cos κ, N sin κ, kx cos κ − ky sin κ))"),
        note="Verified by differentiating, independently of the lead's ∂k/∂φ identity."))
    for ex in ("4.1", "4.2", "4.5"):
        r.append(Record(
            id=f"luhmann:example-{ex}-x0", source=SRC + {"4.1": ", p. 242, example 4.1",
                                                        "4.2": ", p. 242 (example 4.2 data)",
                                                        "4.5": ", p. 280, example 4.5"}[ex],
            item=f"sign of the principal point x'0 in example {ex}", kind="example",
            specs={"old": VersionSpec("not-checkable: the image and object coordinates of "
                                      "the example are not in the errata list", claim="wrong"),
                   "corrected": VersionSpec("not-checkable: the image and object coordinates "
                                            "of the example are not in the errata list",
                                            claim="right")},
            note="x'0 = −0.0494 mm versus +0.0494 mm cannot be decided without the example's "
                 "measurements."))
    r.append(Record(
        id="luhmann:4.76", source=SRC + ", p. 290, formula 4.76", item="rotation of a bundle",
        kind="formula",
        specs={"old": VersionSpec(OLD_476, claim="wrong", check=lambda: _ev476("old")),
               "corrected": VersionSpec("right", claim="right",
                                        check=lambda: _ev476("corrected"))},
        note="R_i = R(ξ,η,ζ)·A_i is a composition of rotations; the check confirms it is a "
             "rotation whichever κ A_i takes. The two prints differ in notation only: the "
             "old one is right once κ_i denotes the κ of the left side."))
    r.append(Record(
        id="luhmann:example-4.8", source=SRC + ", p. 298, example 4.8",
        item="stereo normal case: Z from parallax", kind="example",
        specs={"old": VersionSpec("not-checkable: the image coordinates of example 4.8 are "
                                  "not printed in the errata list; c = 64 mm versus 60.2 mm "
                                  "is a camera datum", check=lambda: _ev48("old"),
                                  claim="wrong"),
               "corrected": VersionSpec(
                   "right-under-condition: Luhmann's negative c (z' = c): Z = c·b/px' = "
                   "−c_course·b/px'; image coordinates not printed, so only old and corrected "
                   "results are checked against each other", check=lambda: _ev48("corrected"),
                   claim="right")},
        derivation=stereo.height_from_parallax,
        steps=("normal case from the collinearity equations: px' = x'1 − x'2 = −c·B/Z",
               "Z = −c·B/px' (course c > 0); Luhmann's c < 0 gives Z = c·b/px'",
               "old: px' = c_old·b/Z_old; corrected Z = c_new·b/px' compared with the print"),
        note="Both prints imply the same parallaxes (19.79 mm and 1.313 mm): the erratum only "
             "changes c; Z scales with c."))
    r.append(Record(
        id="luhmann:table-4.1", source=SRC + ", p. 309, table 4.1",
        item="observations and redundancy of a block", kind="example",
        specs={w: VersionSpec("not-checkable: the numbers of images, points and parameters of "
                              "the block are not printed; both versions satisfy r = n − u "
                              "with the same u = 90", check=lambda w=w: _ev41(w),
                              claim="wrong" if w == "old" else "right")
               for w in ("old", "corrected")},
        note="110 − 20 = 112 − 22 = 90: the correction is self-consistent but so was the "
             "old print."))
    r.append(figure("luhmann:fig-4.11", SRC + ", p. 255, Abb. 4.11", "vector X0 in the "
                    "drawing", "figure only", claim="right"))
    r.append(figure("luhmann:fig-4.14", SRC + ", p. 260, Abb. 4.14", "b1 = −250 versus 250",
                    "the data of the figure are not printed", claim="right"))
    return r
