"""The exercises of chapter 12 (products), judged as the grader does.

The checks of ``test_chapter08.py`` (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), the master graded to full marks and the untouched copy to zero by the real
grader, and the references by an independent route: ``cv2.projectPoints`` for the image
points, and SymPy (:mod:`photolib.derive.products`) or a ray intersection by hand for the
numbers.
"""

from __future__ import annotations

import math
import pickle
import subprocess
import sys

import cv2
import numpy as np
import pytest
import sympy as sp

import photolib as pl
from photolib.derive import products as dp
from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import ch12_products as ch12
from photolib.grading.exercises import chapter
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for

from .conftest import ROOT

EXERCISES = ch12.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")
MANY = tuple(f"s{i:07d}" for i in range(40))


def _judge(ex, sid, value):
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def test_module_is_the_registered_chapter():
    assert ch12.CHAPTER == "12-products"
    assert chapter("12-products") == EXERCISES
    assert len(EXERCISES) >= 4
    assert {"number", "function", "choice"} <= {ex.kind for ex in EXERCISES}


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_reference_is_accepted(ex, sid):
    verdict = _judge(ex, sid, ex.reference(parameters_for(ex, sid)))
    assert verdict.status == "correct", verdict.message
    assert verdict.points == ex.points


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_each_mistake_is_recognised_with_its_hint(ex):
    assert ex.mistakes, f"{ex.id} declares no mistakes"
    for index, mistake in enumerate(ex.mistakes):
        applied = 0
        for sid in MANY:
            wrong = mistake.wrong(parameters_for(ex, sid))
            if wrong is None:
                continue
            applied += 1
            verdict = _judge(ex, sid, wrong)
            assert verdict.status == "wrong", (ex.id, index, sid)
            assert verdict.mistake == mistake.tag, (ex.id, index, sid, verdict.message)
            assert verdict.message == f"not correct: {mistake.message}", (ex.id, index, sid)
            if applied >= 4:
                break
        assert applied, f"{ex.id}: mistake {index} ({mistake.tag}) never applies"


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_students_get_different_variants(ex):
    texts = {ex.statement.format(**parameters_for(ex, sid)) for sid in STUDENTS}
    assert len(texts) >= 2
    assert parameters_for(ex, STUDENTS[0]) == parameters_for(ex, STUDENTS[0])


def test_hidden_inputs_differ_from_the_public_ones():
    ex = BY_ID["prd.ortho-to-image"]
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    hidden = ex.cases(rng_for(STUDENTS[0], ex.id, "hidden"), params)
    assert len(public) == len(hidden) >= 3 and public != hidden
    for case in public + hidden:
        assert all(np.ndim(a) == 0 for a in case) and [float(a) for a in case] == list(case)


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_untouched_answer_is_not_answered(ex):
    value = (lambda *args: ...) if ex.kind == "function" else ...
    assert _judge(ex, STUDENTS[0], value).status == "not-answered"


def test_a_slightly_wrong_function_is_wrong_without_a_hint():
    ex = BY_ID["prd.ortho-to-image"]
    f = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], lambda X, Y: f(X, Y) + 0.001)
    assert verdict.status == "wrong" and verdict.mistake == "other"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_relief_reference_is_what_opencv_sees(sid):
    p = parameters_for(BY_ID["prd.relief-displacement"], sid)
    c, H, h, r_top = p["c_mm"], p["H"], p["dh"], p["r_mm"]
    R_g = r_top * (H - h) / c                       # plan distance of the tower
    X = np.array([[R_g, 0.0, 0.0], [R_g, 0.0, h]])
    R_cv, t = np.diag([1.0, -1.0, -1.0]), np.array([0.0, 0.0, H])   # camera at (0, 0, H), nadir
    uv, _ = cv2.projectPoints(X, cv2.Rodrigues(R_cv)[0], t, np.diag([c, c, 1.0]), None)
    r_foot, r_seen = np.hypot(*uv.reshape(-1, 2).T)
    assert math.isclose(r_seen, r_top, rel_tol=1e-9)
    assert math.isclose(ch12._relief(p), r_top - r_foot, rel_tol=1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_ortho_reference_agrees_with_opencv(sid):
    ex = BY_ID["prd.ortho-to-image"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    R = pl.rotation_opk(*np.radians([p["omega_deg"], p["phi_deg"], p["kappa_deg"]]))
    X0 = np.array([p["X0"], p["Y0"], p["Z0"]])
    cases = ex.cases(rng_for(sid, ex.id, "public"), p)
    XYZ = np.array([[X, Y, p["a"] + p["b"] * (X - p["X0"]) + p["d"] * (Y - p["Y0"])]
                    for X, Y in cases])
    R_cv, t = pl.opencv_pose_from_exterior(X0, R)
    uv, _ = cv2.projectPoints(XYZ, cv2.Rodrigues(R_cv)[0], t, np.diag([p["c_mm"], p["c_mm"], 1.0]),
                              None)
    uv = uv.reshape(-1, 2)
    ours = np.array([f(*case) for case in cases])
    np.testing.assert_allclose(ours, np.column_stack([uv[:, 0], -uv[:, 1]]), atol=1e-7)


@pytest.mark.parametrize("sid", STUDENTS)
def test_dtm_accuracy_reference_by_sympy_first_order(sid):
    p = parameters_for(BY_ID["prd.dtm-accuracy"], sid)
    exact, first = dp.ortho_error_from_height_error()
    r_max = math.hypot(*ch12._FORMATS[p["format"]])
    H, h = 2000.0, 300.0                              # any flight: the result does not depend on it
    R_g = r_max * (H - h) / p["c_mm"]               # the ground point at the format corner
    dZ = sp.solve(sp.Eq(first.subs({dp.Rg: R_g, dp.H: H, dp.h: h}), p["tol_m"]), dp.dZ)[0]
    assert math.isclose(ch12._dtm_accuracy(p), float(dZ), rel_tol=1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_occluded_length_by_a_ray_intersection(sid):
    p = parameters_for(BY_ID["prd.occluded-length"], sid)
    C, edge = np.array([0.0, p["H"]]), np.array([p["d"], p["h"]])
    t = C[1] / (C[1] - edge[1])                   # C + t·(edge − C) reaches Z = 0
    end = C + t * (edge - C)
    assert math.isclose(ch12._occluded(p), end[0] - p["d"], rel_tol=1e-9)
    value = dp.occluded_length().subs({dp.d: p["d"], dp.h: p["h"], dp.H: p["H"]})
    assert math.isclose(ch12._occluded(p), float(value), rel_tol=1e-12)


def test_every_product_task_has_a_reference_and_a_distinct_distractor():
    for _task, right, wrong, _ in ch12._TASKS:
        assert right in ch12._PRODUCTS and wrong in ch12._PRODUCTS and right != wrong
    seen = {parameters_for(BY_ID["prd.product"], sid)["i"] for sid in MANY}
    assert seen == set(range(len(ch12._TASKS)))


# -- the notebooks, graded by the real grader -----------------------------------------------------

_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[2:], Limits(timeout=60), jobs=1)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""
MASTER = ROOT / "solutions" / "12-products.ipynb"
COPY = ROOT / "exercises" / "12-products.ipynb"


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    out = tmp_path_factory.mktemp("ch12") / "graded.pickle"
    proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), str(MASTER), str(COPY)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out, "rb") as f:
        return pickle.load(f)


def test_master_gets_full_marks(graded):
    r = graded[str(MASTER)]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total == sum(ex.points for ex in EXERCISES)


def test_untouched_copy_gets_zero(graded):
    r = graded[str(COPY)]
    assert r.status == "no-student-id" and r.detail == ""
    assert r.total == 0 and {j.status for j in r.judgements} == {"not-answered"}
    assert r.output.count("not answered yet") == len(EXERCISES)
