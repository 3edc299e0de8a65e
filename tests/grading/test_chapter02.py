"""The exercises of chapter 02 (optics), judged as the grader does.

The same checks as for chapter 08 (reference accepted, every declared mistake recognised with
its hint, variants differ, untouched answers not answered), plus checks of the references by
independent routes: intersecting the construction rays with ``numpy.linalg.solve``, root
finding on the light cone, SciPy's Bessel zeros, Fermat's principle minimised with
``scipy.optimize``, and the corner ray's angle from a dot product.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import sympy as sp
from scipy import optimize, special

from photolib.grading.exercises import ch02_optics as ch02
from photolib.grading.notebook import parameters_for

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch02.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000004", "s3000005")


def _sid_with(ex, **wanted):
    return next(s for s in (f"s{i}" for i in range(500))
                if all(parameters_for(ex, s)[k] == v for k, v in wanted.items()))


# -- the same checks as for the other chapters ---------------------------------------------------

class TestChapter02(ChapterChecks, BatchGradedChecks):
    module = ch02
    chapter_name = "02-optics"
    kinds = {"number", "array", "expression", "choice"}
    students = STUDENTS
    reference_students = 3
    mistake_students = STUDENTS + tuple(f"s{i}" for i in range(40))
    mistake_limit = 4
    variant_students = 3


def test_the_printed_wrong_t_formula_gets_the_erratum_hint():
    ex = BY_ID["opt.depth-of-field"]
    p = parameters_for(ex, STUDENTS[0])
    f, a, k, u = p["f_mm"], p["a_m"] * 1e3, p["k"], p["u_um"] * 1e-3
    m_b = (a - f) / f                                  # the scale number, as the summary names it
    t_printed = 2 * u * k * (1 + m_b) / (m_b**2 - (u * k / f) ** 2)
    ref = ch02._dof(p)
    verdict = _judge(ex, STUDENTS[0], np.array([ref[0], ref[1], t_printed * 1e-3]))
    assert verdict.status == "wrong" and verdict.mistake == "erratum"
    assert "de-summary:depth-of-field-t" in verdict.message


# -- the references by an independent route ------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_image_distance_is_where_the_construction_rays_meet(sid):
    p = parameters_for(BY_ID["opt.image-distance"], sid)
    a, f, H = p["a_m"] * 1e3, p["f_mm"], 1.0
    # centre ray y = −H z/a and focal ray y = H(1 − z/f): solve for (z, y)
    A = np.array([[H / a, 1.0], [H / f, 1.0]])
    z, _ = np.linalg.solve(A, [0.0, H])
    assert math.isclose(ch02._image_distance(p), z, rel_tol=1e-12)


@pytest.mark.parametrize("sid", STUDENTS)
def test_depth_of_field_limits_are_roots_of_the_cone_blur(sid):
    p = parameters_for(BY_ID["opt.depth-of-field"], sid)
    a, f, k, u = p["a_m"] * 1e3, p["f_mm"], p["k"], p["u_um"] * 1e-3

    def blur(x):
        apx, ap = x * f / (x - f), a * f / (a - f)
        return f / k * abs(apx - ap) / apx - u
    near = optimize.brentq(blur, 1.001 * f, a)
    far = optimize.brentq(blur, a, 1e9)
    np.testing.assert_allclose(ch02._dof(p), np.array([near, far, far - near]) * 1e-3, rtol=1e-8)


@pytest.mark.parametrize("sid", STUDENTS)
def test_airy_radius_from_scipys_first_zero_of_j1(sid):
    p = parameters_for(BY_ID["opt.airy-radius"], sid)
    expected = special.jn_zeros(1, 1)[0] / math.pi * p["wavelength_nm"] * 1e-3 * p["k"]
    assert math.isclose(ch02._airy(p), expected, rel_tol=1e-14)
    # the rounded 1.22 is accepted as well
    assert _judge(BY_ID["opt.airy-radius"], sid,
                  1.22 * p["wavelength_nm"] * 1e-3 * p["k"]).status == "correct"


@pytest.mark.parametrize("sid", STUDENTS)
def test_snell_reference_is_fermats_path(sid):
    p = parameters_for(BY_ID["opt.snell"], sid)
    n1, n2 = p["n1"], p["n2"]
    alpha = math.radians(p["alpha_deg"])
    # choose the end point below the interface so that the stationary path enters at α
    x_end = math.tan(alpha) + 1.0

    def T(u):
        return n1 * math.hypot(1.0, u) + n2 * math.hypot(1.0, x_end - u)
    u = optimize.minimize_scalar(T, bounds=(0.0, x_end), method="bounded",
                                 options={"xatol": 1e-13}).x
    a_found, b_found = math.atan(u), math.atan(x_end - u)
    ours = math.degrees(math.asin(n1 * math.sin(a_found) / n2))
    assert math.isclose(ours, math.degrees(b_found), abs_tol=1e-5)
    assert 0.0 < ch02._snell(p) < p["alpha_deg"]      # into the denser glass: towards the normal


@pytest.mark.parametrize("sid", STUDENTS)
def test_corner_vignetting_from_the_corner_ray(sid):
    p = parameters_for(BY_ID["opt.vignetting-corner"], sid)
    ray = np.array([p["width"] / 2, p["height"] / 2, -p["c_mm"]])
    cos_tau = -ray[2] / np.linalg.norm(ray)
    assert math.isclose(ch02._corner(p), cos_tau**4, rel_tol=1e-13)


@pytest.mark.parametrize("quantity", ["near", "far", "depth"])
def test_dof_limit_expressions_agree_with_root_finding(quantity):
    ex = BY_ID["opt.dof-limit"]
    sid = _sid_with(ex, quantity=quantity)
    p = parameters_for(ex, sid)
    f, k, u = sp.symbols("f k u")
    fn = sp.lambdify((f, k, u), ex.reference(p))
    F, K, U = 50.0, 8.0, 0.01
    A = p["n"] * F

    def blur(x):
        apx, ap = x * F / (x - F), A * F / (A - F)
        return F / K * abs(apx - ap) / apx - U
    near = optimize.brentq(blur, 1.0001 * F, A)
    far = optimize.brentq(blur, A, 1e12)
    expected = {"near": near, "far": far, "depth": far - near}[quantity]
    assert math.isclose(fn(F, K, U), expected, rel_tol=1e-8)


def test_dof_limit_accepts_a_typed_formula():
    ex = BY_ID["opt.dof-limit"]
    sid = _sid_with(ex, quantity="near")
    n = parameters_for(ex, sid)["n"]
    typed = f"{n}*f*f**2/(f**2 + u*k*({n}*f - f))"
    assert _judge(ex, sid, typed).status == "correct"
    assert _judge(ex, sid, f"{n}*f*f**2/(f**2 - u*k*({n}*f - f))").mistake == "swapped"


def test_dof_limit_symbols_are_positive_quantities():
    """f, k and u are declared positive: a form that is equal only for positive f passes,
    one that is wrong for positive f does not."""
    ex = BY_ID["opt.dof-limit"]
    sid = _sid_with(ex, quantity="near")
    n = parameters_for(ex, sid)["n"]
    assert _judge(ex, sid, f"{n}*Abs(f)*f**2/(f**2 + u*k*({n}*f - f))").status == "correct"
    assert _judge(ex, sid, f"{n}*f*f**2/(f**2 + u*k*({n}*f + f))").status != "correct"


@pytest.mark.parametrize("sid", STUDENTS)
def test_choice_reference_points_at_the_right_statement(sid):
    ex = BY_ID["opt.stop-down"]
    p = parameters_for(ex, sid)
    assert f"({ex.reference(p)}) the depth of field grows and the Airy disk becomes twice" \
        in p["options"]
    # the physics behind it: twice k doubles the Airy radius and lengthens the depth of field
    import photolib.optics as po
    assert math.isclose(po.airy_radius(0.55, 2 * p["k"]), 2 * po.airy_radius(0.55, p["k"]))
    d1 = po.depth_of_field(3000.0, 50.0, p["k"], 0.03)
    d2 = po.depth_of_field(3000.0, 50.0, 2 * p["k"], 0.03)
    assert d2.depth > d1.depth


def test_stop_down_variant_does_not_carry_the_answer():
    # the parameters a student sees are the f-numbers and the printed options only: the
    # letters of the right and the wrong options are read from the text
    ex = BY_ID["opt.stop-down"]
    letters = set()
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) == {"k", "k2", "options"}
        parts = re.split(r"(?:^|; )\(([a-d])\) ", p["options"])[1:]   # letter, text, …
        printed = dict(zip(parts[::2], parts[1::2]))
        assert sorted(printed) == list("abcd")
        right = next(k for k, text in printed.items()
                     if text.startswith("the depth of field grows") and "twice" in text)
        assert ex.reference(p) == right
        letters.add(right)
    assert len(letters) > 1                       # the correct letter moves between students


# -- the grating and the edge: references by independent routes ----------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_grating_order_is_where_the_phasors_add_in_phase(sid):
    """θ_m found as the root of the phase step minus 2πm (scipy.optimize), not by arcsin."""
    ex = BY_ID["opt.grating-order"]
    p = parameters_for(ex, sid)
    lam, d = p["lambda_nm"] * 1e-3, p["d_um"]
    theta = optimize.brentq(lambda t: 2 * math.pi * d * math.sin(t) / lam - 2 * math.pi * p["m"],
                            0.0, math.pi / 2)
    assert ex.reference(p) == pytest.approx(math.degrees(theta), abs=1e-9)
    rounded = round(ex.reference(p), 2)                    # the precision the task asks for
    assert _judge(ex, sid, rounded).correct


@pytest.mark.parametrize("sid", STUDENTS)
def test_the_highest_order_is_the_last_real_direction(sid):
    ex = BY_ID["opt.grating-highest"]
    p = parameters_for(ex, sid)
    existing = [m for m in range(0, 50) if m * p["lambda_nm"] * 1e-3 / p["d_um"] <= 1.0]
    assert ex.reference(p) == max(existing)
    assert parameters_for(BY_ID["opt.grating-order"], sid) == p       # one scenario, one draw


@pytest.mark.parametrize("sid", STUDENTS)
def test_edge_fringe_is_the_first_maximum_of_the_fresnel_pattern(sid):
    """The first maximum of ½[(½ + C)² + (½ + S)²] located by a dense scan of SciPy's
    Fresnel integrals, in µm."""
    ex = BY_ID["opt.edge-fringe"]
    p = parameters_for(ex, sid)
    lam, z = p["lambda_nm"] * 1e-3, p["z_mm"] * 1e3
    w = np.linspace(0.0, 2.0, 2_000_001)
    S, C = special.fresnel(w)
    intensity = 0.5 * ((0.5 + C) ** 2 + (0.5 + S) ** 2)
    w1 = w[np.argmax(intensity)]
    assert ex.reference(p) == pytest.approx(w1 * math.sqrt(lam * z / 2), rel=2e-6)
    assert _judge(ex, sid, float(f"{ex.reference(p):.3g}")).correct     # 3 significant digits
