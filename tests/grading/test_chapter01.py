"""The exercises of chapter 01 (what photogrammetry is), judged as the grader does.

The checks of ``test_chapter08.py`` (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), the master graded to full marks and the untouched copy to zero by the batch
grader, and the references by independent routes: ``photolib.project`` for the image scale
and the ground size, counting on a grid of ground points the images that see each point for
the flight plan, and the chapter's history table for the history question.
"""

from __future__ import annotations

import math
import pickle
import subprocess
import sys

import numpy as np
import pytest

import photolib as pl
from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import ch01_introduction as ch01
from photolib.grading.exercises import chapter
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for
from photolib.nb import intro as ni

from .conftest import ROOT

EXERCISES = ch01.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000005", "s3000006")


def _judge(ex, sid, value):
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def test_module_is_the_registered_chapter():
    assert ch01.CHAPTER == "01-introduction"
    assert chapter("01-introduction") == EXERCISES
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
    for index, mistake in enumerate(ex.mistakes):
        applied = 0
        for sid in STUDENTS:
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


@pytest.mark.parametrize("eid", ["int.classes", "int.history"])
def test_choice_variants_do_not_carry_the_answer(eid):
    ex = BY_ID[eid]
    letters = set()
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) <= {"options", "task"}
        letters.add(ex.reference(p))
    assert len(letters) > 1                       # the correct letter moves between students


@pytest.mark.parametrize("ex", [ex for ex in EXERCISES if ex.kind == "function"],
                         ids=lambda ex: ex.id)
def test_hidden_inputs_differ_from_the_public_ones(ex):
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    hidden = ex.cases(rng_for(STUDENTS[0], ex.id, "hidden"), params)
    assert len(public) == len(hidden) >= 3
    assert public != hidden
    for case in public + hidden:
        assert all(np.ndim(arg) == 0 and float(arg) == arg for arg in case)


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_untouched_answer_is_not_answered(ex):
    value = (lambda *args: ...) if ex.kind == "function" else ...
    assert _judge(ex, STUDENTS[0], value).status == "not-answered"


def test_a_slightly_wrong_scale_number_is_wrong_without_a_hint():
    ex = BY_ID["int.scale-number"]
    ref = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], ref * 1.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_scale_number_is_ground_length_over_image_length(sid):
    p = parameters_for(BY_ID["int.scale-number"], sid)
    xy = pl.project([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]], [0.0, 0.0, p["h_m"]], np.eye(3),
                    p["c_mm"])
    image_length_m = (xy[1, 0] - xy[0, 0]) / 1000
    assert math.isclose(ch01._scale_number(p), 100.0 / image_length_m, rel_tol=1e-10)


def _stereo_cover_count(p):
    """Images needed, found by growing the plan until a grid of ground points is covered."""
    gsd = p["pixel_um"] * 1e-3 * p["h_m"] / p["c_mm"]
    S_al, S_ac = p["n_along"] * gsd, p["n_across"] * gsd
    B, A = S_al * (1 - p["overlap_pct"] / 100), S_ac * (1 - p["sidelap_pct"] / 100)
    L, W = p["length_km"] * 1e3, p["width_km"] * 1e3
    x, y = np.linspace(0.0, L, 400), np.linspace(0.0, W, 200)
    # images along a strip, the first stereo model starting at x = 0: add until ≥ 2 see all
    n = 2
    while True:
        cx = S_al / 2 - B + B * np.arange(n)
        if np.all((np.abs(x[:, None] - cx) <= S_al / 2 + 1e-6).sum(axis=1) >= 2):
            break
        n += 1
    k = 1
    while True:
        cy = S_ac / 2 + A * np.arange(k)
        if np.all((np.abs(y[:, None] - cy) <= S_ac / 2 + 1e-6).sum(axis=1) >= 1):
            break
        k += 1
    return float(n * k)


@pytest.mark.parametrize("sid", STUDENTS)
def test_images_reference_by_counting_the_cover(sid):
    p = parameters_for(BY_ID["int.images"], sid)
    assert ch01._images(p) == _stereo_cover_count(p) == ch01._by_hand(p)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_ground_size_reference_by_the_library_footprint(sid):
    ex = BY_ID["int.ground-size"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    n = 1000                                     # any pixel count: pitch = format / n
    for (H,) in ex.cases(rng_for(sid, ex.id, "public"), p):
        F = pl.footprint(n, n, p["format_mm"] / n, p["c_mm"], [0.0, 0.0, H])
        assert math.isclose(f(H), F[1, 0] - F[0, 0], rel_tol=1e-10)


def test_history_answer_is_the_chapter_history():
    year_city = {event[0]: event[2] for event in ni.HISTORY}
    assert "Vienna" in year_city[1910] and "ISP" in year_city[1910]
    assert "Meydenbauer" in year_city[1858] and "word" in year_city[1867]
    ex = BY_ID["int.history"]
    p = parameters_for(ex, STUDENTS[0])
    assert f"({ex.reference(p)}) 1910 in Vienna" in p["options"]


@pytest.mark.parametrize("sid", STUDENTS)
def test_classes_reference_matches_the_number_of_images_in_the_task(sid):
    ex = BY_ID["int.classes"]
    p = parameters_for(ex, sid)
    chosen = next(item[4:] for item in p["options"].split("; ") if item[1] == ex.reference(p))
    if "one photograph" in p["task"]:
        assert chosen.startswith("single-image")
    elif "pairs" in p["task"]:
        assert chosen.startswith("stereo")
    else:
        assert "40" in p["task"] and chosen.startswith("multi-image")


# -- the notebooks, graded by the batch grader ----------------------------------------------------

_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[2:], Limits(timeout=60), jobs=1)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    out = tmp_path_factory.mktemp("ch01") / "graded.pickle"
    paths = [str(ROOT / "solutions" / "01-introduction.ipynb"),
             str(ROOT / "exercises" / "01-introduction.ipynb")]
    proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), *paths],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out, "rb") as f:
        return pickle.load(f)


def test_master_gets_full_marks(graded):
    r = graded[str(ROOT / "solutions" / "01-introduction.ipynb")]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total == sum(ex.points for ex in EXERCISES)


def test_untouched_copy_gets_zero(graded):
    r = graded[str(ROOT / "exercises" / "01-introduction.ipynb")]
    assert r.status == "no-student-id", r.detail
    assert r.total == 0 and {j.status for j in r.judgements} == {"not-answered"}
    assert r.output.count("not answered yet") == len(EXERCISES)
