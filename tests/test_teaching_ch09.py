"""Chapter 09's teaching code (forward intersection of K rays and the dependent relative
orientation by Gauss–Newton, written out in the notebook) agrees with photolib to 1e-9 on
pairs of this test's own, not the notebook's."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl

from .teaching import teaching_functions

CODE = teaching_functions("09-stereo")


def _block(seed, K=3, n=8, noise_mm=0.003):
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-10, 10, n), rng.uniform(-10, 10, n), rng.uniform(-3, 3, n)])
    X0 = np.column_stack([np.linspace(-12, 12, K), rng.uniform(-2, 2, K), rng.uniform(45, 55, K)])
    R = np.array([pl.rotation_opk(*np.radians(rng.uniform(-6, 6, 3))) for _ in range(K)])
    c = float(rng.uniform(30, 60))
    xy = np.array([pl.project(X, X0[k], R[k], c) for k in range(K)])
    return X, X0, R, c, xy + rng.normal(0, noise_mm, xy.shape)


@pytest.mark.parametrize("seed, K", [(0, 2), (1, 2), (2, 3), (3, 4)])
def test_teaching_intersection_is_photolibs(seed, K):
    X, X0, R, c, xy = _block(seed, K)
    ref = pl.forward_intersection(xy, X0, R, c)
    mine = np.array([CODE["intersect_rays"](xy[:, i], X0, R, c) for i in range(len(X))])
    assert np.abs(mine - ref.points).max() < 1e-9 * 50          # 1e-9 relative to the 50 m range
    assert np.abs(mine - X).max() < 0.1                          # and near the truth


def test_teaching_intersection_refuses_parallel_rays():
    with pytest.raises(ValueError, match="parallel"):
        CODE["intersect_rays"]([[2.0, 1.0], [2.0, 1.0]], [[0, 0, 0], [5.0, 0, 0]],
                               [np.eye(3), np.eye(3)], 40.0)


def _pair(seed, n=12, noise_mm=0.002):
    rng = np.random.default_rng(seed)
    c = float(rng.uniform(25, 60))
    X = np.column_stack([rng.uniform(-0.5, 1.5, n), rng.uniform(-1, 1, n), -rng.uniform(2.5, 3.5, n)])
    q = np.r_[rng.uniform(-0.05, 0.05, 2), rng.uniform(-0.05, 0.05, 3)]
    a = pl.project(X, np.zeros(3), np.eye(3), c)
    b = pl.project(X, [1.0, q[0], q[1]], pl.rotation_opk(*q[2:]), c)
    return a + rng.normal(0, noise_mm, a.shape), b + rng.normal(0, noise_mm, b.shape), c, q


@pytest.mark.parametrize("seed", range(4))
def test_teaching_relative_orientation_is_photolibs(seed):
    a, b, c, q = _pair(seed)
    mine, iterations = CODE["relative_orientation_gn"](a, b, c)
    ro = pl.relative_orientation(a, b, c, bx=1.0)
    assert np.abs(mine - ro.params).max() < 1e-9
    assert np.abs(mine - q).max() < 0.01 and 1 < iterations < 30


def test_teaching_jacobian_is_the_numerical_derivative():
    # the Jacobian of the coplanarity residuals against central differences (independent route)
    a, b, c, _ = _pair(7)
    q = np.array([0.02, -0.03, 0.01, 0.02, -0.015])
    _, J = CODE["coplanarity"](q, a, b, c, 1.0)
    h = 1e-6
    num = np.column_stack([(CODE["coplanarity"](q + h * e, a, b, c, 1.0)[0]
                            - CODE["coplanarity"](q - h * e, a, b, c, 1.0)[0]) / (2 * h)
                           for e in np.eye(5)])
    assert np.abs(J - num).max() < 1e-7 * np.abs(J).max()


def test_teaching_relative_orientation_refuses_four_points():
    a, b, c, _ = _pair(1)
    with pytest.raises(ValueError, match="at least 5"):
        CODE["relative_orientation_gn"](a[:4], b[:4], c)
