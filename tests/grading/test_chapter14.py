"""The capstone's five graded steps (chapter 14-project), judged as the grader does.

The common checks (reference accepted, every declared mistake recognised with its hint,
variants differ, untouched answers not answered, the master full marks and the copy zero), and
the steps' references by independent routes: the statement's distortion formula typed out
against photolib.Distortion, the resections against cv2.solvePnP, the intersection against
cv2.triangulatePoints, and the steps' shared numbers (a later step prints the correct result
of the earlier one).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import photolib as pl
from photolib.grading.exercises import ch14_project as ch14
from photolib.grading.notebook import parameters_for
from photolib.nb import project as pj

from .chapter_checks import STUDENTS, BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

BY_ID = {ex.id: ex for ex in ch14.EXERCISES}


class TestChapter14(ChapterChecks, BatchGradedChecks):
    module = ch14
    chapter_name = "14-project"
    kinds = {"number", "array"}
    grade_timeout = 120


@pytest.mark.parametrize("sid", STUDENTS)
def test_steps_share_the_students_draw_and_carry_the_earlier_results(sid):
    p = [parameters_for(ex, sid) for ex in ch14.EXERCISES]
    for q in p[1:]:
        assert (q["view_a"], q["view_b"], q["check"]) == (p[0]["view_a"], p[0]["view_b"],
                                                          p[0]["check"])
    assert pj.intersection_angle(p[0]["view_a"], p[0]["view_b"]) >= pj.MIN_ANGLE_DEG
    q2 = BY_ID["prj.resection"].reference(p[1])
    np.testing.assert_allclose(p[3]["X0_a"], q2[0, :3], atol=5e-4)
    np.testing.assert_allclose(p[3]["angles_b"], q2[1, 3:], atol=5e-8)
    X = BY_ID["prj.intersection"].reference(p[3])
    np.testing.assert_allclose(p[4]["X_check"], X, atol=2e-3)
    # step 1's corner, converted by the statement's formula, is one of step 2's inputs
    np.testing.assert_allclose(BY_ID["prj.image-point"].reference(p[0]),
                               pj.image_coordinates(p[0]["view_a"])[p[0]["k"]], atol=2e-3)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_statement_formula_agrees_with_photolib_distortion(sid):
    p = parameters_for(BY_ID["prj.image-point"], sid)
    np.testing.assert_allclose(ch14._image_point(p), ch14._image_point_reference(p), atol=1e-9)


def _opencv_pose(view, control):
    r = pj.calibration().result
    K = np.array([[r.c, 0, r.x0 + 319.5], [0, r.c, 239.5 - r.y0], [0, 0, 1.0]])
    px = pl.pixel_from_image(pj.image_coordinates(view)[control], 640, 480, 1.0)
    X = pj.board_points()[control]
    ok, rvec, tvec = cv2.solvePnP(X, px, K, None, flags=cv2.SOLVEPNP_ITERATIVE)
    rvec, tvec = cv2.solvePnPRefineLM(X, px, K, None, rvec, tvec,
                                      (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-15))
    R_cv = cv2.Rodrigues(rvec)[0]
    return ok, pl.exterior_from_opencv_pose(R_cv, tvec.ravel()), K, R_cv, tvec


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_resection_and_intersection_agree_with_opencv(sid):
    p = parameters_for(BY_ID["prj.resection"], sid)
    q = BY_ID["prj.resection"].reference(p)
    control = [k for k in range(54) if k not in p["check"]]
    P = []
    for row, view in zip(q, (p["view_a"], p["view_b"])):
        ok, (X0, R), K, R_cv, t = _opencv_pose(view, control)
        assert ok
        np.testing.assert_allclose(row[:3], X0, atol=1e-5)
        np.testing.assert_allclose(pl.rotation_opk(*row[3:]), R, atol=1e-7)
        P.append(K @ np.column_stack([R_cv, t]))
    xa, xb = (pl.pixel_from_image(pj.image_coordinates(v)[p["check"]], 640, 480, 1.0)
              for v in (p["view_a"], p["view_b"]))
    h = cv2.triangulatePoints(P[0], P[1], xa.T, xb.T)
    X_cv = (h[:3] / h[3]).T
    ch = pj.chain(p["view_a"], p["view_b"], p["check"])
    # triangulatePoints minimises an algebraic error, photolib the ray distances: they agree
    # to a fifth of each coordinate's standard deviation (measured: ≤ 0.1 of it)
    assert np.all(np.abs(ch.points - X_cv) < 0.2 * ch.predicted)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_resection_tolerance_is_one_sigma_and_far_from_the_mistakes(sid):
    ex = BY_ID["prj.resection"]
    p = parameters_for(ex, sid)
    q = ex.reference(p)
    _, atol = ex.tolerances(p)
    assert np.all(atol > 0) and np.all(atol[:, :3] < 2.0)       # mm
    assert _judge(ex, sid, q + 0.5 * atol).status == "correct"
    assert _judge(ex, sid, q + 2.0 * atol).status == "wrong"


def test_rounded_answers_are_accepted():
    sid = STUDENTS[0]
    for ex_id, digits in (("prj.image-point", 3), ("prj.check-rms", 3)):
        ex = BY_ID[ex_id]
        value = np.round(ex.reference(parameters_for(ex, sid)), digits)
        assert _judge(ex, sid, value).status == "correct", ex_id
    ex = BY_ID["prj.sigma0"]
    r, s = ex.reference(parameters_for(ex, sid))
    assert _judge(ex, sid, np.array([r, round(s, 3)])).status == "correct"
