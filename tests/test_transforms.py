"""Plane transformations: invariants across all classes, OpenCV and SymPy cross-checks."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from photolib.transforms import (
    AffineTransform,
    BilinearTransform,
    ComposedTransform,
    ConvergenceError,
    DegenerateGeometryError,
    HelmertTransform,
    NewtonInverse,
    PolynomialTransform,
    ProjectiveTransform,
    cross_ratio,
)

# ---------------------------------------------------------------- random transforms per class


def _helmert(rng):
    m, a = rng.uniform(0.5, 2.0), rng.uniform(-np.pi, np.pi)
    return HelmertTransform(a0=rng.normal(0, 5), b0=rng.normal(0, 5), a1=m * np.cos(a), b1=m * np.sin(a))


def _affine(rng):
    M = np.eye(2) + rng.normal(0, 0.2, (2, 2))
    return AffineTransform(a0=rng.normal(0, 5), a1=M[0, 0], a2=M[0, 1],
                           b0=rng.normal(0, 5), b1=M[1, 0], b2=M[1, 1])


def _bilinear(rng):
    M = np.eye(2) + rng.normal(0, 0.1, (2, 2))
    return BilinearTransform(a0=rng.normal(0, 5), a1=M[0, 0], a2=M[0, 1], a3=rng.normal(0, 0.005),
                             b0=rng.normal(0, 5), b1=M[1, 0], b2=M[1, 1], b3=rng.normal(0, 0.005))


def _projective(rng):
    M = np.eye(2) + rng.normal(0, 0.2, (2, 2))
    return ProjectiveTransform(a0=rng.normal(0, 5), a1=M[0, 0], a2=M[0, 1], b0=rng.normal(0, 5),
                               b1=M[1, 0], b2=M[1, 1], c1=rng.normal(0, 0.01), c2=rng.normal(0, 0.01))


def _polynomial(order):
    def make(rng):
        t = PolynomialTransform(order)
        a, b = t.a.copy(), t.b.copy()
        for k, (i, j) in enumerate(t.exponents):
            s = {0: 5.0, 1: 0.1}.get(i + j, 0.3 * 10.0 ** (-(i + j)))
            a[k] += rng.normal(0, s)
            b[k] += rng.normal(0, s)
        return PolynomialTransform(order, a, b)
    return make


FACTORIES = {
    "helmert": (_helmert, HelmertTransform.from_estimate),
    "affine": (_affine, AffineTransform.from_estimate),
    "bilinear": (_bilinear, BilinearTransform.from_estimate),
    "projective": (_projective, ProjectiveTransform.from_estimate),
    "poly2": (_polynomial(2), lambda s, d: PolynomialTransform.from_estimate(s, d, order=2)),
    "poly3": (_polynomial(3), lambda s, d: PolynomialTransform.from_estimate(s, d, order=3)),
}
KINDS = list(FACTORIES)
MIN_POINTS = {"helmert": 2, "affine": 3, "bilinear": 4, "projective": 4, "poly2": 6, "poly3": 10}


def _points(rng, n=30, half=10.0):
    return rng.uniform(-half, half, (n, 2))


# ---------------------------------------------------------------- invariants over all classes


@pytest.mark.parametrize("kind", KINDS)
def test_estimate_recovers_exact_transform(kind):
    rng = np.random.default_rng(1)
    make, estimate = FACTORIES[kind]
    true = make(rng)
    src = _points(rng)
    est = estimate(src, true(src))
    assert type(est) is type(true)
    for k, v in true.params.items():
        assert est.params[k] == pytest.approx(v, rel=1e-8, abs=1e-9), k
    assert est.residuals.shape == (30, 2)
    assert np.max(np.abs(est.residuals)) < 1e-9
    assert est.redundancy == 2 * 30 - est.n_params
    assert est.sigma0 < 1e-9


@pytest.mark.parametrize("kind", KINDS)
def test_estimate_from_many_points_in_bounded_memory(kind):
    """3e4 points, 6e4 equations: no estimator may build a 6e4 × 6e4 matrix (the U of a full
    SVD, 29 GB); each recovers the exact transform."""
    rng = np.random.default_rng(3)
    make, estimate = FACTORIES[kind]
    true = make(rng)
    src = _points(rng, n=30_000)
    est = estimate(src, true(src))
    for k, v in true.params.items():
        assert est.params[k] == pytest.approx(v, rel=1e-8, abs=1e-9), k


@pytest.mark.parametrize("kind", KINDS)
def test_sigma0_estimates_the_noise(kind):
    rng = np.random.default_rng(2)
    make, estimate = FACTORIES[kind]
    true = make(rng)
    src = _points(rng, n=400)
    noise = 0.01
    est = estimate(src, true(src) + rng.normal(0, noise, (400, 2)))
    assert est.sigma0 == pytest.approx(noise, rel=0.1)
    # least squares: residuals orthogonal to the tangent space ⇒ refitting changes nothing
    again = estimate(src, est(src))
    assert np.allclose(again(src), est(src), atol=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_estimate_is_equivariant_to_shift_and_scale_of_src(kind):
    """Normalisation: far-away, large-valued coordinates (e.g. UTM) give the same mapping."""
    rng = np.random.default_rng(3)
    make, estimate = FACTORIES[kind]
    true = make(rng)
    src = _points(rng, n=40)
    dst = true(src) + rng.normal(0, 0.01, (40, 2))
    est = estimate(src, dst)
    # UTM-like coordinates; for cubic polynomials the raw monomials x³ ~ 1e20 would exhaust
    # float64 (a limit of the representation, not of the estimate), so a smaller shift there
    shift = np.array([5.3e5, 5.8e6]) if kind != "poly3" else np.array([530.0, 5800.0])
    scale = 250.0
    est_far = estimate(scale * src + shift, dst)
    assert np.allclose(est_far(scale * src + shift), est(src), atol=1e-6)
    assert est_far.sigma0 == pytest.approx(est.sigma0, rel=1e-6)


@pytest.mark.parametrize("kind", KINDS)
def test_single_point_keeps_rank_and_jacobian_matches_finite_differences(kind):
    rng = np.random.default_rng(4)
    t = FACTORIES[kind][0](rng)
    p = np.array([1.5, -2.0])
    assert t(p).shape == (2,)
    assert np.array_equal(t(p), t(p[None])[0])
    h = 1e-6
    fd = np.column_stack([(t(p + e) - t(p - e)) / (2 * h) for e in np.eye(2) * h])
    assert np.allclose(t.jacobian(p), fd, atol=1e-7)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(KINDS),
       x=st.floats(-10, 10), y=st.floats(-10, 10))
def test_inverse_round_trip(seed, kind, x, y):
    t = FACTORIES[kind][0](np.random.default_rng(seed))
    p = np.array([x, y])
    assert np.allclose(t.inverse(t(p)), p, atol=1e-8)
    if kind in ("helmert", "affine", "projective"):  # onto: every point has a preimage
        assert np.allclose(t(t.inverse(p)), p, atol=1e-8)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1), first=st.sampled_from(KINDS),
       second=st.sampled_from(KINDS), x=st.floats(-10, 10), y=st.floats(-10, 10))
def test_composition_means_right_first(seed, first, second, x, y):
    rng = np.random.default_rng(seed)
    a, b = FACTORIES[second][0](rng), FACTORIES[first][0](rng)
    p = np.array([x, y])
    assert np.allclose((a @ b)(p), a(b(p)), rtol=1e-10, atol=1e-9)
    assert np.allclose((a @ b).inverse((a @ b)(p)), p, atol=1e-7)


@pytest.mark.parametrize(("a", "b", "cls"), [
    ("helmert", "helmert", HelmertTransform), ("helmert", "affine", AffineTransform),
    ("affine", "helmert", AffineTransform), ("projective", "affine", ProjectiveTransform),
    ("helmert", "projective", ProjectiveTransform), ("affine", "bilinear", ComposedTransform),
    ("poly2", "projective", ComposedTransform),
])
def test_composition_class(a, b, cls):
    rng = np.random.default_rng(5)
    assert type(FACTORIES[a][0](rng) @ FACTORIES[b][0](rng)) is cls


def test_closed_form_inverses_have_the_same_class():
    rng = np.random.default_rng(6)
    for kind, cls in (("helmert", HelmertTransform), ("affine", AffineTransform),
                      ("projective", ProjectiveTransform)):
        t = FACTORIES[kind][0](rng)
        assert type(t.inverse) is cls
        assert np.allclose((t.inverse @ t).matrix, np.eye(3), atol=1e-12)
    assert type(_bilinear(rng).inverse) is NewtonInverse


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize("kind", KINDS)
def test_bad_input(kind):
    rng = np.random.default_rng(7)
    make, estimate = FACTORIES[kind]
    t = make(rng)
    src = _points(rng, n=12)
    dst = t(src)
    with pytest.raises(ValueError, match=r"src has shape \(12, 3\); expected \(N, 2\)"):
        estimate(np.column_stack([src, src[:, 0]]), dst)
    with pytest.raises(ValueError, match="points has shape"):
        t(np.zeros((3, 3)))
    bad = dst.copy()
    bad[4, 1] = np.nan
    with pytest.raises(ValueError, match=r"dst contains a non-finite value nan at index \(4, 1\)"):
        estimate(src, bad)
    with pytest.raises(ValueError, match="src has 12 points but dst has 11"):
        estimate(src, dst[:-1])
    n = MIN_POINTS[kind]
    with pytest.raises(ValueError, match=f"at least {n} point pairs, got {n - 1}"):
        estimate(src[: n - 1], dst[: n - 1])
    estimate(src[:n], dst[:n])  # the minimum is enough
    line = np.column_stack([np.linspace(0, 5, 12), 2 * np.linspace(0, 5, 12) + 1])
    if kind == "helmert":  # two distinct points determine a similarity, even collinear ones
        assert HelmertTransform.from_estimate(line, t(line)).sigma0 < 1e-9
        with pytest.raises(DegenerateGeometryError, match="coincide"):
            estimate(np.ones((5, 2)), t(np.ones((5, 2))))
    else:
        with pytest.raises(DegenerateGeometryError, match="src points are collinear"):
            estimate(line, dst)


def test_minimum_points_give_nan_sigma0():
    src = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    t = AffineTransform.from_estimate(src, src * 2)
    assert t.redundancy == 0 and np.isnan(t.sigma0)


def test_projective_degenerate_and_singular():
    src = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]])  # three collinear of four
    with pytest.raises(DegenerateGeometryError, match="three of the points collinear"):
        ProjectiveTransform.from_estimate(src, src + 1.0)
    singular = ProjectiveTransform(a1=1.0, a2=2.0, b1=2.0, b2=4.0)
    with pytest.raises(ValueError, match="singular"):
        _ = singular.inverse
    t = ProjectiveTransform(c1=1.0)
    with pytest.raises(ValueError, match=r"point 0 \[-1.0, 0.0\] lies on the vanishing line"):
        t([-1.0, 0.0])
    with pytest.raises(ValueError, match="has no inverse"):
        _ = AffineTransform(a1=1, a2=1, b1=1, b2=1).inverse


def test_newton_inverse_reports_no_preimage():
    # X = x·y, Y = x + y has a real preimage only where Y² ≥ 4X
    t = BilinearTransform(a1=0.0, a3=1.0, b1=1.0, b2=1.0)
    assert np.allclose(t(t.inverse([2.0, 3.0])), [2.0, 3.0])
    with pytest.raises(ConvergenceError, match="did not converge"):
        t.inverse_with(max_iter=30)([1.0, 0.5])


def test_constructor_rejects_bad_values():
    with pytest.raises(ValueError, match="a1 must be finite"):
        HelmertTransform(a1=np.inf)
    with pytest.raises(ValueError, match="order must be an integer"):
        PolynomialTransform(0)
    with pytest.raises(ValueError, match="a has 3 coefficients; expected 6"):
        PolynomialTransform(2, a=[1, 2, 3])


# ---------------------------------------------------------------- OpenCV as independent route


def test_projective_four_points_matches_opencv():
    rng = np.random.default_rng(8)
    src = np.array([[0, 0], [100, 0], [100, 80], [0, 80]], float) + rng.normal(0, 3, (4, 2))
    dst = np.array([[10, 5], [120, 12], [110, 95], [-4, 70]], float)
    H = cv2.getPerspectiveTransform(src.astype(np.float32), dst.astype(np.float32))
    t = ProjectiveTransform.from_estimate(src, dst)
    assert np.allclose(t.matrix, H / H[2, 2], rtol=1e-4, atol=1e-6)  # float32 input to OpenCV


def test_projective_least_squares_matches_opencv_find_homography():
    rng = np.random.default_rng(9)
    true = _projective(rng)
    src = _points(rng, n=50, half=50.0)
    dst = true(src) + rng.normal(0, 0.05, (50, 2))
    H, _ = cv2.findHomography(src, dst, 0)  # all points, least squares + LM refinement
    t = ProjectiveTransform.from_estimate(src, dst)
    assert np.allclose(t(src), cv2.perspectiveTransform(src[None], H)[0], atol=2e-4)
    ssr_cv = np.sum((cv2.perspectiveTransform(src[None], H)[0] - dst) ** 2)
    assert np.sum(t.residuals**2) <= ssr_cv * (1 + 1e-6)  # ours is the least-squares minimum


@pytest.mark.parametrize(("cls", "cv_fn"), [
    (AffineTransform, cv2.estimateAffine2D), (HelmertTransform, cv2.estimateAffinePartial2D)])
def test_affine_and_helmert_match_opencv(cls, cv_fn):
    rng = np.random.default_rng(10)
    true = _affine(rng) if cls is AffineTransform else _helmert(rng)
    src = _points(rng, n=40)
    dst = true(src) + rng.normal(0, 0.01, (40, 2))
    M, inliers = cv_fn(src, dst, method=cv2.LMEDS, refineIters=100)
    assert inliers.all()
    t = cls.from_estimate(src, dst)
    assert np.allclose(t.matrix[:2], M, atol=1e-4)


def test_bilinear_and_polynomial_match_plain_least_squares():
    rng = np.random.default_rng(11)
    src = _points(rng, n=25)
    dst = _polynomial(3)(rng)(src) + rng.normal(0, 0.01, (25, 2))
    for t, basis in ((BilinearTransform.from_estimate(src, dst), [(0, 0), (1, 0), (0, 1), (1, 1)]),
                     (PolynomialTransform.from_estimate(src, dst, order=3),
                      [(i, d - i) for d in range(4) for i in range(d, -1, -1)])):
        A = np.column_stack([src[:, 0] ** i * src[:, 1] ** j for i, j in basis])
        coef = np.linalg.lstsq(A, dst, rcond=None)[0]
        assert np.allclose(t.a, coef[:, 0], atol=1e-9) and np.allclose(t.b, coef[:, 1], atol=1e-9)


# ---------------------------------------------------------------- SymPy: closed forms


def test_projective_inverse_formula_matches_sympy_and_corrected_2_19():
    a0, a1, a2, b0, b1, b2, c1, c2, X, Y = sp.symbols("a0 a1 a2 b0 b1 b2 c1 c2 X Y")
    H = sp.Matrix([[a1, a2, a0], [b1, b2, b0], [c1, c2, 1]])
    Hi = H.inv()
    Hi = Hi / Hi[2, 2]
    vals = dict(zip((a0, a1, a2, b0, b1, b2, c1, c2), (0.3, 1.1, -0.2, -0.4, 0.25, 0.9, 0.03, -0.05)))
    inv = ProjectiveTransform(**{str(k): v for k, v in vals.items()}).inverse
    expected = np.array(Hi.subs(vals).evalf(), dtype=float)
    assert np.allclose(inv.matrix, expected, rtol=1e-12)
    # the errata's corrected 2.19: x = (a2b0 − a0b2 + (b2 − b0c2)X + (a0c2 − a2)Y) / (…)
    den = a1 * b2 - a2 * b1 + (b1 * c2 - b2 * c1) * X + (a2 * c1 - a1 * c2) * Y
    x219 = (a2 * b0 - a0 * b2 + (b2 - b0 * c2) * X + (a0 * c2 - a2) * Y) / den
    y219 = (a0 * b1 - a1 * b0 + (b0 * c1 - b1) * X + (a1 - a0 * c1) * Y) / den
    P = np.array([[3.0, -2.0], [0.5, 7.0]])
    f = sp.lambdify((X, Y), [x219.subs(vals), y219.subs(vals)])
    assert np.allclose(inv(P), np.array([f(*p) for p in P]), rtol=1e-12)


# ---------------------------------------------------------------- cross ratio


def test_cross_ratio_sympy_identity():
    a, b, c, d = sp.symbols("a b c d")
    lam = ((b - a) / (c - b)) / ((d - a) / (d - c))
    classical = (c - a) * (d - b) / ((c - b) * (d - a))
    printed = ((d - a) / (d - b)) / ((c - a) / (c - b))  # uncorrected 2.21
    assert sp.simplify(lam - (classical - 1)) == 0
    assert sp.simplify(printed - 1 / classical) == 0
    # λ is invariant under every 1-D homography t ↦ (p t + q)/(r t + s)
    p, q, r, s = sp.symbols("p q r s")
    h = [(p * t + q) / (r * t + s) for t in (a, b, c, d)]
    lam_h = ((h[1] - h[0]) / (h[2] - h[1])) / ((h[3] - h[0]) / (h[3] - h[2]))
    assert sp.simplify(lam_h - lam) == 0
    vals = {a: 0.3, b: 1.7, c: 2.2, d: 5.0}
    assert cross_ratio(*vals.values()) == pytest.approx(float(lam.subs(vals)), rel=1e-14)


def test_cross_ratio_invariant_under_central_projection():
    """Four points on a 3-D line and their images in a pinhole camera have the same λ."""
    rng = np.random.default_rng(12)
    P0, direction = np.array([1.0, -2.0, 0.5]), rng.normal(size=3)
    t = np.sort(rng.uniform(-3, 3, 4))
    pts3 = P0 + t[:, None] * direction
    # camera at Z0 = 20 looking down, c = 50 (own small pinhole, independent of photolib)
    k = pts3 - [0.0, 0.0, 20.0]
    img = -50.0 * k[:, :2] / k[:, 2:]
    lam = cross_ratio(*t)
    assert cross_ratio(*pts3) == pytest.approx(lam, rel=1e-10)
    assert cross_ratio(*img) == pytest.approx(lam, rel=1e-9)
    h = _projective(rng)
    assert cross_ratio(*h(img)) == pytest.approx(lam, rel=1e-8)


def test_cross_ratio_errors():
    with pytest.raises(ValueError, match="not collinear"):
        cross_ratio([0, 0], [1, 0], [2, 0.1], [3, 0])
    with pytest.raises(ValueError, match="segment BC has zero length"):
        cross_ratio(0.0, 1.0, 1.0, 3.0)
    with pytest.raises(ValueError, match="same shape"):
        cross_ratio(0.0, [1.0, 0.0], 2.0, 3.0)
    with pytest.raises(ValueError, match="non-finite"):
        cross_ratio(0.0, np.nan, 2.0, 3.0)


# ---------------------------------------------------------------- input handling (red-team audit)
def test_projective_minimal_case_with_three_collinear_dst_points():
    """Four pairs with three dst points on a line: the linear start sent a point to w = 0 and
    LAPACK failed ('SVD did not converge', with DLASCL messages on stderr)."""
    src = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    dst = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]]
    with pytest.raises(DegenerateGeometryError,
                       match=r"three of the points collinear \(dst points 0, 1, 2\)"):
        ProjectiveTransform.from_estimate(src, dst)
    with pytest.raises(DegenerateGeometryError, match=r"\(src points 0, 1, 2\)"):
        ProjectiveTransform.from_estimate(dst, src)
    # a fifth point makes the same three collinear dst points harmless
    t = ProjectiveTransform(a0=1, a1=2, a2=0.3, b0=-1, b1=0.1, b2=1.5, c1=0.05, c2=-0.02)
    src5 = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [0.5, 0.7]])
    est = ProjectiveTransform.from_estimate(src5, t(src5))
    np.testing.assert_allclose(est.matrix, t.matrix, atol=1e-9)


def test_newton_inverse_checks_tolerance_and_iteration_limit():
    t = BilinearTransform(a3=0.1)
    with pytest.raises(ValueError, match="tol must be > 0, got -1.0"):
        NewtonInverse(t, tol=-1.0)
    with pytest.raises(ValueError, match="tol must be finite, got nan"):
        t.inverse_with(tol=np.nan)
    with pytest.raises(ValueError, match="max_iter must be an integer ≥ 1, got 0"):
        t.inverse_with(max_iter=0)


def test_cross_ratio_names_a_non_numeric_point():
    with pytest.raises(ValueError, match="a must be numeric, got 'a'"):
        cross_ratio("a", 1, 2, 3)
    with pytest.raises(ValueError, match=r"c must be real, got complex values"):
        cross_ratio(0.0, 1.0, 2.0 + 1j, 3.0)
