"""Luhmann, Nahbereichsphotogrammetrie (3rd ed. 2010), errata of chapter 2 (pp. 33–90).

Transcribed from the errata list of 11.7.2017 (``002_*`` of the course sources). The image
coordinates x', y' of the book are the symbols ``x, y`` here; object coordinates ``X, Y``.
Primed coefficients a'_i, b'_i, c'_i are ``ap_i, bp_i, cp_i``.
"""

from __future__ import annotations

import mpmath
import sympy as sp

from photolib.derive import adjustment, conic, plane
from photolib.errata._record import Evidence, VersionSpec, figure, formula, numbers_evidence

SRC = "002_b1d9e6507973e20d.txt (Luhmann errata list, 11.7.2017)"
x, y, X, Y = plane.x, plane.y, plane.X, plane.Y
a0, a1, a2, b0, b1, b2, c1, c2 = plane.a0, plane.a1, plane.a2, plane.b0, plane.b1, plane.b2, \
    plane.c1, plane.c2
ap0, ap1, ap2, bp0, bp1, bp2, cp1, cp2 = (plane.ap0, plane.ap1, plane.ap2, plane.bp0, plane.bp1,
                                          plane.bp2, plane.cp1, plane.cp2)


def _inverse_form(u, v):
    """The printed right-hand sides of 2.19 in the variables (u, v)."""
    den = a1 * b2 - a2 * b1 + (b1 * c2 - b2 * c1) * u + (a2 * c1 - a1 * c2) * v
    return sp.Matrix([(a2 * b0 - a0 * b2 + (b2 - b0 * c2) * u + (a0 * c2 - a2) * v) / den,
                      (a0 * b1 - a1 * b0 + (b0 * c1 - b1) * u + (a1 - a0 * c1) * v) / den])


def _primed_form(u, v):
    den = 1 + cp1 * u + cp2 * v
    return sp.Matrix([(ap0 + ap1 * u + ap2 * v) / den, (bp0 + bp1 * u + bp2 * v) / den])


def _forward():
    return sp.Matrix(plane.projective_forward())


def _object_of_image():
    fx, fy = plane.projective_forward()
    return {X: fx, Y: fy}


def _seg(p, q):
    return plane.segment(p, q)


def _cross_old(tA, tB, tC, tD):
    return (_seg(tA, tD) / _seg(tB, tD)) / (_seg(tA, tC) / _seg(tB, tC))


def _cross_new(tA, tB, tC, tD):
    return (_seg(tA, tB) / _seg(tB, tC)) / (_seg(tA, tD) / _seg(tC, tD))


def _invariance_evidence(ratio) -> Evidence:
    residual = plane.cross_ratio_invariance(ratio)
    if residual == 0:
        # a second, numeric look: different values of the two definitions at one point
        pts = dict(zip(plane.t_line, (0, 1, 3, 7)))
        return Evidence("right", "projectively invariant: λ(projected) − λ = 0 identically "
                        f"(value at t = 0, 1, 3, 7: {ratio(*plane.t_line).subs(pts)})")
    return Evidence("wrong", f"not invariant: λ(projected) − λ = {residual}")


def _t_text(falls: bool) -> Evidence:
    ok, (k, nu1, nu2, p1, p2) = adjustment.t_tail_monotone_in_dof()
    with mpmath.workdps(20):
        p5, p30, pinf = (adjustment.t_tail(2, n) for n in (5, 30, mpmath.inf))
    nums = (f"P(|T|>2): ν=5 {mpmath.nstr(p5, 5)}, ν=30 {mpmath.nstr(p30, 5)}, "
            f"normal {mpmath.nstr(pinf, 5)}")
    if not ok:
        return Evidence("not-checkable: tail probability not monotone on the grid", nums)
    if falls:
        return Evidence("wrong", "P rises as ν falls (grid k = 0.25..4, ν = 1..∞); " + nums,
                        counterexample={"k": 2, "nu": (5, 30)}, values=(p5, p30))
    return Evidence("right", "P(|T_ν|>k) decreases in ν at every grid point, smallest step "
                    f"at k={k}, ν {nu1}→{nu2}; " + nums)


OLD_286 = ("right-under-condition: A² = 1 (the conic scaled so that the coefficient of x² + y² "
           "is ±1; A = 1 and A = −1 both give the derived radius)")


def _old286() -> Evidence:
    """2.86 old: solve old² = derived² for A, then compare at each root and in general."""
    from photolib.symcheck import equivalent
    A, D, E, F = conic.A, conic.D, conic.E, conic.F
    old = sp.sqrt(D**2 + E**2 - A * F)
    derived = conic.circle_radius()
    radicand = D**2 + E**2 - A * F
    diff = sp.factor(sp.together(old**2 - derived**2))
    # roots of old² − derived² other than the zero radius (radicand 0, no real circle)
    roots = [rt for rt in sp.solve(diff, A) if sp.simplify(radicand.subs(A, rt)) != 0]
    dom = {A: (0.5, 2.0), D: (1.5, 3.0), E: (1.5, 3.0), F: (-2.0, 1.0)}
    general = equivalent(old, derived, symbols_domain=dom, time_budget=3.0, samples=8)
    at_root = {rt: equivalent(old.subs(A, rt), derived.subs(A, rt), time_budget=3.0).kind
               for rt in roots}
    if (sorted(roots) == [-1, 1] and general.kind == "not-equal"
            and set(at_root.values()) == {"equal"}):
        return Evidence(OLD_286, f"old² − derived² = {diff}: zero for a real circle iff "
                        "A² = 1 (SymPy solve: A = ±1); equal at A = 1 and A = −1, differs in "
                        "general",
                        general.counterexample, general.values)
    return Evidence("wrong", f"roots {roots}, general {general.kind}, at the roots {at_root}")


V2136 = ("right-under-condition: the plane's height at the origin is z1 (a1·x'1 + a2·y'1 = 0), "
         "e.g. point 1 at the origin (x'1 = y'1 = 0, coordinates reduced to P1) or a "
         "horizontal plane; old and corrected prints are identical")


def _m2136():
    """The printed matrix of 2.136 times (z1, z2, z3) (old and corrected alike)."""
    x2, y2, x3, y3 = conic.x2, conic.y2, conic.x3, conic.y3
    det = x2 * y3 - x3 * y2
    M = sp.Matrix([[det, 0, 0], [y2 - y3, y3, -y2], [x3 - x2, -x3, x2]])
    return M * sp.Matrix([conic.z1, conic.z2, conic.z3]) / det


def _plane_rows_2136():
    """Numeric rows (printed vs solved a0, a1, a2) for four configurations of P1, P2, P3."""
    import numpy as np
    cases = (("P1 at the origin, tilted plane", ((0, 0, 2), (3, -1, 9), (-2, 4, -6))),
             ("horizontal plane z = 5, P1 = (1, 2)", ((1, 2, 5), (3, 0, 5), (0, 4, 5))),
             ("z = 1 + 2x' − y', P1 = (1, 2) on its level line through the origin",
              ((1, 2, 1), (3, -1, 8), (-2, 4, -7))),
             ("tilted plane, P1 = (1, 2) elsewhere", ((1, 2, 3), (3, -1, 2), (-2, 4, 7))))
    subs_keys = (conic.x1, conic.y1, conic.z1, conic.x2, conic.y2, conic.z2, conic.x3,
                 conic.y3, conic.z3)
    rows = []
    for name, pts in cases:
        vals = dict(zip(subs_keys, [sp.Integer(v) for p in pts for v in p]))
        printed = [float(e) for e in _m2136().subs(vals)]
        solved = np.linalg.solve(np.array([[1.0, p[0], p[1]] for p in pts]),
                                 np.array([float(p[2]) for p in pts]))
        for k in range(3):
            rows.append((f"{name}: a{k}", printed[k], float(solved[k]), 1e-12))
    return rows


def _ev2136() -> Evidence:
    """2.136: printed − derived is (z1 − a0)·w, so equal exactly when a0 = z1."""
    from photolib.symcheck import equivalent
    printed, derived = _m2136(), conic.plane_through_points()
    d = conic.x2 * conic.y3 - conic.x3 * conic.y2
    w = sp.Matrix([d, conic.y2 - conic.y3, conic.x3 - conic.x2]) / d
    # rational functions: cancel over a common denominator is exact and bounded (no simplify)
    factor = all(sp.cancel(sp.together(e)) == 0
                 for e in printed - derived - (conic.z1 - derived[0]) * w)
    at_origin = equivalent(printed, derived, assumptions={conic.x1: 0, conic.y1: 0},
                           time_budget=3.0)
    # (0, 0, z1) on the plane: a0 = z1, solved for z1 (linear)
    z1_on = sp.solve(sp.Eq(derived[0], conic.z1), conic.z1)
    level = equivalent(printed, derived, assumptions={conic.z1: z1_on[0]}, time_budget=3.0) \
        if len(z1_on) == 1 else None
    general = equivalent(printed, derived, time_budget=3.0)
    ev = numbers_evidence(_plane_rows_2136())
    wrong_rows = [r for r in ev.table if not r[4]]
    if (factor and at_origin.kind == "equal-under-condition" and level is not None
            and level.kind == "equal-under-condition" and general.kind == "not-equal"
            and wrong_rows and all(r[0].startswith("tilted plane, P1 = (1, 2) elsewhere")
                                   for r in wrong_rows)):
        return Evidence(V2136, "printed − derived = (z1 − a0)·(1, (y'2 − y'3)/d, "
                        "(x'3 − x'2)/d) (SymPy cancel, exact): zero iff a0 = z1 ⇔ a1·x'1 + a2·y'1 = 0; "
                        "equal with x'1 = y'1 = 0 and with z1 := the plane's height at the "
                        "origin, differs in general (counterexample); the table: only the "
                        "last configuration differs",
                        general.counterexample, general.values, table=ev.table)
    return Evidence("wrong", f"factorisation {factor}, P1 at origin {at_origin.kind}, "
                    f"level line {None if level is None else level.kind}, general {general.kind}",
                    general.counterexample, general.values, table=ev.table)


def records():
    r = []
    r.append(formula(
        "luhmann:2.19", SRC + ", p. 33, formula 2.19", "inverse projective transformation",
        {"old": VersionSpec("wrong", expr=lambda: _inverse_form(x, y), claim="wrong",
                            target=_forward),
         "corrected": VersionSpec("right", expr=lambda: _inverse_form(X, Y), claim="right")},
        derivation=lambda: sp.Matrix([x, y]), given=_object_of_image,
        steps=("2.18: X = (a0 + a1x' + a2y')/(1 + c1x' + c2y'), Y likewise (homography, h33 = 1)",
               "clear the denominators: two equations linear in x', y'",
               "solve them (Cramer's rule, SymPy) for x', y' as functions of X, Y",
               "check: the printed right-hand side with X, Y := 2.18(x', y') gives back x', y'",
               "old print: read as X = f(x', y') it is compared with 2.18 itself"),
        note="Old print: x, X swapped (the inverse written as if it gave X). Corrected: right.",
    ))
    r.append(formula(
        "luhmann:2.20", SRC + ", p. 33, formula 2.20", "inverse projective transformation, "
        "normalised (primed coefficients)",
        {"old": VersionSpec("wrong", expr=lambda: _primed_form(x, y), claim="wrong",
                            target=_forward),
         "corrected": VersionSpec("right", expr=lambda: _primed_form(X, Y), claim="right")},
        derivation=lambda: sp.Matrix([x, y]),
        given=lambda: {**_object_of_image(), **plane.projective_inverse_primed()},
        steps=("inverse of 2.18 solved as in 2.19",
               "divide numerators and denominator by a1b2 − a2b1 (must be ≠ 0): "
               "a'0 = (a2b0 − a0b2)/(a1b2 − a2b1), …, c'2 = (a2c1 − a1c2)/(a1b2 − a2b1)",
               "the printed version with these a', b', c' and X, Y := 2.18(x', y') must give x', y'"),
        note="The primed coefficients are those of the inverse (derived); they exist iff "
             "a1·b2 − a2·b1 ≠ 0. The old print maps x' to X with the inverse's coefficients.",
    ))
    r.append(Record_cross())
    r.append(formula(
        "luhmann:2.86", SRC + ", p. 56, formula 2.86", "circle radius from the general conic",
        {"old": VersionSpec(OLD_286,
                            expr=lambda: sp.sqrt(conic.D**2 + conic.E**2 - conic.A * conic.F),
                            check=_old286, claim="wrong"),
         "corrected": VersionSpec("right", expr=lambda: sp.sqrt(
             (conic.D**2 + conic.E**2 - conic.A * conic.F) / conic.A**2), claim="right")},
        derivation=conic.circle_radius,
        domain=lambda: {conic.A: (0.5, 2.0), conic.D: (1.5, 3.0), conic.E: (1.5, 3.0),
                        conic.F: (-2.0, 1.0)},
        steps=("circle: A(x² + y²) + 2Dx + 2Ey + F = 0 (A ≠ 0)",
               "centre where the gradient vanishes: (−D/A, −E/A)",
               "g(x) = A|x − centre|² + g(centre), so r² = −g(centre)/A = (D² + E² − AF)/A²"),
        note="Sampled with D² + E² > AF (a real circle). The old print drops the 1/A²: it "
             "gives the radius exactly when A² = 1, i.e. for A = 1 and for A = −1 (a circle "
             "equation multiplied by −1), and for no other A.",
    ))
    r.append(formula(
        "luhmann:2.88", SRC + ", p. 57, formula 2.88 (note)", "circle observation equation "
        "with F = 1",
        {"printed": VersionSpec(
            "right-under-condition: F = 1, i.e. the conic divided by F ≠ 0; circles through "
            "the origin (F = 0) cannot be written so",
            expr=lambda: conic.A * (conic.xc**2 + conic.yc**2) + 2 * conic.D * conic.xc
            + 2 * conic.E * conic.yc + 1, condition={conic.F: 1},
            condition_text="F = 1, i.e. the conic divided by F ≠ 0; circles through the "
                           "origin (F = 0) cannot be written so", claim="right-under-condition")},
        derivation=conic.general_circle,
        steps=("general circle A(x² + y²) + 2Dx + 2Ey + F = 0",
               "printed φ(A, D, E) = −1 is the residual A(x² + y²) + 2Dx + 2Ey + 1",
               "equal to the general form only for F = 1; the conic at (0, 0) is F, "
               "so a circle through the origin has F = 0 and cannot be scaled to F = 1"),
    ))
    # 2.136 — old and corrected printed identically
    r.append(formula(
        "luhmann:2.136", SRC + ", p. 76, formula 2.136", "plane through three points",
        {"old": VersionSpec(V2136, expr=_m2136, check=_ev2136, claim="wrong"),
         "corrected": VersionSpec(V2136, expr=_m2136, check=_ev2136, claim="right")},
        derivation=conic.plane_through_points,
        steps=("plane z = a0 + a1x' + a2y' through P1, P2, P3: three linear equations",
               "solved by SymPy for a0, a1, a2 in general position",
               "the printed matrix has no x'1, y'1: row 1 gives a0 = z1, and rows 2, 3 make the "
               "printed plane pass through P2, P3 and (0, 0, z1)",
               "so printed − derived = (z1 − a0)·(1, (y'2 − y'3)/d, (x'3 − x'2)/d), "
               "d = x'2y'3 − x'3y'2 (SymPy): zero exactly when a0 = z1, i.e. "
               "a1·x'1 + a2·y'1 = 0"),
        note="The transcription shows the 'alte Fassung' and 'richtig' character for "
             "character identical: the erratum lists no visible change. Both are right "
             "exactly when the plane's height at the origin is z1 (a1·x'1 + a2·y'1 = 0): with "
             "P1 as origin (the intended reduction), but also for a horizontal plane or P1 on "
             "the plane's level line through the origin; with P1 elsewhere they give the "
             "plane through (0, 0, z1), P2, P3.",
    ))
    r.append(Record_t())
    r.append(figure("luhmann:p48-T11", SRC + ", p. 48, text", "rotation matrix inserted into "
                    "T11 instead of T12",
                    "the matrices T11, T12 of p. 48 are not printed in the errata list",
                    claim="right"))
    return r


def Record_cross():
    from photolib.errata._record import Record
    return Record(
        id="luhmann:2.21", source=SRC + ", p. 33, formula 2.21", item="cross ratio",
        kind="formula",
        specs={"old": VersionSpec("right", claim="wrong",
                                  expr=lambda: _cross_old(*plane.t_line),
                                  check=lambda: _invariance_evidence(_cross_old)),
               "corrected": VersionSpec("right", claim="right",
                                        expr=lambda: _cross_new(*plane.t_line),
                                        check=lambda: _invariance_evidence(_cross_new))},
        derivation=lambda: sp.Integer(0),
        steps=("points A, B, C, D on a line with signed coordinates t_A … t_D",
               "a central projection between lines is t ↦ (pt + q)/(rt + s)",
               "a definition of λ is valid iff λ(projected points) − λ(points) ≡ 0 (SymPy cancel)"),
        note="Both printings are projective invariants: the old one is 1/(A,B;C,D), the "
             "corrected one AB·CD/(BC·AD). They give different numbers for the same points, so "
             "a course must fix one (photolib uses the corrected, Rüger's); the erratum's "
             "'not arbitrary' is about consistency, not correctness.")


def Record_t():
    from photolib.errata._record import Record
    return Record(
        id="luhmann:p90-t-distribution", source=SRC + ", p. 90, last paragraph",
        item="t-distribution: tail probability versus degrees of freedom", kind="text",
        specs={"old": VersionSpec("wrong", claim="wrong", check=lambda: _t_text(True)),
               "corrected": VersionSpec("right", claim="right", check=lambda: _t_text(False))},
        steps=("P(|T_ν| > k) = I_{ν/(ν+k²)}(ν/2, 1/2) (regularised incomplete beta, mpmath)",
               "evaluated on k = 0.25 … 4 and ν = 1 … 1000, ∞ (normal limit erfc(k/√2))",
               "the probability decreases with ν everywhere on the grid"),
        note="'fällt mit abnehmender Anzahl der Freiheitsgrade' is wrong; 'steigt' is right "
             "(checked on a grid, not proved for all k).")
