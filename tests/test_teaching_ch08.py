"""Chapter 08's teaching code (the DLT and the Gauss–Newton space resection written out in the
notebook) agrees with photolib to 1e-9 on blocks of this test's own, not the notebook's."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl

from .teaching import teaching_functions

CODE = teaching_functions("08-resection-dlt")


def _scene(seed, n=15, noise_mm=0.004):
    rng = np.random.default_rng(seed)
    X0 = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(18, 25)])
    R = pl.rotation_opk(*np.radians(rng.uniform(-8, 8, 3)))
    X = np.column_stack([rng.uniform(-8, 8, n), rng.uniform(-8, 8, n), rng.uniform(-3, 3, n)])
    c = float(rng.uniform(35, 60))
    xy = pl.project(X, X0, R, c) + rng.normal(0, noise_mm, (n, 2))
    return X, xy, c, X0, R


@pytest.mark.parametrize("seed", range(4))
def test_teaching_dlt_is_photolibs(seed):
    X, xy, *_ = _scene(seed)
    L = CODE["dlt"](X, xy)
    assert np.allclose(L, pl.dlt_estimate(X, xy).L, rtol=1e-9, atol=0)


@pytest.mark.parametrize("seed", range(4))
def test_teaching_resection_is_photolibs(seed):
    X, xy, c, X0, R = _scene(seed)
    start = np.r_[X0 + [0.5, -0.4, 1.0], np.array(pl.opk_from_rotation(R)) + 0.02]
    q, sigma0, Sqq, iterations, v = CODE["resection"](X, xy, c, start)
    res = pl.space_resection(X, xy, c, initial=start)
    assert np.allclose(q[:3], res.X0, rtol=0, atol=1e-9 * 25)
    assert np.allclose(q[3:], [res.omega, res.phi, res.kappa], rtol=0, atol=1e-9)
    assert sigma0 == pytest.approx(res.sigma0, rel=1e-9)
    assert np.allclose(np.sqrt(np.diag(Sqq)), res.std, rtol=1e-7)
