"""Polish exercise notes (004_*): fiducial transformations and the bundle unknown count.

Symbols: x_s, y_s are the comparator coordinates x_s, y_s of the notes.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import adjustment, plane
from photolib.errata._record import Evidence, Record, VersionSpec, formula

SRC = "004_81219dec3a1f2881.txt (Polish exercise notes)"
xs, ys = plane.xs, plane.ys
a0, a1, a2, a3, b0, b1, b2, b3 = sp.symbols("a0 a1 a2 a3 b0 b1 b2 b3", real=True)
A = sp.symbols("A11 A12 A13 A21 A22 A23 A31 A32", real=True)
H = sp.Matrix(3, 3, sp.symbols("h11 h12 h13 h21 h22 h23 h31 h32 h33", real=True))


def _helmert_printed():
    return sp.Matrix([a0 + a1 * xs + b1 * ys, b0 + a1 * ys - b1 * xs])


def _bilinear_printed():
    return sp.Matrix([a0 + a1 * xs + a2 * ys + a3 * xs * ys, b0 + b1 * ys + b2 * xs + b2 * xs * ys])


def _bilinear_general():
    return sp.Matrix([a0 + a1 * xs + a2 * ys + a3 * xs * ys, b0 + b1 * ys + b2 * xs + b3 * xs * ys])


def _bilinear_evidence() -> Evidence:
    from photolib.symcheck import equivalent
    n_printed = plane.free_parameter_count(_bilinear_printed(), (a0, a1, a2, a3, b0, b1, b2))
    n_true = plane.free_parameter_count(plane.bilinear_from_corners(), plane.P)
    v = equivalent(_bilinear_printed(), _bilinear_general())
    if n_printed < n_true and v.kind == "not-equal":
        return Evidence("wrong", f"printed form has {n_printed} independent parameters, the "
                        f"bilinear map of a quadrilateral {n_true}; b2 appears twice (b3 "
                        "missing)", v.counterexample, v.values)
    return Evidence("right", f"{n_printed} parameters")


def _projective():
    den = A[6] * xs + A[7] * ys + 1
    return sp.Matrix([(A[0] * xs + A[1] * ys + A[2]) / den, (A[3] * xs + A[4] * ys + A[5]) / den])


def _bundle() -> Evidence:
    rows = []
    for images, points in ((2, 10), (12, 150), (1, 0)):
        printed = 6 * images + 3 * points
        rows.append((f"{images} images, {points} points", printed,
                     adjustment.bundle_unknowns(images, points), 0))
    ok = all(a == b for _, a, b, _ in rows)
    return Evidence("right-under-condition: interior orientation fixed (as the notes say); "
                    "every point with three unknown coordinates" if ok else "wrong",
                    "6 = dim of rigid motions (3 skew generators + 3 shifts), 3 per point",
                    table=[(n, a, b, t, a == b) for n, a, b, t in rows])


def records():
    out = []
    out.append(formula(
        "pl-notes:helmert", SRC + ", 'transformacja Hellmerta'", "4-parameter similarity "
        "(Helmert)", {"printed": VersionSpec("right", expr=_helmert_printed, claim="right")},
        derivation=lambda: plane.helmert(),
        given=lambda: {a1: plane.s_scale * sp.cos(plane.theta),
                       b1: -plane.s_scale * sp.sin(plane.theta)},
        steps=("similarity: s·R(θ)·(x_s, y_s) + (a0, b0) with the plane rotation of the course",
               "a1 = s·cos θ, b1 = −s·sin θ turns it into the printed form"),
        note="Any a1, b1 correspond to s = √(a1² + b1²), θ = atan2(−b1, a1)."))
    out.append(Record(
        id="pl-notes:bilinear", source=SRC + ", 'Transformację bilinearną'",
        item="bilinear transformation", kind="formula",
        specs={"printed": VersionSpec("wrong", expr=_bilinear_printed, check=_bilinear_evidence,
                                      claim="right")},
        derivation=plane.bilinear_from_corners,
        steps=("linear interpolation of four corners: a0 + a1 s + a2 t + a3 s t per coordinate",
               "eight independent coefficients (Jacobian rank 8)"),
        note="y = b0 + b1y_s + b2x_s + b2x_sy_s repeats b2; it must be b3·x_s·y_s."))
    out.append(formula(
        "pl-notes:projective", SRC + ", 'Transformację rzutową'", "projective transformation "
        "with A33 = 1",
        {"printed": VersionSpec("right-under-condition: homography normalised by h33 ≠ 0 "
                                "(A_ij = h_ij/h33)", expr=_projective,
                                condition=lambda: {A[i]: H[i // 3, i % 3] / H[2, 2]
                                                   for i in range(8)},
                                condition_text="homography normalised by h33 ≠ 0 "
                                               "(A_ij = h_ij/h33)", claim="right")},
        derivation=lambda: plane.homography_normalised(H).subs({plane.x: xs, plane.y: ys})))
    out.append(Record(
        id="pl-notes:affine", source=SRC + ", 'Transformację afiniczną'",
        item="affine transformation", kind="text",
        specs={"printed": VersionSpec("not-checkable: the formula is cut off after "
                                      "'x = a1 + a2xs + a3y...'", claim="right")},
        note="The claim that parallel lines stay parallel follows from the linear part."))
    out.append(Record(
        id="pl-notes:bundle-unknowns", source=SRC + ", 'METODA WIĄZEK'",
        item="unknowns = 6·images + 3·points", kind="text",
        specs={"printed": VersionSpec("right-under-condition: interior orientation fixed (as "
                                      "the notes say); every point with three unknown "
                                      "coordinates", check=_bundle, claim="right")}))
    return out
