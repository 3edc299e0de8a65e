"""The exercises of chapter 11 (image measurement), judged as the grader does.

The same checks as for chapters 04-08 (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), plus checks of the references by an independent route: SymPy derivatives and
solutions, SciPy's ``center_of_mass`` and finite differences of the LSM model.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy import ndimage

from photolib.grading.exercises import ch11_image_measurement as ch11
from photolib.grading.notebook import parameters_for

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch11.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


# -- the same checks as for chapters 04-08 --------------------------------------------------------

class TestChapter11(ChapterChecks, BatchGradedChecks):
    module = ch11
    chapter_name = "11-image-measurement"
    kinds = {"number", "array", "function", "expression"}
    students = STUDENTS
    scalar_cases = False            # im.weighted-centroid and im.lsm-step take image windows
    grade_timeout = 120


def test_a_slightly_wrong_function_is_wrong_without_a_hint():
    ex = BY_ID["im.lsm-row"]
    f = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], lambda *a: f(*a) + 0.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_log_value_is_the_sympy_laplacian(sid):
    p = parameters_for(BY_ID["im.log-value"], sid)
    x, y, s = sp.symbols("x y sigma", positive=True)
    G = sp.exp(-(x**2 + y**2) / (2 * s**2)) / (2 * sp.pi * s**2)
    lap = sp.diff(G, x, 2) + sp.diff(G, y, 2)
    # evaluate off the axis: rotation invariance is part of the check
    a = p["r"] / math.sqrt(2)
    assert ch11._log_value(p) == pytest.approx(float(lap.subs({x: a, y: a, s: p["sigma"]})), rel=1e-12)


@pytest.mark.parametrize("sid", STUDENTS)
def test_moment_p1_solves_the_three_moment_equations(sid):
    p = parameters_for(BY_ID["im.moment-p1"], sid)
    g = np.repeat(np.array(p["grey"], float), p["counts"])
    m = [sp.Rational(int(np.sum(g.astype(np.int64) ** i)), len(g)) for i in (1, 2, 3)]
    q, h1, h2 = sp.symbols("q h1 h2", real=True)
    sols = sp.solve([q * h1**i + (1 - q) * h2**i - mi for i, mi in zip((1, 2, 3), m)],
                    [q, h1, h2], dict=True)
    good = [sol for sol in sols if sol[h1] < sol[h2]]
    assert len(good) == 1
    assert ch11._p1(p) == pytest.approx(float(good[0][q]), rel=1e-10)
    assert ch11._p1_printed(p) is not None and abs(ch11._p1_printed(p) - ch11._p1(p)) > 1e-3


@pytest.mark.parametrize("sid", STUDENTS)
def test_circle_points_satisfy_the_conic(sid):
    p = parameters_for(BY_ID["im.circle-conic"], sid)
    xc, yc, r = ch11._circle(p)
    t = np.linspace(0, 2 * np.pi, 7)
    x, y = xc + r * np.cos(t), yc + r * np.sin(t)
    conic = p["A"] * (x**2 + y**2) + 2 * p["D"] * x + 2 * p["E"] * y + p["F"]
    np.testing.assert_allclose(conic, 0.0, atol=1e-9 * max(1.0, abs(p["F"])))


@pytest.mark.parametrize("sid", STUDENTS)
def test_centroid_agrees_with_scipy_center_of_mass(sid):
    p = parameters_for(BY_ID["im.centroid"], sid)
    w = np.maximum(np.array(p["patch"], float) - p["t"], 0.0)
    row, col = ndimage.center_of_mass(w)
    np.testing.assert_allclose(ch11._centroid(p), [col, row], atol=1e-12)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_lsm_row_is_the_derivative_of_the_model(sid):
    """∂/∂q of r0 + r1·g(a0 + a1x + a2y, b0 + b1x + b2y) at the start values, analytic g."""
    p = parameters_for(BY_ID["im.lsm-row"], sid)

    def gfun(c, r):
        return 100 + 30 * np.sin(c / 3.0) * np.cos(r / 5.0) + 0.2 * c * r

    x, y, h = 1.7, -2.3, 1e-6
    q0 = np.array([40.0, 1, 0, 35.0, 0, 1, p["r0"], p["r1"]])

    def model(q):
        return q[6] + q[7] * gfun(q[0] + q[1] * x + q[2] * y, q[3] + q[4] * x + q[5] * y)

    c, r = 40.0 + x, 35.0 + y
    g = gfun(c, r)
    gx = (gfun(c + h, r) - gfun(c - h, r)) / (2 * h)
    gy = (gfun(c, r + h) - gfun(c, r - h)) / (2 * h)
    fd = [(model(q0 + h * e) - model(q0 - h * e)) / (2 * h) for e in np.eye(8)]
    np.testing.assert_allclose(ch11._lsm_reference(p)(x, y, g, gx, gy), fd, rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("sid", STUDENTS)
def test_conic_centre_is_where_the_gradient_vanishes(sid):
    """Numerically: a conic with that xy coefficient, its centre by np.linalg.solve."""
    p = parameters_for(BY_ID["im.conic-centre"], sid)
    expr = ch11._conic_centre(p)
    rng = np.random.default_rng(len(sid))
    a, c = rng.uniform(0.5, 2.0, 2) * abs(p["b"])  # 4ac − b² > 0: an ellipse
    d, e, f = rng.uniform(-5, 5, 3)
    centre = np.linalg.solve([[2 * a, p["b"]], [p["b"], 2 * c]], [-d, -e])
    names = {s.name: s for s in expr.free_symbols}
    value = float(expr.subs({names[k]: v for k, v in zip("acdef", (a, c, d, e, f)) if k in names}))
    assert value == pytest.approx(centre[0 if p["coordinate"] == "x_c" else 1], rel=1e-10)


def test_conic_centre_accepts_a_formula_string():
    ex = BY_ID["im.conic-centre"]
    sid = next(s for s in (f"s{i}" for i in range(200))
               if parameters_for(ex, s)["coordinate"] == "x_c" and parameters_for(ex, s)["b"] == 3)
    assert _judge(ex, sid, "(3*e - 2*c*d)/(4*a*c - 9)").status == "correct"



# -- fairness of the audit (float32, SciPy, rounded answers) --------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_log_value_accepts_four_significant_digits(sid):
    ex = BY_ID["im.log-value"]
    p = parameters_for(ex, sid)
    q = p["r"] ** 2 / (2 * p["sigma"] ** 2)
    value = -(1 - q) * math.exp(-q) / (math.pi * p["sigma"] ** 4)
    assert _judge(ex, sid, float(f"{value:.4g}")).status == "correct"
    assert _judge(ex, sid, -(1 - q) * math.exp(-q)).mistake == "normalisation"


@pytest.mark.parametrize("sid", STUDENTS)
def test_moment_p1_accepts_five_decimals(sid):
    ex = BY_ID["im.moment-p1"]
    p = parameters_for(ex, sid)
    g = np.repeat(np.array(p["grey"], float), p["counts"])
    m1, m2, m3 = (np.mean(g**k) for k in (1, 2, 3))
    s = (m3 - 3 * m1 * m2 + 2 * m1**3) / (m2 - m1**2) ** 1.5
    p1 = 0.5 * (1 + s / math.sqrt(4 + s * s))
    assert _judge(ex, sid, round(p1, 5)).status == "correct"
    assert _judge(ex, sid, 1 - p1).mistake == "sign"


@pytest.mark.parametrize("sid", STUDENTS)
def test_circle_conic_accepts_float32_and_four_decimals(sid):
    ex = BY_ID["im.circle-conic"]
    p = parameters_for(ex, sid)
    f = np.float32
    A, D, E, F = f(p["A"]), f(p["D"]), f(p["E"]), f(p["F"])
    xc, yc = -D / A, -E / A
    v32 = np.array([xc, yc, np.sqrt(xc * xc + yc * yc - F / A)], np.float32)
    assert _judge(ex, sid, v32).status == "correct"
    assert _judge(ex, sid, np.round(v32.astype(float), 4)).status == "correct"


@pytest.mark.parametrize("sid", STUDENTS)
def test_centroid_accepts_float32_and_scipy(sid):
    ex = BY_ID["im.centroid"]
    p = parameters_for(ex, sid)
    w = np.maximum(np.array(p["patch"], np.float32) - np.float32(p["t"]), 0)
    row, col = ndimage.center_of_mass(w)
    rows, cols = np.indices(w.shape)
    v32 = np.array([(cols * w).sum() / w.sum(), (rows * w).sum() / w.sum()], np.float32)
    assert _judge(ex, sid, v32).status == "correct"
    assert _judge(ex, sid, np.round([col, row], 4)).status == "correct"


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_lsm_row_accepts_float32(sid):
    ex = BY_ID["im.lsm-row"]
    r1 = np.float32(parameters_for(ex, sid)["r1"])

    def row(x, y, g, gx, gy):
        x, y, g, gx, gy = (np.float32(v) for v in (x, y, g, gx, gy))
        return np.array([r1 * gx, r1 * gx * x, r1 * gx * y, r1 * gy, r1 * gy * x, r1 * gy * y,
                         1, g], np.float32)
    assert _judge(ex, sid, row).status == "correct"


# -- the exercises of the rewritten chapter: references by independent routes ------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_weighted_centroid_function_is_scipys_and_refuses_an_empty_window(sid):
    from photolib.grading.variants import rng_for

    ex = BY_ID["im.weighted-centroid"]
    p = parameters_for(ex, sid)
    ref = ex.reference(p)
    cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
    for (window,) in cases[:-1]:
        row, col = ndimage.center_of_mass(np.maximum(window - p["t"], 0.0))
        np.testing.assert_allclose(ref(window), [col, row], atol=1e-12)
    with pytest.raises(ValueError, match="empty"):
        ref(*cases[-1])


def _lsm_step_scipy(template, search, q):
    """One Gauss-Newton step with SciPy's map_coordinates (order 1) as the interpolation."""
    f, g, q = (np.asarray(v, float) for v in (template, search, q))
    gy, gx = np.gradient(g)
    h, w = f.shape
    y, x = np.mgrid[:h, :w].astype(float)
    x, y = (x - (w - 1) / 2).ravel(), (y - (h - 1) / 2).ravel()
    cols, rows = q[0] + q[1] * x + q[2] * y, q[3] + q[4] * x + q[5] * y
    gs, gxs, gys = (ndimage.map_coordinates(im, [rows, cols], order=1) for im in (g, gx, gy))
    r1 = q[7]
    A = np.column_stack([r1 * gxs, r1 * gxs * x, r1 * gxs * y, r1 * gys, r1 * gys * x,
                         r1 * gys * y, np.ones_like(x), gs])
    return q + np.linalg.lstsq(A, f.ravel() - q[6] - r1 * gs, rcond=None)[0]


@pytest.mark.parametrize("sid", STUDENTS)
def test_lsm_step_is_a_gauss_newton_step_with_scipy_interpolation(sid):
    from photolib.grading.variants import rng_for

    ex = BY_ID["im.lsm-step"]
    p = parameters_for(ex, sid)
    cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
    for case in cases[:-1]:
        np.testing.assert_allclose(ex.reference(p)(*case), _lsm_step_scipy(*case),
                                   rtol=1e-9, atol=1e-9)
    with pytest.raises(ValueError):
        ex.reference(p)(*cases[-1])


@pytest.mark.parametrize("sid", STUDENTS)
def test_real_target_is_scipys_center_of_mass_of_the_window(sid):
    from photolib.data import yellowtargets

    ex = BY_ID["im.real-target"]
    p = parameters_for(ex, sid)
    rgb = yellowtargets()[0].astype(float)
    y = np.minimum(rgb[..., 0], rgb[..., 1]) - rgb[..., 2]
    w = np.maximum(y[p["r0"]:p["r1"], p["c0"]:p["c1"]] - p["t"], 0.0)
    row, col = ndimage.center_of_mass(w)
    np.testing.assert_allclose(ex.reference(p), [col + p["c0"], row + p["r0"]], atol=1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_ransac_counts_are_the_smallest_n_by_search(sid):
    ex2, ex3 = BY_ID["im.ransac-homography"], BY_ID["im.ransac-fundamental"]
    p = parameters_for(ex2, sid)
    assert p == parameters_for(ex3, sid) == parameters_for(BY_ID["im.ransac-eps"], sid)
    for ex, s in ((ex2, 4), (ex3, 8)):
        clean = (1 - p["eps"]) ** s
        n = 1
        while (1 - clean) ** n > 1 - p["p"]:
            n += 1
        assert ex.reference(p) == n


@pytest.mark.parametrize("sid", STUDENTS)
def test_subpixel_disparity_is_the_vertex_of_numpys_parabola_and_depth_the_calibrations(sid):
    from photolib.data import MOTORCYCLE_CALIBRATION

    ex1, ex2 = BY_ID["im.subpixel-disparity"], BY_ID["im.disparity-depth"]
    p = parameters_for(ex1, sid)
    a, b, _ = np.polyfit([-1.0, 0.0, 1.0], [p["rm"], p["r0"], p["rp"]], 2)
    assert ex1.reference(p) == pytest.approx(p["d0"] - b / (2 * a), abs=1e-9)
    assert p["d"] == round(ex1.reference(p), 3)
    z = float(MOTORCYCLE_CALIBRATION.depth_mm([p["d"]])[0])
    assert ex2.reference(parameters_for(ex2, sid)) == pytest.approx(z, rel=1e-12)
