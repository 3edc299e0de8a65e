"""The exercises of chapters 04-06, judged in this process by calling the registry directly.

For every exercise (:class:`chapter_checks.ChapterChecks`): the reference answer is accepted,
the wrong answer of every declared mistake is recognised with that mistake's hint, students
get different variants, functions are judged on hidden scalar cases and an untouched answer
is not answered. Answers travel through :func:`encode_value`/:func:`decode_value` as they do
from a kernel.
"""

from __future__ import annotations

from photolib.grading.exercises import ch04_rotations, ch05_interior_orientation, ch06_collinearity

from .chapter_checks import ChapterChecks

STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


class TestChapter04(ChapterChecks):
    module = ch04_rotations
    chapter_name = "04-rotations"
    kinds = {"expression", "function"}
    students = STUDENTS
    slow_mistakes = frozenset({'rot.matrix-derivative'})


class TestChapter05(ChapterChecks):
    module = ch05_interior_orientation
    chapter_name = "05-interior-orientation"
    kinds = {"expression", "function"}
    students = STUDENTS


class TestChapter06(ChapterChecks):
    module = ch06_collinearity
    chapter_name = "06-collinearity"
    kinds = {"expression", "function"}
    students = STUDENTS
    slow_mistakes = frozenset({'col.partial-derivative'})


def test_every_answer_kind_is_used():
    modules = (ch04_rotations, ch05_interior_orientation, ch06_collinearity)
    kinds = {ex.kind for module in modules for ex in module.EXERCISES}
    assert {"number", "array", "rotation", "expression", "function"} <= kinds


# ---------------------------------------------------------------------------------------------
# Answers a careful student may give (float32, OpenCV/SciPy, sensibly rounded) are accepted;
# the recognisable mistakes keep their hints. Every expected value below is computed here,
# independently of the exercise's reference (SciPy rotations, NumPy closed forms, complex-step
# derivatives, SymPy).

import math  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import sympy as sp  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from photolib.grading.exercises import exercise  # noqa: E402
from photolib.grading.notebook import parameters_for  # noqa: E402

from .chapter_checks import judge_as_grader  # noqa: E402

MANY = tuple(f"s{i:07d}" for i in range(1, 41))


def _verdict(exercise_id, sid, value):
    return judge_as_grader(exercise(exercise_id), sid, value)


def _assert_hint(exercise_id, sid, value, tag):
    verdict = _verdict(exercise_id, sid, value)
    assert verdict.status == "wrong" and verdict.mistake == tag, (sid, verdict.message)


# -- 04: rot.opk-matrix ---------------------------------------------------------------------
def _opk_scipy(p, sequence="XYZ", senses=(1, 1, 1)):
    """R from SciPy: intrinsic "XYZ" is R_x(ω)·R_y(φ)·R_z(κ), active, right-handed."""
    angles = np.array([p.omega_gon, p.phi_gon, p.kappa_gon]) * np.pi / 200.0 * senses
    if sequence == "ZYX":
        angles = angles[::-1]
    return Rotation.from_euler(sequence, angles).as_matrix()


@pytest.mark.parametrize("sid", STUDENTS)
def test_opk_matrix_from_scipy_is_accepted_also_in_float32(sid):
    p = parameters_for(exercise("rot.opk-matrix"), sid)
    assert _verdict("rot.opk-matrix", sid, _opk_scipy(p)).correct
    assert _verdict("rot.opk-matrix", sid, _opk_scipy(p).astype(np.float32)).correct


@pytest.mark.parametrize("sid", STUDENTS)
def test_opk_matrix_omega_sense_and_reversed_product_have_hints(sid):
    p = parameters_for(exercise("rot.opk-matrix"), sid)
    _assert_hint("rot.opk-matrix", sid, _opk_scipy(p, senses=(-1, 1, 1)), "sense")
    verdict = _verdict("rot.opk-matrix", sid, _opk_scipy(p, sequence="ZYX"))   # R_κ·R_φ·R_ω
    assert verdict.mistake == "order" and "R_κ·R_φ·R_ω" in verdict.message, verdict.message
    _assert_hint("rot.opk-matrix", sid, _opk_scipy(p).T, "transposed")


def _sympy_opk():
    w, f, k = sp.symbols("omega phi kappa")
    Rw = sp.Matrix([[1, 0, 0], [0, sp.cos(w), -sp.sin(w)], [0, sp.sin(w), sp.cos(w)]])
    Rf = sp.Matrix([[sp.cos(f), 0, sp.sin(f)], [0, 1, 0], [-sp.sin(f), 0, sp.cos(f)]])
    Rk = sp.Matrix([[sp.cos(k), -sp.sin(k), 0], [sp.sin(k), sp.cos(k), 0], [0, 0, 1]])
    return Rw * Rf * Rk, (w, f, k)


@pytest.mark.parametrize("sid", STUDENTS)
def test_opk_matrix_built_in_sympy_is_accepted(sid):
    R, (w, f, k) = _sympy_opk()
    p = parameters_for(exercise("rot.opk-matrix"), sid)
    exact = R.subs({w: sp.Rational(str(p.omega_gon)) * sp.pi / 200,
                    f: sp.Rational(str(p.phi_gon)) * sp.pi / 200,
                    k: sp.Rational(str(p.kappa_gon)) * sp.pi / 200})
    assert _verdict("rot.opk-matrix", sid, exact).correct          # exact trigonometric entries
    assert _verdict("rot.opk-matrix", sid, exact.evalf()).correct  # Floats
    assert _verdict("rot.opk-matrix", sid, exact.T.evalf()).mistake == "transposed"
    half = R.subs({f: sp.Rational(str(p.phi_gon)) * sp.pi / 200,
                   k: sp.Rational(str(p.kappa_gon)) * sp.pi / 200})
    verdict = _verdict("rot.opk-matrix", sid, half)                # ω not substituted
    assert verdict.mistake == "type" and "omega" in verdict.message, verdict.message


def test_angles_as_a_sympy_column_are_accepted():
    sid = STUDENTS[0]
    p = parameters_for(exercise("rot.angles-from-matrix"), sid)
    R = np.array(p.R)
    angles = np.degrees([math.atan2(-R[1, 2], R[2, 2]), math.asin(R[0, 2]),
                         math.atan2(-R[0, 1], R[0, 0])])
    assert _verdict("rot.angles-from-matrix", sid, sp.Matrix(angles)).correct
    assert _verdict("rot.angles-from-matrix", sid, sp.Matrix(angles).T).correct
    assert _verdict("rot.angles-from-matrix", sid, sp.Matrix(np.radians(angles))).mistake \
        == "degrees"


# -- 04: rot.ray-direction ------------------------------------------------------------------
def _student_with_unit(unit):
    ex = exercise("rot.ray-direction")
    return next(s for s in MANY if parameters_for(ex, s).unit == unit)


def _ray_scipy(p, scale, dtype=float):
    def ray_direction(x, y, omega, phi, kappa):
        R = Rotation.from_euler("XYZ", np.array([omega, phi, kappa]) * scale).as_matrix()
        v = R @ np.array([x, y, -p.c_mm])
        return (v / np.linalg.norm(v)).astype(dtype)
    return ray_direction


@pytest.mark.parametrize("unit", ["degrees", "gon"])
def test_ray_direction_in_float32_is_accepted(unit):
    sid = _student_with_unit(unit)
    p = parameters_for(exercise("rot.ray-direction"), sid)
    scale = np.pi / (180.0 if unit == "degrees" else 200.0)
    assert _verdict("rot.ray-direction", sid, _ray_scipy(p, scale)).correct
    assert _verdict("rot.ray-direction", sid, _ray_scipy(p, scale, np.float32)).correct


@pytest.mark.parametrize("unit, wrong_scale, tag", [
    ("degrees", np.pi / 200.0, "gon"),          # degrees converted as if gon
    ("gon", np.pi / 180.0, "degrees"),          # gon converted as if degrees
    ("degrees", 1.0, "degrees"),                # not converted at all
])
def test_ray_direction_wrong_angle_unit_has_a_hint(unit, wrong_scale, tag):
    sid = _student_with_unit(unit)
    p = parameters_for(exercise("rot.ray-direction"), sid)
    _assert_hint("rot.ray-direction", sid, _ray_scipy(p, wrong_scale, np.float32), tag)


# -- 05: io.field-angle ---------------------------------------------------------------------
def _tau_numpy(p, dtype=float):
    size = np.array([p.W, p.H], dtype) * dtype(p.pixel_um) / dtype(1000.0)
    return np.degrees(np.arctan(np.linalg.norm(size) / dtype(2.0) / dtype(p.c_mm)))


@pytest.mark.parametrize("sid", MANY)
def test_field_angle_variants_are_realistic_lenses(sid):
    p = parameters_for(exercise("io.field-angle"), sid)
    half_diagonal = math.hypot(p.W * p.pixel_um, p.H * p.pixel_um) / 2000.0
    assert 0.5 * half_diagonal - 1e-3 <= p.c_mm <= 2.0 * half_diagonal + 1e-3
    assert 26.0 < _tau_numpy(p) < 64.0          # from a wide angle to a short telephoto
    assert p.c_mm == round(p.c_mm, 3) and p.pixel_um == round(p.pixel_um, 2)


@pytest.mark.parametrize("sid", STUDENTS)
def test_field_angle_in_float32_or_rounded_is_accepted(sid):
    p = parameters_for(exercise("io.field-angle"), sid)
    tau = _tau_numpy(p)
    assert _verdict("io.field-angle", sid, _tau_numpy(p, np.float32)).correct
    assert _verdict("io.field-angle", sid, round(float(tau), 3)).correct
    assert _verdict("io.field-angle", sid, round(float(tau), 2)).correct
    # what the printed inputs cannot tell apart: the pixel size 0.004 µm off
    shifted = type(p)(p, pixel_um=p.pixel_um + 0.004)
    assert _verdict("io.field-angle", sid, float(_tau_numpy(shifted))).correct


@pytest.mark.parametrize("sid", STUDENTS)
def test_field_angle_mistakes_keep_their_hints(sid):
    p = parameters_for(exercise("io.field-angle"), sid)
    tau = float(_tau_numpy(p))
    diagonal = math.hypot(p.W, p.H) * p.pixel_um / 1000.0
    _assert_hint("io.field-angle", sid, math.radians(tau), "degrees")
    _assert_hint("io.field-angle", sid, 2.0 * tau, "angle-of-view")
    _assert_hint("io.field-angle", sid, math.degrees(math.atan(diagonal / p.c_mm)), "diagonal")
    _assert_hint("io.field-angle", sid, math.degrees(math.atan2(diagonal / 2, -p.c_mm)), "sign-c")
    _assert_hint("io.field-angle", sid,
                 math.degrees(math.atan(diagonal * 1000.0 / 2 / p.c_mm)), "units-mm-m")


# -- 05: io.image-vector --------------------------------------------------------------------
def _brown_delta(p, x, y):
    r2 = x * x + y * y
    radial = p.A1 * r2 + p.A2 * r2 * r2
    return np.array([x * radial + p.B1 * (r2 + 2 * x * x) + 2 * p.B2 * x * y,
                     y * radial + p.B2 * (r2 + 2 * y * y) + 2 * p.B1 * x * y])


def _x_star(p, dtype=float, at_ideal=False, sign=-1.0, c_sign=1.0):
    m = np.array([p.x - p.x0, p.y - p.y0])
    ideal = m + sign * _brown_delta(p, *m)
    if at_ideal:                                     # Δ at the ideal point: x = m − Δ(x)
        for _ in range(100):
            ideal = m - _brown_delta(p, *ideal)
    return np.array([ideal[0], ideal[1], -c_sign * p.c_mm]).astype(dtype)


@pytest.mark.parametrize("sid", STUDENTS + MANY + ("b42",))
def test_image_vector_in_float32_is_accepted(sid):
    assert _verdict("io.image-vector", sid,
                    _x_star(parameters_for(exercise("io.image-vector"), sid), np.float32)).correct


@pytest.mark.parametrize("sid", STUDENTS)
def test_image_vector_mistakes_keep_their_hints(sid):
    p = parameters_for(exercise("io.image-vector"), sid)
    _assert_hint("io.image-vector", sid, _x_star(p, np.float32, at_ideal=True), "distortion-point")
    _assert_hint("io.image-vector", sid, _x_star(p, np.float32, sign=1.0), "sign-distortion")
    _assert_hint("io.image-vector", sid, _x_star(p, np.float32, c_sign=-1.0), "sign-c")


# -- 06: col.dy-dphi ------------------------------------------------------------------------
def _dy_dphi_complex_step(p, transpose=False, phi_sense=1.0):
    """∂y'/∂φ by the complex step (exact to rounding), R written out here."""
    w, k = np.radians(p.omega_deg), np.radians(p.kappa_deg)

    def y_image(phi):
        f = phi_sense * phi
        Rw = np.array([[1, 0, 0], [0, np.cos(w), -np.sin(w)], [0, np.sin(w), np.cos(w)]])
        Rf = np.array([[np.cos(f), 0, np.sin(f)], [0, 1, 0], [-np.sin(f), 0, np.cos(f)]])
        Rk = np.array([[np.cos(k), -np.sin(k), 0], [np.sin(k), np.cos(k), 0], [0, 0, 1]])
        R = Rw @ Rf @ Rk
        d = np.array([p.X - p.X0, p.Y - p.Y0, p.Z - p.Z0])
        kx, ky, N = (R if transpose else R.T) @ d
        return -p.c_mm * ky / N

    h = 1e-30
    return float(y_image(np.radians(p.phi_deg) + 1j * h).imag / h)


@pytest.mark.parametrize("sid", STUDENTS)
def test_dy_dphi_transposed_r_and_reversed_phi_have_hints(sid):
    p = parameters_for(exercise("col.dy-dphi"), sid)
    assert _verdict("col.dy-dphi", sid, _dy_dphi_complex_step(p)).correct
    assert _verdict("col.dy-dphi", sid, float(np.float32(_dy_dphi_complex_step(p)))).correct
    _assert_hint("col.dy-dphi", sid, _dy_dphi_complex_step(p, transpose=True), "transposed")
    _assert_hint("col.dy-dphi", sid, _dy_dphi_complex_step(p, phi_sense=-1.0), "sense")
