"""The exercises of chapters 04-06, judged in this process by calling the registry directly.

For every exercise: the reference answer is accepted, the wrong answer of every declared
mistake is recognised with that mistake's hint, and students get different variants.
Answers travel through :func:`encode_value`/:func:`decode_value` as they do from a kernel.
"""

from __future__ import annotations

import numpy as np
import pytest

from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import (ch04_rotations, ch05_interior_orientation,
                                        ch06_collinearity, chapter)
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for

MODULES = {"04-rotations": ch04_rotations,
           "05-interior-orientation": ch05_interior_orientation,
           "06-collinearity": ch06_collinearity}
EXERCISES = [ex for module in MODULES.values() for ex in module.EXERCISES]
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


def _judge(ex, sid, value):
    """Judge ``value`` (an answer, or a function) for student ``sid`` as the grader does."""
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def test_modules_are_the_registered_chapters():
    for name, module in MODULES.items():
        assert module.CHAPTER == name
        assert chapter(name) == module.EXERCISES
        assert len(module.EXERCISES) >= 4
        kinds = {ex.kind for ex in module.EXERCISES}
        assert "expression" in kinds and "function" in kinds, name


def test_every_answer_kind_is_used():
    kinds = {ex.kind for ex in EXERCISES}
    assert {"number", "array", "rotation", "expression", "function"} <= kinds


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_reference_is_accepted(ex, sid):
    value = ex.reference(parameters_for(ex, sid))
    verdict = _judge(ex, sid, value)
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
    assert parameters_for(ex, STUDENTS[0]) == a  # and the same student the same numbers
    assert ex.statement.format(**a) != ex.statement.format(**b)


@pytest.mark.parametrize("ex", [ex for ex in EXERCISES if ex.kind == "function"],
                         ids=lambda ex: ex.id)
def test_hidden_inputs_differ_from_the_public_ones(ex):
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    hidden = ex.cases(rng_for(STUDENTS[0], ex.id, "hidden"), params)
    assert len(public) == len(hidden) >= 3
    assert not all(np.array_equal(np.asarray(a[0]), np.asarray(b[0]))
                   for a, b in zip(public, hidden))


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_untouched_answer_is_not_answered(ex):
    value = (lambda *args: ...) if ex.kind == "function" else ...
    assert _judge(ex, STUDENTS[0], value).status == "not-answered"


@pytest.mark.parametrize("ex", [ex for ex in EXERCISES if ex.kind == "function"],
                         ids=lambda ex: ex.id)
def test_function_cases_are_scalar_arguments(ex):
    # the batch grader sends each argument to the kernel as one float
    params = parameters_for(ex, STUDENTS[0])
    for purpose in ("public", "hidden"):
        for case in ex.cases(rng_for(STUDENTS[0], ex.id, purpose), params):
            assert all(np.ndim(arg) == 0 for arg in case)
            assert [float(a) for a in case] == list(case)
