"""photolib.monoplot_dtm: the fixed-point iteration of monoplotting on a terrain surface agrees
with an independent root search along the ray (SciPy's brentq on Z_ray(λ) − h(X(λ), Y(λ)))."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import photolib as pl


def _hills(XY):
    XY = np.asarray(XY, float)
    return 300.0 + 40.0 * np.sin(XY[:, 0] / 400.0) * np.cos(XY[:, 1] / 300.0) + 0.05 * XY[:, 0]


def _by_root_search(xy, X0, R, c, x0, y0, surface):
    ray = R @ np.array([xy[0] - x0, xy[1] - y0, -c])
    f = lambda lam: (X0 + lam * ray)[2] - surface((X0 + lam * ray)[None, :2])[0]  # noqa: E731
    lam = brentq(f, 1e-9, 10.0 * X0[2] / abs(ray[2]), xtol=1e-14)
    return X0 + lam * ray


@pytest.mark.parametrize("seed", range(4))
def test_iteration_meets_the_root_of_the_ray(seed):
    rng = np.random.default_rng(seed)
    X0 = np.array([rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(1500, 2500)])
    R = pl.rotation_opk(*np.radians(rng.uniform(-3, 3, 3)))
    c, x0, y0 = 120.0, 0.02, -0.01
    xy = rng.uniform(-80, 80, (5, 2))
    X = pl.monoplot_dtm(xy, X0, R, c, _hills, x0, y0, tol=1e-10)
    for p, got in zip(xy, X):
        np.testing.assert_allclose(got, _by_root_search(p, X0, R, c, x0, y0, _hills), atol=1e-6)
    np.testing.assert_allclose(X[:, 2], _hills(X[:, :2]), atol=1e-9)


def test_a_flat_surface_is_the_plane_and_dtm_objects_work():
    X0, R = np.array([0.0, 0.0, 1000.0]), pl.rotation_opk(0.02, -0.01, 0.3)
    xy = np.array([[10.0, -20.0], [-30.0, 5.0]])
    dtm = pl.DTM(np.full((5, 5), 250.0), origin=(-2000.0, 2000.0), spacing=1000.0)
    np.testing.assert_allclose(pl.monoplot_dtm(xy, X0, R, 100.0, dtm),
                               pl.monoplot(xy, X0, R, 100.0, Z=250.0), atol=1e-9)


def test_history_contracts_by_slope_times_tan_nu():
    """On the plane h = s·X the height error shrinks by the factor s·X'/c per step."""
    s, xp, c = 0.2, 30.0, 100.0
    X, hist = pl.monoplot_dtm([xp, 0.0], [0.0, 0.0, 1000.0], np.eye(3), c,
                              lambda XY: s * XY[:, 0], tol=1e-9, return_iterations=True)
    err = np.abs(hist[:, 0] - X[2])
    np.testing.assert_allclose(err[1:6] / err[:5], s * xp / c, rtol=1e-6)


def test_steep_terrain_does_not_converge_and_says_so():
    with pytest.raises(ValueError, match="did not converge"):
        pl.monoplot_dtm([50.0, 0.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0,
                        lambda XY: 2.5 * XY[:, 0], max_iter=30)


def test_bad_surface_is_named():
    with pytest.raises(ValueError, match="expected 1 finite heights"):
        pl.monoplot_dtm([1.0, 0.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0,
                        lambda XY: np.full(len(XY), np.nan))
    with pytest.raises(TypeError, match="surface must be"):
        pl.monoplot_dtm([1.0, 0.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0, 5.0)
