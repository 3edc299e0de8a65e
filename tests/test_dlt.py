"""DLT: synthetic camera round trips, OpenCV's decomposition, Luhmann's 4.26 checked."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from photolib import project, rotation_opk
from photolib.dlt import dlt_decompose, dlt_estimate, dlt_from_camera
from photolib.transforms import DegenerateGeometryError


def _scene(rng, n=20):
    X = rng.uniform([-10, -10, -3], [10, 10, 3], (n, 3))
    X0 = np.array([2.0, -3.0, 40.0]) + rng.normal(0, 2, 3)
    angles = rng.uniform(-0.3, 0.3, 3)
    return X, X0, angles


def test_synthetic_camera_is_recovered():
    rng = np.random.default_rng(30)
    X, X0, (om, ph, ka) = _scene(rng)
    R = rotation_opk(om, ph, ka)
    xy = project(X, X0, R, c=35.0, x0=0.12, y0=-0.08)
    est = dlt_estimate(X, xy)
    assert est.redundancy == 2 * 20 - 11 and est.sigma0 < 1e-9
    d = dlt_decompose(est)
    assert (d.c_x, d.c_y, d.x0, d.y0, d.skew) == pytest.approx((35.0, 35.0, 0.12, -0.08, 0.0), abs=1e-7)
    assert np.allclose(d.X0, X0, atol=1e-7) and np.allclose(d.R, R, atol=1e-9)
    assert (d.omega, d.phi, d.kappa) == pytest.approx((om, ph, ka), abs=1e-9)


def test_noisy_estimate_has_sigma0_of_the_noise_and_reprojects():
    rng = np.random.default_rng(31)
    X, X0, angles = _scene(rng, n=300)
    xy = project(X, X0, rotation_opk(*angles), c=35.0) + rng.normal(0, 0.002, (300, 2))
    est = dlt_estimate(X, xy)
    assert est.sigma0 == pytest.approx(0.002, rel=0.15)
    d = dlt_decompose(est.L)
    assert np.allclose(d.X0, X0, atol=0.2) and d.c_x == pytest.approx(35.0, rel=0.01)


@pytest.mark.parametrize("seed", range(5))
def test_round_trip_L_decompose_recompose(seed):
    """Any L with a non-singular 3×3 part (shear included) survives decompose → recompose."""
    rng = np.random.default_rng(seed)
    L = dlt_from_camera(rng.uniform(20, 60), rng.uniform(20, 60), *rng.normal(0, 1, 2),
                        rng.normal(0, 20, 3), rotation_opk(*rng.uniform([-3, -1.4, -3], [3, 1.4, 3])),
                        skew=rng.normal(0, 0.5))
    d = dlt_decompose(L)
    assert d.c_x > 0 and d.c_y > 0 and np.linalg.det(d.R) == pytest.approx(1.0)
    assert np.allclose(d.R.T @ d.R, np.eye(3), atol=1e-12)
    L2 = dlt_from_camera(d.c_x, d.c_y, d.x0, d.y0, d.X0, d.R, skew=d.skew)
    assert np.allclose(L2, L, rtol=1e-9, atol=1e-12)


def test_matches_opencv_decompose_projection_matrix():
    """OpenCV's camera looks along +z with y down: P_cv = diag(1, −1, 1)·[A | b]."""
    R = rotation_opk(0.2, -0.1, 0.7)
    X0 = np.array([3.0, -4.0, 25.0])
    L = dlt_from_camera(30.0, 31.0, 0.3, -0.2, X0, R, skew=0.4)
    P = np.diag([1.0, -1.0, 1.0]) @ np.append(L, 1.0).reshape(3, 4)
    K, Rcv, C = cv2.decomposeProjectionMatrix(P)[:3]
    K = K / K[2, 2]
    d = dlt_decompose(L)
    assert np.allclose(K, [[d.c_x, d.skew, d.x0], [0, d.c_y, -d.y0], [0, 0, 1]], atol=1e-9)
    assert np.allclose(Rcv, np.diag([1.0, -1.0, -1.0]) @ d.R.T, atol=1e-9)
    assert np.allclose(C[:3, 0] / C[3, 0], d.X0, atol=1e-9)


def _luhmann_4_26(L, negate=False):
    """4.26 as printed: L = −1/|(L9, L10, L11)|, no shear term, r11 = L(x0·L9 − L1)/c_x, …"""
    a1, a2, a3 = np.asarray(L[0:3]), np.asarray(L[4:7]), np.asarray(L[8:11])
    Ls = -1.0 / np.linalg.norm(a3) * (-1 if negate else 1)
    x0, y0 = Ls**2 * (a1 @ a3), Ls**2 * (a2 @ a3)
    cx = np.sqrt(Ls**2 * (a1 @ a1) - x0**2)
    cy = np.sqrt(Ls**2 * (a2 @ a2) - y0**2)
    R = np.column_stack([Ls * (x0 * a3 - a1) / cx, Ls * (y0 * a3 - a2) / cy, Ls * a3])
    return cx, cy, x0, y0, R


@pytest.mark.parametrize("origin_in_front", [True, False])
def test_luhmann_4_26_sign_rule(origin_in_front):
    """L = −1/|…| is right iff the object origin is in front (N < 0); otherwise det R < 0."""
    R = rotation_opk(0.1, 0.2, -0.3)
    X0 = np.array([1.0, 2.0, 30.0])
    if not origin_in_front:  # look up, away from the origin below
        R = R @ rotation_opk(np.pi, 0.0, 0.0)
    L = dlt_from_camera(40.0, 41.0, 0.2, -0.1, X0, R)
    N_origin = (R.T @ (-X0))[2]
    assert (N_origin < 0) == origin_in_front
    cx, cy, x0, y0, R_l = _luhmann_4_26(L)
    assert (np.linalg.det(R_l) > 0) == origin_in_front
    if not origin_in_front:  # the errata's rule: negate L if det R < 0
        cx, cy, x0, y0, R_l = _luhmann_4_26(L, negate=True)
    d = dlt_decompose(L)
    assert np.allclose([cx, cy, x0, y0], [d.c_x, d.c_y, d.x0, d.y0], atol=1e-9)
    assert np.allclose(R_l, d.R, atol=1e-9) and np.allclose(d.R, R, atol=1e-9)


def test_luhmann_4_26_ignores_the_shear():
    L = dlt_from_camera(40.0, 41.0, 0.2, -0.1, [1.0, 2.0, 30.0], rotation_opk(0.1, 0.2, -0.3), skew=1.5)
    cx, _, _, _, R_l = _luhmann_4_26(L)
    d = dlt_decompose(L)
    assert cx == pytest.approx(np.hypot(d.c_x, d.skew), rel=1e-12)  # 4.26's c_x = sqrt(c_x² + s²)
    assert abs(R_l[:, 0] @ R_l[:, 1]) > 1e-3  # its R is not orthogonal
    assert np.allclose(d.R.T @ d.R, np.eye(3), atol=1e-12)


def test_bad_input():
    rng = np.random.default_rng(33)
    X, X0, angles = _scene(rng)
    xy = project(X, X0, rotation_opk(*angles), c=35.0)
    flat = X.copy()
    flat[:, 2] = 0.5 * flat[:, 0] - 2.0  # all in one (tilted) plane
    with pytest.raises(ValueError, match="coplanar"):
        dlt_estimate(flat, xy)
    with pytest.raises(ValueError, match="at least 6 points, got 5"):
        dlt_estimate(X[:5], xy[:5])
    with pytest.raises(ValueError, match=r"xy has shape \(20, 3\)"):
        dlt_estimate(X, np.column_stack([xy, xy[:, 0]]))
    bad = X.copy()
    bad[3, 2] = np.nan
    with pytest.raises(ValueError, match=r"X contains a non-finite value nan at index \(3, 2\)"):
        dlt_estimate(bad, xy)
    with pytest.raises(ValueError, match="X has 20 points but xy has 19"):
        dlt_estimate(X, xy[:-1])
    with pytest.raises(ValueError, match=r"L has shape \(12,\)"):
        dlt_decompose(np.ones(12))
    with pytest.raises(ValueError, match="singular"):
        dlt_decompose(np.r_[1, 2, 3, 0, 2, 4, 6, 0, 1, 1, 1.0])


def test_errata_example_4_3():
    """The errata's corrected L of example 4.3 (printed to 6 decimals, so L9…L11 have only
    2–3 digits) give its exterior orientation within that rounding. Its principal point
    (−3.7708, 3.8404) has the opposite sign of ours (+3.83, −4.10) although its printed r11
    formula is only consistent with ours (see the module docstring of photolib.dlt)."""
    L = [0.025599, 0.000789, 0.000914, 10.341817, -0.000347, 0.025008, -0.008166, 4.986816,
         0.000082, -0.000239, -0.000551]
    d = dlt_decompose(L)
    assert np.allclose(d.X0, [-471.12, 318.14, 1604.96], rtol=0, atol=2.0)  # mm, of ~1700 mm
    assert np.degrees([d.omega, d.phi, d.kappa]) == pytest.approx([-23.405, -7.767, 0.031], abs=0.05)
    assert (d.c_x, d.c_y) == pytest.approx((42.0688, 43.1747), rel=1e-3)
    assert d.x0 * -3.7708 < 0 and d.y0 * 3.8404 < 0


# -- input handling (red-team audit) --------------------------------------------------------------

def test_coincident_or_collinear_image_points_are_refused():
    """Coincident image points made the normaliser divide by 0 (LinAlgError 'SVD did not
    converge'); collinear ones gave an L with σ0 ≈ 1e-14 as if all were well."""
    rng = np.random.default_rng(34)
    X, X0, angles = _scene(rng)
    xy = project(X, X0, rotation_opk(*angles), c=35.0)
    with pytest.raises(DegenerateGeometryError, match=r"image points \(nearly\) coincide"):
        dlt_estimate(X, np.ones((len(X), 2)))
    near = xy.mean(axis=0) + 1e-9 * rng.standard_normal(xy.shape)   # 1 pm of spread
    with pytest.raises(DegenerateGeometryError, match=r"image points \(nearly\) coincide"):
        dlt_estimate(X, near)
    line = np.column_stack([np.arange(len(X), dtype=float)] * 2)
    with pytest.raises(DegenerateGeometryError, match="image points are collinear"):
        dlt_estimate(X, line)
    flat = X * [1, 1, 0]
    with pytest.raises(DegenerateGeometryError, match="object points are coplanar"):
        dlt_estimate(flat, xy)


def test_dlt_decompose_names_a_non_numeric_L():
    with pytest.raises(ValueError, match=r"L must be numeric with shape \(11,\), got 'abc'"):
        dlt_decompose("abc")


def test_many_points_in_bounded_memory():
    """3e4 points: the design matrix has 6e4 rows, whose full SVD would build a 6e4 × 6e4 U
    (29 GB); the estimate recovers the synthetic camera."""
    rng = np.random.default_rng(33)
    X, X0, angles = _scene(rng, n=30_000)
    R = rotation_opk(*angles)
    est = dlt_estimate(X, project(X, X0, R, c=35.0, x0=0.12, y0=-0.08))
    d = dlt_decompose(est)
    assert est.sigma0 < 1e-9 and np.allclose(d.X0, X0, atol=1e-6) and np.allclose(d.R, R, atol=1e-9)
