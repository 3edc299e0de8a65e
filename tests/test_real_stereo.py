"""Stereo depth on the real Middlebury motorcycle pair against its ground truth.

The bounds come from the data: σ_d is the robust spread of the measured disparities about the
ground truth (what the chapter uses), and the depth errors must follow the propagated
σ_Z = Z²/(f·B)·σ_d — on the motorcycle and on the background twice as far, where a
prediction linear in Z would be too small by the factor of the distances.
"""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib import data

pytest.importorskip("skimage")


def _mad(a):
    return 1.4826 * np.median(np.abs(a - np.median(a)))


@pytest.fixture(scope="module")
def depth():
    from photolib.nb import stereo as ns
    return ns.real_depth(n=300)


def test_most_points_match_and_sigma_d_is_subpixel(depth):
    assert len(depth["d"]) >= 200
    # the chapter's matcher: 11 × 11 NCC with a parabola, so subpixel but not better than the
    # 0.05 px the least-squares matching reports internally
    assert 0.05 < depth["sigma_d"] < 0.5


def test_disparity_errors_are_centred(depth):
    e = depth["d"] - depth["d_true"]
    # the median of N errors of robust σ is known to ~1.25·σ/√N; allow 4 of that
    assert abs(np.median(e)) < 4 * 1.25 * depth["sigma_d"] / np.sqrt(len(e))


def test_depth_errors_follow_the_propagated_sigma_near_and_far(depth):
    near = -depth["Z_true"] < 3000.0
    assert near.sum() > 50 and (~near).sum() > 10
    for m in (near, ~near):
        z = depth["dZ"][m] / depth["sigma_Z"][m]
        # the robust σ of k normalised errors scatters by ~1.65/√(2k) (MAD efficiency)
        assert abs(_mad(z) - 1.0) < 0.1 + 4 * 1.65 / np.sqrt(2 * m.sum())
    # and a prediction linear in Z (σ = |Z|/f·σ_d·const fitted on the near points) misses the far
    k = _mad(depth["dZ"][near]) / np.median(-depth["Z_true"][near])
    far_linear = k * np.median(-depth["Z_true"][~near])
    far_sq = np.median(depth["sigma_Z"][~near])
    assert far_sq > 1.3 * far_linear


def test_depth_is_the_middlebury_formula(depth):
    cal = data.motorcycle().calibration
    # Middlebury's own definition of depth: Z = baseline·f/(d + doffs), as a distance
    dist = cal.baseline_mm * cal.f_px / (depth["d"] + cal.doffs_px)
    np.testing.assert_allclose(-depth["Z"], dist, rtol=1e-12)


def test_points_from_disparity_reproject_into_both_images():
    cal = data.motorcycle().calibration
    rng = np.random.default_rng(5)
    u, v, d = rng.uniform(50, 700, 20), rng.uniform(20, 480, 20), rng.uniform(10, 60, 20)
    X = pl.points_from_disparity(u, v, d, cal.f_px, cal.baseline_mm, cal.cx_px, cal.cy_px,
                                 cal.doffs_px)
    # project with the collinearity equations in pixels (pitch 1: c = f, y' = −(v − cy))
    x1 = pl.project(X, [0, 0, 0], np.eye(3), cal.f_px)
    x2 = pl.project(X, [cal.baseline_mm, 0, 0], np.eye(3), cal.f_px)
    np.testing.assert_allclose(x1[:, 0] + cal.cx_px, u, atol=1e-9)
    np.testing.assert_allclose(-x1[:, 1] + cal.cy_px, v, atol=1e-9)
    np.testing.assert_allclose(x2[:, 0] + cal.cx_px + cal.doffs_px, u - d, atol=1e-9)


def test_sympy_derivation_is_the_library():
    import sympy as sp

    from photolib.derive import stereo as ds
    Xs, Ys, Zs = ds.depth_from_disparity()
    vals = {ds.u1: 400.0, ds.v_row: 100.0, ds.d_px: 40.0, ds.doffs: 31.0, ds.f_px: 995.0,
            ds.B: 193.0, ds.cx1: 311.0, ds.cy: 255.0}
    lib = pl.points_from_disparity(400.0, 100.0, 40.0, 995.0, 193.0, 311.0, 255.0, 31.0)
    np.testing.assert_allclose([float(e.subs(vals)) for e in (Xs, Ys, Zs)], lib, rtol=1e-12)
    s = ds.sigma_depth_disparity().subs({ds.Z_depth: -2500.0, ds.f_px: 995.0, ds.B: 193.0,
                                         ds.s_d: 0.2})
    assert float(s) == pytest.approx(pl.depth_sigma(-2500.0, 995.0, 193.0, 0.2), rel=1e-12)
    assert sp.simplify(Zs + ds.f_px * ds.B / (ds.d_px + ds.doffs)) == 0


@pytest.mark.parametrize("bad, err", [(-31.086, "zero parallax"), (-40.0, "behind")])
def test_degenerate_disparities_are_refused(bad, err):
    with pytest.raises(ValueError, match=err):
        pl.depth_from_disparity(bad, 994.978, 193.001, 31.086)


def test_fundamental_of_the_rectified_pair_is_the_normal_case(depth):
    left = depth["points"]
    right = left - np.column_stack([depth["d"], np.zeros(len(left))])
    F, inl = pl.estimate_fundamental_ransac(left, right, 1.0, rng=0)
    F_normal = np.array([[0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]]) / np.sqrt(2)
    assert inl.mean() > 0.9
    assert min(np.abs(F - F_normal).max(), np.abs(F + F_normal).max()) < 1e-6


@pytest.mark.parametrize("name", ["building2", "rocks2"])
def test_fundamental_of_an_unrectified_pair_agrees_with_opencv(name):
    cv2 = pytest.importorskip("cv2")
    from photolib.nb import stereo as ns
    e = ns.real_epipolar(name)
    x1, x2 = e["x1"][e["inliers"]], e["x2"][e["inliers"]]
    assert len(x1) > 100 and np.median(e["distances"]) < 0.3
    F_cv = cv2.findFundamentalMat(x1, x2, cv2.FM_8POINT)[0].T
    d_cv = pl.epipolar_distances(F_cv / np.linalg.norm(F_cv), x1, x2)
    # both least-squares fits explain the same matches equally well (within 10 %)
    assert np.median(e["distances"]) < 1.1 * np.median(d_cv)


def test_estimate_fundamental_refuses_degenerate_input():
    with pytest.raises(ValueError, match="at least 8"):
        pl.estimate_fundamental(np.zeros((7, 2)), np.zeros((7, 2)))
    line = np.column_stack([np.arange(10.0), 2 * np.arange(10.0)])
    with pytest.raises(ValueError, match="do not determine F"):
        pl.estimate_fundamental(line, line + 1.0)
