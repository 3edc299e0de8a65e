"""Least-squares matching against synthetic images with a known affinity, SymPy and OpenCV."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from photolib.matching import PARAMETER_NAMES, least_squares_matching, lsm_design_matrix
from photolib.errors import InputError
from photolib.transforms._base import ConvergenceError


def _texture(c, r):
    """A smooth analytic grey-value surface (no interpolation error in the truth)."""
    return (120 + 40 * np.sin(c / 3.1) * np.cos(r / 4.3) + 25 * np.cos((c + 2 * r) / 5.7)
            + 15 * np.exp(-((c - 30) ** 2 + (r - 28) ** 2) / 60))


def _search(shape=(64, 64)):
    rr, cc = np.mgrid[: shape[0], : shape[1]].astype(float)
    return _texture(cc, rr)


def _template(params, size=21, noise=0.0, seed=0):
    a0, a1, a2, b0, b1, b2, r0, r1 = params
    y, x = np.mgrid[:size, :size].astype(float) - (size - 1) / 2
    f = r0 + r1 * _texture(a0 + a1 * x + a2 * y, b0 + b1 * x + b2 * y)
    return f + np.random.default_rng(seed).normal(0, noise, f.shape)


TRUE = np.array([31.37, 1.04, 0.06, 29.62, -0.05, 0.97, 8.0, 0.9])


def test_recovers_a_known_affinity_and_radiometry():
    res = least_squares_matching(_template(TRUE), _search(), (30.0, 31.0))
    assert res.converged and res.iterations < 15
    np.testing.assert_allclose(res.params[[0, 3]], TRUE[[0, 3]], atol=0.02)    # shift, px
    np.testing.assert_allclose(res.params[[1, 2, 4, 5]], TRUE[[1, 2, 4, 5]], atol=3e-3)
    # bilinear resampling smooths g a little, so r1 (contrast) comes out slightly high
    np.testing.assert_allclose(res.params[6:], TRUE[6:], rtol=2e-2, atol=1.5)
    assert res.history.shape == (res.iterations + 1, 8)
    np.testing.assert_array_equal(res.history[-1], res.params)


def test_integer_position_agrees_with_opencv_match_template():
    params = np.r_[TRUE[0], 1, 0, TRUE[3], 0, 1, 0, 1]
    f = _template(params).astype(np.float32)
    g = _search().astype(np.float32)
    score = cv2.matchTemplate(g, f, cv2.TM_SQDIFF)
    col, row = np.unravel_index(np.argmin(score), score.shape)[::-1]
    half = (f.shape[1] - 1) / 2
    start = (col + half, row + half)                # template centre in the search image
    res = least_squares_matching(f, g, start)
    assert np.all(np.abs(res.position - start) <= 0.5 + 1e-9)
    np.testing.assert_allclose(res.position, params[[0, 3]], atol=0.02)


@settings(max_examples=15, deadline=None)
@given(dc=st.floats(-1.5, 1.5), dr=st.floats(-1.5, 1.5))
def test_subpixel_shift_round_trip(dc, dr):
    params = np.array([32.0 + dc, 1, 0, 30.0 + dr, 0, 1, 0, 1])
    res = least_squares_matching(_template(params), _search(), (32.0, 30.0))
    np.testing.assert_allclose(res.position, params[[0, 3]], atol=0.02)


def test_sigma0_and_precision_with_noise():
    noise = 2.0
    res = least_squares_matching(_template(TRUE, noise=noise, seed=3), _search(), (30.0, 31.0))
    assert 0.7 * noise < res.sigma0 < 1.5 * noise
    shots = np.array([least_squares_matching(_template(TRUE, noise=noise, seed=s), _search(),
                                             (30.0, 31.0)).params for s in range(30)])
    spread = shots.std(axis=0)
    # predicted σ of the shifts within a factor 2 of the Monte-Carlo spread (+ interpolation bias)
    assert np.all(res.std[[0, 3]] < 2.0 * spread[[0, 3]] + 0.01)
    assert np.all(spread[[0, 3]] < 2.0 * res.std[[0, 3]] + 0.01)


def test_design_matrix_is_the_sympy_linearisation_of_5_72():
    from photolib.derive import image_processing as ip

    lin = ip.lsm_linearised()
    incr = sp.symbols("da0 da1 da2 db0 db1 db2 dr0 dr1", real=True)
    syms = {s.name: s for s in lin.free_symbols}
    rng = np.random.default_rng(40)
    q = rng.uniform(0.5, 1.5, 8)
    x, y, g, gx, gy = rng.uniform(-3, 3, 5)
    row = lsm_design_matrix(q, [x], [y], [g], [gx], [gy])[0]
    values = {syms["x"]: x, syms["y"]: y, syms["g"]: g, syms["g_x"]: gx, syms["g_y"]: gy,
              syms["r1"]: q[7], syms["r0"]: q[6]}
    sym_incr = [syms.get(s.name, s) for s in incr]
    for k, s in enumerate(sym_incr):
        assert float(sp.diff(lin, s).xreplace(values)) == pytest.approx(row[k], rel=1e-12)


def test_design_matrix_against_finite_differences_of_the_model():
    q = np.array([30.2, 1.02, 0.03, 29.1, -0.02, 0.98, 3.0, 1.1])
    x, y, h = 2.5, -1.5, 1e-6

    def model(p):
        return p[6] + p[7] * _texture(p[0] + p[1] * x + p[2] * y, p[3] + p[4] * x + p[5] * y)

    c, r = q[0] + q[1] * x + q[2] * y, q[3] + q[4] * x + q[5] * y
    g = _texture(c, r)
    gx = (_texture(c + h, r) - _texture(c - h, r)) / (2 * h)
    gy = (_texture(c, r + h) - _texture(c, r - h)) / (2 * h)
    row = lsm_design_matrix(q, [x], [y], [g], [gx], [gy])[0]
    fd = [(model(q + h * e) - model(q - h * e)) / (2 * h) for e in np.eye(8)]
    np.testing.assert_allclose(row, fd, rtol=1e-5, atol=1e-6)
    assert len(PARAMETER_NAMES) == 8


def test_flat_template_fails_clearly():
    with pytest.raises(ValueError, match="the template is flat"):
        least_squares_matching(np.full((11, 11), 80.0), _search(), (30.0, 30.0))


def test_one_dimensional_texture_is_singular():
    rr, cc = np.mgrid[:40, :40].astype(float)
    stripes = 100 + 50 * np.sin(cc / 3.0)  # no texture along the rows
    with pytest.raises(ValueError, match="singular"):
        least_squares_matching(stripes[10:21, 10:21], stripes, (15.5, 15.0))


def test_divergence_leaves_the_image():
    f = _template(np.r_[TRUE[0], 1, 0, TRUE[3], 0, 1, 0, 1])
    with pytest.raises(ConvergenceError, match="diverged|leaves the search image"):
        least_squares_matching(f, _search(), (11.0, 11.0))


def test_iteration_limit():
    with pytest.raises(ConvergenceError, match="did not converge in 1 iterations"):
        least_squares_matching(_template(TRUE), _search(), (30.0, 31.0), max_iter=1)
    res = least_squares_matching(_template(TRUE), _search(), (30.0, 31.0), max_iter=1, check=False)
    assert not res.converged and res.iterations == 1


def test_bad_input():
    g = _search()
    with pytest.raises(ValueError, match=r"template has shape \(5,\)"):
        least_squares_matching(np.zeros(5), g, (3.0, 3.0))
    with pytest.raises(ValueError, match=r"initial has shape \(3,\)"):
        least_squares_matching(g[:9, :9], g, (3.0, 3.0, 1.0))
    bad = g.copy()
    bad[2, 3] = np.nan
    with pytest.raises(ValueError, match=r"search contains a non-finite value nan at index \(2, 3\)"):
        least_squares_matching(g[:9, :9], bad, (4.0, 4.0))


# -- input handling (red-team audit) --------------------------------------------------------------

@pytest.mark.parametrize("kwargs, text", [
    ({"max_iter": 0}, "max_iter must be an integer ≥ 1, got 0"),      # was UnboundLocalError
    ({"max_iter": 0, "check": False}, "max_iter must be an integer ≥ 1, got 0"),
    ({"tol": np.nan}, "tol must be finite, got nan"),
])
def test_iteration_controls_are_checked(kwargs, text):
    with pytest.raises(ValueError, match=text):
        least_squares_matching(_template(TRUE), _search(), (31.0, 30.0), **kwargs)


@pytest.mark.parametrize("start", [(3.0, 3.0), (-50.0, 30.0)])
def test_a_start_outside_the_search_image_is_not_called_a_divergence(start):
    with pytest.raises(ValueError, match=r"cannot start: the patch at the initial "
                                               r"position .* does not lie inside the search "
                                               r"image of 64 × 64 pixels") as info:
        least_squares_matching(_template(TRUE), _search(), start)
    assert "diverged" not in str(info.value) and info.value.history.shape == (1, 8)
    assert not isinstance(info.value, ConvergenceError)     # no iteration ran


def test_complex_or_text_images_are_refused():
    f, g = _template(TRUE), _search()
    with pytest.raises(ValueError, match="template must be real, got complex values"):
        least_squares_matching(f + 0j, g, (31.0, 30.0))
    with pytest.raises(ValueError, match="search must be real, got complex values"):
        least_squares_matching(f, g * (1 + 1e-3j), (31.0, 30.0))
    with pytest.raises(ValueError, match="initial must be numeric, got 'ab'"):
        least_squares_matching(f, g, "ab")


# -- a start outside the image is bad input (audit L1) ---------------------------------------------

@pytest.mark.parametrize("start", [(-20.0, -20.0), (3.0, 3.0), (30.0, 70.0)])
def test_a_start_outside_the_image_is_a_value_error_naming_initial(start):
    from photolib.matching import StartOutsideImageError

    with pytest.raises(ValueError, match=r"initial = \(") as info:
        least_squares_matching(_template(TRUE), _search(), start)
    err = info.value
    assert isinstance(err, StartOutsideImageError) and isinstance(err, InputError)
    assert f"initial = ({start[0]!r}, {start[1]!r})" in str(err)
    assert err.history.shape == (1, 8)


def test_a_real_divergence_stays_a_convergence_error_only():
    f = _template(np.r_[TRUE[0], 1, 0, TRUE[3], 0, 1, 0, 1])
    with pytest.raises(ConvergenceError, match="diverged") as info:
        least_squares_matching(f, _search(), (11.0, 11.0))
    assert not isinstance(info.value, ValueError)
