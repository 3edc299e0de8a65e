"""One camera, one type (issue 18): ExteriorOrientation is accepted wherever photolib takes an
exterior orientation — unpacked as (X0, R), or read by NumPy as its six parameters — and the
results hand one back; each route is checked against the plain arrays it replaces."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib.exterior import ExteriorOrientation

X = np.array([[10.0, 20.0, 0.0], [-30.0, 5.0, 2.0], [40.0, -25.0, -1.0], [0.0, 0.0, 3.0],
              [25.0, 30.0, 1.0], [-20.0, -35.0, 0.5]])


def _eo():
    return ExteriorOrientation.from_opk([2.0, -3.0, 500.0], 0.02, -0.015, 0.4)


def test_it_unpacks_as_x0_r_and_reads_as_six_parameters():
    eo = _eo()
    X0, R = eo
    np.testing.assert_array_equal(R, pl.rotation_opk(0.02, -0.015, 0.4))
    np.testing.assert_allclose(np.asarray(eo), [2.0, -3.0, 500.0, 0.02, -0.015, 0.4],
                               rtol=0, atol=1e-12)
    assert np.asarray([eo, eo], dtype=float).shape == (2, 6)
    back = ExteriorOrientation.from_params(eo.params)
    np.testing.assert_allclose(back.R, eo.R, rtol=0, atol=1e-15)


def test_functions_taking_x0_r_accept_it():
    eo = _eo()
    np.testing.assert_array_equal(pl.project(X, *eo, 100.0), pl.project(X, eo.X0, eo.R, 100.0))
    xy = pl.project(X, *eo, 100.0)
    for k in range(len(X)):                       # monoplot: one height per call
        np.testing.assert_allclose(pl.monoplot(xy[k], *eo, 100.0, X[k, 2]), X[k], rtol=0,
                                   atol=1e-9)
    np.testing.assert_array_equal(pl.collinearity_jacobian(X, *eo, 100.0),
                                  pl.collinearity_jacobian(X, eo.X0, eo.R, 100.0))


def test_results_give_one_back_and_the_bundle_takes_a_list_of_them():
    eo = _eo()
    xy = pl.project(X, *eo, 100.0)
    res = pl.space_resection(X, xy, 100.0, initial=ExteriorOrientation.from_opk(
        [0.0, 0.0, 450.0], 0.0, 0.0, 0.35))
    np.testing.assert_allclose(res.orientation.params, eo.params, rtol=0, atol=1e-6)
    # a two-image block: exterior as a list of ExteriorOrientation = the (M, 6) array
    eo2 = ExteriorOrientation.from_opk([60.0, -3.0, 505.0], -0.01, 0.02, 0.38)
    obs = np.vstack([pl.project(X, *e, 100.0) for e in (eo, eo2)])
    img = np.repeat([0, 1], len(X))
    pt = np.tile(np.arange(len(X)), 2)
    start = [ExteriorOrientation.from_params(e.params + [1, -1, 2, 0.005, -0.004, 0.01])
             for e in (eo, eo2)]
    a = pl.bundle_adjustment(obs, img, pt, start, X, 100.0, control=np.arange(len(X)))
    b = pl.bundle_adjustment(obs, img, pt, np.asarray(start), X, 100.0,
                             control=np.arange(len(X)))
    np.testing.assert_array_equal(a.exterior, b.exterior)
    assert [type(o) for o in a.orientations] == [ExteriorOrientation] * 2
    np.testing.assert_allclose(a.orientations[1].params, eo2.params, rtol=0, atol=1e-6)


def test_bad_values_are_named():
    with pytest.raises(ValueError, match=r"X0 has shape \(2,\)"):
        ExteriorOrientation([0.0, 1.0], np.eye(3))
    with pytest.raises(ValueError, match="R"):
        ExteriorOrientation([0.0, 1.0, 2.0], np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match=r"params has shape \(5,\)"):
        ExteriorOrientation.from_params(np.zeros(5))
    with pytest.raises(ValueError, match="NaN|finite"):
        ExteriorOrientation.from_params([0, 0, np.nan, 0, 0, 0])
    locked = ExteriorOrientation([0.0, 0.0, 1.0], pl.rotation_opk(0.1, np.pi / 2, 0.2))
    with pytest.raises(pl.GimbalLockError):
        locked.params  # noqa: B018 - the property raises
