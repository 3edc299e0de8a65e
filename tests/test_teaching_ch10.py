"""Chapter 10's teaching code (the bundle adjustment written out in the notebook: Jacobian
blocks, normal equations in blocks, Schur complement, the Gauss–Newton loop, σ0, redundancy
numbers, covariances) agrees with photolib to 1e-9 on blocks of this test's own (near-nadir
images over a box of points, not the notebook's aerial block); the Schur step also agrees
with the dense solution of the full normal equations."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl

from .teaching import teaching_functions

CODE = teaching_functions("10-bundle-adjustment")
C_MM = 35.0


def _block(seed, images=4, points=25, noise_mm=0.002):
    """``images`` images 30 m above ``points`` points in a 12 m × 12 m × 4 m box, all seen
    everywhere; control points 0–3 (the first four, spread to the corners)."""
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-6, 6, points), rng.uniform(-6, 6, points),
                         rng.uniform(-2, 2, points)])
    X[:4, :2] = [[-6, -6], [6, -6], [6, 6], [-6, 6]]
    ext = np.column_stack([rng.uniform(-4, 4, images), rng.uniform(-4, 4, images),
                           rng.uniform(28, 32, images), rng.normal(0, 0.05, (images, 3))])
    xy = np.vstack([pl.project(X, e[:3], pl.rotation_opk(*e[3:]), C_MM) for e in ext])
    xy += rng.normal(0, noise_mm, xy.shape)
    img = np.repeat(np.arange(images), points)
    pt = np.tile(np.arange(points), images)
    ext0 = ext + rng.normal(0, 1, ext.shape) * np.r_[0.5, 0.5, 0.5, 0.01, 0.01, 0.01]
    P0 = X + rng.normal(0, 0.3, X.shape)
    control = np.arange(4)
    P0[control] = X[control]
    return xy, img, pt, ext0, P0, control


@pytest.mark.parametrize("seed", range(3))
def test_teaching_bundle_is_photolibs(seed):
    xy, img, pt, ext0, P0, control = _block(seed)
    ext, pts, iterations = CODE["bundle"](xy, img, pt, ext0, P0, C_MM, control)
    res = pl.bundle_adjustment(xy, img, pt, ext0, P0, C_MM, control=control)
    assert iterations == res.iterations
    assert np.allclose(ext[:, :3], res.exterior[:, :3], rtol=0, atol=1e-9 * 30)
    assert np.allclose(ext[:, 3:], res.exterior[:, 3:], rtol=0, atol=1e-9)
    assert np.allclose(pts, res.points, rtol=0, atol=1e-9 * 30)
    sigma0, rn, cov_images, cov_points = CODE["bundle_statistics"](xy, img, pt, ext, pts, C_MM,
                                                                   control)
    assert sigma0 == pytest.approx(res.sigma0, rel=1e-9)
    assert np.allclose(rn, res.redundancy_numbers, rtol=0, atol=1e-9)
    assert rn.sum() == pytest.approx(res.redundancy, abs=1e-9)
    for mine, theirs in ((cov_images, res.exterior_covariance), (cov_points, res.point_covariance)):
        assert np.abs(mine - theirs).max() <= 1e-9 * np.abs(theirs).max()


@pytest.mark.parametrize("seed", range(2))
def test_schur_step_is_the_dense_normal_equation_step(seed):
    """Reduced system + back-substitution = the solution of the full N dx = b, with A built
    densely from pl.collinearity_jacobian (rows x′, y′; images, then the new points)."""
    xy, img, pt, ext0, P0, control = _block(seed + 10, images=3, points=12)
    M, P = len(ext0), len(P0)
    new = np.ones(P, bool)
    new[control] = False
    Ac, Ap, obs_l = CODE["linearise"](xy, img, pt, ext0, P0, C_MM, new)
    dy, dp, _, _ = CODE["schur_solve"](*CODE["normal_blocks"](Ac, Ap, obs_l, img, pt, M, P), new)
    slot = np.cumsum(new) - 1
    A = np.zeros((2 * len(xy), 6 * M + 3 * int(new.sum())))
    for k, (j, i) in enumerate(zip(img, pt)):
        e = ext0[j]
        J = pl.collinearity_jacobian(P0[i], e[:3], pl.rotation_opk(*e[3:]), C_MM,
                                     angles=tuple(e[3:]))
        A[2 * k:2 * k + 2, 6 * j:6 * j + 6] = J[:, :6]
        if new[i]:
            A[2 * k:2 * k + 2, 6 * M + 3 * slot[i]:6 * M + 3 * slot[i] + 3] = J[:, 6:]
    dx = np.linalg.solve(A.T @ A, A.T @ obs_l.reshape(-1))
    scale = np.abs(dx).max()
    assert np.allclose(dy.reshape(-1), dx[:6 * M], rtol=0, atol=1e-9 * scale)
    assert np.allclose(dp[new].reshape(-1), dx[6 * M:], rtol=0, atol=1e-9 * scale)
    assert np.all(dp[control] == 0)


def test_teaching_bundle_on_real_chessboard_views_is_photolibs():
    """Eight of OpenCV's chessboard views (corners by cornerSubPix), other control points and
    start values than the notebook's; photolib applies the distortion in its model."""
    from photolib.nb import realdata as nbr
    cal = nbr.chessboard_calibration()
    io = cal.result
    views = [1, 2, 4, 6, 7, 9, 11, 13]
    N = len(cal.object_points)
    img, pt = np.repeat(np.arange(len(views)), N), np.tile(np.arange(N), len(views))
    raw = np.vstack([cal.xy[v] for v in views])
    ideal = io.distortion.correct(raw - [io.x0, io.y0])
    control = np.array([4, 22, 45, 53])
    start = cal.object_points + np.random.default_rng(11).normal(0.0, 2.0, (N, 3))
    start[control] = cal.object_points[control]
    ext0 = io.exterior[views] + np.r_[5.0, -5.0, 10.0, 0.01, -0.01, 0.02]
    ext, pts, _ = CODE["bundle"](ideal, img, pt, ext0, start, io.c, control)
    res = pl.bundle_adjustment(raw, img, pt, ext0, start, io.c, io.x0, io.y0, io.distortion,
                               control=control)
    assert np.allclose(ext, res.exterior, rtol=0, atol=1e-9 * 500)
    assert np.allclose(pts, res.points, rtol=0, atol=1e-9 * 500)
    sigma0, rn, _, _ = CODE["bundle_statistics"](ideal, img, pt, ext, pts, io.c, control)
    assert sigma0 == pytest.approx(res.sigma0, rel=1e-9)
    assert np.allclose(rn, res.redundancy_numbers, rtol=0, atol=1e-9)
