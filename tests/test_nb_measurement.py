"""Chapter 11 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come from SciPy (``gaussian_laplace``, ``stats.skew``, ``center_of_mass``),
OpenCV (``fitEllipseDirect``, ``matchTemplate``) or from the construction of the synthetic
images (true radius, centre, affinity), not from the library under test.
"""

from __future__ import annotations

import math

import cv2
import matplotlib
import numpy as np
import pytest
from scipy import ndimage, stats

matplotlib.use("Agg")

from photolib.nb import measurement as nm  # noqa: E402

from .explorer_checks import assert_explorer_widget, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")


def test_target_image_is_bright_disc_of_known_centre():
    img = nm.target_image(noise=0.0)
    row, col = ndimage.center_of_mass(img - 30.0)
    assert math.hypot(col - 15.4, row - 16.2) < 0.02
    # the area above half height is π r²
    assert abs(np.sum(img > 30 + 85) - math.pi * 25) < 6


@pytest.mark.parametrize("sigma", [1.2, 2.5])
def test_log_report_response_is_scipy_gaussian_laplace(sigma):
    rep = nm.log_report(sigma, 2.0)
    ref = ndimage.gaussian_laplace(nm.scene_image(2.0), sigma) * sigma**2
    assert np.max(np.abs(rep["response"] - ref)) < 0.02 * np.max(np.abs(ref))
    assert abs(rep["rim_radius"] - nm.SCENE_DISC[1]) < 0.7
    assert rep["kernel"] == 2 * math.ceil(4 * sigma) + 1


def test_log_threshold_removes_noise_edges():
    many = nm.log_report(1.0, 0.0)["edges"]
    few = nm.log_report(1.0, 10.0)["edges"]
    assert len(few) < 0.5 * len(many)


@pytest.mark.parametrize("radius, noise", [(4.0, 0.0), (6.0, 8.0), (10.0, 20.0)])
def test_threshold_report_p1_from_scipy_skewness(radius, noise):
    rep = nm.threshold_report(radius, noise)
    s = stats.skew(rep["image"].ravel())           # population skewness, SciPy
    assert rep["result"].p1 == pytest.approx(0.5 * (1 + s / math.sqrt(4 + s * s)), rel=1e-10)
    assert rep["printed_p1"] == pytest.approx(0.5 * (1 + s * math.sqrt(4 + s * s)), rel=1e-10)
    assert abs(rep["result"].p1 - rep["fraction"]) < 0.03
    assert math.hypot(rep["centroid"][0] - 15.4, rep["centroid"][1] - 16.2) < 0.2


@pytest.mark.parametrize("arc, noise", [(360.0, 0.05), (180.0, 0.1), (90.0, 0.02)])
def test_ellipse_report_agrees_with_opencv(arc, noise):
    rep = nm.ellipse_report(arc, noise)
    (cx, cy), _, _ = cv2.fitEllipseDirect(rep["xy"].astype(np.float32))
    assert np.hypot(*(rep["fit"].centre - (cx, cy))) < 2e-3 + 1e-2 * noise
    assert rep["centre_error"] < (0.05 if arc == 360.0 else 2.0)


def test_ellipse_points_without_noise_lie_on_the_true_ellipse():
    (cx, cy), (a, b), th = nm.ELLIPSE_TRUE
    p = nm.ellipse_points(250.0, 0.0) - (cx, cy)
    u = p @ [math.cos(th), math.sin(th)]
    v = p @ [-math.sin(th), math.cos(th)]
    np.testing.assert_allclose((u / a) ** 2 + (v / b) ** 2, 1.0, atol=1e-12)


def test_lsm_report_converges_to_the_truth_and_opencv_agrees():
    rep = nm.lsm_report(2.0, 0.0)
    assert rep["failure"] is None and rep["error"] < 0.05
    f = nm.lsm_template(noise=0.0).astype(np.float32)
    score = cv2.matchTemplate(nm.lsm_search_image().astype(np.float32), f, cv2.TM_CCOEFF_NORMED)
    col, row = np.unravel_index(np.argmax(score), score.shape)[::-1]
    # the affine template is not an exact copy, so OpenCV's integer peak may be ±1 px
    assert abs(col + 10 - nm.LSM_TRUE[0]) <= 1.5 and abs(row + 10 - nm.LSM_TRUE[3]) <= 1.5


def test_lsm_report_far_start_fails_or_is_wrong():
    rep = nm.lsm_report(5.0, 2.0)
    assert rep["failure"] is not None and "diverged" in rep["failure"]
    assert len(rep["history"]) >= 2


def test_plot_log_profile_zero_at_sqrt2_sigma():
    fig = nm.plot_log_profile(2.0)
    x, y = fig.axes[0].lines[0].get_data()
    k = np.flatnonzero(np.diff(np.sign(y)))[0]
    assert abs(x[k] - math.sqrt(2) * 2.0) < 0.1


@pytest.mark.parametrize("cls, name, a, b", [
    (nm.LoGExplorer, "sigma", 1.0, 3.5),
    (nm.ThresholdExplorer, "radius", 3.0, 10.0),
    (nm.EllipseExplorer, "arc_deg", 60.0, 360.0),
    (nm.LSMExplorer, "offset", 0.5, 6.0),
])
def test_explorers_redraw(cls, name, a, b):
    ex = cls()
    assert_explorer_widget(ex, ex.title)
    ex.controls[name].value = a
    assert moves(ex, name, b) == (True, True)


def test_explorer_reports_match_the_functions():
    ex = nm.LSMExplorer(offset=1.0, noise=0.0)
    assert ex.report["error"] == nm.lsm_report(1.0, 0.0)["error"]
    ex.set(offset=5.0, noise=2.0)
    assert ex.report["failure"] is not None
