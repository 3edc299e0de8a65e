"""Bundle adjustment (photolib.bundle), checked by independent routes.

* ``scipy.optimize.least_squares`` (trust region, finite-difference Jacobian with
  ``jac_sparsity``) on the same residual function, written here from the collinearity
  equations with our own rotation matrix and distortion polynomial;
* the full (not reduced) normal equations assembled from that finite-difference Jacobian as a
  ``scipy.sparse`` matrix, solved with ``scipy.sparse.linalg``, and its dense inverse for the
  covariance, Q_vv and the redundancy numbers;
* simulated blocks with known truth (seeded), a gross error injected and found;
* mpmath (``photolib.derive.adjustment``: erfc and the incomplete beta function) for the
  critical values the library takes from SciPy's distributions, Student's density integrated
  by quadrature for the deprecated ``student_t_cdf``.
"""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
import pytest
import scipy.sparse as sps
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats
from scipy.integrate import quad
from scipy.optimize import least_squares
from scipy.optimize._numdiff import approx_derivative, group_columns
from scipy.sparse.linalg import spsolve

import photolib as pl
from photolib import bundle as bd
from photolib.derive import adjustment as adj

C = 50.0


def _rot(o, p, k):
    """R = R_ω·R_φ·R_κ written out (test's own, not the library's)."""
    co, so, cp, sp_, ck, sk = np.cos(o), np.sin(o), np.cos(p), np.sin(p), np.cos(k), np.sin(k)
    Ro = np.array([[1, 0, 0], [0, co, -so], [0, so, co]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    return Ro @ Rp @ Rk


def _block(strips=2, per=3, noise=0.003, seed=0, A1=0.0, flat=False):
    """Aerial block: images 200 m apart in strips 300 m apart, 500 m high, c = 50 mm.

    ``flat``: exact nadir images at one height over a plane (c and Z0 then trade off)."""
    rng = np.random.default_rng(seed)
    f = 0.0 if flat else 1.0
    ext = np.array([[k * 200.0, s * 300.0, 500.0 + f * rng.normal(0, 5),
                     *np.radians(f * rng.normal(0, 1, 3))]
                    for s in range(strips) for k in range(per)])
    gx = np.arange(-150.0, (per - 1) * 200.0 + 151.0, 75.0)
    gy = np.arange(-150.0, (strips - 1) * 300.0 + 151.0, 75.0)
    P = np.array([[x, y, f * rng.uniform(0, 30)] for x in gx for y in gy])
    dist = pl.Distortion(A1=A1) if A1 else None
    xy, ji, pi = [], [], []
    for j, e in enumerate(ext):
        p = pl.project(P, e[:3], _rot(*e[3:]), C, distortion=dist)
        ok = np.all(np.abs(p) < 60.0, axis=1)
        xy.append(p[ok])
        ji += [j] * int(ok.sum())
        pi += list(np.flatnonzero(ok))
    xy = np.vstack(xy) + rng.normal(0, noise, (len(ji), 2))
    keep = np.bincount(pi, minlength=len(P))
    assert keep.min() >= 2
    return xy, np.array(ji), np.array(pi), ext, P


def _corners(P):
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    targets = [lo, hi, [lo[0], hi[1]], [hi[0], lo[1]]]
    return sorted({int(np.argmin(np.linalg.norm(P[:, :2] - t, axis=1))) for t in targets})


def _start(ext, P, control, seed=3):
    rng = np.random.default_rng(seed)
    P0 = P.copy()
    free = np.setdiff1d(np.arange(len(P)), control)
    P0[free] += rng.normal(0, 2.0, (len(free), 3))
    return ext + np.r_[1.0, -1.0, 2.0, 0.01, -0.01, 0.02], P0


def _residual_function(xy, ji, pi, n_img, control, P_fixed, calib=()):
    """x ↦ v (2N,) with x = (exterior 6M, free points 3·Pf, c, x0, y0, A1 as in calib)."""
    free = np.setdiff1d(np.arange(len(P_fixed)), control)

    def fun(x):
        ext = x[:6 * n_img].reshape(-1, 6)
        P = P_fixed.copy()
        P[free] = x[6 * n_img:6 * n_img + 3 * len(free)].reshape(-1, 3)
        vals = dict(zip(calib, x[6 * n_img + 3 * len(free):]))
        c, x0, y0, A1 = (vals.get("c", C), vals.get("x0", 0.0), vals.get("y0", 0.0),
                         vals.get("A1", 0.0))
        out = np.empty_like(xy)
        for j in range(n_img):
            m = ji == j
            k = (P[pi[m]] - ext[j, :3]) @ _rot(*ext[j, 3:])        # rows: Rᵀ(X − X0)
            red = xy[m] - [x0, y0]
            delta = A1 * red * np.sum(red**2, axis=1, keepdims=True)  # Δ at the measured point
            out[m] = np.column_stack([x0 - c * k[:, 0] / k[:, 2], y0 - c * k[:, 1] / k[:, 2]]) \
                + delta - xy[m]
        return out.ravel()

    sparsity = sps.lil_matrix((2 * len(xy), 6 * n_img + 3 * len(free) + len(calib)), dtype=int)
    slot = {p: n for n, p in enumerate(free)}
    for n, (j, i) in enumerate(zip(ji, pi)):
        for r in (2 * n, 2 * n + 1):
            sparsity[r, 6 * j:6 * j + 6] = 1
            if i in slot:
                sparsity[r, 6 * n_img + 3 * slot[i]:6 * n_img + 3 * slot[i] + 3] = 1
            sparsity[r, 6 * n_img + 3 * len(free):] = 1
    return fun, sparsity, free


@pytest.fixture(scope="module")
def block():
    xy, ji, pi, ext, P = _block()
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control)
    return xy, ji, pi, ext, P, control, ext0, P0, res


def _scipy_solution(xy, ji, pi, ext0, P0, control, calib=(), interior0=()):
    """SciPy's trust-region solution, polished by Gauss–Newton steps on the full sparse
    normal equations (finite-difference Jacobian, ``spsolve``); returns (x, v, J, free)."""
    fun, sparsity, free = _residual_function(xy, ji, pi, len(ext0), control, P0, calib)
    x = np.r_[ext0.ravel(), P0[free].ravel(), list(interior0)]
    x = least_squares(fun, x, jac_sparsity=sparsity, x_scale="jac", method="trf").x
    groups = group_columns(sparsity)
    for _ in range(3):
        J = sps.csr_matrix(approx_derivative(fun, x, method="3-point", abs_step=1e-5,
                                             sparsity=(sparsity, groups)))
        x = x + spsolve((J.T @ J).tocsc(), -(J.T @ fun(x)))
    return x, fun(x), J, free


@pytest.fixture(scope="module")
def block_scipy(block):
    xy, ji, pi, ext, P, control, ext0, P0, res = block
    return _scipy_solution(xy, ji, pi, ext0, P0, control)


def test_agrees_with_scipy_least_squares(block, block_scipy):
    xy, ji, pi, ext, P, control, ext0, P0, res = block
    x, v, _, free = block_scipy
    M = len(ext)
    # SciPy's solution is limited by its finite-difference Jacobian (~1e-6 m here, 1e-4 σ);
    # ours is at least as good a minimum of the same sum of squares
    ext_scipy = x[:6 * M].reshape(-1, 6)
    np.testing.assert_allclose(res.exterior[:, :3], ext_scipy[:, :3], atol=1e-5)
    np.testing.assert_allclose(res.exterior[:, 3:], ext_scipy[:, 3:], atol=1e-8)
    np.testing.assert_allclose(res.points[free].ravel(), x[6 * M:], atol=1e-5)
    np.testing.assert_allclose(res.residuals.ravel(), v, atol=1e-8)
    assert np.sum(res.residuals**2) <= v @ v * (1 + 1e-12)
    assert np.max(np.abs(res.exterior[:, :3] - ext_scipy[:, :3])) < 1e-3 * np.min(
        np.sqrt(np.einsum("mii->mi", res.exterior_covariance)[:, :3]))
    assert res.converged and res.iterations < 10
    np.testing.assert_array_equal(res.points[control], P[control])


def test_covariance_and_redundancy_numbers_from_the_full_sparse_normal_equations(block,
                                                                                 block_scipy):
    xy, ji, pi, ext, P, control, ext0, P0, res = block
    x, v, J, free = block_scipy
    N = (J.T @ J).tocsc()
    Q = np.linalg.inv(N.toarray())
    Jd = J.toarray()
    Qvv = np.eye(len(Jd)) - Jd @ Q @ Jd.T       # brute force, dense, P = I
    r = len(Jd) - Jd.shape[1]
    assert res.redundancy == r == res.n_observations - res.n_unknowns
    np.testing.assert_allclose(res.redundancy_numbers.ravel(), np.diag(Qvv), atol=1e-6)
    assert math.isclose(res.redundancy_numbers.sum(), r, rel_tol=1e-9)
    s2 = v @ v / r
    assert math.isclose(res.sigma0, math.sqrt(s2), rel_tol=1e-7)
    M = len(ext)
    for k in range(M):
        np.testing.assert_allclose(res.exterior_covariance[k],
                                   s2 * Q[6 * k:6 * k + 6, 6 * k:6 * k + 6], rtol=1e-4, atol=1e-12)
    for n, p in enumerate(free[:10]):
        b = 6 * M + 3 * n
        np.testing.assert_allclose(res.point_covariance[p], s2 * Q[b:b + 3, b:b + 3], rtol=1e-4,
                                   atol=1e-12)
    assert np.all(res.point_covariance[control] == 0.0)


def test_noise_free_block_recovers_the_truth():
    xy, ji, pi, ext, P = _block(noise=0.0, seed=4)
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    seen = []
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, callback=seen.append)
    np.testing.assert_allclose(res.exterior, ext, atol=1e-7)
    np.testing.assert_allclose(res.points, P, atol=1e-6)
    assert res.sigma0 < 1e-9
    assert [h.iteration for h in seen] == list(range(1, res.iterations + 1))
    assert seen == list(res.history)
    assert seen[0].vtv > seen[-1].vtv


def test_sigma0_estimates_the_noise_put_in():
    xy, ji, pi, ext, P = _block(strips=2, per=4, noise=0.004, seed=7)
    control = _corners(P)
    res = bd.bundle_adjustment(xy, ji, pi, *_start(ext, P, control), C, control=control)
    # σ0² ~ σ²·χ²_r/r: r > 500 gives σ0 within a few % of 4 µm
    assert 0.0037 < res.sigma0 < 0.0043
    assert res.redundancy > 500


def test_free_network_minimum_norm():
    xy, ji, pi, ext, P = _block(seed=2)
    ext0, P0 = _start(ext, P, [])
    free = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, datum="free")
    assert free.datum_defect == 7 and free.redundancy == free.n_observations - free.n_unknowns + 7
    assert math.isclose(free.redundancy_numbers.sum(), free.redundancy, rel_tol=1e-9)
    # the centroid of the approximate points is kept exactly (translation constraints)
    np.testing.assert_allclose(free.points.mean(axis=0), P0.mean(axis=0), atol=1e-8)
    # minimal constraints: point a fixed, point b fixed, Z of point c fixed (3 + 3 + 1 = 7)
    a, b, c = 0, len(P) - 1, 7
    fun_P = free.points.copy()

    def fun(x):
        Q = fun_P.copy()
        mask = np.ones(Q.shape, bool)
        mask[a] = mask[b] = False
        mask[c, 2] = False
        Q[mask] = x[6 * len(ext):]
        ext_ = x[:6 * len(ext)].reshape(-1, 6)
        out = []
        for j in range(len(ext_)):
            m = ji == j
            k = (Q[pi[m]] - ext_[j, :3]) @ _rot(*ext_[j, 3:])
            out.append(np.column_stack([-C * k[:, 0] / k[:, 2], -C * k[:, 1] / k[:, 2]]) - xy[m])
        return np.vstack(out).ravel()

    mask = np.ones(P.shape, bool)
    mask[a] = mask[b] = False
    mask[c, 2] = False
    x0 = np.r_[free.exterior.ravel(), free.points[mask]]
    sol = least_squares(fun, x0 + 1e-3, method="lm", xtol=1e-15, ftol=1e-15)
    # residuals and σ0 do not depend on the datum
    np.testing.assert_allclose(free.residuals.ravel(), sol.fun, atol=1e-7)
    # the minimum-norm datum has the smallest trace of the point covariance (same network)
    J = sol.jac
    Q = np.linalg.inv(J.T @ J) * free.sigma0**2
    trace_min = np.trace(Q[6 * len(ext):, 6 * len(ext):])
    assert np.trace(free.point_covariance.sum(axis=0)) < trace_min


def test_self_calibration_recovers_c_principal_point_and_A1():
    xy, ji, pi, ext, P = _block(strips=3, per=4, noise=0.001, seed=11, A1=-3e-6)
    control = np.flatnonzero(np.random.default_rng(0).random(len(P)) < 0.3)
    ext0, P0 = _start(ext, P, control)
    calib = ("c", "x0", "y0", "A1")
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C + 0.3, control=control, calibrate=calib)
    x, _, _, _ = _scipy_solution(xy, ji, pi, ext0, P0, control, calib, (C + 0.3, 0.0, 0.0, 0.0))
    got = res.interior()
    np.testing.assert_allclose([got[n] for n in calib], x[-4:], rtol=1e-6, atol=1e-9)
    assert abs(got["c"] - C) < 0.05 and abs(got["A1"] + 3e-6) < 3e-7
    assert res.interior_covariance.shape == (4, 4)
    assert res.calibrate == calib


def test_gross_error_is_found_by_data_snooping():
    xy, ji, pi, ext, P = _block(strips=2, per=4, noise=0.003, seed=5)
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    clean = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control)
    # 2n tests: at α = 0.001 about n/500 false alarms are expected; at 1e-5 none
    assert len(bd.data_snooping(clean, 0.001, sigma=0.003).flagged) < 0.002 * clean.n_observations
    assert bd.data_snooping(clean, 1e-5, sigma=0.003).worst is None
    bad = xy.copy()
    k = int(np.argmax(clean.redundancy_numbers[:, 0]))
    bad[k, 0] += 0.05                                   # 50 µm blunder
    res = bd.bundle_adjustment(bad, ji, pi, ext0, P0, C, control=control)
    for snoop in (bd.data_snooping(res, 1e-5, sigma=0.003), bd.data_snooping(res, 1e-5)):
        assert snoop.worst == (k, 0), snoop.test
    w = bd.data_snooping(res, 0.001, sigma=0.003)
    np.testing.assert_allclose(w.statistic, res.standardised_residuals * res.sigma0 / 0.003)
    assert w.critical == pytest.approx(stats.norm.ppf(1 - 0.0005), abs=1e-12)


def _quantile_mpmath(alpha, nu):
    """k with P(|T_ν| > k) = α from mpmath (40 digits): log t_tail(e^u) = log α solved for u,
    t_tail being erfc or the regularised incomplete beta function
    (:func:`photolib.derive.adjustment.t_tail`). In logs, so that α = 1e-300 keeps its digits
    (``adj.t_quantile`` stops at an absolute residual of 1e-30)."""
    with mpmath.workdps(40):
        target = mpmath.log(mpmath.mpf(alpha))
        g = lambda u: mpmath.log(adj.t_tail(mpmath.exp(u), nu)) - target
        lo, hi = mpmath.mpf(-5), mpmath.mpf(1)
        while g(hi) > 0:
            lo, hi = hi, hi + 8
        u = mpmath.findroot(g, (lo, hi), solver="illinois", verify=False)
        assert abs(g(u)) < 1e-30, (alpha, nu, g(u))
        return mpmath.exp(u)


@pytest.mark.parametrize("alpha", [0.1, 0.05, 0.01, 0.001, 1e-5])
@pytest.mark.parametrize("dof", [1, 2, 5, 17, 120])
def test_critical_values_agree_with_mpmath(alpha, dof):
    """SciPy's quantiles (the library) against mpmath's root of erfc and of the incomplete
    beta function."""
    assert bd.critical_value(alpha) == pytest.approx(float(_quantile_mpmath(alpha, math.inf)),
                                                     rel=1e-13)
    assert bd.critical_value(alpha, "t", dof) == pytest.approx(
        float(_quantile_mpmath(alpha, dof)), rel=1e-12)
    if dof > 1:
        # τ²/r ~ Beta(1/2, (r − 1)/2) (Pope), a different route from τ(t)
        tau2 = dof * stats.beta.ppf(1 - alpha, 0.5, (dof - 1) / 2)
        assert bd.critical_value(alpha, "tau", dof) == pytest.approx(math.sqrt(tau2), rel=1e-8)


def test_t_critical_value_agrees_with_mpmath_derivation():
    assert bd.critical_value(0.05, "t", 5) == pytest.approx(float(adj.t_quantile(0.05, 5)),
                                                            rel=1e-12)


def _t_density(nu):
    """Student's density f(x) = Γ((ν+1)/2) / (√(νπ)·Γ(ν/2)) · (1 + x²/ν)^(−(ν+1)/2), written out
    (ν = inf: the normal density)."""
    if math.isinf(nu):
        return lambda x: math.exp(-0.5 * x * x) / math.sqrt(2 * math.pi)
    logc = math.lgamma((nu + 1) / 2) - math.lgamma(nu / 2) - 0.5 * math.log(nu * math.pi)
    return lambda x: math.exp(logc - (nu + 1) / 2 * math.log1p(x * x / nu))


def _t_cdf_by_quadrature(t, nu):
    """P(T_ν ≤ t) = ½ + ∫₀ᵗ f(x) dx, integrated by QUADPACK."""
    part = quad(_t_density(nu), 0.0, abs(t), epsabs=1e-14, epsrel=1e-13, limit=200)[0]
    return 0.5 + math.copysign(part, t)


def _t_tail_by_quadrature(t, nu):
    """P(|T_ν| > |t|) = 2∫_|t|^∞ f(x) dx, relative accuracy (no 1 − cdf)."""
    return 2 * quad(_t_density(nu), abs(t), math.inf, epsabs=0.0, epsrel=1e-12, limit=200)[0]


@settings(max_examples=40, deadline=None)
@given(st.floats(-30.0, 30.0), st.one_of(st.integers(1, 300), st.just(math.inf)))
def test_deprecated_t_cdf_and_critical_value_against_the_integrated_density(t, dof):
    with pytest.warns(DeprecationWarning, match=r"student_t_cdf is deprecated.*scipy\.stats"):
        got = bd.student_t_cdf(t, dof)
    # SciPy's t.cdf is good to about 1e-12 except near t = 0 for ν = 1, where it returns
    # 0.5 for |t| ≲ 1e-9 (measured: t.cdf(1e-9, 1) = 0.5, exact 0.5 + 3.2e-10): allow 1e-9
    assert got == pytest.approx(_t_cdf_by_quadrature(t, dof), abs=1e-12 if abs(t) > 1e-6
                                else 1e-9)
    p = _t_tail_by_quadrature(t, dof)
    if 1e-10 < p < 1 - 1e-10:
        assert bd.critical_value(p, "t", dof) == pytest.approx(abs(t), rel=1e-9, abs=1e-9)


@pytest.mark.parametrize("module", ["photolib", "photolib.bundle"])
def test_student_t_cdf_is_deprecated_and_delegates_to_scipy(module):
    import importlib

    mod = importlib.import_module(module)
    assert "student_t_cdf" not in mod.__all__ and "critical_value" in mod.__all__
    for t, nu in ((2.0, 5), (-1.5, 1), (0.3, math.inf), (4.0, 2.5)):
        with pytest.warns(DeprecationWarning, match="use scipy.stats.t.cdf"):
            got = mod.student_t_cdf(t, nu)
        assert isinstance(got, float)
        assert got == pytest.approx(_t_cdf_by_quadrature(t, nu), abs=1e-12)


def test_critical_value_rises_as_degrees_of_freedom_fall():
    """Luhmann p. 90, corrected text (luhmann:p90-t-distribution): the tail P(|T| > k) 'steigt'
    as ν falls, so at a fixed α the critical value rises."""
    ks = [bd.critical_value(0.05, "t", nu) for nu in (1, 3, 10, 30, math.inf)]
    assert all(a > b for a, b in zip(ks, ks[1:]))
    assert ks[-1] == bd.critical_value(0.05)


def test_inner_constraints_span_the_null_space_of_the_free_network():
    xy, ji, pi, ext, P = _block(seed=1)
    fun, sparsity, free = _residual_function(xy, ji, pi, len(ext), [], P)
    J = least_squares(fun, np.r_[ext.ravel(), P.ravel()], jac_sparsity=sparsity, max_nfev=1,
                      jac="3-point", diff_step=1e-6).jac.toarray()
    sv = np.linalg.svd(J, compute_uv=False)
    assert sv[-8] / sv[0] > 1e-7 and sv[-7] / sv[0] < 1e-7      # defect exactly 7
    assert bd.inner_constraints(P).shape == (3 * len(P), 7)
    assert adj.similarity_parameters() == 7


def test_counts_agree_with_the_derivation(block):
    *_, P, control, _, _, res = block
    rays = res.n_observations // 2
    counts = adj.block_redundancy(len(res.exterior), len(P), rays, control=len(control))
    assert (counts["n"], counts["u"], counts["r"]) == (res.n_observations, res.n_unknowns,
                                                       res.redundancy)


def test_normal_matrix_pattern_matches_the_full_normal_matrix(block, block_scipy):
    xy, ji, pi, ext, P, control, ext0, P0, res = block
    _, _, J, free = block_scipy
    N = (abs(J).T @ abs(J)).toarray() > 0
    pat = bd.normal_matrix_pattern(ji, pi, len(ext), len(P), fixed=control)
    np.testing.assert_array_equal(pat, N)
    # the point part is block diagonal (3×3 blocks)
    Npp = pat[6 * len(ext):, 6 * len(ext):]
    assert Npp.sum() == 9 * len(free)


# -- bad input -------------------------------------------------------------------------------------

def _args(block):
    xy, ji, pi, ext, P, control, ext0, P0, _ = block
    return [xy, ji, pi, ext0, P0, C], {"control": control}


@pytest.mark.parametrize("change, error, text", [
    (lambda a, k: a.__setitem__(0, a[0][:, :1]), ValueError, "xy has shape"),
    (lambda a, k: a.__setitem__(1, a[1][:-1]), ValueError, "image_index has shape"),
    (lambda a, k: a.__setitem__(2, a[2].astype(float)), ValueError, "must hold integers"),
    (lambda a, k: a.__setitem__(3, a[3][:, :5]), ValueError, "exterior has shape"),
    (lambda a, k: a.__setitem__(4, a[4][:, :2]), ValueError, "points has shape"),
    (lambda a, k: a[0].__setitem__((3, 1), np.nan), ValueError, "xy contains a non-finite"),
    (lambda a, k: a[4].__setitem__((2, 0), np.inf), ValueError, "points contains a non-finite"),
    (lambda a, k: a[2].__setitem__(0, 10_000), ValueError, "point_index contains 10000"),
    (lambda a, k: a.__setitem__(5, -50.0), ValueError, "c must be > 0"),
    (lambda a, k: k.__setitem__("control", k["control"][:2]), bd.DatumError, "2 observed control"),
    (lambda a, k: k.__setitem__("control", None), bd.DatumError, "0 observed control"),
    (lambda a, k: k.__setitem__("datum", "fixed"), ValueError, "datum must be"),
    (lambda a, k: k.__setitem__("calibrate", ("c", "k1")), ValueError, "calibrate"),
    (lambda a, k: k.__setitem__("distortion", 1e-5), TypeError, "distortion must be"),
])
def test_bad_input_is_named(block, change, error, text):
    args, kwargs = _args(block)
    args = [np.array(a, copy=True) if isinstance(a, np.ndarray) else a for a in args]
    kwargs = dict(kwargs)
    change(args, kwargs)
    with pytest.raises(error, match=text):
        bd.bundle_adjustment(*args, **kwargs)


def test_collinear_control_points_are_a_datum_error(block):
    args, kwargs = _args(block)
    P = args[4].copy()
    line = [0, 1, 2]
    P[line] = [[0, 0, 0], [10, 0, 0], [20, 0, 0]]
    with pytest.raises(bd.DatumError, match="straight line"):
        bd.bundle_adjustment(*args[:4], P, C, control=line)


def test_image_with_too_few_points_and_point_seen_once(block):
    xy, ji, pi, ext, P, control, ext0, P0, _ = block
    rows2 = np.flatnonzero(ji == 2)
    keep = np.setdiff1d(np.arange(len(ji)), rows2[2:])        # image 2 keeps two points
    with pytest.raises(bd.DatumError, match="image 2 has"):
        bd.bundle_adjustment(xy[keep], ji[keep], pi[keep], ext0, P0, C, control=control)
    # a new point with a single ray
    p = next(p for p in range(len(P)) if p not in control and np.sum(pi == p) >= 2)
    drop = np.flatnonzero(pi == p)[1:]
    keep = np.setdiff1d(np.arange(len(xy)), drop)
    with pytest.raises(bd.DatumError, match=f"point {p} is observed in 1 image"):
        bd.bundle_adjustment(xy[keep], ji[keep], pi[keep], ext0, P0, C, control=control)


def test_duplicate_observation_and_no_convergence(block):
    xy, ji, pi, ext, P, control, ext0, P0, _ = block
    with pytest.raises(ValueError, match="observed twice"):
        bd.bundle_adjustment(np.vstack([xy, xy[:1]]), np.r_[ji, ji[:1]], np.r_[pi, pi[:1]],
                             ext0, P0, C, control=control)
    with pytest.raises(pl.ConvergenceError, match="did not converge"):
        bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, max_iter=1)
    last = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, max_iter=1, check=False)
    assert not last.converged and last.iterations == 1


def test_estimate_is_the_iterate_whose_update_is_below_tol_and_is_linearised_once(block,
                                                                                   monkeypatch):
    """The loop stops at the iterate whose own Gauss–Newton update is below tol and returns it
    unchanged; its statistics reuse that iteration's normal equations (one linearisation and
    one normal-equation assembly per iteration, none more), and with ``check=False`` at the
    iteration limit the last update is applied and the statistics linearise there."""
    from photolib.bundle import _adjustment as ad

    xy, ji, pi, ext, P, control, ext0, P0, res = block
    extent = float(np.max(np.ptp(P0, axis=0)))
    calls = {"linearise": 0, "normals": 0}

    def counted(fn, key):
        def run(*args):
            calls[key] += 1
            return fn(*args)
        return run

    monkeypatch.setattr(ad, "linearise", counted(ad.linearise, "linearise"))
    monkeypatch.setattr(ad, "normals", counted(ad.normals, "normals"))
    again = bd.bundle_adjustment(xy, ji, pi, res.exterior, res.points, C, control=control)
    assert again.iterations == 1 and calls == {"linearise": 1, "normals": 1}
    last = again.history[-1]
    assert last.max_length_update <= 1e-10 * extent and last.max_angle_update <= 1e-10
    np.testing.assert_array_equal(again.exterior, res.exterior)  # the update is not applied
    np.testing.assert_array_equal(again.points, res.points)
    np.testing.assert_allclose(again.point_covariance, res.point_covariance, rtol=1e-12,
                               atol=0)
    calls.update(linearise=0, normals=0)
    bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control)
    assert calls["linearise"] == calls["normals"] == res.iterations
    calls.update(linearise=0, normals=0)
    cut = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, max_iter=2,
                               check=False)
    assert not cut.converged and calls == {"linearise": 3, "normals": 3}


def test_undetermined_self_calibration_is_a_datum_error():
    """Nadir images at one height over a plane: c and the flying height trade off exactly."""
    xy, ji, pi, ext, P = _block(noise=0.0, flat=True)
    control = _corners(P)
    bd.bundle_adjustment(xy, ji, pi, ext, P, C, control=control)        # fine without c
    with pytest.raises(bd.DatumError, match="singular"):
        bd.bundle_adjustment(xy, ji, pi, ext, P, C, control=control, calibrate=("c",))


def test_critical_value_bad_input():
    with pytest.raises(ValueError, match="alpha"):
        bd.critical_value(1.5)
    with pytest.raises(ValueError, match="τ test needs"):
        bd.critical_value(0.01, "tau", 1)
    with pytest.raises(ValueError, match="test must be"):
        bd.critical_value(0.01, "chi2")
    with pytest.warns(DeprecationWarning), pytest.raises(ValueError, match="dof must be"):
        bd.student_t_cdf(1.0, 0)


# -- input handling (red-team audit) --------------------------------------------------------------

def _pair(X0s):
    """Two images of a small block, taken from the projection centres ``X0s``."""
    X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 3.0], [3, 7, 1.0]])
    ext = np.array([[*X0, 0.0, 0.0, 0.0] for X0 in X0s])
    xy = np.vstack([pl.project(X, e[:3], pl.rotation_opk(*e[3:]), 20.0) for e in ext])
    return xy, np.repeat([0, 1], 6), np.tile(np.arange(6), 2), ext, X


@pytest.mark.parametrize("shift", [0.0, 0.01])
def test_zero_base_is_a_datum_error_naming_the_points(shift):
    """Both images from one X0: the rays of the new points are parallel (was a bare
    LinAlgError 'Singular matrix' from the 3 × 3 point blocks)."""
    xy, ji, pi, ext, X = _pair([(5.0, 5.0, 30.0), (5.0, 5.0, 30.0)])
    start = ext + [[shift, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]]
    with pytest.raises(bd.DatumError, match=r"object points 4, 5 cannot be intersected: "
                                            r"their rays are parallel"):
        bd.bundle_adjustment(xy, ji, pi, start, X, 20.0, control=[0, 1, 2, 3])


@pytest.mark.parametrize("kwargs, text", [
    ({"max_iter": 0}, r"max_iter must be an integer ≥ 1, got 0"),
    ({"max_iter": 0, "check": False}, r"max_iter must be an integer ≥ 1, got 0"),
    ({"max_iter": 2.5}, r"max_iter must be an integer, got 2.5"),
    ({"tol": -1.0}, r"tol must be > 0, got -1.0"),
    ({"tol": np.nan}, r"tol must be finite, got nan"),
])
def test_iteration_limit_and_tolerance_are_checked(kwargs, text):
    xy, ji, pi, ext, X = _pair([(3.0, 5.0, 30.0), (7.0, 5.0, 30.0)])
    with pytest.raises(ValueError, match=text):
        bd.bundle_adjustment(xy, ji, pi, ext + 0.01, X, 20.0, control=[0, 1, 2, 3], **kwargs)


@pytest.mark.parametrize("control, text", [
    ([0, 1, 2, 9], r"control contains 9, outside 0 … 5"),
    ([0, 1, 2, -1], r"control contains -1, outside 0 … 5"),
    ([0.0, 1.9, 2.5, 3.1], r"control must hold integer point indices or be a bool mask of "
                           r"length 6, got dtype float64"),
    (np.array([1, 1, 1, 1, 0, 0]), r"control lists point 0 2 times.*0/1 array is read as "
                                   r"indices"),
    (np.ones(5, bool), r"control mask has shape \(5,\); expected \(6,\)"),
])
def test_control_indices_are_checked(control, text):
    xy, ji, pi, ext, X = _pair([(3.0, 5.0, 30.0), (7.0, 5.0, 30.0)])
    with pytest.raises(ValueError, match=text):
        bd.bundle_adjustment(xy, ji, pi, ext + 0.01, X, 20.0, control=control)


def test_control_as_indices_mask_or_array_give_the_same_result():
    xy, ji, pi, ext, X = _pair([(3.0, 5.0, 30.0), (7.0, 5.0, 30.0)])
    mask = np.array([True, True, True, True, False, False])
    results = [bd.bundle_adjustment(xy, ji, pi, ext + 0.01, X, 20.0, control=c)
               for c in ([0, 1, 2, 3], np.array([3, 2, 1, 0], np.uint8), mask)]
    for r in results[1:]:
        np.testing.assert_array_equal(r.exterior, results[0].exterior)
    by_name = bd.bundle_adjustment(xy, ji, pi, ext + 0.01, X, 20.0, control=mask, calibrate="c")
    assert by_name.calibrate == ("c",)


@pytest.mark.parametrize("alpha, dof", [(a, d) for a in (1e-12, 1e-16, 1e-20, 1e-50, 1e-300)
                                         for d in (math.inf, 1, 2, 5, 30)])
def test_critical_values_for_tiny_alpha_agree_with_mpmath(alpha, dof):
    """The quantile is taken of the upper tail P(T > k) = α/2: with 1 − cdf every α ≤ 1e-16
    gave the same wrong k (8.29 for the normal, 2796 instead of 2855 for t(5) at 1e-16). At
    α = 1e-300 SciPy's t(5).isf gives −inf; the library solves its logsf there instead."""
    test = "normal" if math.isinf(dof) else "t"
    ref = float(_quantile_mpmath(alpha, dof))
    assert bd.critical_value(alpha, test, dof) == pytest.approx(ref, rel=1e-13)


def test_critical_value_out_of_floating_point_reach_is_an_error():
    # ν = 0.5: P(T > k) ~ C·k^(−1/2), so α = 1e-300 needs k ≈ 1e600
    assert _quantile_mpmath(1e-300, 0.5) > 1e308      # mpmath: 4.1e599
    with pytest.raises(ValueError, match=r"critical value for a tail of 5e-301 with dof = 0.5 "
                                         r"is out of floating-point reach"):
        bd.critical_value(1e-300, "t", 0.5)


def test_degrees_of_freedom_must_be_numbers():
    for f in (lambda: bd.student_t_cdf(1.0, "a"), lambda: bd.critical_value(0.05, "t", "a")):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)   # student_t_cdf's
            with pytest.raises(ValueError, match=r"dof must be a real number > 0 "
                                                 r"\(inf: normal\), got 'a'"):
                f()
    with pytest.raises(ValueError, match="dof must be > 0, got nan"):
        bd.critical_value(0.05, "t", np.nan)


def test_inner_constraints_and_pattern_check_their_input():
    with pytest.raises(ValueError, match=r"points contains a non-finite value nan at index "
                                         r"\(0, 0\)"):
        bd.inner_constraints([[np.nan, 2.0, 3.0], [1.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"points has shape \(3,\); expected \(P, 3\)"):
        bd.inner_constraints([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"image_index contains 5, outside 0 … 1"):
        bd.normal_matrix_pattern([0, 5], [0, 0], 2, 1)
    with pytest.raises(ValueError, match=r"image_index contains -1, outside 0 … 1"):
        bd.normal_matrix_pattern([0, -1], [0, 0], 2, 1)
    with pytest.raises(ValueError, match=r"fixed contains 3, outside 0 … 0"):
        bd.normal_matrix_pattern([0, 1], [0, 0], 2, 1, fixed=[3])


# -- control points with errors and partial control (Polish notes: Xw, Yw, Zw known or observed) -

SIG_IMG = 0.003  # a-priori σ of an image coordinate, mm


def _weighted_residual_function(xy, ji, pi, n_img, sig, P_obs):
    """x ↦ (image residuals/σ_image, control residuals/σ_c) with x = (exterior 6M, every point
    coordinate with σ ≠ 0); the test's own collinearity as in :func:`_residual_function`."""
    unknown = sig != 0                                   # (P, 3)
    observed = np.isfinite(sig) & (sig > 0)

    def fun(x):
        ext = x[:6 * n_img].reshape(-1, 6)
        P = P_obs.copy()
        P[unknown] = x[6 * n_img:]
        out = np.empty_like(xy)
        for j in range(n_img):
            m = ji == j
            k = (P[pi[m]] - ext[j, :3]) @ _rot(*ext[j, 3:])
            out[m] = np.column_stack([-C * k[:, 0] / k[:, 2], -C * k[:, 1] / k[:, 2]]) - xy[m]
        ctrl = (P - P_obs)[observed] / sig[observed]
        return np.r_[out.ravel() / SIG_IMG, ctrl]
    return fun, unknown, observed


@pytest.fixture(scope="module")
def mixed_control():
    """Corners observed with σ = 5 cm, two height and two plan control points (fixed), the
    rest new; start values off as in :func:`_start`."""
    xy, ji, pi, ext, P = _block()
    corners = _corners(P)
    ext0, P0 = _start(ext, P, corners)
    sig = np.full((len(P), 3), np.inf)
    sig[corners] = 0.05
    height, plan = [5, 12], [20, 30]
    sig[height, 2] = 0.0
    sig[plan, :2] = 0.0
    P0[corners] = P[corners] + np.random.default_rng(7).normal(0, 0.05, (4, 3))  # "measured"
    P0[height, 2], P0[plan, :2] = P[height, 2], P[plan, :2]
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control_sigma=sig, sigma_image=SIG_IMG)
    return xy, ji, pi, ext0, P0, sig, res


@pytest.mark.slow
def test_weighted_and_partial_control_agree_with_scipy(mixed_control):
    xy, ji, pi, ext0, P0, sig, res = mixed_control
    fun, unknown, observed = _weighted_residual_function(xy, ji, pi, len(ext0), sig, P0)
    x = least_squares(fun, np.r_[ext0.ravel(), P0[unknown]], x_scale="jac", method="lm",
                      xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    M = len(ext0)
    # polish with Gauss–Newton on the dense finite-difference Jacobian
    for _ in range(2):
        J = approx_derivative(fun, x, method="3-point", abs_step=1e-6)
        x = x + np.linalg.lstsq(J, -fun(x), rcond=None)[0]
    J = approx_derivative(fun, x, method="3-point", abs_step=1e-6)
    f = fun(x)
    np.testing.assert_allclose(res.exterior[:, :3], x[:6 * M].reshape(-1, 6)[:, :3], atol=1e-5)
    np.testing.assert_allclose(res.exterior[:, 3:], x[:6 * M].reshape(-1, 6)[:, 3:], atol=1e-8)
    np.testing.assert_allclose(res.points[unknown], x[6 * M:], atol=1e-5)
    np.testing.assert_array_equal(res.points[~unknown], P0[~unknown])     # fixed stay
    # the estimate is the iterate whose own update is below tol (1e-10 · 684 m extent): the
    # image residuals may differ from the optimum's by about c/H · 7e-8 m = 7e-9 mm
    np.testing.assert_allclose(res.residuals.ravel(), f[:2 * len(xy)] * SIG_IMG, atol=1e-8)
    np.testing.assert_allclose(res.control_residuals[observed], f[2 * len(xy):] * sig[observed],
                               atol=1e-7)
    # redundancy by hand: 2 per ray + 3 per corner; 6 per image + 3 per point − fixed coords
    n, n_c = 2 * len(xy), 3 * 4
    u = 6 * M + 3 * len(P0) - 2 * 1 - 2 * 2
    assert (res.n_observations, res.n_control_observations, res.n_unknowns) == (n, n_c, u)
    assert res.redundancy == n + n_c - u == len(f) - len(x)
    # σ0 (image unit) and the covariance: (JᵀJ)⁻¹ of the weighted problem is σ_image²·Q
    r = len(f) - len(x)
    assert math.isclose(res.sigma0, SIG_IMG * math.sqrt(f @ f / r), rel_tol=1e-7)
    Q = np.linalg.inv(J.T @ J) * (f @ f / r)
    cols = np.full(sig.shape, -1)
    cols[unknown] = 6 * M + np.arange(unknown.sum())
    for p in [5, 20, *_corners(P0), 40]:
        c = cols[p][cols[p] >= 0]
        e = np.flatnonzero(cols[p] >= 0)
        np.testing.assert_allclose(res.point_covariance[p][np.ix_(e, e)], Q[np.ix_(c, c)],
                                   rtol=1e-4, atol=1e-12)
        assert np.all(res.point_covariance[p][cols[p] < 0] == 0.0)
    for k in range(M):
        np.testing.assert_allclose(res.exterior_covariance[k], Q[6 * k:6 * k + 6, 6 * k:6 * k + 6],
                                   rtol=1e-4, atol=1e-14)
    # redundancy numbers of every observation, the control ones included: diag(I − J(JᵀJ)⁻¹Jᵀ)
    rk = 1.0 - np.einsum("ij,ji->i", J, np.linalg.solve(J.T @ J, J.T))
    np.testing.assert_allclose(res.redundancy_numbers.ravel(), rk[:n], atol=1e-6)
    np.testing.assert_allclose(res.control_redundancy_numbers[observed], rk[n:], atol=1e-6)
    assert np.all(res.control_redundancy_numbers[~observed] == 0.0)
    assert math.isclose(res.redundancy_numbers.sum() + res.control_redundancy_numbers.sum(), r,
                        rel_tol=1e-9)
    tau = res.control_standardised_residuals
    assert np.all(np.isfinite(tau[observed])) and np.all(np.isnan(tau[~observed]))


def test_small_control_sigma_is_fixed_control_and_large_is_a_new_point(block):
    xy, ji, pi, ext, P, control, ext0, P0, fixed = block
    tight = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, control_sigma=1e-9,
                                 sigma_image=SIG_IMG)
    np.testing.assert_allclose(tight.points, fixed.points, atol=1e-9)
    np.testing.assert_allclose(tight.exterior, fixed.exterior, atol=1e-9)
    assert tight.redundancy == fixed.redundancy          # + 3·4 observations, + 3·4 unknowns
    assert math.isclose(tight.sigma0, fixed.sigma0, rel_tol=1e-9)
    np.testing.assert_allclose(tight.point_covariance, fixed.point_covariance, atol=1e-14)
    np.testing.assert_allclose(tight.control_redundancy_numbers[control], 0.0, atol=1e-9)
    # σ = 0 passed explicitly is the fixed control, bit for bit; sigma_image changes nothing
    same = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, control_sigma=0.0,
                                sigma_image=0.5)
    np.testing.assert_array_equal(same.points, fixed.points)
    assert same.sigma0 == fixed.sigma0 and same.n_control_observations == 0
    # one corner observed with σ = 1e4 m (others fixed): it becomes a new point
    loose = np.zeros((len(control), 3))
    loose[0] = 1e4
    weak = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, control_sigma=loose,
                                sigma_image=SIG_IMG)
    rest = list(control[1:])
    new = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=rest)
    np.testing.assert_allclose(weak.points, new.points, atol=1e-6)
    # the same cofactors Q (σ̂0² differs: 3 more observations, the same vᵀPv)
    np.testing.assert_allclose(weak.point_covariance[control[0]] / weak.sigma0**2,
                               new.point_covariance[control[0]] / new.sigma0**2, rtol=1e-5)
    assert weak.redundancy == new.redundancy + 3
    assert math.isclose(weak.sigma0**2 * weak.redundancy, new.sigma0**2 * new.redundancy,
                        rel_tol=1e-6)
    np.testing.assert_allclose(weak.control_redundancy_numbers[control[0]], 1.0, atol=1e-9)


def test_height_and_plan_control_points(block):
    """Four corners in plan only (X, Y fixed), heights from four others: datum fixed."""
    xy, ji, pi, ext, P, control, ext0, P0, _ = block
    sig = np.full((len(P), 3), np.inf)
    sig[control, :2] = 0.0
    heights = [10, 25, 50, 70]
    sig[heights, 2] = 0.0
    P0 = P0.copy()
    P0[heights, 2] = P[heights, 2]
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control_sigma=sig)
    assert res.n_unknowns == 6 * len(ext) + 3 * len(P) - 8 - 4
    assert res.redundancy == 2 * len(xy) - res.n_unknowns
    np.testing.assert_array_equal(res.points[control, :2], P0[control, :2])
    np.testing.assert_array_equal(res.points[heights, 2], P0[heights, 2])
    assert np.all(res.point_std[control, 2] > 0) and np.all(res.point_std[control, :2] == 0)
    assert np.abs(res.points - P).max() < 0.5
    assert math.isclose(res.redundancy_numbers.sum(), res.redundancy, rel_tol=1e-9)
    # the same block with fixed corners and the full sparse normal equations of SciPy's route
    fun, unknown, _ = _weighted_residual_function(xy, ji, pi, len(ext), sig, P0)
    x = np.r_[res.exterior.ravel(), res.points[unknown]]
    J = approx_derivative(fun, x, method="3-point", abs_step=1e-6)
    assert np.linalg.norm(J.T @ fun(x)) < 1e-6 * np.linalg.norm(J.T @ J) ** 0.5  # a minimum


@pytest.mark.parametrize("known, text", [
    ((slice(None), [2]), "fix only 4 of the 7"),             # heights only
    ((slice(None), [0, 1]), "fix only 6 of the 7"),          # plan only: height free
])
def test_partial_control_that_leaves_the_datum_free_is_a_datum_error(block, known, text):
    xy, ji, pi, ext, P, control, ext0, P0, _ = block
    sig = np.full((len(P), 3), np.inf)
    sig[np.ix_(control, known[1])] = 0.0
    with pytest.raises(bd.DatumError, match=text):
        bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control_sigma=sig)


@pytest.mark.parametrize("kwargs, text", [
    (dict(control_sigma=-0.01), r"point \d+, coordinate X is -0.01"),
    (dict(control_sigma=[0.01, np.nan, 0.01]), "coordinate Y is nan"),
    (dict(control_sigma=np.ones((3, 3))), r"shape \(3, 3\); with control \(4 points\)"),
    (dict(control_sigma="0.01"), "real numbers"),
    (dict(control_sigma=0.01), "sigma_image"),
    (dict(control_sigma=0.01, sigma_image=-1.0), "sigma_image must be > 0"),
    (dict(control=None, control_sigma=np.ones(4)), r"shape \(4,\); expected \(90, 3\)"),
])
def test_bad_control_sigma_is_named(block, kwargs, text):
    args, kw = _args(block)
    with pytest.raises(ValueError, match=text):
        bd.bundle_adjustment(*args, **(kw | kwargs))


# -- reliability ------------------------------------------------------------------------------

@pytest.mark.parametrize("alpha, beta", [(0.001, 0.80), (0.05, 0.80), (0.01, 0.90), (0.1, 0.3)])
def test_non_centrality_from_scipy_quantiles(alpha, beta):
    ref = stats.norm.ppf(1 - alpha / 2) + stats.norm.ppf(beta)
    assert bd.non_centrality(alpha, beta) == pytest.approx(ref, rel=1e-10)


def test_reliability_from_the_dense_redundancy_numbers(block, block_scipy):
    xy, ji, pi, ext, P, control, ext0, P0, res = block
    _, _, J, _ = block_scipy
    Jd = J.toarray()
    rk = 1.0 - np.einsum("ij,ji->i", Jd, np.linalg.solve(Jd.T @ Jd, Jd.T))
    d0 = stats.norm.ppf(1 - 0.0005) + stats.norm.ppf(0.8)
    rel = bd.reliability(res, sigma=SIG_IMG)
    np.testing.assert_allclose(rel.mdb.ravel(), d0 * SIG_IMG / np.sqrt(rk), rtol=1e-5)
    np.testing.assert_allclose(rel.external.ravel(), d0 * np.sqrt((1 - rk) / rk), rtol=1e-5)
    # external reliability: ∇0 on one observation, re-adjusted; the adjusted observations move
    # by ∇0·√(1 − r_k), i.e. ∇xᵀN∇x = ∇0²(1 − r_k), and ∇x = (JᵀJ)⁻¹Jᵀe_k∇0 (linearised)
    k = int(np.argmax(rk[::2] > 0.5)) * 2            # an x′ with a good redundancy number
    obs, e = divmod(k, 2)
    moved = xy.copy()
    moved[obs, e] += rel.mdb[obs, e]
    again = bd.bundle_adjustment(moved, ji, pi, res.exterior, res.points, C, control=control)
    dl = (moved + again.residuals - (xy + res.residuals)).ravel()
    assert math.isclose(np.linalg.norm(dl), rel.mdb[obs, e] * math.sqrt(1 - rk[k]), rel_tol=1e-3)
    dx = np.linalg.solve(Jd.T @ Jd, Jd[k]) * rel.mdb[obs, e]
    M = len(ext)
    free = np.setdiff1d(np.arange(len(P)), control)
    np.testing.assert_allclose((again.points - res.points)[free].ravel(), dx[6 * M:], rtol=0,
                               atol=2e-3 * np.abs(dx).max())
    assert math.isclose(np.sqrt(dx @ (Jd.T @ Jd) @ dx) / SIG_IMG, rel.external[obs, e],
                        rel_tol=1e-4)
    # uncontrolled observations: ∇0 infinite; default σ is σ̂0
    assert np.all(np.isinf(rel.mdb[res.redundancy_numbers <= 1e-12]))
    assert bd.reliability(res).sigma == res.sigma0


def test_reliability_of_control_observations(mixed_control):
    *_, sig, res = mixed_control
    rel = bd.reliability(res)
    assert rel.sigma == SIG_IMG
    obs = np.isfinite(sig) & (sig > 0)
    rc = res.control_redundancy_numbers[obs]
    np.testing.assert_allclose(rel.control_mdb[obs], rel.delta0 * sig[obs] / np.sqrt(rc))
    assert np.all(np.isnan(rel.control_mdb[~obs]))
    with pytest.raises(ValueError, match="beta must be in"):
        bd.reliability(res, beta=1.0)
    with pytest.raises(TypeError, match="BundleResult"):
        bd.reliability({"sigma0": 1.0})


# -- inner constraints need a datum to fix (audit B1) ----------------------------------------------

@pytest.mark.parametrize("points, match", [
    (np.zeros((0, 3)), "at least 3 points, got 0"),
    ([[1.0, 0, 0], [-1.0, 0, 0]], "at least 3 points, got 2"),
    ([[0.0, 0, 0], [1.0, 1, 1], [2.0, 2, 2], [-3.0, -3, -3]], "on a straight line"),
    ([[1.0, 2, 3]] * 4, "on a straight line"),
])
def test_inner_constraints_refuse_too_few_or_collinear_points(points, match):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")        # was: Mean of empty slice, a (0, 7) result
        with pytest.raises(bd.DatumError, match=match):
            bd.inner_constraints(points)


def test_inner_constraints_of_three_points_have_rank_7():
    B = bd.inner_constraints([[0.0, 0, 0], [1.0, 0, 0], [0.0, 1, 0.2]])
    assert B.shape == (9, 7) and np.linalg.matrix_rank(B) == 7


def test_the_old_spelling_of_the_standardised_residuals_still_works_with_a_warning(block):
    """One spelling convention (-ise, as quantise, normalise): standardized_residuals moved."""
    res = block[-1]
    with pytest.warns(DeprecationWarning, match="standardised_residuals"):
        old = res.standardized_residuals
    np.testing.assert_array_equal(old, res.standardised_residuals)
    with pytest.warns(DeprecationWarning, match="control_standardised_residuals"):
        old = res.control_standardized_residuals
    np.testing.assert_array_equal(old, res.control_standardised_residuals)
