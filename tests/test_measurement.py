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


def test_fit_circle_many_points_in_bounded_memory():
    """2e5 edge points (a full SVD would build a 2e5 × 2e5 U: 320 GB); the fit recovers the
    circle the noisy points were drawn from within a few standard errors σ·sqrt(2/N)."""
    rng = np.random.default_rng(7)
    n, sigma = 200_000, 0.01
    t = rng.uniform(0, 2 * np.pi, n)
    rad = 12.5 + rng.normal(0, sigma, n)
    fit = fit_circle(np.column_stack([40.0 + rad * np.cos(t), -7.0 + rad * np.sin(t)]))
    se = sigma * np.sqrt(2.0 / n)
    np.testing.assert_allclose(fit.centre, [40.0, -7.0], atol=6 * se)
    assert abs(fit.radius - 12.5) < 6 * sigma / np.sqrt(n)
    assert abs(fit.sigma0 - sigma) < 0.02 * sigma


def test_fit_circle_bad_input():
    with pytest.raises(ValueError, match="at least 3 points, got 2"):
        fit_circle([[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="collinear"):
        fit_circle([[0, 0], [1, 1], [2, 2], [3, 3]])
    with pytest.raises(ValueError, match=r"xy has shape \(3, 3\)"):
        fit_circle(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="non-finite"):
        fit_circle([[0, 0], [1, np.inf], [2, 0]])


# ---------------------------------------------------------------- LoG filtering, zero crossings

import cv2  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from photolib.fitting import (  # noqa: E402
    circle_from_conic,
    conic_to_ellipse,
    fit_ellipse,
    fit_plane,
    plane_through_points,
)
from photolib.measurement import (  # noqa: E402
    edge_points,
    gaussian_radius,
    log_filter,
    log_kernel_1d,
    sobel_gradient,
    weighted_centroid,
    zero_crossings,
)
from photolib.transforms._base import DegenerateGeometryError  # noqa: E402


def _scene(seed=30, shape=(48, 64)):
    rng = np.random.default_rng(seed)
    return rng.uniform(0, 255, shape)


@pytest.mark.parametrize("sigma", [1.0, 1.7, 3.0])
def test_log_filter_matches_scipy_gaussian_laplace(sigma):
    """SciPy samples the same separable kernels (mirrored borders); ours fixes Σg'' = 0."""
    img = ndimage.gaussian_filter(_scene(), 1.0)
    ours = log_filter(img, sigma)
    ref = ndimage.gaussian_laplace(img, sigma, mode="reflect", truncate=4.0)
    assert np.max(np.abs(ours - ref)) < 1.5e-2 * np.max(np.abs(ref))


def test_log_filter_is_exact_on_a_quadratic_where_scipy_is_not():
    """∇²(x² + y²) = 4: the zero-sum, second-moment-normalised g'' gets it exactly."""
    yy, xx = np.mgrid[:41, :41].astype(float)
    img = (xx - 20.0) ** 2 + (yy - 20.0) ** 2
    inner = (slice(14, -14), slice(14, -14))
    np.testing.assert_allclose(log_filter(img, 1.5)[inner], 4.0, rtol=1e-10)
    scipy_inner = ndimage.gaussian_laplace(img, 1.5)[inner]
    assert np.max(np.abs(scipy_inner - 4.0)) > 1e-4  # sampled tails: not exact


def test_log_filter_matches_opencv_blur_then_laplacian_inside():
    """cv2.GaussianBlur followed by cv2.Laplacian (3 × 3, discrete) is the same LoG up to
    the discretisation of ∇²; on a smooth image they agree inside the borders."""
    img = ndimage.gaussian_filter(_scene(31, (80, 80)), 3.0)
    sigma = 2.5
    k = 2 * gaussian_radius(sigma) + 1
    cv = cv2.Laplacian(cv2.GaussianBlur(img, (k, k), sigma, borderType=cv2.BORDER_REFLECT),
                       cv2.CV_64F, ksize=1, borderType=cv2.BORDER_REFLECT)
    ours = log_filter(img, sigma)
    inner = (slice(15, -15), slice(15, -15))
    assert np.max(np.abs(ours[inner] - cv[inner])) < 0.05 * np.max(np.abs(ours[inner]))


def test_log_kernel_is_the_sampled_5_42():
    """The 2-D outer combination of the 1-D kernels is ∇²G (5.42) sampled, up to the sum normalisation."""
    sigma = 2.0
    g, g2 = log_kernel_1d(sigma)
    K = np.outer(g, g2) + np.outer(g2, g)
    r = np.arange(len(g)) - len(g) // 2
    ref = laplacian_of_gaussian(np.hypot(*np.meshgrid(r, r)), sigma)
    assert np.max(np.abs(K - ref)) < 2e-2 * np.max(np.abs(ref))
    assert abs(K.sum()) < 1e-12


def test_log_zero_crossing_of_a_step_is_at_the_edge():
    img = np.zeros((20, 40))
    img[:, 20:] = 100.0  # edge between col 19 and 20
    zc = zero_crossings(log_filter(img, 2.0), threshold=1.0)
    cols = np.unique(np.nonzero(zc)[1])
    assert set(cols) <= {19, 20} and len(cols) >= 1


def test_log_zero_crossings_of_a_disc_lie_on_its_rim():
    yy, xx = np.mgrid[:61, :61]
    img = 200.0 * (np.hypot(xx - 30.2, yy - 29.7) < 12.0)
    zc = zero_crossings(log_filter(img, 1.5), threshold=5.0)
    r = np.hypot(*(np.argwhere(zc)[:, ::-1] - [30.2, 29.7]).T)
    assert len(r) > 50 and np.all(np.abs(r - 12.0) < 1.2)


def test_log_filter_bad_input():
    with pytest.raises(ValueError, match="sigma must be > 0"):
        log_filter(np.zeros((5, 5)), -1.0)
    with pytest.raises(ValueError, match=r"image has shape \(5,\)"):
        log_filter(np.zeros(5), 1.0)
    img = np.zeros((5, 5))
    img[2, 2] = np.nan
    with pytest.raises(ValueError, match=r"image contains a non-finite value nan at index \(2, 2\)"):
        log_filter(img, 1.0)
    with pytest.raises(ValueError, match="threshold must be ≥ 0"):
        zero_crossings(np.zeros((4, 4)), -1.0)


# ---------------------------------------------------------------- gradient edges


def test_sobel_matches_opencv():
    img = _scene(32)
    gc, gr = sobel_gradient(img)
    cv_c = cv2.Sobel(img, cv2.CV_64F, 1, 0, ksize=3, borderType=cv2.BORDER_REFLECT) / 8
    cv_r = cv2.Sobel(img, cv2.CV_64F, 0, 1, ksize=3, borderType=cv2.BORDER_REFLECT) / 8
    np.testing.assert_allclose(gc, cv_c, atol=1e-10)
    np.testing.assert_allclose(gr, cv_r, atol=1e-10)


@pytest.mark.parametrize("angle_deg", [0.0, 25.0, 60.0])
def test_subpixel_edge_of_a_blurred_straight_edge(angle_deg):
    """A smooth step (erf profile) across the line n·p = d: edge points lie on that line."""
    from scipy.special import erf

    a = np.radians(angle_deg)
    n = np.array([np.cos(a), np.sin(a)])
    yy, xx = np.mgrid[:40, :40].astype(float)
    d = 20.37 * (n[0] + n[1]) / 1.0
    img = 50 + 100 * (1 + erf((xx * n[0] + yy * n[1] - d) / (np.sqrt(2) * 1.2))) / 2
    e = edge_points(img, 5.0)
    inner = np.all((e.colrow > 4) & (e.colrow < 35), axis=1)
    dist = e.colrow[inner] @ n - d
    assert inner.sum() > 20
    assert np.max(np.abs(dist)) < (0.03 if angle_deg == 0.0 else 0.1)  # oblique: bilinear m±
    assert np.all(e.direction[inner] @ n > np.cos(np.radians(1.0)))  # Sobel direction within 1°


def test_edge_points_bad_input():
    with pytest.raises(ValueError, match="threshold must be > 0"):
        edge_points(np.zeros((5, 5)), 0.0)
    assert len(edge_points(np.zeros((5, 5)), 1.0).colrow) == 0


# ---------------------------------------------------------------- weighted centroid


def test_centroid_matches_scipy_center_of_mass_swapped():
    rng = np.random.default_rng(33)
    yy, xx = np.mgrid[:21, :25]
    img = 20 + 150 * np.exp(-((xx - 11.37) ** 2 + (yy - 9.81) ** 2) / 8) + rng.normal(0, 1, xx.shape)
    c = weighted_centroid(img, background=40.0)
    w = np.maximum(img - 40.0, 0)
    row, col = ndimage.center_of_mass(w)  # SciPy: (row, col)
    np.testing.assert_allclose(c.colrow, [col, row], atol=1e-12)
    assert abs(c.colrow[0] - 11.37) < 0.05 and abs(c.colrow[1] - 9.81) < 0.05


def test_centroid_precision_by_monte_carlo():
    rng = np.random.default_rng(34)
    yy, xx = np.mgrid[:15, :15]
    clean = 200 * np.exp(-((xx - 7.2) ** 2 + (yy - 6.9) ** 2) / 6) + 10
    sigma_g = 2.0
    cs = np.array([weighted_centroid(clean + rng.normal(0, sigma_g, clean.shape), 0.0).colrow
                   for _ in range(800)])
    pred = weighted_centroid(clean, 0.0, sigma_g=sigma_g).std
    np.testing.assert_allclose(cs.std(axis=0), pred, rtol=0.12)


def test_centroid_bad_input():
    with pytest.raises(ValueError, match="the target is empty"):
        weighted_centroid(np.full((5, 5), 10.0), background=20.0)
    img = np.ones((4, 4))
    img[1, 2] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        weighted_centroid(img)
    with pytest.raises(ValueError, match="sigma_g must be ≥ 0"):
        weighted_centroid(np.ones((4, 4)), 0.0, sigma_g=-1.0)


# ---------------------------------------------------------------- ellipse, circle from conic, plane


def _ellipse_points(c, a, b, theta, t):
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return c + (R @ np.vstack([a * np.cos(t), b * np.sin(t)])).T


def _same_angle(a, b):
    return abs(((a - b) + np.pi / 2) % np.pi - np.pi / 2) < 1e-6


@settings(max_examples=40, deadline=None)
@given(cx=st.floats(-500, 500), cy=st.floats(-500, 500), a=st.floats(2, 100),
       ratio=st.floats(0.2, 0.9), theta=st.floats(0, 3.1))
def test_fit_ellipse_round_trip(cx, cy, a, ratio, theta):
    t = np.linspace(0, 2 * np.pi, 13)[:-1]
    fit = fit_ellipse(_ellipse_points([cx, cy], a, ratio * a, theta, t))
    np.testing.assert_allclose(fit.centre, [cx, cy], atol=1e-6 * (1 + a))
    np.testing.assert_allclose(fit.axes, [a, ratio * a], rtol=1e-6)
    assert _same_angle(fit.angle, theta)


def test_fit_ellipse_matches_opencv_fit_ellipse_direct():
    rng = np.random.default_rng(35)
    t = rng.uniform(0.0, 4.0, 60)  # an arc: the algebraic criterion matters
    xy = _ellipse_points([320.5, 240.2], 80.0, 45.0, 0.6, t) + rng.normal(0, 0.5, (60, 2))
    fit = fit_ellipse(xy)
    (cx, cy), (w, h), ang = cv2.fitEllipseDirect(xy.astype(np.float32))
    axes = np.sort([w / 2, h / 2])[::-1]
    major_deg = ang if w >= h else ang + 90.0
    np.testing.assert_allclose(fit.centre, [cx, cy], atol=1e-2)
    np.testing.assert_allclose(fit.axes, axes, rtol=1e-3)
    assert abs(((np.degrees(fit.angle) - major_deg) + 90) % 180 - 90) < 0.1
    (cx2, cy2), _, _ = cv2.fitEllipse(xy.astype(np.float32))  # another algebraic criterion
    assert np.hypot(cx2 - fit.centre[0], cy2 - fit.centre[1]) < 3.0


def test_conic_to_ellipse_against_sympy_expansion():
    """Expand ((x−xc)·u)²/a² + ((x−xc)·v)²/b² − 1 with SymPy and convert back."""
    x, y = sp.symbols("x y")
    xc, yc, a, b, th = 3, -2, 5, 2, sp.Rational(1, 3)
    u = sp.Matrix([sp.cos(th), sp.sin(th)])
    d = sp.Matrix([x - xc, y - yc])
    poly = sp.Poly(sp.expand((d.dot(u)) ** 2 / a**2 + (d.dot(sp.Matrix([-u[1], u[0]]))) ** 2 / b**2 - 1), x, y)
    coeff = [float(poly.coeff_monomial(m)) for m in (x**2, x * y, y**2, x, y, 1)]
    e = conic_to_ellipse(-7.5 * np.array(coeff))  # any scale and sign
    np.testing.assert_allclose(e.centre, [3, -2], atol=1e-12)
    np.testing.assert_allclose(e.axes, [5, 2], rtol=1e-12)
    assert _same_angle(e.angle, 1 / 3)


def test_ellipse_bad_input():
    with pytest.raises(ValueError, match="at least 5 points, got 4"):
        fit_ellipse(np.random.default_rng(0).normal(size=(4, 2)))
    with pytest.raises(DegenerateGeometryError, match="collinear"):
        fit_ellipse(np.column_stack([np.arange(6.0), 2 * np.arange(6.0)]))
    with pytest.raises(ValueError, match="non-finite"):
        fit_ellipse([[0, 0], [1, 0], [0, 1], [1, np.nan], [2, 3]])
    with pytest.raises(ValueError, match="not an ellipse"):
        conic_to_ellipse([1, 0, -1, 0, 0, -1])  # hyperbola x² − y² = 1
    with pytest.raises(ValueError, match="imaginary"):
        conic_to_ellipse([1, 0, 1, 0, 0, 1])  # x² + y² = −1


def test_circle_from_conic_is_2_86_corrected_and_old_print_needs_A_1():
    rng = np.random.default_rng(36)
    for _ in range(10):
        c, r, A = rng.uniform(-5, 5, 2), rng.uniform(0.5, 4), rng.uniform(0.2, 3)
        # A((x−cx)² + (y−cy)²) − A r² = 0 → D = −A cx, E = −A cy, F = A(|c|² − r²)
        D, E, F = -A * c[0], -A * c[1], A * (c @ c - r * r)
        centre, radius = circle_from_conic(A, D, E, F)
        np.testing.assert_allclose(centre, c, atol=1e-12)
        assert radius == pytest.approx(r, rel=1e-12)
        old = np.sqrt(D * D + E * E - A * F)  # luhmann:2.86 old print
        assert old == pytest.approx(A * r, rel=1e-12)  # = r only for A = 1
    with pytest.raises(ValueError, match="A = 0"):
        circle_from_conic(0.0, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="no real circle"):
        circle_from_conic(1.0, 0.0, 0.0, 1.0)


def test_plane_through_points_against_sympy_and_2_136():
    from photolib.derive import conic as dc

    rng = np.random.default_rng(37)
    P = rng.uniform(-10, 10, (3, 3))
    plane = plane_through_points(*P)
    np.testing.assert_allclose(plane.distance(P), 0.0, atol=1e-12)
    subs = dict(zip((dc.x1, dc.y1, dc.z1, dc.x2, dc.y2, dc.z2, dc.x3, dc.y3, dc.z3), P.ravel()))
    a0, a1, a2 = (float(v) for v in dc.plane_through_points().xreplace(subs))
    n = plane.normal
    np.testing.assert_allclose([a0, a1, a2], [plane.d / n[2], -n[0] / n[2], -n[1] / n[2]], rtol=1e-10)
    # 2.136 printed (P1 at the origin): right after reducing to P1, wrong without
    Q = P - P[0]
    (x2, y2, _), (x3, y3, _) = Q[1], Q[2]
    det = x2 * y3 - x3 * y2
    printed = np.array([[det, 0, 0], [y2 - y3, y3, -y2], [x3 - x2, -x3, x2]]) @ Q[:, 2] / det
    assert printed[1:] == pytest.approx([a1, a2], rel=1e-10) and abs(printed[0]) < 1e-10
    (x2, y2, _), (x3, y3, _) = P[1], P[2]
    det = x2 * y3 - x3 * y2
    unreduced = np.array([[det, 0, 0], [y2 - y3, y3, -y2], [x3 - x2, -x3, x2]]) @ P[:, 2] / det
    assert not np.allclose(unreduced, [a0, a1, a2], rtol=1e-3)


def test_fit_plane_matches_scipy_svd_and_lstsq():
    from scipy import linalg

    rng = np.random.default_rng(38)
    XY = rng.uniform(-50, 50, (100, 2))
    P = np.column_stack([XY, 3 + 0.2 * XY[:, 0] - 0.1 * XY[:, 1]]) + rng.normal(0, 0.05, (100, 3))
    fit = fit_plane(P)
    _, _, Vt = linalg.svd(P - P.mean(axis=0))
    assert abs(abs(fit.normal @ Vt[2]) - 1) < 1e-12 and fit.normal[2] > 0
    # the orthogonal fit is close to (not equal to) the z-regression with small noise
    coef = linalg.lstsq(np.column_stack([np.ones(100), XY]), P[:, 2])[0]
    n_reg = np.array([-coef[1], -coef[2], 1.0]) / np.linalg.norm([-coef[1], -coef[2], 1.0])
    assert np.degrees(np.arccos(min(1.0, fit.normal @ n_reg))) < 0.05
    assert fit.sigma0 == pytest.approx(0.05, rel=0.2)
    np.testing.assert_allclose(fit.distances, fit.plane.distance(P), atol=1e-12)


def test_plane_bad_input():
    with pytest.raises(DegenerateGeometryError, match="collinear"):
        plane_through_points([0, 0, 0], [1, 1, 1], [2, 2, 2])
    with pytest.raises(DegenerateGeometryError, match="collinear"):
        fit_plane([[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]])
    with pytest.raises(ValueError, match="at least 3 points, got 2"):
        fit_plane([[0, 0, 0], [1, 1, 1]])
    with pytest.raises(ValueError, match="non-finite"):
        plane_through_points([0, 0, np.nan], [1, 0, 0], [0, 1, 0])


# -- input handling (red-team audit) --------------------------------------------------------------

@pytest.mark.parametrize("pts, text", [
    ([[0, 0], [1, 0], [0, 1], [1, 1], [1, 0], [0, 0]], "at least 5 distinct points, got 4"),
    ([[0, 0], [1, 0], [2, 0], [3, 0], [1, 1]], "do not determine a conic"),   # 4 on a line
    ([[0, 0], [1, 0], [2, 0], [3, 0], [0, 1], [1, 1], [2, 1], [3, 1]], "pair of straight lines"),
])
def test_fit_ellipse_refuses_point_sets_without_one_conic(pts, text):
    """4 distinct points among 6 gave an arbitrary ellipse with σ0 = 0; 8 points on two
    parallel lines one with a = 8515, b = 0.5."""
    with pytest.raises(DegenerateGeometryError, match=text):
        fit_ellipse(np.array(pts, float))


def test_fit_ellipse_through_exactly_five_points_still_works():
    t = np.array([0.1, 1.3, 2.2, 3.9, 5.0])
    p = np.column_stack([3 + 5 * np.cos(t), -1 + 2 * np.sin(t)])
    fit = fit_ellipse(p)
    np.testing.assert_allclose(fit.centre, [3.0, -1.0], atol=1e-9)
    np.testing.assert_allclose(fit.axes, [5.0, 2.0], atol=1e-9)


@pytest.mark.parametrize("args, text", [
    (([[0, 0, 0], [5, 5, 5]], [1, 0, 0], [0, 1, 0]), r"p1 has shape \(2, 3\); expected \(3,\)"),
    (([0, 0, 0], [1, 0], [0, 1, 0]), r"p2 has shape \(2,\); expected \(3,\)"),
    (([0, 0, 0], [1, 0, 0], "abc"), r"p3 must be numeric"),
])
def test_plane_through_points_needs_one_point_each(args, text):
    with pytest.raises(ValueError, match=text):   # an (N, 3) argument used to lose rows 1 …
        plane_through_points(*args)


def test_image_functions_refuse_complex_and_text():
    img = _scene()
    with pytest.raises(ValueError, match="image must be real, got complex values"):
        log_filter(img + 1j, 1.0)
    with pytest.raises(ValueError, match=r"image must be numeric, got 'a' at index \(0, 0\)"):
        log_filter([["a"] * 5] * 5, 1.0)
    with pytest.raises(ValueError, match="image must be numeric, got 'a'"):
        moment_threshold(["a", "b"])
    with pytest.raises(ValueError, match="max_iter must be an integer ≥ 1, got 0"):
        fit_circle(np.column_stack([np.cos([0, 1, 2, 3.0]), np.sin([0, 1, 2, 3.0])]), max_iter=0)
    with pytest.raises(ValueError, match="tol must be > 0, got -1.0"):
        fit_circle(np.column_stack([np.cos([0, 1, 2, 3.0]), np.sin([0, 1, 2, 3.0])]), tol=-1.0)


# -- LoG at small σ (audit M1) ---------------------------------------------------------------------

def _three_tap_laplacian_from_the_constraints():
    """The symmetric 3-tap kernel (a, b, a) with Σk = 0 and ½Σx²k = 1, solved by SymPy."""
    a, b = sp.symbols("a b")
    sol = sp.solve([2 * a + b, sp.Rational(1, 2) * (a + a) - 1], [a, b], dict=True)[0]
    return np.array([sol[a], sol[b], sol[a]], dtype=float)


def _old_kernel(sigma, truncate=4.0):
    """The construction before the fix (shift to Σ = 0, then scale): right for σ ≳ 0.25."""
    rad = gaussian_radius(sigma, truncate)
    x = np.arange(-rad, rad + 1, dtype=float)
    g = np.exp(-(x**2) / (2.0 * sigma**2))
    g /= g.sum()
    g2 = (x**2 / sigma**4 - 1.0 / sigma**2) * g
    g2 -= g2.sum() * g
    return g2 / (0.5 * np.sum(x**2 * g2))


@pytest.mark.parametrize("sigma", np.geomspace(1e-3, 8.0, 41))
def test_log_kernel_keeps_both_constraints_for_every_sigma(sigma):
    """Σg'' = 0 (flat → 0) and ½Σx²g'' = 1 (∇²x² = 2) hold at every σ, finite, no warnings."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        g, g2 = log_kernel_1d(sigma)
        L = log_filter(np.full((7, 9), 10.0), sigma)
    x = np.arange(len(g)) - len(g) // 2
    assert np.isfinite(g2).all() and abs(g.sum() - 1.0) < 1e-14
    assert abs(g2.sum()) < 1e-12 * np.abs(g2).sum()
    assert abs(0.5 * np.sum(x**2 * g2) - 1.0) < 1e-12
    assert np.isfinite(L).all() and np.max(np.abs(L)) < 1e-10    # was 40 (σ = 0.1), NaN (0.02)


@pytest.mark.parametrize("sigma", [1e-3, 0.02, 0.05, 0.1, 0.2, 0.25])
def test_log_kernel_tends_to_the_discrete_laplacian(sigma):
    """With 3 taps the two constraints leave one kernel: [1, −2, 1] (SymPy), for every σ."""
    g, g2 = log_kernel_1d(sigma)
    np.testing.assert_allclose(g2, _three_tap_laplacian_from_the_constraints(), rtol=0, atol=1e-12)


@pytest.mark.parametrize("sigma", [1e-3, 0.02, 0.05])
def test_log_filter_of_a_vanishing_sigma_is_scipys_discrete_laplacian(sigma):
    """σ → 0: the Gaussian is the unit impulse, the LoG the 5-point Laplacian (mirrored border)."""
    img = _scene(33, (20, 24))
    np.testing.assert_allclose(log_filter(img, sigma), ndimage.laplace(img, mode="reflect"),
                               rtol=0, atol=1e-9)


def test_log_filter_near_the_three_tap_limit_is_the_blurred_discrete_laplacian():
    """σ = 0.2 (3 taps, outer Gaussian taps 3.7e-6): SciPy's separable correlation with the
    sampled Gaussian and the kernel of the two constraints (SymPy)."""
    img = _scene(34, (20, 24))
    sigma = 0.2
    g = np.exp(-np.arange(-1, 2.0) ** 2 / (2 * sigma**2))
    g /= g.sum()
    lap = _three_tap_laplacian_from_the_constraints()
    ref = (ndimage.correlate1d(ndimage.correlate1d(img, lap, axis=1, mode="reflect"), g, axis=0,
                               mode="reflect")
           + ndimage.correlate1d(ndimage.correlate1d(img, g, axis=1, mode="reflect"), lap, axis=0,
                                 mode="reflect"))
    np.testing.assert_allclose(log_filter(img, sigma), ref, rtol=0, atol=1e-9)


@pytest.mark.parametrize("sigma", [0.3, 0.5, 1.0, 2.0, 4.0])
def test_log_kernel_is_unchanged_where_the_old_construction_was_right(sigma):
    np.testing.assert_allclose(log_kernel_1d(sigma)[1], _old_kernel(sigma), rtol=1e-11, atol=1e-13)
