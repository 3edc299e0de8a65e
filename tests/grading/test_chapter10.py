"""The exercises of chapter 10 (bundle adjustment), judged as the grader does.

The same checks as ``test_chapter08.py`` (reference accepted, every declared mistake
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

from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import ch10_bundle_adjustment as ch10
from photolib.grading.exercises import chapter
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for

EXERCISES = ch10.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000000", "s3000001")


def _judge(ex, sid, value):
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def test_module_is_the_registered_chapter():
    assert ch10.CHAPTER == "10-bundle-adjustment"
    assert chapter("10-bundle-adjustment") == EXERCISES
    assert len(EXERCISES) >= 4
    assert {"number", "choice", "function"} <= {ex.kind for ex in EXERCISES}


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_reference_is_accepted(ex, sid):
    verdict = _judge(ex, sid, ex.reference(parameters_for(ex, sid)))
    assert verdict.status == "correct", verdict.message
    assert verdict.points == ex.points


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_each_mistake_is_recognised_with_its_hint(ex):
    assert ex.mistakes, f"{ex.id} declares no mistakes"
    students = [f"s{i:07d}" for i in range(40)]
    for index, mistake in enumerate(ex.mistakes):
        applied = 0
        for sid in students:
            wrong = mistake.wrong(parameters_for(ex, sid))
            if wrong is None:
                continue
            applied += 1
            verdict = _judge(ex, sid, wrong)
            assert verdict.status == "wrong", (ex.id, index, sid)
            assert verdict.mistake == mistake.tag, (ex.id, index, sid, verdict.message)
            assert verdict.message == f"not correct: {mistake.message}", (ex.id, index, sid)
        assert applied, f"{ex.id}: mistake {index} ({mistake.tag}) never applies"


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_students_get_different_variants(ex):
    a, b = (parameters_for(ex, sid) for sid in STUDENTS[:2])
    assert a != b
    assert parameters_for(ex, STUDENTS[0]) == a
    assert ex.statement.format(**a) != ex.statement.format(**b)


def test_hidden_inputs_differ_from_the_public_ones():
    ex = BY_ID["bun.normal-contribution"]
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    hidden = ex.cases(rng_for(STUDENTS[0], ex.id, "hidden"), params)
    assert len(public) == len(hidden) >= 3
    assert not all(np.array_equal(a[0], b[0]) for a, b in zip(public, hidden))


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_untouched_answer_is_not_answered(ex):
    value = (lambda *args: ...) if ex.kind == "function" else ...
    assert _judge(ex, STUDENTS[0], value).status == "not-answered"


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


# -- the notebooks, graded in a process of their own (as tests/grading/test_folders.py) ---------

_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[2:], Limits(timeout=120), jobs=1)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    import pickle
    import subprocess
    import sys

    from .conftest import ROOT

    paths = [ROOT / d / "10-bundle-adjustment.ipynb" for d in ("solutions", "exercises")]
    out = tmp_path_factory.mktemp("ch10") / "graded.pickle"
    proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), *map(str, paths)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out, "rb") as f:
        results = pickle.load(f)
    return {("master" if "solutions" in k else "copy"): v for k, v in results.items()}


def test_master_gets_full_marks(graded):
    r = graded["master"]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total == sum(ex.points for ex in EXERCISES)


def test_untouched_copy_gets_zero(graded):
    r = graded["copy"]
    assert r.status == "no-student-id", r.detail
    assert r.total == 0 and {j.status for j in r.judgements} == {"not-answered"}
    assert r.output.count("not answered yet") == len(EXERCISES)
    assert "Traceback" not in r.output
