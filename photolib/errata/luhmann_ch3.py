"""Luhmann errata of chapter 3: example 3.7, table 3.3 with the text of p. 163/164, figures.

Example 3.7 gives M_b = 1:125, h = 5 m, b = 1.2 m and s_px' = 4 µm; the results are not
printed in the errata list, so they are recomputed here from the inputs for both readings of
the relation between s_px' and s_x'.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import stereo
from photolib.errata._record import Evidence, Record, VersionSpec, figure

SRC = "002_b1d9e6507973e20d.txt (Luhmann errata list, 11.7.2017)"

#: printed inputs of example 3.7 (m, mm, µm as printed)
EX37 = {"m": 125, "h_m": 5.0, "b_m": 1.2, "s_px_um": 4.0}
#: table 3.3 (corrected): rows in mm; the header is empty in the source, the columns are
#: assigned Rollei 6008, DCS 645M, DCS 460, JAI, Basler by matching the text's values
TABLE33 = {"total": (0.0767, -0.2641, 0.2229, -0.0045, -0.5674),
           "iterative": (-0.0008, -0.0134, -0.0438, -0.0003, 0.2385)}
#: values quoted in the text of p. 164 (µm, magnitudes as printed, signs as printed)
TEXT33 = {"DCS 645M": (1, -13.4), "DCS 460": (2, -43.8), "Rollei 6008": (0, 0.8),
          "JAI": (3, 0.3), "Basler": (4, 238.0)}


def example_37(factor_name: str):
    """Recompute σ_XY and σ_Z (mm) of example 3.7 with ``s_px' = s_x'·factor``."""
    m, h, b, spx = EX37["m"], EX37["h_m"], EX37["b_m"], EX37["s_px_um"]
    derived_factor = stereo.parallax_sigma_independent() / stereo.s_x  # √2, by propagation
    factor = derived_factor if factor_name == "sqrt2" else 1 / derived_factor
    s_x_um = spx / float(factor)
    s_xy_mm = float(stereo.sigma_XY().subs({stereo.m: m, stereo.s_x: s_x_um})) / 1000
    s_z_mm = float(stereo.sigma_Z().subs({stereo.h: h, stereo.b: b, stereo.m: m,
                                         stereo.s_px: spx})) / 1000
    return {"s_x_um": s_x_um, "s_XY_mm": s_xy_mm, "s_Z_mm": s_z_mm, "factor": factor}


EX37_NEW = ("not-checkable: empirical claim about stereoscopic parallax measurement "
            "(s_px' = s_x'/√2 when both images are viewed at once); it contradicts "
            "σ(px') = √2·σ(x') for independent readings, and the example's results are not "
            "printed in the errata list")


def relation_37(old: bool):
    """The printed relation s_px' = f(s_x') of example 3.7: √2·s_x' (old) or s_x'/√2 (corrected)."""
    return stereo.s_x * sp.sqrt(2) if old else stereo.s_x / sp.sqrt(2)


def _ev37(old: bool, printed=None) -> Evidence:
    """Example 3.7: the printed relation compared with error propagation, then the numbers.

    ``printed`` defaults to the transcription :func:`relation_37`; the verdict follows from
    the comparison (the old relation must equal σ(px') = √2·σ(x'), the corrected must not).
    """
    from photolib.symcheck import equivalent
    printed = relation_37(old) if printed is None else printed
    v = equivalent(printed, stereo.parallax_sigma_independent(), time_budget=3.0)
    res = example_37("sqrt2" if old else "inv")
    nums = (f"s_x' = {res['s_x_um']:.3f} µm, σ_XY = {res['s_XY_mm']:.3f} mm, "
            f"σ_Z = {res['s_Z_mm']:.3f} mm")
    if old:
        if v.kind != "equal":
            return Evidence("wrong", f"s_px' = {printed} differs from σ(px') = √2·σ(x') of "
                            f"independent readings ({v.method})", v.counterexample, v.values)
        return Evidence("right-under-condition: x'1 and x'2 measured independently with "
                        "equal σ (law of error propagation of px' = x'1 − x'2)",
                        f"σ(px') = √2·σ(x') by propagation, equal to the print ({v.method}); "
                        + nums, table=[("s_Z_mm", None, res["s_Z_mm"], None, True)])
    if v.kind == "equal":
        return Evidence("right", f"s_px' = {printed} equals σ(px') = √2·σ(x') ({v.method})")
    indep = example_37("sqrt2")
    return Evidence(EX37_NEW, "s_px' = s_x'/√2 is an assumption about how a stereoscopic "
                    "observer measures, not a consequence of px' = x'1 − x'2; for independent "
                    f"readings σ(px') = √2·σ(x') (σ_XY = {indep['s_XY_mm']:.3f} mm; the print "
                    f"differs, {v.method}). With the assumption: " + nums,
                    v.counterexample, v.values,
                    table=[("s_Z_mm", None, res["s_Z_mm"], None, True),
                           ("s_XY_mm", None, res["s_XY_mm"], None, True)])


def _ev33_text() -> Evidence:
    rows, bad = [], []
    for name, (col, quoted) in TEXT33.items():
        table_um = TABLE33["iterative"][col] * 1000
        same_mag = abs(abs(table_um) - abs(quoted)) <= 0.5 + 1e-9
        same_sign = (table_um < 0) == (quoted < 0)
        rows.append((name, quoted, table_um, 0.5, same_mag and same_sign))
        if not same_sign:
            bad.append(f"{name}: text {quoted:+g} µm, table {table_um:+g} µm (sign dropped)")
    if all(r[4] for r in rows):
        return Evidence("right", "text values equal the table (mm → µm)", table=rows)
    if all(abs(abs(r[1]) - abs(r[2])) <= 0.5 + 1e-9 for r in rows):
        return Evidence("right-under-condition: text quotes magnitudes; "
                        + "; ".join(bad), "magnitudes agree to the rounding", table=rows)
    return Evidence("wrong", "; ".join(bad), table=rows)


def records():
    r = []
    r.append(Record(
        id="luhmann:example-3.7", source=SRC + ", p. 138, example 3.7",
        item="stereo accuracy: parallax σ from coordinate σ", kind="example",
        specs={"old": VersionSpec("right-under-condition: x'1 and x'2 measured independently "
                                  "with equal σ (law of error propagation of px' = x'1 − x'2)",
                                  check=lambda: _ev37(True), claim="wrong",
                                  expr=lambda: relation_37(True)),
               "corrected": VersionSpec(
                   EX37_NEW, check=lambda: _ev37(False), claim="right",
                   expr=lambda: relation_37(False))},
        derivation=stereo.parallax_sigma_independent,
        steps=("px' = x'1 − x'2; independent x'1, x'2 with σ s_x': σ(px') = √2·s_x' (propagation)",
               "σ_XY = m·s_x' with m = 125",
               "Z = −c·b/px': |dZ/dpx'| = Z²/(c·b) = (h/b)·m, so σ_Z = (h/b)·m·s_px' = 2.083 mm",
               "old (s_px' = √2·s_x'): s_x' = 2.83 µm, σ_XY = 0.354 mm; corrected "
               "(s_px' = s_x'/√2): s_x' = 5.66 µm, σ_XY = 0.707 mm"),
        note="Recomputed from the printed inputs: σ_Z = (h/b)·m·s_px' = 2.083 mm in both "
             "versions; σ_XY = m·s_x' = 0.354 mm with the old s_px' = √2·s_x' (s_x' = 2.83 "
             "µm) and 0.707 mm with the corrected s_px' = s_x'/√2 (s_x' = 5.66 µm). The "
             "results of the example are not in the errata list, so neither number can be "
             "compared with a print. The old relation follows from error propagation for "
             "independent readings; the corrected one is the list's remark that simultaneous "
             "stereoscopic viewing measures parallax better, an empirical claim."))
    r.append(Record(
        id="luhmann:table-3.3", source=SRC + ", p. 163/164, table 3.3 and text",
        item="iterative distortion correction: text versus table", kind="example",
        specs={"corrected": VersionSpec(
            "right-under-condition: text quotes magnitudes; Rollei 6008: text +0.8 µm, table "
            "-0.8 µm (sign dropped); JAI: text +0.3 µm, table -0.3 µm (sign dropped)",
            check=_ev33_text, claim="right")},
        steps=("table row 'Iterative Korrektur' in mm → µm",
               "compare with the values quoted in the text (DCS 645M −13.4, DCS 460 −43.8, "
               "Rollei 0.8, JAI 0.3, Basler 238 µm)"),
        note="The table header (the camera names) is empty in the transcription: the "
             "column-to-camera assignment (Rollei 6008, DCS 645M, DCS 460, JAI, Basler) is "
             "inferred by matching the values the text quotes, the only assignment they fit "
             "(Basler: 238.5 µm against the quoted 238, at the 0.5 µm rounding bound). The "
             "table values themselves, the 'Gesamteffekt' row included, need the cameras' "
             "distortion parameters and image positions, which are not printed: not "
             "recomputable. The text's '3-4 iterations' "
             "refers to Abb. 3.67a (a figure). Only the consistency of text and table is checked."))
    r.append(figure("luhmann:fig-3.45", SRC + ", p. 142, Abb. 3.45", "principal point versus "
                    "piercing point of the optical axis", "figure only", claim="right"))
    r.append(figure("luhmann:fig-3.52", SRC + ", p. 148, Abb. 3.52", "label Δr'",
                    "figure label only", claim="right"))
    r.append(figure("luhmann:fig-3.67b", SRC + ", p. 163, Abb. 3.67b", "curve of iterative "
                    "correction", "figure only; the curve is not in the errata text",
                    claim="right"))
    r.append(figure("luhmann:fig-3.74-3.75", SRC + ", p. 170, Abb. 3.74/3.75",
                    "frame-transfer sensor drawings", "figure only", claim="right"))
    return r
