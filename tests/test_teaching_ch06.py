"""Chapter 06's teaching code (the ray on a plane and on a terrain surface, the analytic and the
numerical Jacobian of the collinearity equations, one linearised resection step) agrees with
photolib to 1e-9 on scenes of this test's own, not the notebook's."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl

from .teaching import teaching_functions

CODE = teaching_functions("06-collinearity")


def _aerial(seed):
    rng = np.random.default_rng(seed)
    X0 = np.array([rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(1000, 3000)])
    angles = np.radians(rng.uniform(-4, 4, 3) + [0.0, 0.0, rng.uniform(0, 360)])
    c, x0, y0 = float(rng.uniform(80, 160)), float(rng.uniform(-0.05, 0.05)), float(rng.uniform(-0.05, 0.05))
    xy = rng.uniform(-90, 90, (6, 2))
    return rng, X0, angles, pl.rotation_opk(*angles), c, x0, y0, xy


@pytest.mark.parametrize("seed", range(4))
def test_ray_on_plane_is_monoplot(seed):
    rng, X0, _, R, c, x0, y0, xy = _aerial(seed)
    for p in xy:
        Z = float(rng.uniform(-100, 800))
        np.testing.assert_allclose(CODE["ray_on_plane"](p, X0, R, c, Z, x0, y0),
                                   pl.monoplot(p, X0, R, c, Z=Z, x0=x0, y0=y0), rtol=0, atol=1e-9)


def test_ray_on_plane_refuses_a_plane_behind_the_camera():
    _, X0, _, R, c, x0, y0, xy = _aerial(0)
    with pytest.raises(ValueError, match="behind the camera"):
        CODE["ray_on_plane"](xy[0], X0, R, c, X0[2] + 50.0, x0, y0)
    with pytest.raises(ValueError, match="behind the camera"):
        pl.monoplot(xy[0], X0, R, c, Z=X0[2] + 50.0, x0=x0, y0=y0)


@pytest.mark.parametrize("seed", range(4))
def test_ray_on_surface_is_monoplot_dtm(seed):
    _, X0, _, R, c, x0, y0, xy = _aerial(seed)

    def terrain(XY):
        return 250.0 + 30.0 * np.cos(XY[:, 0] / 200.0) + 0.1 * XY[:, 1]

    start = float(terrain(X0[None, :2])[0])
    for p in xy:
        X, k = CODE["ray_on_surface"](p, X0, R, c, terrain, start, tol=1e-6, x0=x0, y0=y0)
        lib = pl.monoplot_dtm(p, X0, R, c, terrain, x0, y0, Z_start=start, tol=1e-6)
        np.testing.assert_allclose(X, lib, rtol=0, atol=1e-9)
        assert k >= 1 and abs(X[2] - terrain(X[None, :2])[0]) < 1e-5


def test_ray_on_surface_says_when_it_does_not_converge():
    with pytest.raises(ValueError, match="no convergence"):
        CODE["ray_on_surface"]([60.0, 0.0], np.array([0.0, 0.0, 1000.0]), np.eye(3), 100.0,
                               lambda XY: 1.7 * XY[:, 0] - 500.0, 0.0, max_iter=20)


@pytest.mark.parametrize("seed", range(4))
def test_analytic_partials_are_photolibs_and_the_numerical_ones_agree(seed):
    rng, X0, angles, R, c, *_ = _aerial(seed)
    ray = R @ np.array([rng.uniform(-60, 60), rng.uniform(-60, 60), -c])
    X = X0 + ray * (X0[2] - 200.0) / -ray[2]
    J = CODE["collinearity_partials"](X, X0, *angles, c)
    lib = pl.collinearity_jacobian(X, X0, R, c, angles=tuple(angles))
    np.testing.assert_allclose(J, lib, rtol=0, atol=1e-9)
    Jn = CODE["numerical_jacobian"](X, X0, *angles, c)
    np.testing.assert_allclose(Jn, J, rtol=0, atol=1e-6 * max(1.0, np.max(np.abs(J))))


@pytest.mark.parametrize("seed", range(3))
def test_resection_step_is_one_photolib_iteration(seed):
    rng = np.random.default_rng(100 + seed)
    X = np.column_stack([rng.uniform(-30, 30, 9), rng.uniform(-30, 30, 9), rng.uniform(-4, 4, 9)])
    truth = np.r_[rng.uniform(-3, 3, 2), rng.uniform(80, 120), np.radians(rng.uniform(-5, 5, 3))]
    c = 40.0
    xy = pl.project(X, truth[:3], pl.rotation_opk(*truth[3:]), c) + rng.normal(0, 0.002, (9, 2))
    q0 = truth + np.r_[2.0, -2.0, 5.0, np.radians([1.0, -1.5, 2.0])]
    q1, dq = CODE["resection_step"](q0, X, xy, c)
    one = pl.space_resection(X, xy, c, initial=q0, max_iter=1, check=False)
    np.testing.assert_allclose(q1, np.r_[one.X0, one.omega, one.phi, one.kappa], rtol=0,
                               atol=1e-9)
    np.testing.assert_allclose(q1 - q0, dq, rtol=0, atol=1e-12)
