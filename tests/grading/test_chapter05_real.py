"""The real-image exercises of chapter 05 (a measured chessboard corner, this lens's distortion).

Independent routes: the corner is read back from the photograph by OpenCV's own detector
(``findChessboardCorners`` + ``cornerSubPix`` called here, not through photolib), the image
frame from OpenCV's pixel convention in docs/conventions.md, the distortion from the formulas of
the conventions' table typed out here, and the whole chain against the chapter's adjustment:
the corner corrected by the task's Δ must lie where the calibrated exterior orientation
projects the board corner, within the measurement noise (a few σ0).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import photolib as pl
from photolib.grading.exercises import ch05_interior_orientation as ch05
from photolib.grading.notebook import parameters_for
from photolib.nb import realdata as rd

from .chapter_checks import judge_as_grader as _judge

STEP1 = ch05.real_corner
STEP2 = ch05.real_distortion
STUDENTS = [f"s{i:07d}" for i in range(12)]


@pytest.fixture(scope="module")
def cal():
    return rd.chessboard_calibration()


@pytest.mark.parametrize("sid", STUDENTS[:4])
def test_the_corner_is_where_opencv_finds_it(sid):
    import photolib.data as pdata

    p = parameters_for(STEP1, sid)
    cb = pdata.chessboard()
    gray = cb.images[list(cb.files).index(p["file"])]
    gray = gray if gray.ndim == 2 else cv2.cvtColor(gray, cv2.COLOR_RGB2GRAY)
    gray = np.ascontiguousarray(gray).astype(np.uint8)
    found, corners = cv2.findChessboardCorners(gray, (9, 6))
    assert found
    corners = cv2.cornerSubPix(gray, corners, rd.SUBPIX_WINDOW, (-1, -1),
                               (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 30, 0.001))
    col, row = corners.reshape(-1, 2)[p["corner"]]
    assert (p["col"], p["row"]) == pytest.approx((col, row), abs=0.0051)   # printed to 0.01 px


@pytest.mark.parametrize("sid", STUDENTS)
def test_step1_is_opencvs_pixel_frame(sid):
    p = parameters_for(STEP1, sid)
    # docs/conventions.md, OpenCV row: x'0 = cx − (W − 1)/2, y'0 = (H − 1)/2 − cy for a point
    expected = np.array([p["col"] - (640 - 1) / 2, (480 - 1) / 2 - p["row"]])
    assert np.allclose(STEP1.reference(p), expected, atol=1e-12)
    assert _judge(STEP1, sid, np.round(expected, 2)).correct
    assert parameters_for(STEP2, sid)["xy_corner_x"] == round(float(expected[0]), 2)


@pytest.mark.parametrize("sid", STUDENTS)
def test_step2_is_the_conventions_formula(sid):
    p = parameters_for(STEP2, sid)
    xb, yb = p["xy_corner_x"] - p["x0"], p["xy_corner_y"] - p["y0"]
    r2 = xb * xb + yb * yb
    dr_over_r = p["A1"] * r2 + p["A2"] * r2**2 + p["A3"] * r2**3
    dx = xb * dr_over_r + p["B1"] * (r2 + 2 * xb * xb) + 2 * p["B2"] * xb * yb
    dy = yb * dr_over_r + p["B2"] * (r2 + 2 * yb * yb) + 2 * p["B1"] * xb * yb
    assert np.allclose(STEP2.reference(p), [dx, dy], atol=1e-9)
    assert _judge(STEP2, sid, np.round([dx, dy], 2)).correct          # to 0.01 px, as asked


@pytest.mark.parametrize("sid", STUDENTS)
def test_the_corrected_corner_is_where_the_calibration_projects_it(sid, cal):
    """Measured − Δ (the task's answer) agrees with the collinearity projection of the board
    corner with the chapter's exterior orientation of that view, within 5 σ0 per coordinate
    (σ0 = the adjustment's a-posteriori precision of one image coordinate)."""
    p = parameters_for(STEP2, sid)
    view = list(cal.files).index(p["file"])
    res = cal.result
    X0, angles = res.exterior[view, :3], res.exterior[view, 3:]
    pp = np.array([res.x0, res.y0])
    projected = pp + pl.project(cal.object_points[p["corner"]][None], X0,
                                pl.rotation_opk(*angles), res.c)[0]
    corrected = np.array([p["xy_corner_x"], p["xy_corner_y"]]) - STEP2.reference(p)
    # printing to 0.01 px and 4-digit coefficients add at most ~0.01 px
    assert np.all(np.abs(corrected - projected) < 5 * res.sigma0 + 0.02)


def test_the_mistakes_are_told_apart():
    sid = STUDENTS[0]
    p1, p2 = parameters_for(STEP1, sid), parameters_for(STEP2, sid)
    for ex, p in ((STEP1, p1), (STEP2, p2)):
        for mistake in ex.mistakes:
            verdict = _judge(ex, sid, mistake.wrong(p))
            assert verdict.status == "wrong" and verdict.mistake == mistake.tag, (ex.id, mistake)
