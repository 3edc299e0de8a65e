"""Stereo: normal case, forward intersection, coplanarity, relative/absolute orientation.

Independent routes: SymPy (photolib.derive.stereo, lambdified), OpenCV (triangulatePoints,
findEssentialMat/recoverPose, computeCorrespondEpilines), SciPy (least_squares, Rotation),
Monte Carlo for the error propagation, and a pinhole written out here.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize
from scipy.spatial.transform import Rotation

from photolib import (PointBehindCameraError, absolute_orientation, epipolar_lines,
                      essential_matrix, forward_intersection, fundamental_matrix,
                      height_from_parallax, normal_case_accuracy, normal_case_points,
                      normal_case_rotation, normalised_image_points, opencv_pose_from_exterior,
                      relative_orientation, rotation_opk)
from photolib.derive import stereo as ds
from photolib.transforms import ConvergenceError, DegenerateGeometryError

D = np.diag([1.0, -1.0, -1.0])  # course camera frame (−z viewing, y up) → OpenCV's


def _rot(w, p, k):
    """R_ω·R_φ·R_κ written out here, independent of photolib."""
    Rx = np.array([[1, 0, 0], [0, np.cos(w), -np.sin(w)], [0, np.sin(w), np.cos(w)]])
    Ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    Rz = np.array([[np.cos(k), -np.sin(k), 0], [np.sin(k), np.cos(k), 0], [0, 0, 1]])
    return Rx @ Ry @ Rz


def _pinhole(X, X0, R, c, x0=0.0, y0=0.0):
    k = (np.asarray(X, float) - X0) @ R
    return np.column_stack([x0 - c * k[:, 0] / k[:, 2], y0 - c * k[:, 1] / k[:, 2]])


def _pair(rng, n=12):
    """Two convergent cameras 40 m above a 30 m × 30 m field with 8 m of relief."""
    X = rng.uniform([-15, -15, 0], [15, 15, 8], (n, 3))
    X01, X02 = np.array([-6.0, 1.0, 40.0]), np.array([7.0, -1.5, 41.0])
    R1, R2 = _rot(0.02, 0.08, 0.1), _rot(-0.03, -0.07, 0.05)
    return X, X01, R1, X02, R2


# -- normal case ----------------------------------------------------------------------------------

def test_height_from_parallax_is_the_sympy_derivation():
    f = sp.lambdify((ds.c, ds.B, ds.px), ds.height_from_parallax())
    px = np.array([0.5, 2.0, 19.79])
    np.testing.assert_allclose(height_from_parallax(px, 60.2, 1200.0), f(60.2, 1200.0, px),
                               rtol=1e-14)


def test_normal_case_points_agree_with_opencv_triangulation():
    rng = np.random.default_rng(90)
    X = rng.uniform([-30, -20, -220], [50, 20, -180], (10, 3))
    c, B = 50.0, 25.0
    xy1, xy2 = _pinhole(X, np.zeros(3), np.eye(3), c), _pinhole(X, [B, 0, 0], np.eye(3), c)
    P = []
    for X0 in (np.zeros(3), np.array([B, 0.0, 0.0])):
        Rcv, t = opencv_pose_from_exterior(X0, np.eye(3))
        P.append(np.diag([c, c, 1.0]) @ np.column_stack([Rcv, t]))
    flip = np.array([1.0, -1.0])
    H = cv2.triangulatePoints(P[0], P[1], (xy1 * flip).T, (xy2 * flip).T)
    np.testing.assert_allclose(normal_case_points(xy1, xy2, c, B), (H[:3] / H[3]).T, atol=1e-8)
    f = sp.lambdify((ds.B, ds.c, ds.x1, ds.y1, ds.px), ds.object_from_parallax())
    px = xy1[:, 0] - xy2[:, 0]
    np.testing.assert_allclose(normal_case_points(xy1, xy2, c, B),
                               np.column_stack(f(B, c, xy1[:, 0], xy1[:, 1], px)), rtol=1e-12)


def test_normal_case_points_with_principal_point_and_single_point():
    X = np.array([3.0, -2.0, -100.0])
    xy1 = _pinhole(X[None], np.zeros(3), np.eye(3), 40.0, 0.1, -0.2)[0]
    xy2 = _pinhole(X[None], np.array([10.0, 0, 0]), np.eye(3), 40.0, 0.1, -0.2)[0]
    out = normal_case_points(xy1, xy2, 40.0, 10.0, 0.1, -0.2)
    assert out.shape == (3,)
    np.testing.assert_allclose(out, X, atol=1e-10)


@pytest.mark.parametrize("px, error, words", [(0.0, DegenerateGeometryError, "zero parallax"),
                                              (-1.0, PointBehindCameraError, "behind"),
                                              (np.nan, ValueError, "non-finite")])
def test_height_from_bad_parallax(px, error, words):
    with pytest.raises(error, match=words):
        height_from_parallax([1.0, px], 50.0, 10.0)


def test_normal_case_bad_inputs():
    with pytest.raises(ValueError, match="c must be > 0"):
        height_from_parallax(1.0, -50.0, 10.0)
    with pytest.raises(ValueError, match="xy2 has shape"):
        normal_case_points([[1.0, 2.0]], [[1.0, 2.0, 3.0]], 50.0, 1.0)
    with pytest.raises(ValueError, match="pair up"):
        normal_case_points([[1.0, 2.0]], [[0.0, 2.0], [0.0, 1.0]], 50.0, 1.0)
    with pytest.raises(DegenerateGeometryError, match="px"):
        normal_case_points([[1.0, 2.0]], [[1.0, 2.0]], 50.0, 1.0)


def test_accuracy_is_the_sympy_propagation_and_example_37():
    from photolib.errata import luhmann_ch3
    acc = normal_case_accuracy(5000.0, 1200.0, 40.0, 0.004, 0.004 / np.sqrt(2))
    expr = ds.sigma_Z().subs({ds.h: 5000, ds.b: 1200, ds.m: 125, ds.s_px: sp.Rational(4, 1000)})
    assert acc.sigma_Z == pytest.approx(float(expr), rel=1e-14)
    for reading in ("sqrt2", "inv"):
        ref = luhmann_ch3.example_37(reading)
        acc = normal_case_accuracy(5000.0, 1200.0, 40.0, 0.004, ref["s_x_um"] / 1000)
        assert acc.sigma_Z == pytest.approx(ref["s_Z_mm"], rel=1e-12)
        assert acc.sigma_XY == pytest.approx(ref["s_XY_mm"], rel=1e-12)
    assert acc.m == 125.0 and acc.base_ratio == pytest.approx(5 / 1.2)


def test_sigma_Z_by_monte_carlo():
    rng = np.random.default_rng(37)
    c, B, h, s_px = 100.0, 300.0, 1500.0, 0.005
    px = c * B / h + s_px * rng.standard_normal(200_000)
    Z = height_from_parallax(px, c, B)
    acc = normal_case_accuracy(h, B, c, s_px, s_px)
    assert np.std(Z) == pytest.approx(acc.sigma_Z, rel=0.01)


def test_accuracy_rejects_bad_values():
    with pytest.raises(ValueError, match="B must be > 0"):
        normal_case_accuracy(100.0, 0.0, 50.0, 0.01, 0.01)
    with pytest.raises(ValueError, match="sigma_px must be finite"):
        normal_case_accuracy(100.0, 10.0, 50.0, np.nan, 0.01)


# -- forward intersection -------------------------------------------------------------------------

def test_forward_intersection_agrees_with_opencv_on_exact_data():
    rng = np.random.default_rng(91)
    X, X01, R1, X02, R2 = _pair(rng)
    c = 35.0
    xy = np.stack([_pinhole(X, X01, R1, c), _pinhole(X, X02, R2, c)])
    res = forward_intersection(xy, [X01, X02], [R1, R2], c)
    P = []
    for X0, R in ((X01, R1), (X02, R2)):
        Rcv, t = opencv_pose_from_exterior(X0, R)
        P.append(np.diag([c, c, 1.0]) @ np.column_stack([Rcv, t]))
    flip = np.array([1.0, -1.0])
    H = cv2.triangulatePoints(P[0], P[1], (xy[0] * flip).T, (xy[1] * flip).T)
    np.testing.assert_allclose(res.points, (H[:3] / H[3]).T, atol=1e-7)
    np.testing.assert_allclose(res.points, X, atol=1e-9)
    assert res.valid.all() and np.max(res.miss) < 1e-9 and np.max(np.abs(res.residuals)) < 1e-9


def _perpendicular_distances(X, centres, dirs):
    out = []
    for X0, d in zip(centres, dirs):
        d = d / np.linalg.norm(d)
        v = X - X0
        out.append(np.linalg.norm(v - (v @ d) * d))
    return np.array(out)


@pytest.mark.parametrize("K", [2, 3])
def test_forward_intersection_minimises_ray_distances_like_scipy(K):
    rng = np.random.default_rng(92 + K)
    X, X01, R1, X02, R2 = _pair(rng, 6)
    X03, R3 = np.array([0.0, 12.0, 38.0]), _rot(0.1, 0.0, -0.2)
    cams = [(X01, R1, 35.0, 0.1, -0.05), (X02, R2, 35.0, 0.1, -0.05), (X03, R3, 28.0, 0.0, 0.02)][:K]
    xy = np.stack([_pinhole(X, X0, R, c, a, b) + 0.01 * rng.standard_normal((6, 2))
                   for X0, R, c, a, b in cams])
    res = forward_intersection(xy, [k[0] for k in cams], [k[1] for k in cams],
                               [k[2] for k in cams], [k[3] for k in cams], [k[4] for k in cams])
    for i in range(6):
        dirs = [R @ np.r_[xy[k][i, 0] - a, xy[k][i, 1] - b, -c]
                for k, (_, R, c, a, b) in enumerate(cams)]
        centres = [k[0] for k in cams]
        sol = optimize.least_squares(_perpendicular_distances, X[i], args=(centres, dirs),
                                     xtol=1e-14, ftol=1e-14, gtol=1e-14)
        np.testing.assert_allclose(res.points[i], sol.x, atol=1e-6)
        np.testing.assert_allclose(res.distances[i], _perpendicular_distances(sol.x, centres, dirs),
                                   atol=1e-6)
        reproj = [_pinhole(res.points[i][None], X0, R, c, a, b)[0] - xy[k][i]
                  for k, (X0, R, c, a, b) in enumerate(cams)]
        np.testing.assert_allclose(res.residuals[i], reproj, atol=1e-10)
    if K == 2:  # the miss distance is the length of the common perpendicular of the rays
        for i in range(6):
            d1 = R1 @ np.r_[xy[0][i, 0] - 0.1, xy[0][i, 1] + 0.05, -35.0]
            d2 = R2 @ np.r_[xy[1][i, 0] - 0.1, xy[1][i, 1] + 0.05, -35.0]
            n = np.cross(d1, d2)
            assert res.miss[i] == pytest.approx(abs((X02 - X01) @ n) / np.linalg.norm(n), rel=1e-8)


def test_parallel_rays_raise_or_are_flagged():
    xy = np.array([[[1.0, 2.0], [3.0, 1.0]], [[1.0, 2.0], [1.0, 1.0]]])   # point 0: zero parallax
    I2 = [np.eye(3), np.eye(3)]
    with pytest.raises(DegenerateGeometryError, match="rays of point 0 are parallel"):
        forward_intersection(xy, [[0, 0, 0], [1.0, 0, 0]], I2, 50.0)
    res = forward_intersection(xy, [[0, 0, 0], [1.0, 0, 0]], I2, 50.0, return_valid=True)
    assert res.valid.tolist() == [False, True] and np.isnan(res.points[0]).all()
    np.testing.assert_allclose(res.points[1], normal_case_points(xy[0, 1], xy[1, 1], 50.0, 1.0))


def test_diverging_rays_are_behind_a_camera():
    xy = np.array([[[-1.0, 0.0]], [[1.0, 0.0]]])   # negative parallax: rays meet behind
    I2 = [np.eye(3), np.eye(3)]
    with pytest.raises(PointBehindCameraError, match="behind camera"):
        forward_intersection(xy, [[0, 0, 0], [1.0, 0, 0]], I2, 50.0)
    assert not forward_intersection(xy, [[0, 0, 0], [1.0, 0, 0]], I2, 50.0,
                                    return_valid=True).valid[0]


def test_forward_intersection_bad_inputs():
    I2 = [np.eye(3), np.eye(3)]
    with pytest.raises(ValueError, match="at least 2 images"):
        forward_intersection([[[1.0, 2.0]]], [[0, 0, 0]], [np.eye(3)], 50.0)
    with pytest.raises(ValueError, match=r"X0 has shape \(3,\)"):
        forward_intersection([[1.0, 2.0], [0.0, 2.0]], [0, 0, 0], I2, 50.0)
    with pytest.raises(ValueError, match="R\\[1\\] is not orthonormal"):
        forward_intersection([[1.0, 2.0], [0.0, 2.0]], [[0, 0, 0], [1, 0, 0]],
                             [np.eye(3), 2 * np.eye(3)], 50.0)
    with pytest.raises(ValueError, match="c must be > 0"):
        forward_intersection([[1.0, 2.0], [0.0, 2.0]], [[0, 0, 0], [1, 0, 0]], I2, [50.0, -1.0])
    with pytest.raises(ValueError, match="non-finite"):
        forward_intersection([[np.nan, 2.0], [0.0, 2.0]], [[0, 0, 0], [1, 0, 0]], I2, 50.0)


# -- coplanarity, essential and fundamental matrix ------------------------------------------------

def test_coplanarity_identity_and_normal_case_y_parallax():
    assert ds.coplanarity_identity() == 0
    assert ds.coplanarity_normal_case() == sp.Symbol("y2", real=True) - ds.y1


def test_essential_matrix_agrees_with_opencv_findEssentialMat():
    rng = np.random.default_rng(93)
    X, X01, R1, X02, R2 = _pair(rng, 30)
    c = 35.0
    xy1, xy2 = _pinhole(X, X01, R1, c), _pinhole(X, X02, R2, c)
    E = essential_matrix(X01, R1, X02, R2)
    xs1 = np.column_stack([xy1, np.full(30, -c)])
    xs2 = np.column_stack([xy2, np.full(30, -c)])
    assert np.max(np.abs(np.einsum("ni,ij,nj->n", xs1, E, xs2))) < 1e-9 * np.abs(E).max() * c**2
    p1, p2 = xy1 * [1, -1] / c, xy2 * [1, -1] / c          # OpenCV normalised coordinates
    E_cv, _ = cv2.findEssentialMat(p1, p2, np.eye(3), method=cv2.LMEDS)
    ours = (D @ E @ D).T
    ours, E_cv = ours / np.linalg.norm(ours), E_cv[:3] / np.linalg.norm(E_cv[:3])
    assert min(np.abs(ours - E_cv).max(), np.abs(ours + E_cv).max()) < 1e-6


def test_epipolar_lines_agree_with_opencv_computeCorrespondEpilines():
    rng = np.random.default_rng(94)
    X, X01, R1, X02, R2 = _pair(rng, 8)
    c1, c2, pp1, pp2 = 35.0, 28.0, (0.12, -0.08), (-0.05, 0.1)
    xy1, xy2 = _pinhole(X, X01, R1, c1, *pp1), _pinhole(X, X02, R2, c2, *pp2)
    F = fundamental_matrix(essential_matrix(X01, R1, X02, R2), c1, c2, *pp1, *pp2)
    l2 = epipolar_lines(F, xy1, image=2)
    l1 = epipolar_lines(F, xy2, image=1)
    assert np.max(np.abs(np.sum(l2[:, :2] * xy2, axis=1) + l2[:, 2])) < 1e-9
    assert np.max(np.abs(np.sum(l1[:, :2] * xy1, axis=1) + l1[:, 2])) < 1e-9
    # OpenCV: u = x', v = −y', K = [[c, 0, x'0], [0, c, −y'0], [0, 0, 1]], F_cv from its poses
    K1 = np.array([[c1, 0, pp1[0]], [0, c1, -pp1[1]], [0, 0, 1.0]])
    K2 = np.array([[c2, 0, pp2[0]], [0, c2, -pp2[1]], [0, 0, 1.0]])
    (Ra, ta), (Rb, tb) = opencv_pose_from_exterior(X01, R1), opencv_pose_from_exterior(X02, R2)
    Rr, tr = Rb @ Ra.T, tb - Rb @ Ra.T @ ta
    tx = np.array([[0, -tr[2], tr[1]], [tr[2], 0, -tr[0]], [-tr[1], tr[0], 0]])
    F_cv = np.linalg.inv(K2).T @ tx @ Rr @ np.linalg.inv(K1)
    lines = cv2.computeCorrespondEpilines((xy1 * [1, -1]).reshape(-1, 1, 2), 1, F_cv).reshape(-1, 3)
    ours = np.column_stack([l2[:, 0], -l2[:, 1], l2[:, 2]])    # a·u − b·v + d = 0
    sign = np.sign(np.sum(ours * lines, axis=1))[:, None]
    np.testing.assert_allclose(ours * sign, lines, atol=1e-6)


def test_epipolar_bad_inputs():
    with pytest.raises(DegenerateGeometryError, match="base is zero"):
        essential_matrix([1, 2, 3], np.eye(3), [1, 2, 3], np.eye(3))
    with pytest.raises(ValueError, match="image must be 1 or 2"):
        epipolar_lines(np.eye(3), [1.0, 2.0], image=3)
    E = essential_matrix([0, 0, 0], np.eye(3), [1.0, 0, 0], np.eye(3))
    E_fwd = essential_matrix([0, 0, 0], np.eye(3), [0, 0, -10.0], np.eye(3))  # forward motion
    with pytest.raises(DegenerateGeometryError, match="epipole"):  # the epipole is (0, 0)
        epipolar_lines(fundamental_matrix(E_fwd, 10.0, 10.0), [[0.0, 0.0]])
    with pytest.raises(ValueError, match="c1 must be > 0"):
        fundamental_matrix(E, 0.0, 10.0)


# -- relative orientation -------------------------------------------------------------------------

def _model_pair(rng, n=15, noise=0.0):
    X = rng.uniform([-4, -4, -22], [14, 4, -18], (n, 3))
    base, angles = np.array([10.0, 0.4, -0.3]), np.array([0.02, -0.03, 0.05])
    R2 = _rot(*angles)
    c = 50.0
    xy1 = _pinhole(X, np.zeros(3), np.eye(3), c) + noise * rng.standard_normal((n, 2))
    xy2 = _pinhole(X, base, R2, c) + noise * rng.standard_normal((n, 2))
    return X, base, angles, R2, c, xy1, xy2


def test_relative_orientation_recovers_exact_geometry():
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(95))
    ro = relative_orientation(xy1, xy2, c, bx=base[0])
    np.testing.assert_allclose(ro.params, np.r_[base[1:], angles], atol=1e-10)
    np.testing.assert_allclose(ro.model, X, atol=1e-8)   # bx = true base: model = object
    assert ro.converged and ro.redundancy == 10 and np.max(np.abs(ro.residuals)) < 1e-10


def test_relative_orientation_agrees_with_scipy_and_opencv_recoverPose():
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(96), 20, noise=0.002)
    ro = relative_orientation(xy1, xy2, c, bx=base[0])

    def coplanarity(q):  # the determinant form, written out independently
        b = np.r_[base[0], q[:2]]
        R = _rot(*q[2:])
        return np.array([np.linalg.det(np.column_stack([b, np.r_[p1, -c], R @ np.r_[p2, -c]]))
                         for p1, p2 in zip(xy1, xy2)]) / (base[0] * c)

    sol = optimize.least_squares(coplanarity, np.zeros(5), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    np.testing.assert_allclose(ro.params, sol.x, atol=1e-8)
    assert ro.sigma0 == pytest.approx(np.sqrt(2 * sol.cost / 15), rel=1e-6)
    # OpenCV on exact data: relative pose R_cv = D·R2ᵀ·D, t ∝ −D·R2ᵀ·b
    _, base, angles, R2, c, e1, e2 = _model_pair(np.random.default_rng(97), 20)
    ro = relative_orientation(e1, e2, c, bx=base[0])
    p1, p2 = e1 * [1, -1] / c, e2 * [1, -1] / c
    E_cv, _ = cv2.findEssentialMat(p1, p2, np.eye(3), method=cv2.LMEDS)
    _, Rcv, tcv, _ = cv2.recoverPose(E_cv[:3], p1, p2, np.eye(3))
    np.testing.assert_allclose(Rcv, D @ ro.R2.T @ D, atol=1e-6)
    t = -D @ ro.R2.T @ ro.base
    np.testing.assert_allclose(tcv.ravel(), t / np.linalg.norm(t), atol=1e-6)


def test_relative_orientation_five_points_and_errors():
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(98), 5)
    ro = relative_orientation(xy1, xy2, c, bx=base[0])
    assert ro.redundancy == 0 and np.isnan(ro.sigma0)
    np.testing.assert_allclose(ro.params, np.r_[base[1:], angles], atol=1e-8)
    with pytest.raises(ValueError, match="at least 5 point pairs"):
        relative_orientation(xy1[:4], xy2[:4], c)
    with pytest.raises(ValueError, match="bx must be ≠ 0"):
        relative_orientation(xy1, xy2, c, bx=0.0)
    line = np.column_stack([np.linspace(-10, 10, 8), np.zeros(8)])
    with pytest.raises(DegenerateGeometryError, match="badly distributed"):
        relative_orientation(line, line - [1.0, 0.0], c)
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(99), 10)
    with pytest.raises(ConvergenceError, match="did not converge"):
        relative_orientation(xy1, xy2, c, bx=base[0], max_iter=1)


# -- absolute orientation -------------------------------------------------------------------------

@settings(max_examples=25, deadline=None)
@given(st.floats(-3, 3), st.floats(-1.4, 1.4), st.floats(-3, 3), st.floats(0.01, 100),
       st.integers(0, 2**32 - 1))
def test_absolute_orientation_round_trip(w, p, k, m, seed):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-5, 5, (6, 3))
    R, X0 = _rot(w, p, k), rng.uniform(-1000, 1000, 3)
    T = absolute_orientation(x, X0 + m * x @ R.T)
    assert T.m == pytest.approx(m, rel=1e-9)
    np.testing.assert_allclose(T.R, R, atol=1e-9)
    np.testing.assert_allclose(T(x), X0 + m * x @ R.T, atol=1e-8 * max(1.0, m * 10))


def test_absolute_orientation_is_the_least_squares_solution():
    rng = np.random.default_rng(100)
    x = rng.uniform(-5, 5, (8, 3))
    R, X0, m = _rot(0.3, -0.2, 1.1), np.array([500.0, 200.0, 80.0]), 3.2
    X = X0 + m * x @ R.T + 0.01 * rng.standard_normal((8, 3))
    T = absolute_orientation(x, X)

    def res(q):
        return (X - (q[:3] + q[6] * x @ Rotation.from_rotvec(q[3:6]).as_matrix().T)).ravel()

    sol = optimize.least_squares(res, np.r_[X0, Rotation.from_matrix(R).as_rotvec(), m],
                                 xtol=1e-15, ftol=1e-15, gtol=1e-15)
    np.testing.assert_allclose(T.X0, sol.x[:3], atol=1e-7)
    np.testing.assert_allclose(T.R, Rotation.from_rotvec(sol.x[3:6]).as_matrix(), atol=1e-9)
    assert T.m == pytest.approx(sol.x[6], rel=1e-9)
    assert T.redundancy == 17 and T.sigma0 == pytest.approx(np.sqrt(2 * sol.cost / 17), rel=1e-7)
    np.testing.assert_allclose(T.residuals, res(sol.x).reshape(8, 3), atol=1e-7)
    np.testing.assert_allclose(rotation_opk(*T.angles), T.R, atol=1e-12)


def test_absolute_orientation_degenerate():
    line = np.outer(np.arange(5.0), [1.0, 2.0, 0.5])
    with pytest.raises(DegenerateGeometryError, match="model points are collinear"):
        absolute_orientation(line, line * 2)
    with pytest.raises(ValueError, match="at least 3 control points"):
        absolute_orientation(np.eye(3)[:2], np.eye(3)[:2])
    three = absolute_orientation(np.eye(3), 2 * np.eye(3))   # 3 points: 9 − 7 = 2
    assert three.redundancy == 2 and three.sigma0 < 1e-12


def test_orientation_unknown_counts():
    assert ds.orientation_unknowns() == {"exterior": 12, "relative": 5, "absolute": 7}


# -- normalised images ----------------------------------------------------------------------------

def test_normalised_images_remove_the_y_parallax():
    rng = np.random.default_rng(101)
    X, X01, R1, X02, R2 = _pair(rng, 10)
    c = 35.0
    xy1, xy2 = _pinhole(X, X01, R1, c), _pinhole(X, X02, R2, c)
    Rn = normal_case_rotation(X01, R1, X02, R2)
    np.testing.assert_allclose(Rn.T @ Rn, np.eye(3), atol=1e-12)
    assert np.linalg.det(Rn) == pytest.approx(1.0)
    n1 = normalised_image_points(xy1, R1, Rn, c)
    n2 = normalised_image_points(xy2, R2, Rn, c)
    np.testing.assert_allclose(n1, _pinhole(X, X01, Rn, c), atol=1e-9)   # as if shot with Rn
    np.testing.assert_allclose(n1[:, 1], n2[:, 1], atol=1e-9)              # no y-parallax
    # and the normal-case formula then gives the object points in the rotated frame
    B = np.linalg.norm(X02 - X01)
    local = normal_case_points(n1, n2, c, B)
    np.testing.assert_allclose(X01 + local @ Rn.T, X, atol=1e-8)


def test_normalisation_errors():
    with pytest.raises(DegenerateGeometryError, match="along the base"):
        normal_case_rotation([0, 0, 0], np.eye(3), [0, 0, 5.0], np.eye(3))
    with pytest.raises(PointBehindCameraError, match="behind the normalised"):
        normalised_image_points([0.0, 0.0], np.eye(3), _rot(0, 3.0, 0), 50.0)


@settings(max_examples=40, deadline=None)
@given(st.floats(-50, 50), st.floats(-50, 50), st.floats(5, 500), st.floats(0.5, 40),
       st.floats(5, 300))
def test_normal_case_round_trip(X, Y, h, B, c):
    P = np.array([X, Y, -h])
    xy1 = _pinhole(P[None], np.zeros(3), np.eye(3), c)
    xy2 = _pinhole(P[None], np.array([B, 0.0, 0.0]), np.eye(3), c)
    np.testing.assert_allclose(normal_case_points(xy1, xy2, c, B)[0], P, rtol=1e-9, atol=1e-9)
    assert height_from_parallax(xy1[0, 0] - xy2[0, 0], c, B) == pytest.approx(-h, rel=1e-12)


# -- input handling (red-team audit) --------------------------------------------------------------

def test_relative_orientation_of_swapped_images_says_so():
    """Images swapped (or bx of the wrong sign): the coplanarity condition is fitted exactly
    (σ0 ≈ 1e-15, converged) but every model point lies behind the cameras (was: NaN model)."""
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(101), 8)
    with pytest.raises(PointBehindCameraError, match=r"all 8 model points .* lie behind the "
                                                     r"cameras.*Flip the sign of bx"):
        relative_orientation(xy2, xy1, c, bx=1.0)
    ro = relative_orientation(xy2, xy1, c, bx=-1.0)            # flipping bx is the fix
    assert ro.converged and np.isfinite(ro.model).all()


def test_relative_orientation_of_identical_images_is_zero_parallax():
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(102), 8)
    with pytest.raises(DegenerateGeometryError, match="zero parallax: every pair of rays is "
                                                      "parallel") as info:
        relative_orientation(xy1, xy1, c)
    assert "badly distributed" not in str(info.value)


@pytest.mark.parametrize("kwargs, text", [
    ({"max_iter": 0}, "max_iter must be an integer ≥ 1, got 0"),      # was UnboundLocalError
    ({"max_iter": 0, "check": False}, "max_iter must be an integer ≥ 1, got 0"),
    ({"tol": -1.0}, "tol must be > 0, got -1.0"),
    ({"tol": np.nan}, "tol must be finite, got nan"),
    ({"initial": "abcde"}, "initial must be numeric, got 'abcde'"),
])
def test_relative_orientation_checks_its_controls(kwargs, text):
    X, base, angles, R2, c, xy1, xy2 = _model_pair(np.random.default_rng(103), 8)
    with pytest.raises(ValueError, match=text):
        relative_orientation(xy1, xy2, c, bx=base[0], **kwargs)


def test_forward_intersection_min_angle_must_be_a_non_negative_number():
    eye = np.eye(3)
    xy = [[[1.0, 0.5]], [[-1.0, 0.5]]]
    for bad, text in ((np.nan, "min_angle must be finite, got nan"),
                      (-1.0, "min_angle must be ≥ 0")):
        with pytest.raises(ValueError, match=text):   # NaN / −1 switched the check off
            forward_intersection(xy, [[0, 0, 0], [20.0, 0, 0]], [eye, eye], 100.0, min_angle=bad)


def test_tiny_base_and_tiny_parallax():
    eye = np.eye(3)
    E = essential_matrix([0, 0, 0], eye, [1e-300, 0, 0], eye)      # was "X01 = X02"
    assert np.isfinite(E).all() and np.abs(E).max() > 0
    with pytest.raises(DegenerateGeometryError, match="X01 = X02"):
        essential_matrix([1.0, 2, 3], eye, [1.0, 2, 3], eye)
    with pytest.raises(DegenerateGeometryError, match="below the rounding"):
        essential_matrix([1e6, 0, 0], eye, [1e6 + 1e-7, 0, 0], eye)
    Rn = normal_case_rotation([0, 0, 0], eye, [1e-300, 0, 0], eye)
    np.testing.assert_allclose(Rn, eye, atol=1e-15)
    with pytest.raises(DegenerateGeometryError, match=r"px\[0\] = 5e-324 is so small that Z = "
                                                      r"−c·B/px' overflows"):
        height_from_parallax(5e-324, 100.0, 20.0)                # was −inf
    with pytest.raises(DegenerateGeometryError, match="overflows"):
        normal_case_points([5e-324, 0.0], [0.0, 0.0], 100.0, 20.0)
    with pytest.raises(ValueError, match="px must be numeric, got 'a'"):
        height_from_parallax("a", 100.0, 20.0)


# -- σ_X of the normal case: independent parallax versus two measured images --------------------

def _mc_sigma_X(x1, x2, B, s, n=400_000, seed=21, parallax_bar=False):
    """Monte Carlo of X = B·x'1/px': px' = x'1 − x'2 from both images, or measured on its own."""
    rng = np.random.default_rng(seed)
    a = x1 + s * rng.standard_normal(n)
    if parallax_bar:                                # px' observed independently of x'1
        px = (x1 - x2) + np.sqrt(2) * s * rng.standard_normal(n)
    else:                                           # x'2 measured, px' = x'1 − x'2
        px = a - (x2 + s * rng.standard_normal(n))
    return np.std(B * a / px)


def test_sigma_X_two_images_example_below_the_middle_of_the_base():
    # B = 20 m, h = 100 m, c = 50 mm, σ = 3 µm, the point below the middle of the base
    B, h, c, s = 20.0, 100.0, 50.0, 3e-3
    x1, x2 = c * (B / 2) / h, c * (B / 2 - B) / h                    # ±5 mm
    mc = _mc_sigma_X(x1, x2, B, s) * 1e3                              # mm
    assert mc == pytest.approx(4.243, rel=0.01)
    m = h / c
    assert mc == pytest.approx(m * s * 1e3 / np.sqrt(2), rel=0.01)    # m·σ/√2, not m·σ
    f = sp.lambdify((ds.x1, ds.x2, ds.B, ds.s_x), ds.sigma_X_two_images())
    assert f(x1, x2, B, s) * 1e3 == pytest.approx(mc, rel=0.01)
    # the independent-parallax formula overestimates this case: 7.35 mm
    full = sp.lambdify((ds.x1, ds.px, ds.B, ds.s_x, ds.s_px), ds.sigma_X_full())
    assert full(x1, x1 - x2, B, s, np.sqrt(2) * s) * 1e3 == pytest.approx(7.348, rel=1e-3)


@pytest.mark.parametrize("X", [0.0, 4.0, 10.0, 20.0, 27.0, -6.0])
def test_sigma_X_two_images_by_monte_carlo(X):
    B, h, c, s = 20.0, 100.0, 50.0, 3e-3
    x1, x2 = c * X / h, c * (X - B) / h
    f = sp.lambdify((ds.x1, ds.x2, ds.B, ds.s_x), ds.sigma_X_two_images())
    assert f(x1, x2, B, s) == pytest.approx(_mc_sigma_X(x1, x2, B, s), rel=0.01)
    # m·σ_x' is exact below a projection centre (x'1·x'2 = 0) and only there
    exact_m = np.isclose(f(x1, x2, B, s), (h / c) * s, rtol=1e-9)
    assert exact_m == (X in (0.0, B))


@pytest.mark.parametrize("X", [0.0, 10.0, 27.0])
def test_sigma_X_full_holds_for_an_independently_measured_parallax(X):
    B, h, c, s = 20.0, 100.0, 50.0, 3e-3
    x1, x2 = c * X / h, c * (X - B) / h
    full = sp.lambdify((ds.x1, ds.px, ds.B, ds.s_x, ds.s_px), ds.sigma_X_full())
    mc = _mc_sigma_X(x1, x2, B, s, parallax_bar=True)
    assert full(x1, x1 - x2, B, s, np.sqrt(2) * s) == pytest.approx(mc, rel=0.01)


def test_covariance_two_images_by_monte_carlo():
    B, c, s = 20.0, 50.0, 3e-3
    l0 = np.array([7.0, 3.0, -3.0])                                   # x'1, y'1, x'2 in mm
    rng = np.random.default_rng(5)
    n = 400_000
    obs = l0 + s * rng.standard_normal((n, 3))
    px = obs[:, 0] - obs[:, 2]
    pts = np.column_stack([B * obs[:, 0] / px, B * obs[:, 1] / px, -c * B / px])
    C_mc = np.cov(pts.T)
    C = sp.lambdify((ds.x1, ds.y1, ds.x2, ds.B, ds.c, ds.s_x), ds.covariance_two_images())
    C_sym = np.array(C(*l0, B, c, s), float)
    scale = np.sqrt(np.outer(np.diag(C_sym), np.diag(C_sym)))
    np.testing.assert_allclose(C_mc / scale, C_sym / scale, atol=0.01)


# -- essential / fundamental matrix checks, single-point intersection (audit T1, T2) ---------------

@pytest.mark.parametrize("E, match", [
    (np.zeros((3, 3)), "E is zero"),
    (np.eye(3), "E has rank 3"),
    (np.outer([1.0, 2.0, 0.5], [0.3, -1.0, 2.0]), "E has rank 1"),
])
def test_fundamental_matrix_refuses_what_is_not_an_essential_matrix(E, match):
    with pytest.raises(DegenerateGeometryError, match=match):
        fundamental_matrix(E, 50.0, 50.0)


def test_fundamental_matrix_accepts_essential_matrices_of_any_scale():
    rng = np.random.default_rng(120)
    for scale in (1e-200, 1e-6, 1.0, 1e6, 1e200):
        X01, X02 = rng.normal(size=3), rng.normal(size=3)
        R1, R2 = _rot(*rng.uniform(-1, 1, 3)), _rot(*rng.uniform(-1, 1, 3))
        E = essential_matrix(X01 * scale, R1, X02 * scale, R2)
        F = fundamental_matrix(E, 35.0, 50.0, 0.1, -0.2, 0.05, 0.0)
        assert np.isfinite(F).all()
        epipolar_lines(F, [[1.0, 2.0], [-3.0, 0.5]])


@pytest.mark.parametrize("F, match", [
    (np.zeros((3, 3)), "F is zero"),
    (np.eye(3), "F has rank 3"),
    (np.outer([1.0, 2.0, 0.5], [0.3, -1.0, 2.0]), "F has rank 1"),
])
def test_epipolar_lines_blame_a_degenerate_F_not_the_point(F, match):
    with pytest.raises(DegenerateGeometryError, match=match) as info:
        epipolar_lines(F, [[1.0, 2.0]])
    assert "epipole" not in str(info.value)


def test_forward_intersection_of_one_point_keeps_its_rank():
    """(K, 2) in: the point (3,) out, like project (2,) and monoplot (3,); fields of one point."""
    eye = np.eye(3)
    args = ([[0, 0, 0], [20.0, 0, 0]], [eye, eye])
    one = forward_intersection([[1.0, 0.5], [-1.0, 0.3]], *args, c=100.0)
    batch = forward_intersection([[[1.0, 0.5]], [[-1.0, 0.3]]], *args, c=100.0)
    assert one.points.shape == (3,) and one.distances.shape == (2,)
    assert one.residuals.shape == (2, 2)
    assert isinstance(one.miss, float) and isinstance(one.angle, float)
    assert isinstance(one.valid, bool) and one.valid
    np.testing.assert_array_equal(one.points, batch.points[0])
    np.testing.assert_array_equal(one.distances, batch.distances[0])
    np.testing.assert_array_equal(one.residuals, batch.residuals[0])
    assert one.miss == batch.miss[0] and one.angle == batch.angle[0]
    flagged = forward_intersection([[-1.0, 0.0], [1.0, 0.0]], *args, c=100.0, return_valid=True)
    assert flagged.valid is False and np.isnan(flagged.points).all()
