"""NCC matching and RANSAC against independent routes.

OpenCV's ``matchTemplate`` (TM_CCOEFF_NORMED) and a per-window ``np.corrcoef`` for the
correlation surface; SciPy's ``ndimage.shift`` of a smooth texture for the subpixel peak, refined
by photolib's least-squares matching; a Monte-Carlo count of clean samples for the number of
trials; OpenCV's ``findHomography`` (RANSAC) and a relative orientation inside the loop.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage

import photolib as pl
from photolib.correlation import (ncc_match, normalised_cross_correlation, ransac,
                                  ransac_trials)
from photolib.stereo import coplanarity_residuals
from photolib.transforms import DegenerateGeometryError


def _texture(rng, shape, smooth=1.5):
    return ndimage.gaussian_filter(rng.standard_normal(shape), smooth) * 50 + 128


def test_surface_is_the_per_window_correlation_coefficient():
    rng = np.random.default_rng(1)
    g = _texture(rng, (24, 30))
    f = _texture(rng, (7, 9))
    rho = normalised_cross_correlation(f, g)
    brute = np.array([[np.corrcoef(f.ravel(), g[r:r + 7, c:c + 9].ravel())[0, 1]
                       for c in range(30 - 9 + 1)] for r in range(24 - 7 + 1)])
    np.testing.assert_allclose(rho, brute, atol=1e-12)


def test_surface_matches_opencv_matchTemplate():
    rng = np.random.default_rng(2)
    g = _texture(rng, (60, 80)).astype(np.float32)
    f = g[20:41, 30:51].copy()
    rho = normalised_cross_correlation(f, g)
    cv = cv2.matchTemplate(g, f, cv2.TM_CCOEFF_NORMED)
    assert rho.shape == cv.shape
    np.testing.assert_allclose(rho, cv, atol=1e-4)   # OpenCV sums grey values ~128 in float32
    assert np.unravel_index(np.argmax(rho), rho.shape) == (20, 30)


@pytest.mark.parametrize("shift", [(0.0, 0.0), (0.3, -0.2), (-0.45, 0.4), (2.25, 1.7)])
def test_subpixel_peak_and_lsm_refinement(shift):
    """A smooth texture shifted by (dcol, drow): NCC finds it to 0.15 px, LSM to 0.02 px."""
    rng = np.random.default_rng(3)
    base = _texture(rng, (80, 80), smooth=2.5)
    moved = ndimage.shift(base, (shift[1], shift[0]), order=3, mode="nearest")
    template = base[30:51, 30:51]
    m = ncc_match(template, moved[10:70, 10:70])
    true = np.array([40.0 + shift[0], 40.0 + shift[1]]) - 10.0      # centre (col, row)
    assert np.abs(m.position - true).max() < 0.15
    assert m.rho > 0.97
    lsm = pl.least_squares_matching(template, moved[10:70, 10:70], m.position)
    assert np.abs(np.array([lsm.params[0], lsm.params[3]]) - true).max() < 0.02


def test_flat_windows_and_bad_matches_are_refused():
    rng = np.random.default_rng(4)
    g = _texture(rng, (40, 40))
    g[:, :15] = 7.0                                                  # a flat strip
    rho = normalised_cross_correlation(g[5:14, 20:29], g)
    assert np.isnan(rho[:, :7]).all() and np.isfinite(rho[:, 7:]).all()
    with pytest.raises(ValueError, match="template is constant"):
        normalised_cross_correlation(np.ones((5, 5)), g)
    with pytest.raises(ValueError, match="smaller than the template"):
        normalised_cross_correlation(g, g[:10, :10])
    with pytest.raises(ValueError, match="border of the search area"):
        ncc_match(g[0:9, 20:29], g[0:20, 10:40])
    with pytest.raises(ValueError, match="no match"):
        ncc_match(_texture(np.random.default_rng(9), (9, 9)), g, min_rho=0.99)
    with pytest.raises(ValueError, match="2-D"):
        normalised_cross_correlation(np.ones((3, 3, 3)), g)


@pytest.mark.parametrize("eps, s", [(0.3, 4), (0.5, 4), (0.4, 5)])
def test_trials_give_the_confidence_in_a_monte_carlo_count(eps, s):
    """Samples of s from 1000 correspondences with ε·1000 outliers, drawn without replacement:
    the j-th point of a sample is clean with probability (n − k − j)/(n − j) given clean
    predecessors (the hypergeometric draw, simulated point by point)."""
    rng = np.random.default_rng(5)
    n, k, runs = 1000, int(eps * 1000), 4000
    N = ransac_trials(0.99, eps, s)
    p_next = np.array([(n - k - j) / (n - j) for j in range(s)])
    clean = np.all(rng.random((runs, N, s)) < p_next, axis=2)
    success_N = clean.any(axis=1).mean()
    success_half = clean[:, :N // 2].any(axis=1).mean()
    assert success_N >= 0.99 - 3 * np.sqrt(0.99 * 0.01 / runs)
    assert success_half < 0.97


def test_trials_formula_edges():
    assert ransac_trials(0.99, 0.0, 4) == 1
    with pytest.raises(ValueError, match="confidence"):
        ransac_trials(1.0, 0.3, 4)
    with pytest.raises(ValueError, match="outlier_ratio"):
        ransac_trials(0.99, 1.0, 4)


def _homography_data(rng, n=60, outliers=18, noise=0.2):
    T = pl.ProjectiveTransform(15, 1.05, 0.12, -8, -0.08, 0.97, 4e-4, -3e-4)
    src = rng.uniform(0, 500, (n, 2))
    dst = T(src) + noise * rng.standard_normal((n, 2))
    bad = rng.choice(n, outliers, replace=False)
    dst[bad] += rng.uniform(15, 60, (outliers, 2)) * rng.choice([-1, 1], (outliers, 2))
    return src, dst, bad


def test_homography_ransac_finds_opencvs_inliers_and_refits_them():
    rng = np.random.default_rng(6)
    src, dst, bad = _homography_data(rng)
    res = ransac(len(src), 4, lambda i: pl.ProjectiveTransform.from_estimate(src[i], dst[i]),
                 lambda T: np.linalg.norm(T(src) - dst, axis=1), 1.5, rng=7)
    truth = np.ones(len(src), bool)
    truth[bad] = False
    np.testing.assert_array_equal(res.inliers, truth)
    _, mask = cv2.findHomography(src, dst, cv2.RANSAC, 1.5)
    np.testing.assert_array_equal(res.inliers, mask.ravel().astype(bool))
    clean = pl.ProjectiveTransform.from_estimate(src[truth], dst[truth])
    np.testing.assert_allclose(list(res.model.params.values()), list(clean.params.values()),
                               rtol=1e-9, atol=1e-12)
    assert res.trials <= res.required_trials + 1 and res.required_trials < 100


def test_relative_orientation_inside_the_loop():
    rng = np.random.default_rng(8)
    X = rng.uniform([-4, -4, -22], [14, 4, -18], (40, 3))
    base, R2, c = np.array([10.0, 0.4, -0.3]), pl.rotation_opk(0.02, -0.03, 0.05), 50.0
    xy1 = pl.project(X, np.zeros(3), np.eye(3), c) + 0.002 * rng.standard_normal((40, 2))
    xy2 = pl.project(X, base, R2, c) + 0.002 * rng.standard_normal((40, 2))
    xy2[:8, 1] += rng.uniform(0.2, 0.5, 8)                          # y-parallax blunders
    x1 = np.column_stack([xy1, np.full(40, -c)])
    x2 = np.column_stack([xy2, np.full(40, -c)])

    def fit(i):
        return pl.relative_orientation(xy1[i], xy2[i], c, bx=10.0)

    def residuals(ro):
        return np.abs(coplanarity_residuals(ro.params, x1, x2, 10.0, c)[0])

    res = ransac(40, 5, fit, residuals, 0.015, rng=3)              # 5σ of the y-parallax
    assert not res.inliers[:8].any() and res.inliers[8:].all()
    clean = fit(np.arange(8, 40))
    np.testing.assert_allclose(res.model.params, clean.params, atol=1e-10)


def test_ransac_without_consensus_says_so():
    rng = np.random.default_rng(9)
    src, dst = rng.uniform(0, 100, (20, 2)), rng.uniform(0, 100, (20, 2))
    with pytest.raises(DegenerateGeometryError, match="no model supported by more than its own 4"):
        ransac(20, 4, lambda i: pl.ProjectiveTransform.from_estimate(src[i], dst[i]),
               lambda T: np.linalg.norm(T(src) - dst, axis=1), 1e-6, rng=1, max_trials=50)
    with pytest.raises(ValueError, match="fewer than the sample size"):
        ransac(3, 4, lambda i: None, lambda m: np.zeros(3), 1.0)
