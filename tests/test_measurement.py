"""Image measurement: LoG against SymPy/SciPy/finite differences, Tsai's moments, circle fit."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy import ndimage, optimize

from photolib.measurement import fit_circle, laplacian_of_gaussian, moment_threshold

# ---------------------------------------------------------------- Laplacian of Gaussian


def test_log_matches_sympy_laplacian_of_normalised_gaussian():
    x, y = sp.symbols("x y", real=True)
    s = sp.symbols("sigma", positive=True)
    G = sp.exp(-(x**2 + y**2) / (2 * s**2)) / (2 * sp.pi * s**2)
    lap = sp.lambdify((x, y, s), sp.diff(G, x, 2) + sp.diff(G, y, 2))
    rng = np.random.default_rng(20)
    for xv, yv, sv in rng.uniform([-5, -5, 0.5], [5, 5, 3], (20, 3)):
        assert laplacian_of_gaussian(np.hypot(xv, yv), sv) == pytest.approx(lap(xv, yv, sv), rel=1e-12, abs=1e-15)


def test_log_printed_versions():
    """The errata's corrected 5.42 is the Laplacian; the original print is not (even up to scale)."""
    r = np.linspace(0.0, 6.0, 13)
    sigma = 1.7
    corrected = -1 / (np.pi * sigma**4) * (1 - r**2 / (2 * sigma**2)) * np.exp(-(r**2) / (2 * sigma**2))
    original = -(1 - r / sigma**2) * np.exp(-(r**2) / (2 * sigma**2))
    assert np.allclose(laplacian_of_gaussian(r, sigma), corrected, rtol=1e-13)
    ratio = laplacian_of_gaussian(r[:5], sigma) / original[:5]
    assert np.ptp(ratio) > 0.1 * abs(ratio[0])  # not proportional: the zero crossing moves


def test_log_matches_finite_difference_laplacian():
    sigma, h = 2.0, 1e-3
    G = lambda x, y: np.exp(-(x**2 + y**2) / (2 * sigma**2)) / (2 * np.pi * sigma**2)
    rng = np.random.default_rng(21)
    for x, y in rng.uniform(-6, 6, (10, 2)):
        fd = (G(x + h, y) + G(x - h, y) + G(x, y + h) + G(x, y - h) - 4 * G(x, y)) / h**2
        assert laplacian_of_gaussian(np.hypot(x, y), sigma) == pytest.approx(fd, rel=1e-5, abs=1e-10)


def test_log_matches_scipy_gaussian_laplace_of_a_unit_impulse():
    """SciPy's discrete LoG of a unit impulse samples ∇²G (its kernel is normalised to sum 1)."""
    sigma, n = 4.0, 81
    img = np.zeros((n, n))
    img[n // 2, n // 2] = 1.0
    kernel = ndimage.gaussian_laplace(img, sigma, truncate=6.0)
    yy, xx = np.mgrid[:n, :n] - n // 2
    ours = laplacian_of_gaussian(np.hypot(xx, yy), sigma)
    assert np.max(np.abs(kernel - ours)) < 1e-3 * np.max(np.abs(ours))
    assert abs(ours.sum()) < 1e-6 * np.abs(ours).sum()  # ∬∇²G = 0


def test_log_bad_input():
    with pytest.raises(ValueError, match="sigma must be > 0"):
        laplacian_of_gaussian(1.0, 0.0)
    with pytest.raises(ValueError, match="r contains a non-finite value"):
        laplacian_of_gaussian([0.0, np.nan], 1.0)


# ---------------------------------------------------------------- moment-preserving threshold


def _moments(g):
    return [np.mean(np.asarray(g, float) ** i) for i in (1, 2, 3)]


@pytest.mark.parametrize(("p1", "h1", "h2"), [(0.3, 10.0, 200.0), (0.8, 40.0, 90.0), (0.5, 0.0, 1.0)])
def test_moment_threshold_recovers_a_bilevel_image(p1, h1, h2):
    n = 1000
    k = round(p1 * n)
    img = np.random.default_rng(22).permutation(np.r_[np.full(k, h1), np.full(n - k, h2)]).reshape(25, 40)
    t = moment_threshold(img)
    assert (t.p1, t.h1, t.h2) == pytest.approx((p1, h1, h2), rel=1e-9, abs=1e-9)
    assert t.threshold == h1


def test_moment_threshold_preserves_the_first_three_moments():
    rng = np.random.default_rng(23)
    img = np.clip(np.r_[rng.normal(60, 12, 3000), rng.normal(180, 20, 1200)], 0, 255).round()
    t = moment_threshold(img)
    m = _moments(img)
    for i, mi in enumerate(m, start=1):
        assert t.p1 * t.h1**i + (1 - t.p1) * t.h2**i == pytest.approx(mi, rel=1e-10)
    assert t.h1 < t.threshold < t.h2
    assert np.mean(img <= t.threshold) == pytest.approx(t.p1, abs=2e-3)  # the p1-tile
    assert 60 - 15 < t.h1 < 60 + 15 and 180 - 25 < t.h2 < 180 + 25


def test_moment_solution_against_sympy_and_the_printed_5_50():
    """Solve m_i = p1 h1^i + p2 h2^i (i = 1, 2, 3) with SymPy; the printed p1 is wrong."""
    p, h1, h2 = sp.symbols("p h1 h2", real=True)
    rng = np.random.default_rng(24)
    img = rng.gamma(2.0, 30.0, 500).round()
    m1, m2, m3 = (sp.Rational(v).limit_denominator(10**12) for v in _moments(img))
    eqs = [p * h1**i + (1 - p) * h2**i - mi for i, mi in zip((1, 2, 3), (m1, m2, m3))]
    sols = [s for s in sp.solve(eqs, [p, h1, h2], dict=True) if s[h1] < s[h2]]
    assert len(sols) == 1
    t = moment_threshold(img)
    assert (t.p1, t.h1, t.h2) == pytest.approx(
        (float(sols[0][p]), float(sols[0][h1]), float(sols[0][h2])), rel=1e-9)
    sd = np.sqrt(float(m2 - m1**2))
    s = float(m3 + 2 * m1**3 - 3 * m1 * m2) / sd**3  # skewness as printed in 5.50
    printed_p1 = 0.5 * (1 + s * np.sqrt(4 + s**2))
    assert abs(printed_p1 - t.p1) > 0.1 and printed_p1 > 1  # skewed image: printed p1 > 1
    assert t.h2 == pytest.approx(float(m1) + sd * np.sqrt(t.p1 / (1 - t.p1)), rel=1e-12)  # 5.49


def test_moment_threshold_bad_input():
    with pytest.raises(ValueError, match="constant"):
        moment_threshold(np.full((4, 4), 7))
    with pytest.raises(ValueError, match="empty"):
        moment_threshold([])
    with pytest.raises(ValueError, match=r"image contains a non-finite value nan at index \(2,\)"):
        moment_threshold([1.0, 2.0, np.nan])


# ---------------------------------------------------------------- circle fit


def test_fit_circle_three_points_is_the_circumcircle():
    rng = np.random.default_rng(25)
    P = rng.uniform(-10, 10, (3, 2))
    # circumcentre from the perpendicular bisectors: 2(Pi − P0)·c = |Pi|² − |P0|²
    A = 2 * (P[1:] - P[0])
    b = np.sum(P[1:] ** 2, axis=1) - np.sum(P[0] ** 2)
    c = np.linalg.solve(A, b)
    fit = fit_circle(P)
    assert np.allclose(fit.centre, c, atol=1e-9)
    assert fit.radius == pytest.approx(np.linalg.norm(P[0] - c), rel=1e-10)
    assert np.isnan(fit.sigma0) and fit.iterations == 0


def test_fit_circle_geometric_matches_scipy_least_squares():
    rng = np.random.default_rng(26)
    t = rng.uniform(0.2, 2.5, 40)  # an arc: algebraic and geometric fits differ
    xy = np.column_stack([1e3 + 25 * np.cos(t), -4e2 + 25 * np.sin(t)]) + rng.normal(0, 0.3, (40, 2))
    fit = fit_circle(xy)
    res = optimize.least_squares(lambda q: np.hypot(*(xy - q[:2]).T) - q[2],
                                 x0=[1e3, -4e2, 20.0], xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.allclose(fit.centre, res.x[:2], atol=1e-7)
    assert fit.radius == pytest.approx(res.x[2], abs=1e-7)
    assert fit.sigma0 == pytest.approx(np.sqrt(2 * res.cost / 37), rel=1e-8)
    algebraic = fit_circle(xy, refine=False)
    assert np.sum(fit.residuals**2) < np.sum(algebraic.residuals**2)


def test_fit_circle_through_the_origin():
    t = np.linspace(0, 2 * np.pi, 9)[:-1]
    fit = fit_circle(np.column_stack([5 + 5 * np.cos(t), 5 * np.sin(t)]))  # F = 0: 2.88 fails here
    assert np.allclose(fit.centre, [5, 0], atol=1e-12) and fit.radius == pytest.approx(5.0)


def test_fit_circle_bad_input():
    with pytest.raises(ValueError, match="at least 3 points, got 2"):
        fit_circle([[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="collinear"):
        fit_circle([[0, 0], [1, 1], [2, 2], [3, 3]])
    with pytest.raises(ValueError, match=r"xy has shape \(3, 3\)"):
        fit_circle(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="non-finite"):
        fit_circle([[0, 0], [1, np.inf], [2, 0]])
