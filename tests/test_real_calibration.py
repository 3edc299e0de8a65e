"""The chessboard camera of chapters 05 and 08: test-field calibration and resection on real data.

Bounds come from the data: the adjustment's own standard deviations (agreement with OpenCV on
the same corners within 3σ), an F test of the two σ0, and σ0 itself (rays within two
measurement σ). The plane test-field calibration is first checked on exact synthetic images.
"""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib.testfield import (
    camera_constant_from_homographies,
    exterior_from_homography,
    plane_field_calibration,
    plane_homography,
)
from photolib.transforms._base import DegenerateGeometryError

cv2 = pytest.importorskip("cv2")
rd = pytest.importorskip("photolib.nb.realdata")


# -- the method on exact synthetic images ----------------------------------------------------

def _board():
    i, j = np.meshgrid(np.arange(9), np.arange(6))
    return np.column_stack([25.0 * i.ravel(), -25.0 * j.ravel(), np.zeros(54)])


def _views():
    return [(np.array([100.0, -60.0, 400.0]), (0.0, 0.0, 0.1)),
            (np.array([250.0, -40.0, 350.0]), (0.1, 0.5, -0.2)),
            (np.array([-60.0, -90.0, 380.0]), (-0.05, -0.45, 0.3)),
            (np.array([100.0, 150.0, 330.0]), (-0.5, 0.0, 1.4)),
            (np.array([110.0, -260.0, 360.0]), (0.5, 0.05, -1.2)),
            (np.array([60.0, -70.0, 300.0]), (0.2, -0.25, 3.0))]


def test_plane_field_calibration_recovers_an_exact_camera():
    P = _board()
    true = pl.Distortion(A1=-9e-7, A2=-4e-12, B1=-8e-7, B2=-2.7e-6)
    c, x0, y0 = 530.0, 22.0, 5.5
    xy = [pl.project(P, X0, pl.rotation_opk(*a), c, x0, y0, distortion=true) for X0, a in _views()]
    res = plane_field_calibration(xy, P, terms=("c", "x0", "y0", "A1", "A2", "B1", "B2"))
    assert res.converged and res.sigma0 < 1e-8
    assert abs(res.c - c) < 1e-6 and abs(res.x0 - x0) < 1e-6 and abs(res.y0 - y0) < 1e-6
    for k in ("A1", "A2", "B1", "B2"):
        assert res.distortion.params[k] == pytest.approx(true.params[k], rel=1e-6)
    for (X0, a), e in zip(_views(), res.exterior):
        assert np.allclose(e[:3], X0, atol=1e-6) and np.allclose(e[3:], a, atol=1e-9)


def test_start_values_from_a_homography_are_the_camera():
    P = _board()
    X0, R = np.array([250.0, -40.0, 350.0]), pl.rotation_opk(0.1, 0.5, -0.2)
    xy = pl.project(P, X0, R, 530.0)
    G = plane_homography(P[:, :2], xy)
    X0e, Re = exterior_from_homography(G, 530.0, P[:, :2].mean(axis=0))
    assert np.allclose(X0e, X0, atol=1e-6) and np.allclose(Re, R, atol=1e-9)
    Gs = [plane_homography(P[:, :2], pl.project(P, X, pl.rotation_opk(*a), 530.0))
          for X, a in _views()]
    assert camera_constant_from_homographies(Gs) == pytest.approx(530.0, rel=1e-9)


def test_plane_methods_name_what_is_wrong():
    P = _board()
    parallel = [plane_homography(P[:, :2], pl.project(P, [x, -60.0, 400.0], np.eye(3), 500.0))
                for x in (80.0, 120.0)]
    with pytest.raises(DegenerateGeometryError, match="parallel to the test field"):
        camera_constant_from_homographies(parallel)
    with pytest.raises(ValueError, match="needs ≥ 2 homographies, got 1"):
        camera_constant_from_homographies(parallel[:1])
    with pytest.raises(ValueError, match="Z = 0; the largest |Z| is 1"):
        plane_field_calibration([P[:, :2]] * 2, P + [0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="≥ 2 images .* got 1"):
        plane_field_calibration([P[:, :2]], P)
    with pytest.raises(ValueError, match=r"xy_images\[1\] has 53 points, object_points 54"):
        plane_field_calibration([P[:, :2], P[:53, :2]], P)


def test_detect_corners_refuses_wrong_images():
    with pytest.raises(ValueError, match="grey .* uint8 array, got shape .* dtype float64"):
        rd.detect_corners(np.zeros((48, 64)))
    with pytest.raises(ValueError, match="found no 9 × 6 board"):
        rd.detect_corners(np.full((48, 64), 128, dtype=np.uint8))


# -- the real camera ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def cal():
    return rd.chessboard_calibration()


def test_calibration_of_the_real_camera_converges(cal):
    res = cal.result
    assert len(cal.xy) == 14 and all(c.shape == (54, 2) for c in cal.corners)
    assert res.converged and res.redundancy == 2 * 14 * 54 - (6 * 14 + 8)
    assert np.all(res.exterior[:, 2] > 0)  # every camera on the +Z side of the board


def test_interior_orientation_agrees_with_opencv_on_the_same_corners(cal):
    """c, x'0, y'0 of cv2.calibrateCamera within 3σ of the course's adjustment."""
    s, cv = cal.sigma, cal.opencv_interior("opencv")
    for k in ("c", "x0", "y0"):
        assert abs(cv[k] - getattr(cal.result, k)) <= 3 * s[k], k


@pytest.mark.slow  # importing scipy.stats
def test_both_models_fit_equally_well(cal):
    """σ0² of the course (Δ at the measured point) and of OpenCV (at the ideal point): their
    ratio inside the two-sided 99 % F bounds for the redundancy r of both adjustments."""
    stats = pytest.importorskip("scipy.stats")
    r = cal.result.redundancy
    ratio = (cal.result.sigma0 / cal.opencv_sigma0()) ** 2
    assert stats.f.ppf(0.005, r, r) < ratio < stats.f.ppf(0.995, r, r)


def test_radial_distortion_agrees_with_opencv_within_the_data(cal):
    radii = np.linspace(20.0, cal.r_data, 12)
    rc = rd.radial_comparison(cal, radii)
    assert np.all(np.abs(rc["ours"] - rc["opencv"]) <= 3 * rc["sigma"])


def test_rays_of_both_calibrations_agree_to_the_measuring_noise(cal):
    """Inside the measured radius the two calibrations put each pixel's ray within 2σ0."""
    d = rd.ray_difference(cal)
    assert len(d["pixels"]) > 400 and d["max_px"] <= 2 * cal.result.sigma0


@pytest.mark.slow
def test_the_published_calibration_is_reproduced_with_its_corner_window(cal):
    """With cornerSubPix's (11, 11) half window the published c, x'0, y'0 lie within 3σ; with
    the chapter's 11 × 11 window the published c lies more than 3σ off: the measuring tool."""
    wide = rd.chessboard_calibration(window=(11, 11))
    pub = wide.opencv_interior("published")
    for k in ("c", "x0", "y0"):
        assert abs(pub[k] - getattr(wide.result, k)) <= 3 * wide.sigma[k], k
    assert abs(pub["c"] - cal.result.c) > 3 * cal.sigma["c"]
    assert wide.result.sigma0 > cal.result.sigma0


def test_every_view_pose_agrees_with_opencv_within_its_sigma(cal):
    """The poses of calibrateCamera (converted by exterior_from_opencv_pose) within 3σ of the
    bundle's pose of each view (σ from its exterior covariance)."""
    for k, (rvec, tvec) in enumerate(zip(cal.opencv["rvecs"], cal.opencv["tvecs"])):
        R_cv, _ = cv2.Rodrigues(rvec.reshape(3, 1))
        X0, R = pl.exterior_from_opencv_pose(R_cv, tvec)
        e, sd = cal.result.exterior[k], np.sqrt(np.diag(cal.result.exterior_covariance[k]))
        assert np.all(np.abs(X0 - e[:3]) <= 3 * sd[:3]), k
        assert np.all(np.abs(np.array(pl.opk_from_rotation(R)) - e[3:]) <= 3 * sd[3:]), k


def test_resection_of_a_real_view(cal):
    view = rd.resect_view(cal, 0)
    o = view.ours
    assert o.converged and o.redundancy == 2 * 54 - 6
    X0_same, R_same = view.same_input  # solvePnP, same points and K: the same minimum
    # ours is converged (a run to tol 1e-14 moves X0 by < 1e-11 mm); solvePnPRefineLM stops
    # short of it by up to ~1e-5 mm at 370 mm (measured 1.2e-5 mm in X on view 0, 3e-8 of
    # the distance; R by 2.6e-8): allow 5e-5 mm (1.4e-7 of the distance) and 1e-7 in R
    assert np.max(np.abs(X0_same - o.X0)) < 5e-5 and np.max(np.abs(R_same - o.R)) < 1e-7
    X0_b, R_b, cov = view.bundle  # fixed interior: the bundle's pose of this view
    assert np.max(np.abs(X0_b - o.X0)) < 1e-6 and np.max(np.abs(R_b - o.R)) < 1e-9
    X0_cv, _ = view.opencv_own  # OpenCV's own calibration, within the calibration's σ
    assert np.all(np.abs(X0_cv - o.X0) <= 3 * np.sqrt(np.diag(cov))[:3])
    with pytest.raises(ValueError, match="index must be 0 … 13, got 14"):
        rd.resect_view(cal, 14)
