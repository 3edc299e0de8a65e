"""Records changed or added after the independent audit of the catalogue, re-checked by
other routes (NumPy, photolib's DLT estimator, plain arithmetic; no SymPy derivation reused).
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from photolib import errata
from photolib.dlt import dlt_estimate
from photolib.errata import luhmann_dlt
from photolib.errata.cli import describe
from photolib.transforms._base import DegenerateGeometryError


def _rot_opk(w, p, k):
    cw, sw, cp, sp_, ck, sk = (math.cos(w), math.sin(w), math.cos(p), math.sin(p),
                               math.cos(k), math.sin(k))
    Rw = np.array([[1, 0, 0], [0, cw, -sw], [0, sw, cw]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    return Rw @ Rp @ Rk


def test_476_each_print_equals_one_reading_only():
    rec = errata.get("luhmann:4.76")
    assert all(v.startswith("not-checkable: notation") for v in rec.verdicts.values())
    vals = dict(xi=0.3, eta=-0.7, zeta=1.1, omega=0.2, phi=0.5, kappa=-0.4, kappa_i=0.9)
    syms = {s.name: s for e in rec.versions.values() for s in e.free_symbols}
    num = {k: np.array(e.subs({syms[n]: v for n, v in vals.items() if n in syms}).evalf(),
                       dtype=float) for k, e in rec.versions.items()}
    R = _rot_opk(vals["xi"], vals["eta"], vals["zeta"])
    with_kappa = R @ _rot_opk(vals["omega"], vals["phi"], vals["kappa"])
    with_kappa_i = R @ _rot_opk(vals["omega"], vals["phi"], vals["kappa_i"])
    assert np.allclose(num["corrected"], with_kappa) and not np.allclose(num["old"], with_kappa)
    assert np.allclose(num["old"], with_kappa_i) and not np.allclose(num["corrected"],
                                                                     with_kappa_i)
    for M in num.values():                                   # a rotation either way
        assert np.allclose(M.T @ M, np.eye(3)) and np.isclose(np.linalg.det(M), 1)


def test_example_48_corrected_is_only_the_old_scaled_by_c():
    rec = errata.get("luhmann:example-4.8")
    assert all(v.startswith("not-checkable: the image coordinates") for v in
               rec.verdicts.values())
    scaled = [z * (-60.2 / 64.0) for z in (3.88, 58.49)]
    assert np.allclose(scaled, [-3.6496, -55.0172], atol=1e-4)
    assert np.allclose(scaled, [-3.65, -55.02], atol=0.01)     # what the print shows
    assert "−3.6496 m, −55.017 m" in rec.verdicts["corrected"]


def test_example_37_recomputed_numbers():
    m, h, b, s_px = 125, 5000.0, 1200.0, 4e-3                 # mm
    s_z = (h / b) * m * s_px
    s_xy_old, s_xy_new = m * s_px / math.sqrt(2), m * s_px * math.sqrt(2)
    assert (round(s_z, 3), round(s_xy_old, 3), round(s_xy_new, 3)) == (2.083, 0.354, 0.707)
    rec = errata.get("luhmann:example-3.7")
    assert rec.verdicts["corrected"].startswith("not-checkable: empirical claim")
    assert rec.verdicts["old"].startswith("right-under-condition: x'1 and x'2 measured "
                                          "independently")
    assert "2.083 mm" in rec.note and "0.707 mm" in rec.note and "0.354 mm" in rec.note
    ev = rec.evaluate("corrected")
    assert {r[0]: round(r[2], 3) for r in ev.table} == {"s_Z_mm": 2.083, "s_XY_mm": 0.707}


def test_286_old_needs_a_squared_one():
    rec = errata.get("luhmann:2.86")
    assert rec.verdicts["old"].startswith("right-under-condition: A² = 1")
    D, E, F = 2.0, 1.7, -0.6

    def radius(A):                       # centre and radius by completing the square
        cx, cy = -D / A, -E / A
        return math.sqrt(cx**2 + cy**2 - F / A)

    old = math.sqrt(D**2 + E**2 - F * 1.0)
    for A in (1.0, -1.0):
        assert math.sqrt(D**2 + E**2 - A * F) == pytest.approx(radius(A), rel=1e-14)
    assert old != pytest.approx(radius(2.0), rel=1e-3)
    assert math.sqrt(D**2 + E**2 - 2.0 * F) != pytest.approx(radius(2.0), rel=1e-3)


def test_normal_case_xi_needs_no_y0():
    rec = errata.get("de-summary:normal-case-simplified")
    assert rec.verdicts["printed"].endswith("and Z0 = 0 (Y0 does not enter the ξ line)")
    spec = rec.specs["printed"]
    assert "Y0" not in {str(k) for k in spec.condition()}
    c, x0, X, Y, Z, X0 = 0.15, 0.01, 3.0, -2.0, -40.0, 1.0
    for Y0 in (0.0, 7.5, -3.0):                                # R = I, Z0 = 0, any Y0
        d = np.array([X - X0, Y - Y0, Z - 0.0])
        full = x0 - c * d[0] / d[2]                            # collinearity with R = I
        printed = x0 - c * 1.0 * (X - X0) / (1.0 * Z)
        assert printed == pytest.approx(full, rel=1e-14)
    d = np.array([X - X0, Y, Z - 2.0])                         # Z0 ≠ 0 breaks it
    assert x0 - c * (X - X0) / Z != pytest.approx(x0 - c * d[0] / d[2], rel=1e-6)


def test_table_33_and_549_notes():
    assert "inferred by matching" in errata.get("luhmann:table-3.3").note
    rec = errata.get("luhmann:5.49-h1")
    assert list(rec.specs) == ["old"] and "ambiguous" in rec.note
    # the text's values match the iterative row only in this column order
    row = [-0.0008, -0.0134, -0.0438, -0.0003, 0.2385]
    quoted = {"Rollei 6008": 0.8, "DCS 645M": 13.4, "DCS 460": 43.8, "JAI": 0.3, "Basler": 238}
    order = [min(range(5), key=lambda i: abs(abs(row[i]) * 1000 - q)) for q in quoted.values()]
    assert order == [0, 1, 2, 3, 4]


@pytest.mark.parametrize("rid", ["de-summary:pixel-resolution", "de-summary:exposure",
                                 "de-summary:gain", "de-summary:full-well"])
def test_text_records_labelled_as_readings(rid):
    rec = errata.get(rid)
    text = describe(rec)
    assert "reading (printed, the catalogue's reading of a sentence" in text
    assert "printed (printed)" not in text
    assert "catalogue's reading of the sentence" in rec.note
    assert list(rec.verdicts) == ["printed"]                   # JSON schema unchanged


def test_json_schema_unchanged_for_one_record():
    res = subprocess.run([sys.executable, "-m", "photolib", "errata", "--id", "de-summary:gain",
                          "--json"], capture_output=True, text=True, timeout=120)
    obj = json.loads(res.stdout)
    assert set(obj) == {"id", "source", "item", "verdicts", "note"}
    assert list(obj["verdicts"]) == ["printed"]


def _field(relief):
    return np.array([[float(v) for v in p] for p in luhmann_dlt.dlt_test_field(relief)])


def test_example_43_planar_field_rank_numpy():
    rec = errata.get("luhmann:example-4.3-planar")
    assert rec.verdicts == {"corrected": "right"}
    for relief, rank in ((0, 8), (5, 11), (200, 11)):
        P = _field(relief)
        A = np.zeros((32, 11))
        for k, (X, Y, Z, x, y) in enumerate(P):
            A[2 * k] = [X, Y, Z, 1, 0, 0, 0, 0, -x * X, -x * Y, -x * Z]
            A[2 * k + 1] = [0, 0, 0, 0, X, Y, Z, 1, -y * X, -y * Y, -y * Z]
        A /= np.linalg.norm(A, axis=0)
        assert np.linalg.matrix_rank(A, tol=1e-9) == rank, relief
    # the image points are the printed camera's: a 3-D field gives back the printed L
    P = _field(200)
    est = dlt_estimate(P[:, :3], P[:, 3:])
    assert np.allclose(est.L, luhmann_dlt.L_PRINTED, rtol=1e-8, atol=1e-12)
    with pytest.raises(DegenerateGeometryError, match="coplanar"):
        dlt_estimate(_field(0)[:, :3], _field(0)[:, 3:])


def test_dlt_test_field_rejects_bad_relief():
    with pytest.raises(ValueError, match="relief must be a non-negative number of mm, got -1"):
        luhmann_dlt.dlt_test_field(-1)


def test_rotation_2d_comment_readings_numpy():
    rec = errata.get("de-summary:rotation-2d-comment")
    assert rec.verdicts["printed"].startswith("right-under-condition: the stacked entries read "
                                              "row by row")
    t, x, y = 0.7, 1.3, -0.4
    c, s = math.cos(t), math.sin(t)
    lines_345_353 = np.array([x * c + y * s, y * c - x * s])   # the summary's own x', y'
    first, second = (c, s, -s, c), (c, -s, s, c)               # as printed, top to bottom
    rows = [np.array(e).reshape(2, 2) for e in (first, second)]
    cols = [M.T for M in rows]
    assert np.allclose(rows[0] @ [x, y], lines_345_353)
    assert not np.allclose(cols[0] @ [x, y], lines_345_353)
    for M, N in (rows, cols):
        assert np.allclose(N @ M, np.eye(2))


def test_profile_at_45_degrees():
    rec = errata.get("pl-notes:profile-dx-dy")
    assert rec.verdicts == {"printed": "wrong"}
    a = math.radians(45)
    assert math.isclose(10 * math.cos(a), 10 * math.sin(a))
    assert "45°, 225°" in rec.evaluate("printed").detail


def _printed_2136(P):
    """Luhmann 2.136 as printed (no x'1, y'1 in it), evaluated with NumPy."""
    (_, _, z1), (x2, y2, z2), (x3, y3, z3) = P
    det = x2 * y3 - x3 * y2
    M = np.array([[det, 0, 0], [y2 - y3, y3, -y2], [x3 - x2, -x3, x2]]) / det
    return M @ np.array([z1, z2, z3])


def test_2136_condition_is_the_height_at_the_origin_not_only_p1_at_the_origin():
    """The print is right exactly when a0 = z1 (a1·x'1 + a2·y'1 = 0), not only for P1 = 0."""
    rng = np.random.default_rng(2136)
    for _ in range(20):
        a = rng.uniform(-2, 2, 3)                               # z = a0 + a1x' + a2y'
        xy = rng.uniform(-10, 10, (3, 2))
        on_level = rng.uniform(-5, 5) * np.array([-a[2], a[1]])  # a1·x + a2·y = 0
        for p1, right in ((xy[0], False), (on_level, True), (np.zeros(2), True)):
            pts = np.vstack([p1, xy[1:]])
            P = np.column_stack([pts, a[0] + pts @ a[1:]])
            assert np.allclose(_printed_2136(P), a, atol=1e-9) == right
        flat = np.column_stack([xy, np.full(3, a[0])])            # horizontal: any P1
        assert np.allclose(_printed_2136(flat), [a[0], 0, 0], atol=1e-9)
    rec = errata.get("luhmann:2.136")
    for version in ("old", "corrected"):
        verdict = rec.verdicts[version]
        assert verdict.startswith("right-under-condition: the plane's height at the origin "
                                  "is z1 (a1·x'1 + a2·y'1 = 0)"), verdict
        assert "horizontal plane" in verdict
        assert [r[4] for r in rec.evaluate(version).table] == [True] * 9 + [False] * 3


def test_example_37_verdicts_follow_from_the_transcribed_relation():
    """The check compares the printed s_px'(s_x') with propagation; a swapped print flips it."""
    import sympy as sp

    from photolib.derive import stereo
    from photolib.errata import luhmann_ch3
    s_x = stereo.s_x
    assert luhmann_ch3._ev37(True, printed=s_x / sp.sqrt(2)).verdict == "wrong"
    assert luhmann_ch3._ev37(False, printed=s_x * sp.sqrt(2)).verdict == "right"
    rec = errata.get("luhmann:example-3.7")
    assert rec.evaluate("old").verdict == rec.specs["old"].verdict
    ev = rec.evaluate("corrected")
    assert ev.verdict == rec.specs["corrected"].verdict and ev.counterexample
    sx = float(next(iter(ev.counterexample.values())))
    # independent readings x'1, x'2 with σ = sx: σ(x'1 − x'2) by simulation, not SymPy
    rng = np.random.default_rng(37)
    sim = np.std(rng.normal(0, sx, 200_000) - rng.normal(0, sx, 200_000))
    assert sim == pytest.approx(math.sqrt(2) * sx, rel=0.01)
    assert float(rec.versions["corrected"].subs(s_x, sx)) == pytest.approx(sim / 2, rel=0.01)


def test_426_sign_rule_is_checked_on_example_43(monkeypatch):
    """The 4.26 check uses det R and r3·X0 of example 4.3; a broken sign rule makes it 'wrong'."""
    from photolib.derive import dlt as ddlt
    ev = luhmann_dlt._426_sign()
    assert ev.verdict == errata.get("luhmann:4.26").specs["printed"].verdict
    assert "r3·X0 = 1649.69 mm" in ev.detail and "D²·(L9² + L10² + L11²) = 1" in ev.detail
    # NumPy, independently: L < 0 gives det R > 0 here, and the object origin is in front
    L = np.array(luhmann_dlt.L_PRINTED)
    a1, a2, a3 = L[0:3], L[4:7], L[8:11]
    Ls = -1 / np.linalg.norm(a3)
    x0, y0 = Ls**2 * (a1 @ a3), Ls**2 * (a2 @ a3)
    cx, cy = np.sqrt(Ls**2 * (a1 @ a1) - x0**2), np.sqrt(Ls**2 * (a2 @ a2) - y0**2)
    R = np.column_stack([Ls * (x0 * a3 - a1) / cx, Ls * (y0 * a3 - a2) / cy, Ls * a3])
    X0 = np.linalg.solve(np.vstack([a1, a2, a3]), -np.array([L[3], L[7], 1.0]))
    assert np.linalg.det(R) > 0 and R[:, 2] @ X0 > 0
    assert R[:, 2] @ X0 == pytest.approx(1649.69, abs=0.01)
    real = ddlt.decompose

    def flipped(L, sign=-1):                                  # det R with the wrong sign
        out = dict(real(L, sign))
        out["det"] = -out["det"]
        return out
    monkeypatch.setattr(ddlt, "decompose", flipped)
    assert luhmann_dlt._426_sign().verdict == "wrong"
