"""Chapter 06's exercises by independent routes (SciPy rotations, OpenCV projection, the
forward displacements of refraction and earth curvature), the scenarios' shared numbers, and
the implementation exercise's degenerate case and hints. The common checks (reference
accepted, every mistake recognised with its hint, variants) are ``TestChapter06`` in
``test_chapter_exercises.py``."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import photolib as pl
from photolib.grading.exercises import ch06_collinearity as ch06
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

from .chapter_checks import judge_as_grader as _judge

BY_ID = {ex.id: ex for ex in ch06.EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")
T = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
M = np.diag([1.0, -1.0, -1.0])


def _scipy_nav(p):
    R_nb = Rotation.from_euler("ZYX", np.radians([p["heading_deg"], p["pitch_deg"],
                                                  p["roll_deg"]])).as_matrix()
    bore = Rotation.from_euler("XYZ", np.radians([p["bx_deg"], p["by_deg"],
                                                  p["bz_deg"]])).as_matrix()
    return T @ R_nb, T @ R_nb @ M @ bore


def _opencv_project(X, X0, R, c, x0=0.0, y0=0.0):
    """(x', y') in mm by cv2.projectPoints: OpenCV's camera looks along +z with y down."""
    R_cv = np.diag([1.0, -1.0, -1.0]) @ R.T
    K = np.array([[c, 0.0, x0], [0.0, c, 0.0], [0.0, 0.0, 1.0]])
    uv, _ = cv2.projectPoints(np.asarray(X, float).reshape(-1, 1, 3), cv2.Rodrigues(R_cv)[0],
                              -R_cv @ np.asarray(X0, float), K, np.zeros(5))
    uv = uv.reshape(-1, 2)
    return np.column_stack([uv[:, 0], y0 - uv[:, 1]])


# -- direct georeferencing ----------------------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_nav_steps_agree_with_scipy_and_opencv(sid):
    p = parameters_for(BY_ID["col.nav-rotation"], sid)
    R_nav, R = _scipy_nav(p)
    np.testing.assert_allclose(ch06._nav_rotation(p), R, atol=1e-12)
    np.testing.assert_allclose(p["R_nav"], R_nav, atol=1e-9)
    X0 = np.array([p["E"], p["N"], p["U"]]) - R_nav @ [p["lx"], p["ly"], p["lz"]]
    np.testing.assert_allclose(BY_ID["col.nav-centre"].reference(p), X0, atol=1e-8)
    # cv2.Rodrigues takes the nearest rotation to the printed (9-decimal) R: 1e-6 mm apart
    xy = _opencv_project([[p["X"], p["Y"], p["Z"]]], p["X0"], np.array(p["R"]), p["c_mm"])[0]
    np.testing.assert_allclose(BY_ID["col.nav-image"].reference(p), xy, atol=1e-6)


@pytest.mark.parametrize("sid", STUDENTS)
def test_nav_steps_share_the_numbers_and_carry_the_earlier_results(sid):
    ps = [parameters_for(BY_ID[i], sid) for i in ("col.nav-rotation", "col.nav-centre",
                                                 "col.nav-image")]
    assert ps[0] == ps[1] == ps[2]
    p = ps[0]
    np.testing.assert_allclose(p["R"], BY_ID["col.nav-rotation"].reference(p), atol=1e-9)
    np.testing.assert_allclose(p["X0"], BY_ID["col.nav-centre"].reference(p), atol=1e-4)
    assert _judge(BY_ID["col.nav-image"], sid, BY_ID["col.nav-image"].reference(p)).correct
    xy = BY_ID["col.nav-image"].reference(p)
    assert np.all(np.abs(xy) < 0.6 * 100.0)          # the ground point is in a normal format


def test_nav_rotation_of_a_level_flight_north_is_the_docstrings():
    p = {"roll_deg": 0.0, "pitch_deg": 0.0, "heading_deg": 0.0, "bx_deg": 0.0, "by_deg": 0.0,
         "bz_deg": 0.0}
    np.testing.assert_allclose(ch06._nav_rotation(p), pl.rotation_opk(0.0, 0.0, math.pi / 2),
                               atol=1e-15)


# -- refraction and earth curvature ------------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_refraction_constant_is_photolibs_ardc(sid):
    p = parameters_for(BY_ID["col.refraction-constant"], sid)
    K = pl.refraction_constant(p["H_m"], p["h_m"], model="ardc")
    assert BY_ID["col.refraction-constant"].reference(p) == pytest.approx(K * 1e6, rel=1e-12)
    assert 5.0 < K * 1e6 < 80.0


@pytest.mark.parametrize("sid", STUDENTS)
def test_corrected_point_displaced_forward_gives_the_measured_one(sid):
    """Refraction outwards by K(r + r³/c²), then curvature inwards by r³(H − h)/(2Rc²): the
    physical displacements applied to the corrected point return the measured one (to the
    terms of second order in the relative displacements, below 0.05 µm)."""
    p = parameters_for(BY_ID["col.refraction-corrected"], sid)
    xc = BY_ID["col.refraction-corrected"].reference(p)
    c, K, H = p["c_mm"], p["K_urad"] * 1e-6, p["H_m"] - p["h_m"]
    r = np.hypot(*xc)
    curved = xc * (1.0 - r**2 * H / (2.0 * 6371000.0 * c**2))
    measured = curved * (1.0 + K * (1.0 + (curved @ curved) / c**2))
    np.testing.assert_allclose(measured, [p["x"], p["y"]], atol=5e-5)   # second order: (r²H/2Rc²)²·r
    assert 1e-3 < np.max(np.abs(xc - [p["x"], p["y"]])) < 0.1      # µm, not nothing, not mm


@pytest.mark.parametrize("sid", STUDENTS)
def test_refraction_ground_point_projects_to_the_corrected_point(sid):
    p = parameters_for(BY_ID["col.refraction-ground"], sid)
    X = BY_ID["col.refraction-ground"].reference(p)
    R = Rotation.from_euler("XYZ", np.radians([p["omega_deg"], p["phi_deg"],
                                               p["kappa_deg"]])).as_matrix()
    np.testing.assert_allclose(_opencv_project([X], [p["X0"], p["Y0"], p["Z0"]], R, p["c_mm"])[0],
                               [p["xc"], p["yc"]], atol=1e-9)
    assert X[2] == pytest.approx(p["Zg"])
    step2 = BY_ID["col.refraction-corrected"].reference(p)
    np.testing.assert_allclose([p["xc"], p["yc"]], step2, atol=1e-5)


# -- image point to object point on a given height (function) ---------------------------------

@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_ground_point_reference_projects_back_with_opencv(sid):
    ex = BY_ID["col.ground-point"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    R = Rotation.from_euler("XYZ", np.radians([p["omega_deg"], p["phi_deg"],
                                               p["kappa_deg"]])).as_matrix()
    cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
    regular = [case for case in cases if case[2] < p["Z0"]]
    assert len(regular) == len(cases) - 1 >= 5
    for x, y, Z in regular:
        X = f(x, y, Z)
        assert X[2] == pytest.approx(Z)
        back = _opencv_project([X], [p["X0"], p["Y0"], p["Z0"]], R, p["c_mm"], p["x0_mm"],
                               p["y0_mm"])[0]
        np.testing.assert_allclose(back, [x, y], atol=1e-9)
    x, y, Z = next(case for case in cases if case[2] > p["Z0"])
    with pytest.raises(ValueError, match="behind the camera"):
        f(x, y, Z)


def _plain(p, principal=1.0, check=True):
    R = pl.rotation_opk(*np.radians([p["omega_deg"], p["phi_deg"], p["kappa_deg"]]))
    X0 = np.array([p["X0"], p["Y0"], p["Z0"]])

    def ground_point(x, y, Z):
        ray = R @ np.array([x - principal * p["x0_mm"], y - principal * p["y0_mm"], -p["c_mm"]])
        lam = (Z - X0[2]) / ray[2]
        if check and lam <= 0:
            raise ValueError("behind the camera")
        return X0 + lam * ray
    return ground_point


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_ground_point_judges_a_careful_and_a_careless_student(sid):
    ex = BY_ID["col.ground-point"]
    p = parameters_for(ex, sid)
    assert _judge(ex, sid, _plain(p)).correct
    no_pp = _judge(ex, sid, _plain(p, principal=0.0))
    assert no_pp.mistake == "principal-point" and "principal point" in no_pp.message
    unchecked = _judge(ex, sid, _plain(p, check=False))
    assert not unchecked.correct and "degenerate input" in unchecked.message

    def wrong_error(x, y, Z):
        if Z > p["Z0"]:
            raise ZeroDivisionError("no")
        return _plain(p)(x, y, Z)
    assert not _judge(ex, sid, wrong_error).correct
