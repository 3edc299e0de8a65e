"""Luhmann 4.26 (DLT decomposition) and example 4.3, recomputed from the printed L1..L11.

The printed L are rounded to six decimals; every recomputed quantity gets a tolerance from
that rounding: the largest change over ±0.5·10⁻⁶ in each L (linear bound by finite
differences), plus half a unit of the printed last digit.
"""

from __future__ import annotations

import mpmath
import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive import dlt
from photolib.errata._record import Evidence, Record, VersionSpec, formula, numbers_evidence

SRC = "002_b1d9e6507973e20d.txt (Luhmann errata list, 11.7.2017)"

#: example 4.3 (corrected print)
L_PRINTED = (0.025599, 0.000789, 0.000914, 10.341817, -0.000347, 0.025008, -0.008166,
             4.986816, 0.000082, -0.000239, -0.000551)
PRINTED = {"cx": (42.0688, 1e-4), "cy": (43.1747, 1e-4), "x0": (-3.7708, 1e-4),
           "y0": (3.8404, 1e-4), "X0": (-471.12, 0.01), "Y0": (318.14, 0.01),
           "Z0": (1604.96, 0.01), "omega": (-23.405, 0.001), "phi": (-7.767, 0.001),
           "kappa": (0.031, 0.001)}
R_PRINTED = ((0.990725, -0.000546, -0.135153), (0.066680, 0.917685, 0.393592),
             (0.118394, -0.397306, 0.909295))
L_SYM = sp.Symbol("L", real=True)


def recompute(L=L_PRINTED) -> dict:
    """All quantities of example 4.3 from the eleven L (det R > 0 fixes the sign of L)."""
    d = dlt.decompose_proper(L)
    w, p, k = dlt.opk_from_matrix(d["R"])
    out = {"cx": d["cx"], "cy": d["cy"], "x0": d["x0"], "y0": d["y0"], "X0": d["X0"][0],
           "Y0": d["X0"][1], "Z0": d["X0"][2], "omega": w, "phi": p, "kappa": k}
    for i in range(3):
        for j in range(3):
            out[f"r{i + 1}{j + 1}"] = d["R"][i, j]
    out["L_sign"] = d["D"]
    return out


def rounding_tolerance() -> dict:
    """Worst-case change of each quantity over ±0.5e-6 in every printed L (linear bound)."""
    base = recompute()
    tol = {k: mpmath.mpf(0) for k in base}
    for i in range(11):
        Lp = list(L_PRINTED)
        Lp[i] += 0.5e-6
        moved = recompute(Lp)
        for key in tol:
            tol[key] += abs(moved[key] - base[key])
    return tol


def _ev43() -> Evidence:
    got, tol = recompute(), rounding_tolerance()
    rows = [(k, v, got[k], tol[k] + t) for k, (v, t) in PRINTED.items()]
    rows += [(f"r{i + 1}{j + 1}", R_PRINTED[i][j], got[f"r{i + 1}{j + 1}"],
              tol[f"r{i + 1}{j + 1}"] + 5e-7) for i in range(3) for j in range(3)]
    return numbers_evidence(rows, reason_bad=None)


def _426_expr():
    L1, L9 = dlt.Ls[0], dlt.Ls[8]
    return L_SYM * (col.x0 * L9 - L1) / dlt.cx


def _426_target():
    """r11 from the DLT of a general R, with L := D = −r3·X0 (the denominator constant)."""
    return col.r[0]


def _426_given():
    Lval = dlt.dlt_from_orientation()
    sub = dict(zip(dlt.Ls, Lval))
    R = col.rotation_symbols()
    D = -(R[:, 2].T * sp.Matrix([col.X0, col.Y0, col.Z0]))[0]
    return {**sub, L_SYM: D}


def _426_sign() -> Evidence:
    """Is L = −1/√(L9² + L10² + L11²) the sign that gives det R = +1 in example 4.3?"""
    from photolib.symcheck import equivalent
    form = equivalent(_426_expr().subs(_426_given()), _426_target(), time_budget=3.0)
    if form.kind != "equal":
        return Evidence("wrong", "r11 = L(x'0·L9 − L1)/c_x does not hold with L = −r3·X0",
                        form.counterexample, form.values)
    neg, pos = dlt.decompose(L_PRINTED, -1), dlt.decompose(L_PRINTED, +1)
    return Evidence("right-under-condition: L = −1/√(L9²+L10²+L11²) only when "
                    "r3·X0 > 0; in general sign(L) must give det R = +1 (the added note)",
                    "r11 form equal to the derivation with L = −r3·X0; "
                    f"example 4.3: det R = {mpmath.nstr(neg['det'], 6)} with L < 0, "
                    f"{mpmath.nstr(pos['det'], 6)} with L > 0",
                    values=(neg["det"], pos["det"]))


def records():
    r = []
    r.append(formula(
        "luhmann:4.26", SRC + ", p. 251, formula 4.26", "DLT: r11 from L and the sign of L",
        {"printed": VersionSpec(
            "right-under-condition: L = −1/√(L9²+L10²+L11²) only when r3·X0 > 0; in general "
            "sign(L) must give det R = +1 (the added note)",
            expr=_426_expr, claim="right-under-condition", check=_426_sign)},
        derivation=_426_target, given=_426_given,
        steps=("collinearity with c_x, c_y: x' = x'0 − c_x·kx/N, kx = r1·(X − X0), N = r3·(X − X0)",
               "divide by the constant D = −r3·X0 of the denominator: L9..L11 = r3/D, "
               "L1..L3 = (x'0·r3 − c_x·r1)/D",
               "so r11 = D(x'0·L9 − L1)/c_x and |D| = 1/√(L9² + L10² + L11²); the sign of D "
               "is sign(−r3·X0), fixed by det R = +1"),
        note="The form r11 = L(x'0L9 − L1)/c_x is right with L = D (checked symbolically for a "
             "general R); the printed sign of L is a special case."))
    r.append(Record(
        id="luhmann:example-4.3", source=SRC + ", p. 253, example 4.3",
        item="DLT parameters and their decomposition", kind="example",
        specs={"old": VersionSpec("not-checkable: the old DLT parameters are not printed in "
                                  "the errata list", claim="wrong"),
               "corrected": VersionSpec("wrong", check=_ev43, claim="right")},
        steps=("decompose the printed L1..L11: x'0 = L²(L1L9 + L2L10 + L3L11), "
               "c_x² = L²(L1² + L2² + L3²) − x'0², likewise y'0, c_y with L5..L7",
               "R columns r1 = L(x'0·L9..11 − L1..3)/c_x, r2 likewise, r3 = L·L9..11, "
               "sign of L from det R > 0",
               "X0 from [L1 L2 L3; L5 L6 L7; L9 L10 L11]·X0 = −(L4, L8, 1)",
               "ω = atan2(−r23, r33), φ = asin r13, κ = atan2(−r12, r11)",
               "tolerance: rounding of the printed L (±0.5e-6) propagated, plus half a digit"),
        note="From the printed L: x'0 = +3.829 mm and y'0 = −4.098 mm (printed −3.7708 and "
             "+3.8404): opposite signs, and |y'0| is 0.26 mm off where the rounding of L moves "
             "it by at most ±0.05 mm (|x'0|: 0.058 mm off, ±0.046 mm). c_x, c_y, X0, R and "
             "ω, φ, κ agree within the rounding of L. The DLT R "
             "is not orthogonal (r1·r2 ≈ 0.0137): the DLT has a shear parameter."))
    return r
