"""The exercises of chapter 07, judged in this process by calling the registry directly.

As ``test_chapter_exercises.py`` does for 04-06: the reference answer is accepted, the wrong
answer of every declared mistake is recognised with that mistake's hint, students get
different variants, functions are judged on hidden inputs and an untouched answer is not
answered. The references themselves are checked against independent routes (closed forms
and the library's cross ratio) below.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from photolib.grading.exercises import ch07_plane_transformations as ch07
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

from .chapter_checks import ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch07.EXERCISES
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


def _by_id(exercise_id):
    return next(ex for ex in EXERCISES if ex.id == exercise_id)


class TestChapter07(ChapterChecks):
    module = ch07
    chapter_name = "07-plane-transformations"
    kinds = {"number", "array", "expression", "function"}
    students = STUDENTS
    variant_fallback = tuple(f"s{i}" for i in range(50))
    scalar_cases = False     # homography-function and map-points-function take point lists


def test_the_quadrant_mistake_applies_to_some_student():
    ex = _by_id("plane.helmert-angle")
    applied = [sid for sid in (f"s{i}" for i in range(40))
               if ex.mistakes[2].wrong(parameters_for(ex, sid)) is not None]
    assert applied


@pytest.mark.parametrize("ex", [_by_id("plane.bilinear-function")], ids=lambda ex: ex.id)
def test_functions_are_judged_on_hidden_inputs(ex):
    # a function right on the public inputs only is not accepted (the hidden inputs differ:
    # ChapterChecks.test_hidden_inputs_differ_from_the_public_ones)
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    ref = ex.reference(params)
    public_set = {tuple(c) for c in public}

    def cheat(x, y):
        out = ref(x, y)
        return out if (float(x), float(y)) in public_set else out + 1.0
    assert _judge(ex, STUDENTS[0], cheat).status == "wrong"


# -- the references, by independent routes -------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_helmert_reference_by_complex_numbers(sid):
    # X + iY = (a0 + i b0) + (a1 + i b1)(x + i y): two points determine it directly
    p = parameters_for(_by_id("plane.helmert-two-points"), sid)
    z = [complex(*q) for q in p["src"]]
    w = [complex(*q) for q in p["dst"]]
    k = (w[1] - w[0]) / (z[1] - z[0])
    t = w[0] - k * z[0]
    expected = [t.real, t.imag, k.real, k.imag]
    np.testing.assert_allclose(ch07._helmert_reference(p), expected, rtol=0, atol=1e-7)


@pytest.mark.parametrize("sid", STUDENTS)
def test_helmert_angle_reference_by_complex_argument(sid):
    p = parameters_for(_by_id("plane.helmert-angle"), sid)
    alpha = np.angle(complex(p["a1"], p["b1"])) % (2 * math.pi)
    assert math.isclose(ch07._angle_gon(p), alpha * 200 / math.pi, abs_tol=1e-9)
    assert 0.0 <= ch07._angle_gon(p) < 400.0


@pytest.mark.parametrize("sid", STUDENTS)
def test_projective_reference_by_dlt_null_space(sid):
    # homography from the 4 point pairs as the null vector of the 8×9 DLT matrix
    p = parameters_for(_by_id("plane.projective-point"), sid)
    rows = []
    for (x, y), (X, Y) in zip(p["img"], p["obj"]):
        rows.append([x, y, 1, 0, 0, 0, -X * x, -X * y, -X])
        rows.append([0, 0, 0, x, y, 1, -Y * x, -Y * y, -Y])
    h = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    v = h @ [*p["P"], 1.0]
    np.testing.assert_allclose(ch07._projective_reference(p), v[:2] / v[2], atol=1e-7)


@pytest.mark.parametrize("sid", STUDENTS)
def test_cross_ratio_reference_keeps_the_library_cross_ratio(sid):
    from photolib.transforms import cross_ratio
    p = parameters_for(_by_id("plane.cross-ratio"), sid)
    s_D = ch07._cross_reference(p)
    assert s_D > p["sC"]
    assert math.isclose(cross_ratio(0.0, p["sB"], p["sC"], s_D),
                        cross_ratio(p["a"], p["b"], p["c"], p["d"]), rel_tol=1e-12)


@pytest.mark.parametrize("point", ["A", "B", "C", "D"])
def test_solved_cross_ratio_reproduces_lambda(point):
    import sympy as sp
    sol = ch07._solved_reference({"point": point})
    values = dict(zip(sp.symbols("t_A t_B t_C t_D"), (0.3, 1.7, 4.1, 9.2)))
    lam = ((1.7 - 0.3) * (9.2 - 4.1)) / ((4.1 - 1.7) * (9.2 - 0.3))
    names = {s.name: s for s in sol.free_symbols}
    subs = {names[s.name]: v for s, v in values.items() if s.name in names}
    subs[names["lam"]] = lam
    assert f"t_{point}" not in names
    assert math.isclose(float(sol.subs(subs)), values[sp.Symbol(f"t_{point}")], rel_tol=1e-12)


@pytest.mark.parametrize("sid", STUDENTS)
def test_fiducial_reference_by_normal_equations(sid):
    p = parameters_for(_by_id("plane.fiducial-affine"), sid)
    pix, cal = np.array(p["pix"]), np.array(p["cal"])
    A = np.column_stack([np.ones(4), pix])
    N = A.T @ A
    coef = np.linalg.solve(N, A.T @ cal)          # (3, 2): x' and y' columns
    expected = np.array([1.0, *p["P"]]) @ coef
    np.testing.assert_allclose(ch07._fiducial_reference(p), expected, atol=1e-7)
    # and the result is a point inside the format, in mm
    assert np.all(np.abs(expected) < 110.0)


def test_bilinear_printed_hint_repeats_the_x_coefficient():
    p = parameters_for(_by_id("plane.bilinear-function"), STUDENTS[0])
    wrong = ch07._printed.wrong(p)
    x, y = 120.0, 340.0
    X, Y = wrong(x, y)
    assert math.isclose(X, p["a0"] + p["a1"] * x + p["a2"] * y + p["a3"] * x * y)
    assert math.isclose(Y, p["b0"] + p["b1"] * x + p["b2"] * y + p["b1"] * x * y)


# -- answers of a careful student are accepted, the mistakes keep their hints ----------------

def _helmert_complex(src, dst):
    z = [complex(*q) for q in src]
    w = [complex(*q) for q in dst]
    k = (w[1] - w[0]) / (z[1] - z[0])
    t = w[0] - k * z[0]
    return np.array([t.real, t.imag, k.real, k.imag])


@pytest.mark.parametrize("sid", STUDENTS)
def test_helmert_from_opencv_or_rounded_is_accepted(sid):
    import cv2
    ex = _by_id("plane.helmert-two-points")
    p = parameters_for(ex, sid)
    M, _ = cv2.estimateAffinePartial2D(np.array(p["src"]), np.array(p["dst"]))
    assert _judge(ex, sid, np.array([M[0, 2], M[1, 2], M[0, 0], M[1, 0]])).correct
    exact = _helmert_complex(p["src"], p["dst"])
    rounded = [round(float(v), n) for v, n in zip(exact, (3, 3, 7, 7))]   # to 1 mm and 1e-7
    assert _judge(ex, sid, np.array(rounded)).correct
    assert _judge(ex, sid, exact.astype(np.float32)).correct


@pytest.mark.parametrize("sid", STUDENTS)
def test_helmert_mistakes_keep_their_hints(sid):
    ex = _by_id("plane.helmert-two-points")
    p = parameters_for(ex, sid)
    exact = _helmert_complex(p["src"], p["dst"])
    assert _judge(ex, sid, _helmert_complex(p["dst"], p["src"])).mistake == "swapped"
    assert _judge(ex, sid, exact * [1, 1, 1, -1]).mistake == "sign-b1"
    assert _judge(ex, sid, exact * [1e3, 1e3, 1, 1]).status == "wrong"      # a0, b0 in mm
    # the tolerance of a1, b1 stays far below a scale error of 1e-4 (100 ppm)
    assert _judge(ex, sid, exact * [1, 1, 1 + 1e-4, 1 + 1e-4]).status == "wrong"


def _cross_by_1d_homography(p):
    """s_D from the 1-D projective map t = (α s + β)/(γ s + 1) fitted through A, B, C."""
    s = np.array([0.0, p["sB"], p["sC"]])
    t = np.array([p["a"], p["b"], p["c"]])
    alpha, beta, gamma = np.linalg.solve(np.column_stack([s, np.ones(3), -t * s]), t)
    return (p["d"] - beta) / (alpha - gamma * p["d"])


@pytest.mark.parametrize("sid", STUDENTS)
def test_cross_ratio_rounded_to_a_millimetre_is_accepted(sid):
    ex = _by_id("plane.cross-ratio")
    p = parameters_for(ex, sid)
    s_D = _cross_by_1d_homography(p)
    assert _judge(ex, sid, round(float(s_D), 3)).correct
    assert _judge(ex, sid, float(np.float32(s_D))).correct
    # the simple ratio (affine) keeps its hint; 10 cm off is wrong
    affine = (p["d"] - p["a"]) / (p["b"] - p["a"]) * p["sB"]
    assert _judge(ex, sid, affine).mistake == "affine-ratio"
    assert _judge(ex, sid, float(s_D) + 0.1).status == "wrong"


# -- the new references, by independent routes ----------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_fiducial_centroid_reference_by_scipy(sid):
    from scipy import ndimage
    p = parameters_for(_by_id("plane.fiducial-centroid"), sid)
    w = np.maximum(np.array(p["patch"], float) - p["background"], 0.0)
    row, col = ndimage.center_of_mass(w)
    np.testing.assert_allclose(ch07._mark_reference(p), np.add(p["origin"], [col, row]),
                               atol=1e-9)
    # the step 2 parameters carry step 1's correct result, rounded as printed
    p2 = parameters_for(_by_id("plane.fiducial-affine"), sid)
    np.testing.assert_allclose(p2["pix"][0], ch07._mark_reference(p), atol=0.005 + 1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_fiducial_sigma0_reference_by_normal_equations(sid):
    p = parameters_for(_by_id("plane.fiducial-sigma0"), sid)
    pix, cal = np.array(p["pix"]) * [1.0, -1.0], np.array(p["cal"])
    A = np.column_stack([np.ones(4), pix])
    coef = np.linalg.lstsq(A, cal, rcond=None)[0]
    v = A @ coef - cal
    assert ch07._sigma0_um(p) == pytest.approx(1000 * np.sqrt(np.sum(v ** 2) / (8 - 6)),
                                                rel=1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_homography_function_reference_by_eigenvector_and_opencv(sid):
    import cv2
    ex = _by_id("plane.homography-function")
    p = parameters_for(ex, sid)
    clean, noisy, degenerate = ex.cases(rng_for(sid, ex.id, "public"), p)
    ref = ex.reference(p)
    # four pairs: the exact solution, as OpenCV's getPerspectiveTransform
    H4 = cv2.getPerspectiveTransform(np.float32(clean[0]), np.float32(clean[1]))
    np.testing.assert_allclose(ref(*clean), H4, rtol=1e-4, atol=1e-6)
    # eight noisy pairs: the normalised linear solution as the eigenvector of AᵀA
    src, dst = np.array(noisy[0]), np.array(noisy[1])
    Ts, Td = ch07._hartley(src), ch07._hartley(dst)
    u = src @ Ts[:2, :2].T + Ts[:2, 2]
    U = dst @ Td[:2, :2].T + Td[:2, 2]
    rows = []
    for (x, y), (X, Y) in zip(u, U):
        rows += [[x, y, 1, 0, 0, 0, -X * x, -X * y, -X], [0, 0, 0, x, y, 1, -Y * x, -Y * y, -Y]]
    A = np.array(rows)
    h = np.linalg.eigh(A.T @ A)[1][:, 0]
    H = np.linalg.inv(Td) @ h.reshape(3, 3) @ Ts
    np.testing.assert_allclose(ref(*noisy), H / H[2, 2], rtol=1e-7, atol=1e-9)
    with pytest.raises(ValueError, match="collinear"):
        ref(*degenerate)


@pytest.mark.parametrize("sid", STUDENTS)
def test_map_points_reference_by_opencv(sid):
    import cv2
    ex = _by_id("plane.map-points-function")
    p = parameters_for(ex, sid)
    cases = ex.cases(rng_for(sid, ex.id, "public"), p)
    for H, pts in cases[:2]:
        cv = cv2.perspectiveTransform(np.array(pts, float)[None], np.array(H, float))[0]
        np.testing.assert_allclose(ch07._map_checked(H, pts), cv, rtol=1e-12, atol=1e-9)
    with pytest.raises(ValueError, match="singular"):
        ch07._map_checked(*cases[2])


@pytest.mark.parametrize("sid", STUDENTS)
def test_church_scenario_references_by_null_space_and_line_coordinates(sid):
    p = parameters_for(_by_id("plane.church-homography"), sid)
    rows = []
    for (x, y), (X, Y) in zip(p["img"], p["obj"]):
        rows += [[x, y, 1, 0, 0, 0, -X * x, -X * y, -X], [0, 0, 0, x, y, 1, -Y * x, -Y * y, -Y]]
    h = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    np.testing.assert_allclose(ch07._church_H(p), h / h[2, 2], rtol=1e-7,
                               atol=1e-9 * np.abs(h / h[2, 2]).max())
    # step 2 carries step 1's correct H
    p2 = parameters_for(_by_id("plane.church-point"), sid)
    np.testing.assert_allclose(p2["H"], ch07._church_H(p2), rtol=1e-12, atol=1e-15)
    # step 3: λ from the positions along the line through the outer points
    P = np.array(p["line_pts"])
    axis = (P[-1] - P[0]) / np.linalg.norm(P[-1] - P[0])
    a, b, c, d = (P - P.mean(axis=0)) @ axis
    lam = (b - a) * (d - c) / ((c - b) * (d - a))
    assert ch07._church_lambda(p) == pytest.approx(lam, abs=ch07._church_lambda_atol(p)[1])
