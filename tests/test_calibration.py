"""Plumb-line calibration (photolib.calibration): recovery, an independent solver, the
derivation, the datum of r0, and degenerate input."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import least_squares

from photolib.calibration import _design, plumb_line
from photolib.derive import distortion as dd
from photolib.derive import plumb_line as pd
from photolib.distortion import Distortion
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError

TRUE = {"A1": -2e-5, "A2": 4e-8}


def _ideal_lines(extent=1.0, hw=18.0, hh=12.0):
    """Four horizontal and four vertical object lines, imaged straight (mm)."""
    x = np.linspace(-hw, hw, 15) * extent
    y = np.linspace(-hh, hh, 11) * extent
    lines = [np.column_stack([x, np.full_like(x, v * extent)]) for v in (-10.0, -5.0, 4.0, 9.0)]
    lines += [np.column_stack([np.full_like(y, v * extent), y]) for v in (-15.0, -8.0, 6.0, 14.0)]
    return lines


def _measured(true, seed=1, noise=1e-3, extent=1.0):
    rng = np.random.default_rng(seed)
    return [true.distort(p) + rng.normal(0.0, noise, p.shape) for p in _ideal_lines(extent)]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_recovers_a1_a2_within_their_sigma(seed):
    fit = plumb_line(_measured(Distortion(**TRUE), seed), c=35.0)
    assert fit.converged and fit.iterations <= 10
    assert fit.terms == ("A1", "A2")
    for name, value in TRUE.items():
        assert abs(fit.distortion.params[name] - value) < 3.0 * fit.sigma[name]
    assert 0.7e-3 < fit.sigma0 < 1.3e-3  # the simulated noise, 1 µm per coordinate
    assert fit.redundancy == 4 * 15 + 4 * 11 - 2 * 8 - 2
    assert len(fit.residuals_um) == 8 and np.all(fit.rms_um < 3.0)


def test_recovers_tangential_terms():
    true = Distortion(A1=-2e-5, A2=4e-8, B1=5e-6, B2=-4e-6)
    fit = plumb_line(_measured(true, seed=4), c=35.0, terms=("B2", "A1", "B1", "A2"))
    assert fit.terms == ("A1", "A2", "B1", "B2")  # sorted as in the model
    for name in fit.terms:
        assert abs(fit.distortion.params[name] - true.params[name]) < 3.0 * fit.sigma[name]


def test_noise_free_recovery_is_exact():
    true = Distortion(A1=-3e-5, A2=5e-8, A3=-2e-11, r0=10.0)
    fit = plumb_line(_measured(true, noise=0.0), c=35.0, r0=10.0, terms=("A1", "A2", "A3"))
    for name in fit.terms:
        assert fit.distortion.params[name] == pytest.approx(true.params[name], rel=1e-7)
    assert fit.sigma0 < 1e-10
    assert fit.distortion.params["r0"] == 10.0


def _scipy_fit(lines, terms, r0=0.0):
    """The same model, solved by SciPy (MINPACK Levenberg–Marquardt, numeric Jacobian)."""
    xy = np.concatenate(lines)
    k = np.repeat(np.arange(len(lines)), [len(p) for p in lines])
    scale = np.array([{"A1": 1e-5, "A2": 1e-8, "B1": 1e-6, "B2": 1e-6}[t] for t in terms])

    def residuals(u):
        p = u[:len(terms)] * scale
        th, d = u[len(terms)::2][k], u[len(terms) + 1::2][k]
        model = Distortion(r0=r0, **dict(zip(terms, p)))
        n = np.column_stack([np.cos(th), np.sin(th)])
        f = np.sum(n * (xy - model.delta(xy)), axis=1) - d
        g = n - np.einsum("ni,nij->nj", n, model.jacobian_xy(xy))
        return f / np.hypot(g[:, 0], g[:, 1])

    start = []
    for p in lines:  # line start values by the normal of the principal axes
        m = p.mean(axis=0)
        n = np.linalg.svd(p - m)[2][-1]
        start += [np.arctan2(n[1], n[0]), n @ m]
    sol = least_squares(residuals, np.r_[np.zeros(len(terms)), start], method="lm",
                        xtol=1e-15, ftol=1e-15, gtol=1e-15)
    r = len(xy) - len(sol.x)
    return sol.x[:len(terms)] * scale, float(np.sqrt(2 * sol.cost / r))


@pytest.mark.parametrize("terms", [("A1", "A2"), ("A1", "A2", "B1", "B2")])
def test_agrees_with_scipy_least_squares(terms):
    lines = _measured(Distortion(A1=-2e-5, A2=4e-8, B1=2e-6), seed=7)
    fit = plumb_line(lines, c=35.0, terms=terms)
    params, sigma0 = _scipy_fit(lines, terms)
    for name, value in zip(terms, params):
        assert abs(fit.distortion.params[name] - value) < 1e-3 * fit.sigma[name]
    # the same minimum: SciPy's numeric Jacobian stops a hair above it in the flat B1 direction
    assert fit.sigma0 == pytest.approx(sigma0, rel=1e-7)
    assert fit.sigma0 <= sigma0 * (1 + 1e-12)


def test_jacobian_agrees_with_sympy_derivation():
    model = Distortion(A1=-2e-5, A2=4e-8, A3=1e-11, r0=8.0, B1=3e-6, B2=-2e-6)
    xy = np.array([[12.0, -7.0], [-3.0, 9.5], [16.0, 11.0]])
    k = np.array([0, 0, 1])
    theta, dist = np.array([0.3, -2.0]), np.array([4.0, -6.5])
    v, A = _design(xy, k, theta, dist, model, ("A1", "A2", "A3", "B1", "B2"))
    args = (dd.x, dd.y, dd.r0, *pd.UNKNOWNS)
    residual = sp.lambdify(args, pd.residual())
    jacobian = sp.lambdify(args, pd.residual_jacobian())
    condition, gradient = sp.lambdify(args, pd.condition()), sp.lambdify(
        args, pd.jacobian_observations())
    for i, (x, y) in enumerate(xy):
        values = (x, y, 8.0, -2e-5, 4e-8, 1e-11, 3e-6, -2e-6, theta[k[i]], dist[k[i]])
        assert residual(*values) == pytest.approx(v[i], rel=1e-12)
        got = np.r_[A[i, :5], A[i, 5 + 2 * k[i]], A[i, 6 + 2 * k[i]]]
        np.testing.assert_allclose(got, np.ravel(jacobian(*values)), rtol=1e-9, atol=1e-14)
        # the weight ‖∂f/∂(x, y)‖ differs from 1 by about |∂Δ/∂x| (< 1 % here)
        assert abs(np.hypot(*np.ravel(gradient(*values))) - 1.0) < 0.01
        assert residual(*values) != condition(*values)


def test_invariances_behind_the_limits():
    assert sp.simplify(pd.radial_line_invariance()) == 0
    assert sp.simplify(pd.r0_datum()) == 0
    assert pd.tangential_projective_part() == sp.zeros(2, 1)


def test_r0_is_a_datum_the_fit_is_the_same_scaled():
    lines = _measured(Distortion(**TRUE), seed=3)
    seidel = plumb_line(lines, c=35.0)
    balanced = plumb_line(lines, c=35.0, r0=12.0)
    s = 1.0 - balanced.distortion.conrady["K0"]
    for name in ("A1", "A2"):
        assert balanced.distortion.params[name] == pytest.approx(
            s * seidel.distortion.params[name], rel=1e-8)
    xy = np.concatenate(lines)
    np.testing.assert_allclose(balanced.distortion.correct(xy), s * seidel.distortion.correct(xy),
                               atol=1e-10)
    assert balanced.sigma0 == pytest.approx(seidel.sigma0, rel=1e-8)
    np.testing.assert_allclose(np.concatenate(balanced.residuals_um),
                               np.concatenate(seidel.residuals_um), atol=1e-7)


def test_coverage_of_the_format_matters():
    centre = plumb_line(_measured(Distortion(**TRUE), seed=5, extent=0.35), c=35.0)
    full = plumb_line(_measured(Distortion(**TRUE), seed=5, extent=1.0), c=35.0)
    corner = float(np.hypot(18.0, 12.0))
    assert centre.radial_sigma(corner) > 20 * full.radial_sigma(corner)
    assert centre.sigma["A1"] > 10 * full.sigma["A1"]


def test_radial_sigma_propagates_the_covariance():
    fit = plumb_line(_measured(Distortion(A1=-2e-5), seed=6), c=35.0, r0=5.0, terms=("A1", "B1"))
    r = np.array([0.0, 5.0, 20.0])
    np.testing.assert_allclose(fit.radial_sigma(r), fit.sigma["A1"] * np.abs(r * (r**2 - 25.0)),
                               rtol=1e-12)


def test_image_vector_uses_principal_point_distortion_and_c():
    lines = [p + [0.1, -0.05] for p in _measured(Distortion(**TRUE), seed=2)]
    fit = plumb_line(lines, c=35.0, principal_point=(0.1, -0.05))
    assert abs(fit.distortion.params["A1"] - TRUE["A1"]) < 3 * fit.sigma["A1"]
    x = fit.image_vector([10.1, 4.95])
    np.testing.assert_allclose(x, np.r_[fit.distortion.correct([10.0, 5.0]), -35.0])


def test_not_converging_raises_or_reports():
    lines = _measured(Distortion(**TRUE), seed=1)
    with pytest.raises(ConvergenceError, match="max_iter=1"):
        plumb_line(lines, c=35.0, max_iter=1)
    fit = plumb_line(lines, c=35.0, max_iter=1, check=False)
    assert not fit.converged and fit.iterations == 1


def _two_lines():
    t = np.linspace(-10.0, 10.0, 5)
    return [np.column_stack([t, np.full(5, 3.0)]), np.column_stack([np.full(5, 4.0), t])]


@pytest.mark.parametrize("lines, match", [
    ([[[0, 1], [1, 1]], [[0, 2], [1, 2], [2, 2]]], r"lines\[0\] has 2 point"),
    ([np.column_stack([np.arange(9.0), np.ones(9)])], "at least 2 lines"),
    ([[[0, 1], [1, 1], [np.nan, 1]], [[0, 2], [1, 2], [2, 2]]], r"lines\[0\]"),
    ([np.ones((4, 3)), np.ones((4, 3))], r"lines\[0\].*\(N, 2\)"),
    ([[1.0, 2.0], [3.0, 4.0]], r"lines\[0\] has 1 point"),
    (5, "sequence"),
])
def test_bad_input_raises(lines, match):
    with pytest.raises(ValueError, match=match):
        plumb_line(lines, c=35.0)


def test_lines_through_the_principal_point_raise():
    t = np.linspace(-15.0, 15.0, 9)
    rays = [np.column_stack([t * np.cos(a), t * np.sin(a)]) for a in (0.0, 0.7, 1.6, 2.5)]
    rays = [Distortion(**TRUE).distort(p) for p in rays]
    with pytest.raises(DegenerateGeometryError, match="all 4 lines pass through the principal point"):
        plumb_line(rays, c=35.0)


def test_undetermined_parameter_is_named():
    t = np.linspace(-15.0, 15.0, 9)
    horizontal = [np.column_stack([t, np.full_like(t, v)]) for v in (-8.0, 3.0, 9.0)]
    with pytest.raises(DegenerateGeometryError, match="do not determine B1"):
        plumb_line(horizontal, c=35.0, terms=("B1", "B2"))


@pytest.mark.parametrize("kwargs, match", [
    ({"terms": ("A1", "C1")}, "C1.*cannot determine"),
    ({"terms": ("A1", "x0")}, "cannot be estimated"),
    ({"terms": ("K1",)}, "unknown parameter"),
    ({"terms": ()}, "at least one"),
    ({"terms": ("A1", "A1")}, "repeat"),
    ({"c": -35.0}, "c"),
    ({"r0": -1.0}, "r0"),
    ({"principal_point": (0.0, np.nan)}, "principal_point"),
    ({"principal_point": (0.0, 0.0, 1.0)}, "principal_point"),
])
def test_bad_options_raise(kwargs, match):
    args = {"c": 35.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        plumb_line(_measured(Distortion(**TRUE)), **args)


def test_low_redundancy_and_coincident_points_raise():
    three = [np.array([[0.0, 5.0], [1.0, 5.0], [2.0, 5.0]]),
             np.array([[5.0, 0.0], [5.0, 1.0], [5.0, 2.0]])]
    with pytest.raises(ValueError, match="redundancy r = 6 points"):
        plumb_line(three, c=35.0)
    same = [np.full((4, 2), 3.0)] + _two_lines()
    with pytest.raises(DegenerateGeometryError, match=r"lines\[0\]: all its points coincide"):
        plumb_line(same, c=35.0)
