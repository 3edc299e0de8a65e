"""The exercises of chapter 10 (bundle adjustment), judged as the grader does.

The same checks as ``ChapterChecks`` (reference accepted, every declared mistake
recognised with its hint, variants differ, functions judged on hidden cases, untouched
answers not answered), plus the references by an independent route: counts by hand, SciPy's
t quantile, the σ0 of ``numpy.linalg.lstsq``, the trace of a brute-force Q_vv, and the
contribution of an observation from the full product AᵀPA. The solution master gets full
marks and the generated student copy none (``photolib.grading.batch`` in a real kernel).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from photolib.grading.exercises import ch10_bundle_adjustment as ch10
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch10.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000000", "s3000001")


class TestChapter10(ChapterChecks, BatchGradedChecks):
    module = ch10
    chapter_name = "10-bundle-adjustment"
    kinds = {"number", "choice", "function"}
    students = STUDENTS
    slow_mistakes = frozenset({'bun.redundancy'})
    mistake_students = tuple(f"s{i:07d}" for i in range(40))
    scalar_cases = False            # bun.normal-contribution takes a design row and a σ
    grade_timeout = 120


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_redundancy_by_hand(sid):
    p = parameters_for(BY_ID["bun.redundancy"], sid)
    n = 2 * p["rays"]
    u = 6 * p["images"] + 3 * (p["points"] - p["control"]) + p["k"]
    d = 7 if p["datum"] == "free" else 0
    assert ch10._redundancy(p) == n - u + d > 0


@pytest.mark.parametrize("sid", STUDENTS)
def test_sigma0_is_that_of_a_least_squares_fit_with_those_residuals(sid):
    """Build a linear model whose residuals are exactly v; lstsq's residual sum gives σ0."""
    p = parameters_for(BY_ID["bun.sigma0"], sid)
    v = np.array(p["v"])
    rng = np.random.default_rng(0)
    A = rng.normal(size=(p["n"], p["u"]))
    Q, _ = np.linalg.qr(A, mode="complete")
    v_perp = Q[:, p["u"]:] @ (Q[:, p["u"]:].T @ v)           # v orthogonal to the columns
    obs = A @ rng.normal(size=p["u"]) + v_perp
    x, ssq, rank, _ = np.linalg.lstsq(A, obs, rcond=None)
    assert rank == p["u"]
    s0 = math.sqrt(float(ssq[0]) / (p["n"] - p["u"]))
    s0_own = ch10._sigma0(p | {"v": v_perp.tolist()})
    assert s0 == pytest.approx(s0_own, rel=1e-10)
    assert ch10._sigma0(p) == pytest.approx(math.sqrt(v @ v / (p["n"] - p["u"])), rel=1e-12)


def test_redundancy_numbers_sum_by_brute_force():
    """trace(Q_vv P) of a random free-network-like design with a 7-dimensional null space."""
    rng = np.random.default_rng(1)
    n, u, d = 60, 25, 7
    A = rng.normal(size=(n, u - d)) @ rng.normal(size=(u - d, u))   # rank u − d
    Qvv = np.eye(n) - A @ np.linalg.pinv(A.T @ A) @ A.T
    assert np.trace(Qvv) == pytest.approx(n - u + d, abs=1e-9)
    for sid in STUDENTS:
        p = parameters_for(BY_ID["bun.redundancy-sum"], sid)
        options = {s[1]: int(s.split(") ")[1]) for s in p["options"].split("; ")}
        u = 6 * p["images"] + 3 * p["points"]
        assert options[p["correct"]] == p["n"] - u + 7


@pytest.mark.parametrize("sid", STUDENTS)
def test_critical_value_is_scipys(sid):
    p = parameters_for(BY_ID["bun.critical-t"], sid)
    assert ch10._critical(p) == pytest.approx(stats.t.ppf(1 - p["alpha"] / 2, p["dof"]),
                                              rel=1e-10)
    assert ch10._critical(p) > stats.norm.ppf(1 - p["alpha"] / 2)   # p. 90, corrected


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_contribution_sums_to_the_full_normal_matrix(sid):
    ex = BY_ID["bun.normal-contribution"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    cases = ex.cases(rng_for(sid, ex.id, "public"), p)
    A = np.array([a for a, _ in cases])
    P = np.diag([1.0 / s**2 for _, s in cases])
    np.testing.assert_allclose(sum(f(a, s) for a, s in cases), A.T @ P @ A, rtol=1e-12)


def test_critical_hint_names_the_erratum():
    ex = BY_ID["bun.critical-t"]
    sid = STUDENTS[0]
    p = parameters_for(ex, sid)
    verdict = _judge(ex, sid, stats.norm.ppf(1 - p["alpha"] / 2))
    assert verdict.mistake == "erratum" and "luhmann:p90-t-distribution" in verdict.message



# -- fairness and hints of the audit --------------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_sigma0_accepts_three_decimals(sid):
    ex = BY_ID["bun.sigma0"]
    p = parameters_for(ex, sid)
    v = np.array(p["v"])
    s0 = math.sqrt(v @ v / (p["n"] - p["u"]))
    assert _judge(ex, sid, round(s0, 3)).status == "correct"
    assert _judge(ex, sid, round(math.sqrt(v @ v / p["n"]), 3)).mistake == "divisor"


def test_redundancy_sum_options_are_all_different():
    ex = BY_ID["bun.redundancy-sum"]
    for i in range(1000):
        options = parameters_for(ex, f"s{i}")["options"].split("; ")
        values = [o.split(") ")[1] for o in options]
        assert len(set(values)) == 4, (i, options)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_normal_contribution_float32_and_micrometre_hint(sid):
    ex = BY_ID["bun.normal-contribution"]

    def f32(a, sigma):
        a = np.asarray(a, np.float32)
        return np.outer(a, a) / np.float32(sigma) ** 2
    assert _judge(ex, sid, f32).status == "correct"
    verdict = _judge(ex, sid, lambda a, s: np.outer(a, a) / (1000.0 * s) ** 2)
    assert verdict.mistake == "units-um"


# -- the new exercises: references by an independent route ----------------------------------------

def test_tiny_block_design_matrix_is_the_numerical_derivative():
    """A of the tiny blocks against central differences of pl.project in every unknown."""
    import photolib as pl
    rng = np.random.default_rng(3)
    x, A, ell, _ = ch10.tiny_block(rng, points=6, control=3, images=3, noise=False)
    new = np.arange(6) >= 3

    def computed(xv):
        ext = xv[:18].reshape(3, 6)
        pts = np.zeros((6, 3))
        pts[new] = xv[18:].reshape(-1, 3)
        pts[~new] = control
        return np.concatenate([pl.project(pts, e[:3], pl.rotation_opk(*e[3:]), 35.0).ravel()
                               for e in ext])
    # the control points (fixed, not in x): the first draws of the same generator
    rng = np.random.default_rng(3)
    control = np.column_stack([rng.uniform(-5, 5, 6), rng.uniform(-5, 5, 6),
                               rng.uniform(-1.5, 1.5, 6)])[:3]
    h = 1e-6
    numeric = np.column_stack([(computed(x + h * e) - computed(x - h * e)) / (2 * h)
                               for e in np.eye(len(x))])
    np.testing.assert_allclose(numeric, A, rtol=0, atol=1e-6 * np.abs(A).max())


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_gauss_newton_step_is_a_weighted_lstsq(sid):
    ex = BY_ID["bun.gauss-newton-step"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
    for x, A, ell, sigma in cases[:3]:
        dx, *_ = np.linalg.lstsq(A / sigma[:, None], ell / sigma, rcond=None)
        np.testing.assert_allclose(f(x, A, ell, sigma), x + dx, rtol=0, atol=1e-9)
    x, A, ell, sigma = cases[3]                        # the free network
    assert np.linalg.svd(A / sigma[:, None], compute_uv=False)[-7] < 1e-10 * np.abs(A).max()
    with pytest.raises(ValueError, match="singular normal matrix"):
        f(x, A, ell, sigma)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_sigma0_redundancy_by_the_dense_qvv(sid):
    ex = BY_ID["bun.sigma0-redundancy"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
    for A, sigma, v in cases[:3]:
        P = np.diag(1.0 / sigma**2)
        Qvv = np.linalg.inv(P) - A @ np.linalg.pinv(A.T @ P @ A) @ A.T
        n, u = A.shape
        got = f(A, sigma, v)
        assert got[0] == pytest.approx(math.sqrt(v @ P @ v / (n - u)), rel=1e-10)
        np.testing.assert_allclose(got[1:], np.diag(Qvv @ P), rtol=0, atol=1e-9)
        assert got[1:].sum() == pytest.approx(n - u, abs=1e-8)
        assert np.abs(A.T @ P @ v).max() < 1e-6 * np.abs(A.T @ P).max()   # v adjusted
    A, sigma, v = cases[3]
    assert A.shape[0] == A.shape[1]
    with pytest.raises(ValueError, match="redundancy"):
        f(A, sigma, v)


@pytest.mark.parametrize("sid", STUDENTS)
def test_count_scenario_agrees_with_the_derived_block_redundancy(sid):
    steps = [BY_ID[i] for i in ("bun.count-n", "bun.count-u", "bun.count-r")]
    p = parameters_for(steps[0], sid)
    assert all(parameters_for(s, sid) == p for s in steps)
    n, u, r = (s.reference(p) for s in steps)
    assert (n, u) == (p["n"], p["u"])
    assert r == ch10._redundancy(p)                # photolib.derive.adjustment.block_redundancy


@pytest.mark.parametrize("sid", STUDENTS)
def test_snoop_scenario_steps_build_on_each_other(sid):
    s1, s2, s3 = (BY_ID[i] for i in ("bun.snoop-sigma0", "bun.snoop-w", "bun.snoop-tau"))
    p = parameters_for(s1, sid)
    v = np.array(p["v"])
    assert p["s0"] == round(s1.reference(p), 3) == round(math.sqrt(v @ v / (p["n"] - p["u"])), 3)
    assert p["vk"] == p["v"][p["k"] - 1]
    w, tau = s2.reference(p), s3.reference(p)
    assert tau == pytest.approx(w * p["sigma"] / p["s0"], rel=1e-12)
    assert _judge(s2, sid, round(w, 2)).status == "correct"
    assert _judge(s3, sid, round(tau, 2)).status == "correct"
    assert _judge(s2, sid, round(tau, 2)).mistake == "sigma-posteriori"


@pytest.mark.parametrize("ident, digits", [("bun.sigma0", 2), ("bun.snoop-sigma0", 2),
                                           ("bun.snoop-w", 2), ("bun.snoop-tau", 2),
                                           ("bun.critical-t", 3)])
def test_answers_rounded_as_the_statement_asks_are_accepted(ident, digits):
    ex = BY_ID[ident]
    for sid in (f"s{i}" for i in range(150)):
        value = round(ex.reference(parameters_for(ex, sid)), digits)
        assert _judge(ex, sid, value).status == "correct", (sid, value)
