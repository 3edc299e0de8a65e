"""The capstone's chain (photolib.nb.project) checked by independent routes: OpenCV's solvePnP
and triangulatePoints on the same corrected corners, the board geometry as the truth, and the
check points' errors against the precision predicted from σ0 (bounds from the noise)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import photolib as pl
from photolib.nb import project as pj

W, H = 640, 480


def _K():
    r = pj.calibration().result
    return np.array([[r.c, 0, r.x0 + (W - 1) / 2], [0, r.c, (H - 1) / 2 - r.y0], [0, 0, 1.0]])


def _opencv_pose(view, control):
    K = _K()
    px = pl.pixel_from_image(pj.image_coordinates(view)[control], W, H, 1.0)
    X = pj.board_points()[control]
    ok, rvec, tvec = cv2.solvePnP(X, px, K, None, flags=cv2.SOLVEPNP_ITERATIVE)
    assert ok
    rvec, tvec = cv2.solvePnPRefineLM(X, px, K, None, rvec, tvec,
                                      (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-15))
    R_cv = cv2.Rodrigues(rvec)[0]
    return R_cv, tvec.ravel()


def test_board_geometry_is_the_data_sets():
    import photolib.data as pdata
    cb = pdata.chessboard()
    X = pj.board_points()
    assert cb.extra["square_mm"] == 25.0 and X.shape == (54, 3)
    for k in (0, 8, 9, 53):
        row, col = pj.corner_grid(k)
        np.testing.assert_array_equal(X[k], [25.0 * col, -25.0 * row, 0.0])
    # the measured corners run along the board like the object points: neighbours in a row
    # are about one square apart in the image, rows farther apart than columns' neighbours
    px = pj.pixel_corners(0)
    assert np.all(np.linalg.norm(np.diff(px[:9], axis=0), axis=1) > 10)


@pytest.mark.parametrize("views, check", [((2, 11), [4, 13, 20, 31, 39, 48]),
                                          ((0, 5), [1, 10, 26, 33, 45, 52]),
                                          ((8, 3), [0, 17, 22, 36, 44, 53])])
def test_chain_agrees_with_opencv_and_the_board(views, check):
    ch = pj.chain(*views, check)
    P = []
    for view, res in zip(views, ch.resections):
        R_cv, t = _opencv_pose(view, list(ch.control))
        X0, R = pl.exterior_from_opencv_pose(R_cv, t)
        np.testing.assert_allclose(res.X0, X0, atol=1e-5)          # mm (two solvers' stopping rules)
        np.testing.assert_allclose(res.R, R, atol=1e-7)   # σ of the angles: 1e-3
        assert res.redundancy == 2 * len(ch.control) - 6
        # σ0 is the corner measurement noise: the calibration's σ0 within ±35 %
        assert 0.65 < res.sigma0 / pj.calibration().result.sigma0 < 1.35
        P.append(_K() @ np.column_stack([R_cv, t]))
    px = [pl.pixel_from_image(xy, W, H, 1.0) for xy in ch.xy]
    h = cv2.triangulatePoints(P[0], P[1], px[0].T, px[1].T)
    X_cv = (h[:3] / h[3]).T
    # algebraic (OpenCV) and geometric (photolib) intersection: a fifth of the σ at most
    assert np.all(np.abs(ch.points - X_cv) < 0.2 * ch.predicted)
    # the accuracy at the check points: no error beyond 4σ of its prediction, RMS within
    # what six points' chi distribution allows (ratio 0.3 … 2.5 covers > 99.9 %)
    assert np.all(np.abs(ch.errors) < 4 * ch.predicted)
    assert 0.3 < ch.rms / ch.predicted_rms < 2.5
    np.testing.assert_array_equal(ch.true, pj.board_points()[list(check)])


def test_predicted_precision_matches_a_monte_carlo_of_the_image_noise():
    """σ0 on the check points' image coordinates alone (orientations fixed): the propagated σ
    agrees with the scatter of intersections of noisy coordinates (400 draws, ±15 %)."""
    ch = pj.chain(2, 11, [4, 13, 20, 31, 39, 48])
    ra, rb = ch.resections
    s = 0.15
    zero = [type(ra)(*(np.zeros((6, 6)) if f == "covariance" else getattr(r, f)
                      for f in r.__dataclass_fields__)) for r in (ra, rb)]
    predicted = pj.predicted_precision(*zero, *ch.xy, s)
    rng = np.random.default_rng(7)
    cam = pj.calibration().result
    runs = [pl.forward_intersection(np.stack([ch.xy[0] + rng.normal(0, s, ch.xy[0].shape),
                                              ch.xy[1] + rng.normal(0, s, ch.xy[1].shape)]),
                                    [ra.X0, rb.X0], [ra.R, rb.R], cam.c, cam.x0, cam.y0).points
            for _ in range(400)]
    np.testing.assert_allclose(np.std(runs, axis=0), predicted, rtol=0.15)


def test_bad_input_is_refused_with_the_value():
    with pytest.raises(ValueError, match="differ"):
        pj.chain(3, 3, [1, 2])
    with pytest.raises(ValueError, match="54"):
        pj.corner_grid(54)
    with pytest.raises(ValueError, match="view"):
        pj.image_coordinates(14)
    with pytest.raises(ValueError, match="control"):
        pj.resect(0, [1, 2, 3])


def test_pairs_have_a_usable_intersection_angle():
    assert len(pj.PAIRS) >= 50
    assert all(pj.intersection_angle(a, b) >= pj.MIN_ANGLE_DEG for a, b in pj.PAIRS)
    rng = np.random.default_rng(0)
    chk = pj.draw_check_points(rng)
    assert len(set(chk)) == 6 and {pj.corner_grid(k)[0] // 3 for k in chk} == {0, 1}
