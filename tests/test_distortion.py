"""Distortion: model by an independent polar formulation, inversion, Jacobians, OpenCV conversion."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import photolib as pl

STRONG = dict(A1=-6e-5, A2=4e-8, A3=-1e-11, r0=0.0, B1=4e-6, B2=-3e-6, C1=2e-4, C2=-1e-4)


def _delta_polar(xy, A1=0.0, A2=0.0, A3=0.0, r0=0.0, B1=0.0, B2=0.0, C1=0.0, C2=0.0):
    """Independent route: Δr'(r) along the radius by angle θ, Brown's decentring written with
    the decentring vector (P1, P2) as Δx = P1(r² + 2x²) + 2P2xy, Δy = 2P1xy + P2(r² + 2y²),
    affinity as a matrix."""
    x, y = xy[:, 0], xy[:, 1]
    r = np.hypot(x, y)
    th = np.arctan2(y, x)
    dr = A1 * r * (r**2 - r0**2) + A2 * r * (r**4 - r0**4) + A3 * r * (r**6 - r0**6)
    rad = np.column_stack([dr * np.cos(th), dr * np.sin(th)])
    tan = np.column_stack([B1 * (r**2 + 2 * x**2) + 2 * B2 * x * y, 2 * B1 * x * y + B2 * (r**2 + 2 * y**2)])
    aff = xy @ np.array([[C1, 0.0], [C2, 0.0]])
    return rad + tan + aff


def test_delta_matches_polar_formulation():
    rng = np.random.default_rng(0)
    xy = rng.uniform(-20, 20, (500, 2))
    for params in (STRONG, dict(A1=1e-4, r0=12.0), dict(B1=1e-5), dict(C2=3e-4)):
        np.testing.assert_allclose(pl.Distortion(**params).delta(xy), _delta_polar(xy, **params),
                                   rtol=1e-11, atol=1e-14)


def test_zero_crossing_at_r0():
    d = pl.Distortion(A1=2e-5, A2=-1e-8, r0=15.0)
    assert d.radial_profile(15.0) == pytest.approx(0.0, abs=1e-15)
    assert abs(d.delta([15.0 / np.sqrt(2)] * 2)).max() < 1e-14


def test_conrady_round_trip_is_exact():
    d = pl.Distortion(A1=3e-5, A2=-2e-8, A3=1e-12, r0=14.0)
    d2 = pl.Distortion.from_conrady(**d.conrady)
    xy = np.random.default_rng(1).uniform(-20, 20, (50, 2))
    np.testing.assert_allclose(d2.delta(xy), d.delta(xy), rtol=1e-10, atol=1e-15)
    with pytest.raises(ValueError, match="no zero-crossing radius"):
        pl.Distortion.from_conrady(K0=1e-3, K1=1e-5)  # K1 r0² = −K0 < 0 has no root


@pytest.mark.parametrize("method", ["newton", "fixed-point"])
def test_correct_inverts_distort(method):
    d = pl.Distortion(**STRONG)
    ideal = np.random.default_rng(2).uniform(-18, 18, (400, 2))
    measured, rep = d.distort(ideal, method=method, return_report=True)
    assert rep.converged and rep.method == method
    np.testing.assert_allclose(d.correct(measured), ideal, atol=1e-9)


def test_newton_converges_faster_than_fixed_point():
    d = pl.Distortion(**STRONG)
    ideal = np.random.default_rng(3).uniform(-18, 18, (100, 2))
    a, ra = d.distort(ideal, "newton", return_report=True)
    b, rb = d.distort(ideal, "fixed-point", return_report=True)
    np.testing.assert_allclose(a, b, atol=1e-8)
    assert ra.iterations < rb.iterations
    assert len(ra.history) == ra.iterations


@settings(max_examples=150, deadline=None)
@given(st.floats(-20, 20), st.floats(-20, 20), st.floats(-8e-5, 8e-5), st.floats(-5e-6, 5e-6))
def test_round_trip_hypothesis(x, y, A1, B1):
    d = pl.Distortion(A1=A1, B1=B1, A2=1e-9)
    try:
        m = d.distort([x, y], max_iter=100)
    except pl.DistortionDivergenceError:
        # only allowed where the map x − Δ(x) folds over: I − ∂Δ/∂x singular nearby
        J = np.eye(2) - d.jacobian_xy([x, y])
        assert abs(np.linalg.det(J)) < 0.5
        return
    np.testing.assert_allclose(d.correct(m), [x, y], atol=1e-8)


def test_divergence_raises_with_the_point():
    # pincushion so strong that x − Δ(x) folds: points beyond the fold have no measured position
    d = pl.Distortion(A1=1e-3)
    ideal = np.array([[1.0, 0.0], [40.0, 0.0]])
    with pytest.raises(pl.DistortionDivergenceError, match=r"point 1 \(ideal \[40.0, 0.0\]\)") as exc:
        d.distort(ideal, "fixed-point")
    assert exc.value.index == 1 and not exc.value.report.converged
    # Newton finds a real root of x − Δ(x) = 40 at x ≈ −43.5: beyond the fold, on the mirrored
    # sheet. It must be refused, not returned.
    with pytest.raises(pl.DistortionDivergenceError, match="beyond the fold"):
        d.distort(ideal, "newton", max_iter=30)


@pytest.mark.parametrize("method", ["newton", "fixed-point"])
def test_each_point_iterates_on_its_own(method):
    """Points leave the iteration at their own step: a result does not depend on the batch,
    and every point's residual is within what its own tolerance promises."""
    d = pl.Distortion(**STRONG)
    rng = np.random.default_rng(7)
    ideal = rng.uniform(-12, 12, (5000, 2))  # more than one block of 4096
    batch, rep = d.distort(ideal, method, tol=1e-9, return_report=True)
    alone = np.array([d.distort(p, method, tol=1e-9) for p in ideal[::97]])
    np.testing.assert_array_equal(batch[::97], alone)
    assert rep.converged and rep.max_step < 1e-9
    assert np.max(np.abs(d.correct(batch) - ideal)) < 1e-8


def test_fold_check_at_the_result_not_the_last_iterate():
    # a point on the valid sheet close to the fold: det(I − ∂Δ/∂x) small but positive
    d = pl.Distortion(A1=1e-3)
    r_fold = 1 / np.sqrt(3e-3)  # d/dr (r − A1 r³) = 0
    x = 0.98 * r_fold  # det = 1 − 3·A1·x² = 0.04: checked again at the result
    ideal = [[x - 1e-3 * x**3, 0.0]]
    m = d.distort(ideal, tol=1e-12)
    np.testing.assert_allclose(m, [[x, 0.0]], rtol=1e-9)


def test_jacobians_against_finite_differences():
    d = pl.Distortion(**STRONG)
    xy = np.random.default_rng(4).uniform(-15, 15, (10, 2))
    J = d.jacobian_xy(xy)
    h = 1e-5
    for k in range(2):
        e = np.zeros(2)
        e[k] = h
        num = (d.delta(xy + e) - d.delta(xy - e)) / (2 * h)
        np.testing.assert_allclose(J[:, :, k], num, rtol=1e-7, atol=1e-12)
    Jp = d.jacobian_params(xy)
    assert Jp.shape == (10, 2, 7)
    names = ("A1", "A2", "A3", "B1", "B2", "C1", "C2")
    for k, name in enumerate(names):
        p = d.params
        hp = 1e-3 * max(abs(p[name]), 1e-9)
        up, dn = dict(p), dict(p)
        up[name] += hp
        dn[name] -= hp
        num = (pl.Distortion(**up).delta(xy) - pl.Distortion(**dn).delta(xy)) / (2 * hp)
        np.testing.assert_allclose(Jp[:, :, k], num, rtol=1e-6, atol=1e-12 * np.abs(num).max())


def test_to_opencv_reproduces_cv2_projection_within_reported_residual():
    c = 24.0
    d = pl.Distortion(A1=-2e-4, A2=1e-7, B1=1e-5, B2=-2e-5)
    fit = d.to_opencv(c, 18.0, 12.0, n=31)
    assert not fit.exact and fit.max_um < 10
    ideal = np.random.default_rng(5).uniform([-18, -12], [18, 12], (300, 2))
    objp = np.column_stack([ideal[:, 0] / c, -ideal[:, 1] / c, np.ones(len(ideal))])
    K = np.array([[c, 0, 0], [0, c, 0], [0, 0, 1.0]])
    p, _ = cv2.projectPoints(objp, np.zeros(3), np.zeros(3), K, np.array(fit.coefficients))
    cv_meas = p.reshape(-1, 2) * [1, -1]
    ours = d.distort(ideal)
    err = np.hypot(*(cv_meas - ours).T) * 1000
    assert err.max() <= fit.max_um * 1.2


def test_from_opencv_inverts_cv2_undistort_within_residual():
    c, k = 24.0, np.array([-0.12, 0.05, 4e-4, -3e-4, -0.01])
    d, fit = pl.Distortion.from_opencv(k, c, 18.0, 12.0)
    meas = np.random.default_rng(6).uniform([-16, -10], [16, 10], (200, 2))
    pts = (meas * [1, -1]).reshape(-1, 1, 2)
    K = np.array([[c, 0, 0], [0, c, 0], [0, 0, 1.0]])
    und = cv2.undistortPoints(pts, K, k, None, None, None,
                              (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-14))
    cv_ideal = und.reshape(-1, 2) * c * [1, -1]
    err = np.hypot(*(d.correct(meas) - cv_ideal).T) * 1000
    assert err.max() <= fit.max_um * 1.5 + 0.05


def test_zero_distortion_conversion_is_exact():
    fit = pl.Distortion().to_opencv(30.0, 10.0, 10.0)
    assert fit.exact and fit.coefficients == pytest.approx((0, 0, 0, 0, 0), abs=1e-15)


def test_opencv_form_signs_against_cv2_at_first_order():
    # tiny distortion: evaluation point does not matter at first order, so the naive map is right
    c = 20.0
    d = pl.Distortion(A1=1e-7, B1=1e-8, B2=-2e-8)
    k = np.array(d.opencv_form(c))
    ideal = np.array([[5.0, 3.0], [-7.0, 2.0], [1.0, -8.0]])
    objp = np.column_stack([ideal[:, 0] / c, -ideal[:, 1] / c, np.ones(3)])
    K = np.array([[c, 0, 0], [0, c, 0], [0, 0, 1.0]])
    p, _ = cv2.projectPoints(objp, np.zeros(3), np.zeros(3), K, k)
    cv_delta = p.reshape(-1, 2) * [1, -1] - ideal
    np.testing.assert_allclose(cv_delta, d.delta(ideal), rtol=1e-4)


@pytest.mark.parametrize("kwargs,match", [
    (dict(A1=float("nan")), "A1 must be finite"), (dict(r0=-1.0), "r0 must be >= 0"),
    (dict(B2="x"), "B2 must be a real number"),
])
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        pl.Distortion(**kwargs)


def test_bad_calls():
    d = pl.Distortion(A1=1e-5)
    with pytest.raises(ValueError, match=r"xy has shape \(3,\)"):
        d.delta([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="method must be"):
        d.distort([1.0, 2.0], method="secant")
    with pytest.raises(ValueError, match="max_iter must be"):
        d.distort([1.0, 2.0], max_iter=0)
    with pytest.raises(TypeError, match="distortion must be a photolib.Distortion"):
        pl.project([0.0, 0.0, 0.0], [0.0, 0.0, 10.0], np.eye(3), 50.0, distortion={"A1": 1})


def test_pixels_round_trip_and_centre():
    colrow = np.array([[0.0, 0.0], [1023.0, 767.0], [511.5, 383.5]])
    xy = pl.image_from_pixel(colrow, 1024, 768, 0.005)
    np.testing.assert_allclose(xy[2], [0.0, 0.0], atol=1e-15)
    assert xy[0, 0] < 0 and xy[0, 1] > 0  # top-left pixel: left and up
    np.testing.assert_allclose(pl.pixel_from_image(xy, 1024, 768, 0.005), colrow, atol=1e-9)
    with pytest.raises(ValueError, match="pixel_size x must be > 0"):
        pl.image_from_pixel(colrow, 1024, 768, 0.0)


# -- input handling (red-team audit) --------------------------------------------------------------

@pytest.mark.parametrize("method", ["newton", "fixed-point"])
def test_distort_of_no_points_is_empty(method):
    d = pl.Distortion(A1=-1e-4, B1=1e-5)
    out, rep = d.distort(np.zeros((0, 2)), method, return_report=True)
    assert out.shape == (0, 2) and rep.converged and rep.iterations == 0


@pytest.mark.parametrize("max_iter, text", [(0, "an integer ≥ 1, got 0"), (2.5, "an integer, got 2.5"),
                                            ("a", "an integer, got 'a'")])
def test_distort_iteration_limit_must_be_a_positive_integer(max_iter, text):
    with pytest.raises(ValueError, match=f"max_iter must be {text}"):
        pl.Distortion(A1=-1e-4).distort([[1.0, 1.0]], max_iter=max_iter)


def test_pixel_size_of_the_wrong_shape_or_type_is_named():
    with pytest.raises(ValueError, match=r"pixel_size has shape \(3,\); expected a scalar or "
                                         r"\(2,\)"):
        pl.image_from_pixel([0.0, 0.0], 3, 3, [0.01, 0.01, 0.01])
    with pytest.raises(ValueError, match=r"pixel_size must be numeric .*, got 'a'"):
        pl.pixel_from_image([0.0, 0.0], 3, 3, "a")
    np.testing.assert_array_equal(pl.image_from_pixel([0.0, 0.0], 3, 3, [0.01, 0.02]),
                                  [-0.01, 0.02])


def test_root_on_an_outer_sheet_is_refused():
    """A1 > 0 with A2 < 0: r − Δr rises to a maximum 18.39 mm at r = 30.03 mm, falls, and rises
    again, so the ideal radius 20 mm has no measured position on the sheet through the centre;
    Newton finds r' = 56.24 on the outer sheet, where I − ∂Δ/∂x is positive again."""
    d = pl.Distortion(A1=5.2e-4, A2=-1e-7)
    r = np.linspace(0.0, 30.0, 3001)
    f = r - d.radial_profile(r)
    assert np.all(np.diff(f) > 0) and f.max() < 20.0   # the valid sheet never reaches 20 mm
    s_fold = np.roots([-5 * -1e-7, -3 * 5.2e-4, 1.0])   # 1 − 3A1 s − 5A2 s² = 0, s = r²
    assert d.fold_radius == pytest.approx(np.sqrt(s_fold.real.min()), rel=1e-12)
    with pytest.raises(pl.DistortionDivergenceError, match="outside the radial fold at r' = 30.025") as info:
        d.distort([20.0, 0.0])
    assert info.value.beyond_fold and not info.value.converging
    # an ideal radius the valid sheet reaches (18 mm < 18.39 mm) still inverts: the root of
    # r − Δr(r) = 18 inside the fold, found here by bisection
    lo, hi = 0.0, d.fold_radius
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid - float(d.radial_profile(mid)) < 18.0 else (lo, mid)
    assert d.distort([18.0, 0.0]) == pytest.approx([lo, 0.0], abs=1e-9)


def test_stopped_by_max_iter_while_contracting_is_flagged():
    d = pl.Distortion(A1=-5e-4)
    with pytest.raises(pl.DistortionDivergenceError, match="converges slowly") as info:
        d.distort([[20.0, 14.0]], method="fixed-point", tol=1e-12, max_iter=30)
    assert info.value.converging
    steps = info.value.report.history
    assert steps[-1] < steps[-2] < steps[-3]
    # and it does converge with more iterations, to Newton's answer
    assert d.distort([[20.0, 14.0]], method="fixed-point", tol=1e-12, max_iter=200) == \
        pytest.approx(d.distort([[20.0, 14.0]]), abs=1e-10)
    with pytest.raises(pl.DistortionDivergenceError) as info:
        pl.Distortion(A1=5e-3).distort([15.0, -9.0], method="fixed-point")
    assert not info.value.converging
