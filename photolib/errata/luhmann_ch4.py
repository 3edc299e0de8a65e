"""Luhmann errata of chapter 4 (without the DLT): 4.13, x'0 sign, 4.18b, 4.76, 4.8, table 4.1.

Symbols: ``z_p`` is Luhmann's z' (the image-space z of the image plane; the course has
``z' = −c``); ``X0s, Y0s, Z0s`` are the components of his vector X0* (4.11); ``k_x, k_y, N``
his auxiliary values; r11..r33 the elements of R. ``check-formula`` also takes the book's
spellings (``kx``, ``ky``, ``zp`` or ``z'``, ``κ``; ``X0_star`` for X0*, see ``aliases``).
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive import dlt, stereo
from photolib.derive.rotation import kappa, omega, phi, rotation_opk
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


EX48_OLD = ("not-checkable: the image coordinates of example 4.8 are not printed in the errata "
            "list; c = 64 mm versus 60.2 mm is a camera datum")
EX48_NEW = ("not-checkable: the image coordinates of example 4.8 are not printed in the errata "
            "list, so Z cannot be recomputed independently; the corrected Z only equal the old "
            "ones scaled by c_new/c_old (−3.6496 m, −55.017 m)")


def _ev48(which: str) -> Evidence:
    """Example 4.8: neither print can be recomputed; the corrected Z are the old Z·c_new/c_old."""
    b = EX48["b"]
    c_old, z1_old, z2_old = EX48["old"]
    # course: Z = −c·B/px' with c > 0; Luhmann prints c < 0, so c_course = −c_printed
    Zf = stereo.height_from_parallax()
    pxs = [sp.solve(sp.Eq(Zf.subs({stereo.c: -c_old, stereo.B: b}), z), stereo.px)[0]
           for z in (z1_old, z2_old)]
    if which == "old":
        return Evidence(EX48_OLD, f"implied parallaxes px' = {float(pxs[0]):.4f}, "
                        f"{float(pxs[1]):.4f} mm")
    c_new, z1_new, z2_new = EX48["corrected"]
    rows = []
    for name, px, z_old, z_new in (("Z1", pxs[0], z1_old, z1_new), ("Z2", pxs[1], z2_old, z2_new)):
        z = float(Zf.subs({stereo.c: -c_new, stereo.B: b, stereo.px: px}))
        tol = 0.005 + abs(z_new) * 0.005 / abs(z_old)
        rows.append((name + " (m)", z_new, z, tol))
    ev = numbers_evidence(rows)
    if ev.verdict != "right":      # the corrected Z would not even follow from the old ones
        return Evidence("not-checkable: the corrected Z are not the old Z scaled by "
                        "c_new/c_old", ev.detail, table=ev.table)
    return Evidence(EX48_NEW, "the parallaxes px' = c·b/Z of the old print, used again with "
                    "c = −60.2 mm, give the corrected Z: a consistency of the two prints, not "
                    "a check of either (the parallaxes themselves come from the old print)",
                    table=ev.table)


def _ev41(which: str) -> Evidence:
    us = {w: [n - r for n, r in TABLE41[w]] for w in TABLE41}
    same = us["old"] == us["corrected"]
    rows = [(f"u column {i + 1}", us["corrected"][i], us[which][i], 0, us[which][i] ==
             us["corrected"][i]) for i in range(3)]
    return Evidence("not-checkable: the numbers of images, points and parameters of the "
                    "block are not printed; both versions satisfy r = n − u with the same u = "
                    f"{us[which][0]}" if same else "wrong",
                    f"u = n − r per column: {us[which]}", table=rows)


V476 = ("not-checkable: notation — the errata list defines neither A_i nor ξ, η, ζ; if A_i "
        "takes the κ of R_i(ω, φ, κ), the corrected print equals the composition R(ξ, η, ζ)·A_i "
        "and the old one differs wherever κ_i ≠ κ; if A_i has an image-specific κ_i, the "
        "reverse. Both prints are rotations")
xi_b, eta_b, zeta_b = sp.symbols("xi eta zeta", real=True)
kappa_i = sp.Symbol("kappa_i", real=True)


def _print476(which: str) -> sp.Matrix:
    """The printed right side of 4.76: R(ξ, η, ζ)·A_i(ω, φ, κ_i) (old) or A_i(ω, φ, κ)."""
    k = kappa_i if which == "old" else kappa
    return rotation_opk(xi_b, eta_b, zeta_b) * rotation_opk(omega, phi, k)


def bundle_rotation_476(reading: str) -> sp.Matrix:
    """R_i of image i of a bundle from first principles, under one reading of A_i's κ.

    A direction x in image i turns into the bundle frame by A_i and from there into the object
    frame by R(ξ, η, ζ): X = R(ξ, η, ζ)·(A_i·x), so R_i = R(ξ, η, ζ)·A_i by associativity.
    ``reading="kappa"``: A_i's third angle is the κ of the left side R_i(ω, φ, κ);
    ``reading="kappa_i"``: it is an image-specific κ_i. R and A_i are parametrised as the
    course's R_ω·R_φ·R_κ (the same on both sides, so the choice does not matter).

    >>> bool(bundle_rotation_476("kappa").has(kappa_i))
    False
    """
    if reading not in ("kappa", "kappa_i"):
        raise ValueError(f"reading must be 'kappa' or 'kappa_i', got {reading!r}")
    R = rotation_opk(xi_b, eta_b, zeta_b)
    A = rotation_opk(omega, phi, kappa if reading == "kappa" else kappa_i)
    x = sp.Matrix(sp.symbols("u v w", real=True))
    X = R * (A * x)
    return X.jacobian(x)          # the matrix that maps x to X


def _ev476(which: str) -> Evidence:
    """4.76: entry-wise comparison of each print with the derivation under both readings."""
    from photolib.symcheck import equivalent
    printed = _print476(which)
    res = {rd: equivalent(printed, bundle_rotation_476(rd), time_budget=3.0)
           for rd in ("kappa", "kappa_i")}
    want = {"old": ("not-equal", "equal"), "corrected": ("equal", "not-equal")}[which]
    got = (res["kappa"].kind, res["kappa_i"].kind)
    if not dlt.composed_rotation_is_rotation():
        return Evidence("wrong", "R(ξ, η, ζ)·A(ω, φ, κ) is not a rotation")
    if got != want:
        return Evidence(f"not-checkable: comparison gave {got}", str(got))
    bad = res["kappa"] if which == "old" else res["kappa_i"]
    return Evidence(V476, f"entry-wise: A_i with the κ of R_i {got[0]} ({res['kappa'].method}), "
                    f"A_i with κ_i {got[1]} ({res['kappa_i'].method}); the prints differ in "
                    "the name of one argument only",
                    bad.counterexample, bad.values)


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
        aliases={"X0_star": "X0s", "Y0_star": "Y0s", "Z0_star": "Z0s"},      # his X0*, Y0*, Z0*
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
        specs={w: VersionSpec(V476, claim="wrong" if w == "old" else "right",
                              expr=lambda w=w: _print476(w), check=lambda w=w: _ev476(w))
               for w in ("old", "corrected")},
        steps=("X = R(ξ, η, ζ)·(A_i·x): image i → bundle frame (A_i) → object frame, so "
               "R_i = R(ξ, η, ζ)·A_i",
               "reading 1: A_i = A(ω, φ, κ) with the κ of the left side R_i(ω, φ, κ)",
               "reading 2: A_i = A(ω, φ, κ_i) with an angle κ_i of image i",
               "each print compared entry-wise with both derivations: each equals one of them"),
        note="The old and corrected prints differ only in the name of A_i's third argument. "
             "The errata list defines neither A_i nor ξ, η, ζ, so which κ belongs in A_i is a "
             "question of notation that no derivation decides. Each print equals the "
             "derivation under one reading and differs from it under the other (a "
             "counterexample: errata --id luhmann:4.76); either way R_i is a rotation (orthonormal, det 1)."))
    r.append(Record(
        id="luhmann:example-4.8", source=SRC + ", p. 298, example 4.8",
        item="stereo normal case: Z from parallax", kind="example",
        specs={"old": VersionSpec(EX48_OLD, check=lambda: _ev48("old"), claim="wrong"),
               "corrected": VersionSpec(EX48_NEW, check=lambda: _ev48("corrected"),
                                        claim="right")},
        derivation=stereo.height_from_parallax,
        steps=("normal case from the collinearity equations: px' = x'1 − x'2 = −c·B/Z",
               "Z = −c·B/px' (course c > 0); Luhmann's c < 0 gives Z = c·b/px'",
               "old: px' = c_old·b/Z_old; c_new·b/px' reproduces the corrected Z: a "
               "consistency of the two prints, no independent check"),
        note="Both prints imply the same parallaxes (19.79 mm and 1.313 mm): the erratum only "
             "changes c, and Z scales with c. That is all the two prints show: the parallaxes "
             "come from the old print itself, so the corrected Z are no more checked than the "
             "old ones. Deciding either needs the image coordinates, which the list leaves out."))
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
