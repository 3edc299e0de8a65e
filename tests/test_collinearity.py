"""Projection against cv2.projectPoints, Jacobian against finite differences and Luhmann 4.18."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import sympy as sp

import photolib as pl
from photolib.derive import collinearity as dcol


def _scene(seed=0, n=200):
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-40, 40, n), rng.uniform(-30, 30, n), rng.uniform(-5, 15, n)])
    X0 = np.array([3.0, -2.0, 300.0])
    R = pl.rotation_opk(0.04, -0.06, 0.7)
    return X, X0, R


def _cv_project(X, X0, R, c, x0, y0, dist_cv=None):
    # R_cv = diag(1,−1,−1)·Rᵀ, t = −R_cv·X0; pixel = image (mm) with y flipped
    Rcv, t = pl.opencv_pose_from_exterior(X0, R)
    rvec, _ = cv2.Rodrigues(Rcv)
    K = np.array([[c, 0, x0], [0, c, -y0], [0, 0, 1.0]])
    p, _ = cv2.projectPoints(X, rvec, t, K, dist_cv)
    p = p.reshape(-1, 2)
    return np.column_stack([p[:, 0], -p[:, 1]])


def test_project_matches_opencv():
    X, X0, R = _scene()
    got = pl.project(X, X0, R, c=100.0, x0=0.12, y0=-0.3)
    np.testing.assert_allclose(got, _cv_project(X, X0, R, 100.0, 0.12, -0.3), atol=1e-10)


def test_project_with_distortion_matches_opencv_forward_model():
    """Our distortion is evaluated at the measured point: the measured point m must satisfy
    m − Δ(m) = ideal; OpenCV applies its model at the ideal point. Convert our model to
    OpenCV by least squares and compare within the fit's own residual."""
    X, X0, R = _scene(1)
    c = 50.0
    d = pl.Distortion(A1=-4e-5, A2=2e-8, B1=3e-6, B2=-5e-6)
    fit = d.to_opencv(c, 20.0, 20.0, n=31)
    got = pl.project(X, X0, R, c, distortion=d)
    ideal = pl.project(X, X0, R, c)
    np.testing.assert_allclose(d.correct(got), ideal, atol=1e-9)
    cv = _cv_project(X, X0, R, c, 0.0, 0.0, np.array(fit.coefficients))
    inside = np.all(np.abs(ideal) <= 20.0, axis=1)
    err_um = np.hypot(*(got[inside] - cv[inside]).T) * 1000
    assert err_um.max() <= fit.max_um * 1.5 + 1e-6


def test_single_point_keeps_rank():
    X, X0, R = _scene()
    assert pl.project(X[0], X0, R, 100.0).shape == (2,)
    assert pl.collinearity_jacobian(X[0], X0, R, 100.0).shape == (2, 9)


def test_point_behind_camera_raises_or_flags():
    X, X0, R = _scene()
    X = X.copy()
    X[5, 2] = 400.0  # above the camera
    with pytest.raises(pl.PointBehindCameraError, match=r"X\[5\].*N = .*≥ 0"):
        pl.project(X, X0, R, 100.0)
    xy, valid = pl.project(X, X0, R, 100.0, return_valid=True)
    assert not valid[5] and valid.sum() == len(X) - 1
    assert np.isnan(xy[5]).all() and np.isfinite(xy[valid]).all()


@pytest.mark.parametrize("bad,match", [
    (dict(c=0.0), "c must be > 0"), (dict(c=-50.0), "c must be > 0"),
    (dict(c=float("nan")), "c must be finite"), (dict(X=np.ones((4, 2))), r"X has shape \(4, 2\)"),
    (dict(X0=[0.0, 1.0]), r"X0 has shape \(2,\)"), (dict(R=np.ones((3, 3))), "not orthonormal"),
    (dict(X=[[0.0, np.nan, 0.0]]), r"X contains a non-finite value nan at index \(0, 1\)"),
])
def test_project_bad_input(bad, match):
    args = dict(X=np.zeros((1, 3)), X0=[0.0, 0.0, 10.0], R=np.eye(3), c=50.0)
    args.update(bad)
    with pytest.raises(ValueError, match=match):
        pl.project(**args)


def test_jacobian_against_finite_differences():
    X, X0, R = _scene(2, n=20)
    c = 80.0
    w, p, k = pl.opk_from_rotation(R)
    J = pl.collinearity_jacobian(X, X0, R, c)

    def f(params):
        X0_, ang, Xp = params[:3], params[3:6], params[6:]
        return pl.project(Xp, X0_, pl.rotation_opk(*ang), c)

    for i in range(len(X)):
        base = np.concatenate([X0, [w, p, k], X[i]])
        num = np.zeros((2, 9))
        for j in range(9):
            h = 1e-6 if j in (3, 4, 5) else 1e-4
            e = np.zeros(9)
            e[j] = h
            num[:, j] = (f(base + e) - f(base - e)) / (2 * h)
        np.testing.assert_allclose(J[i], num, rtol=1e-6, atol=1e-7)


def test_jacobian_needs_angles_at_gimbal_lock():
    R = pl.rotation_opk(0.2, np.pi / 2, 0.1)
    X0 = np.zeros(3)
    X = np.array([[1.0, 2.0, -50.0]])
    if (R.T @ (X[0] - X0))[2] >= 0:
        X = -X
    with pytest.raises(pl.GimbalLockError):
        pl.collinearity_jacobian(X, X0, R, 50.0)
    J = pl.collinearity_jacobian(X, X0, R, 50.0, angles=(0.2, np.pi / 2, 0.1))
    assert np.isfinite(J).all()
    with pytest.raises(ValueError, match="do not give R"):
        pl.collinearity_jacobian(X, X0, R, 50.0, angles=(0.0, 0.0, 0.0))


def _luhmann_418b(version):
    """Luhmann 4.18b ∂y'/∂φ as printed: 'old' and 'corrected' (z' = −c, k_x, k_y, N)."""
    kx, ky, N, zp = dcol.luhmann_symbols()
    k = dcol.kappa
    if version == "old":
        return zp / N * (ky / N * (kx * sp.cos(k) + ky * sp.sin(k)) + N * sp.sin(k))
    return zp / N * (ky / N * (ky * sp.sin(k) - kx * sp.cos(k)) + N * sp.sin(k))


@pytest.mark.parametrize("version,matches", [("corrected", True), ("old", False)])
def test_luhmann_418b_against_the_derivation(version, matches):
    """The derivative from SymPy's diff (not from the print) decides which 4.18b is right."""
    J = dcol.jacobian()
    kx, ky, N, zp = dcol.luhmann_symbols()
    kvec = dcol.k_vector()
    subs = {kx: kvec[0], ky: kvec[1], N: kvec[2], zp: -dcol.c}
    diff = _luhmann_418b(version).subs(subs) - J["phi"][1]
    rng = np.random.default_rng(3)
    vals = []
    for _ in range(5):
        point = {s: rng.uniform(-1, 1) for s in diff.free_symbols}
        point[dcol.Z0] = 10.0
        point[dcol.c] = 1.5
        vals.append(abs(float(diff.subs(point))))
    assert (max(vals) < 1e-12) == matches


def test_luhmann_form_equals_diff_for_every_entry():
    J, L = dcol.jacobian(), dcol.luhmann_418()
    kx, ky, N, zp = dcol.luhmann_symbols()
    kvec = dcol.k_vector()
    subs = {kx: kvec[0], ky: kvec[1], N: kvec[2], zp: -dcol.c}
    rng = np.random.default_rng(4)
    for name in dcol.PARAMETERS:
        for i in range(2):
            e = L[name][i].subs(subs) - J[name][i]
            point = {s: rng.uniform(-1, 1) for s in e.free_symbols}
            point[dcol.Z0], point[dcol.c] = 10.0, 2.0
            assert abs(float(e.subs(point))) < 1e-12, (name, i)


def test_collinearity_derivation_is_consistent():
    assert dcol.collinear_check() == sp.zeros(3, 1)


def test_monoplot_inverts_projection():
    X, X0, R = _scene(5)
    X[:, 2] = 2.5
    d = pl.Distortion(A1=-3e-5, B1=2e-6)
    xy = pl.project(X, X0, R, 60.0, 0.1, -0.05, distortion=d)
    back = pl.monoplot(xy, X0, R, 60.0, 2.5, 0.1, -0.05, distortion=d)
    np.testing.assert_allclose(back, X, atol=1e-8)


def test_monoplot_rejects_rays_missing_the_plane():
    with pytest.raises(ValueError, match="behind the camera"):
        pl.monoplot([0.0, 0.0], [0.0, 0.0, 10.0], np.eye(3), 50.0, Z=20.0)
    R = pl.rotation_opk(np.pi / 2, 0.0, 0.0)  # looking horizontally
    with pytest.raises(ValueError, match="parallel"):
        pl.monoplot([0.0, 0.0], [0.0, 0.0, 10.0], R, 50.0, Z=0.0)


def test_projection_of_large_n_is_blockwise_identical():
    rng = np.random.default_rng(7)
    n = 3 * 8192 + 17
    X = np.column_stack([rng.uniform(-50, 50, n), rng.uniform(-50, 50, n), rng.uniform(0, 10, n)])
    X0, R = np.array([0.0, 0.0, 500.0]), pl.rotation_opk(0.01, 0.02, 0.3)
    k = (X - X0) @ R
    want = np.column_stack([-100 * k[:, 0] / k[:, 2], -100 * k[:, 1] / k[:, 2]])
    np.testing.assert_allclose(pl.project(X, X0, R, 100.0), want, rtol=1e-13, atol=1e-12)


# -- input handling (red-team audit) --------------------------------------------------------------

def test_project_with_distortion_and_no_point_in_front():
    """All points behind the camera, or none at all, with distortion: NaN rows / an empty
    result (was 'zero-size array to reduction operation maximum' from Distortion.distort)."""
    X, X0, R = _scene(n=7)
    d = pl.Distortion(A1=-1e-6, B1=1e-6)
    behind = X0 + [0.0, 0.0, 100.0] + X * 0.1            # all above the camera
    xy, valid = pl.project(behind, X0, R, 100.0, distortion=d, return_valid=True)
    assert xy.shape == (7, 2) and np.isnan(xy).all() and not valid.any()
    xy, valid = pl.project(np.zeros((0, 3)), X0, R, 100.0, distortion=d, return_valid=True)
    assert xy.shape == (0, 2) and valid.shape == (0,)
    assert pl.project(np.zeros((0, 3)), X0, R, 100.0, distortion=d).shape == (0, 2)


def test_jacobian_refuses_points_not_in_front_of_the_camera():
    X, X0, R = _scene(n=10)
    X = X.copy()
    X[4] = X0 + R @ [0.0, 0.0, 10.0]                      # behind: N = +10
    with pytest.raises(pl.PointBehindCameraError, match=r"X\[4\] .* N = 10 ≥ 0"):
        pl.collinearity_jacobian(X, X0, R, 100.0)
    with pytest.raises(pl.PointBehindCameraError, match=r"X\[0\] .* N = 0 ≥ 0"):
        pl.collinearity_jacobian([1.0, 2.0, 100.0], [0.0, 0.0, 100.0], np.eye(3), 100.0)  # N = 0
    assert pl.collinearity_jacobian(np.zeros((0, 3)), X0, R, 100.0).shape == (0, 2, 9)


@pytest.mark.parametrize("angles", [(0.04, -0.06), (0.04, -0.06, 0.7, 9.0), "abc"])
def test_jacobian_needs_exactly_three_angles(angles):
    X, X0, R = _scene(n=3)
    with pytest.raises(ValueError, match=r"angles must be the three angles \(omega, phi, kappa\)"):
        pl.collinearity_jacobian(X, X0, R, 100.0, angles=angles)


def test_complex_and_text_input_is_refused_with_the_argument_name():
    X, X0, R = _scene(n=3)
    with pytest.raises(ValueError, match=r"X must be real with shape \(N, 3\) or \(3,\), got "
                                         r"complex values"):
        pl.project(X + 1j, X0, R, 100.0)
    with pytest.raises(ValueError, match=r"X0 must be real with shape \(3,\)"):
        pl.project(X, X0 + 0j, R, 100.0)
    with pytest.raises(ValueError, match=r"c must be a real number"):
        pl.project(X, X0, R, np.complex128(100.0))
    with pytest.raises(ValueError, match=r"X must be numeric with shape \(N, 3\) or \(3,\), got "
                                         r"'a' at index \(0, 0\)"):
        pl.project([["a", 2, 0]], X0, R, 100.0)
