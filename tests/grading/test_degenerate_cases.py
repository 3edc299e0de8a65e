"""Function exercises with a degenerate hidden case, where raising ValueError is the answer.

The reference raises ``ValueError`` naming the problem (collinear points here); a student's
function is right on that input only when it raises ``ValueError`` too, in ``check()`` and
in the batch grader's extraction alike, and it is told which way it went wrong otherwise.
"""

from __future__ import annotations

import numpy as np
import pytest

from photolib.grading.encode import Raised
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, reference_outputs
from photolib.grading.spec import Exercise, Params

CASES = [((0.0, 0.0), (4.0, 0.0), (0.0, 3.0)),      # a right triangle: area 6
         ((1.0, 1.0), (2.0, 2.0), (3.0, 3.0))]      # collinear: no triangle


def _area(a, b, c):
    """Area of the triangle a, b, c; ValueError for collinear points."""
    a, b, c = (np.asarray(v, float) for v in (a, b, c))
    d = (b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]
    if abs(d) < 1e-12:
        raise ValueError("the three points are collinear")
    return abs(d) / 2


EX = Exercise(id="t.triangle-area", points=1, title="t", kind="function", answer="area",
              statement="", parameters=lambda rng: {}, cases=lambda rng, p: CASES,
              reference=lambda p: _area)


def _no_check(a, b, c):
    a, b, c = (np.asarray(v, float) for v in (a, b, c))
    return abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]) / 2


def _type_error(a, b, c):
    value = _no_check(a, b, c)
    if value == 0:
        raise TypeError("collinear")
    return value


def _verdict(func):
    return judge(EX, Params(), function_outputs(func, CASES), reference_outputs(CASES))


def test_raising_value_error_on_the_degenerate_case_is_right():
    assert reference_outputs(CASES)(_area)[1].value_error
    assert _verdict(_area).correct

    class CollinearError(ValueError):
        pass

    def subclass(a, b, c):
        try:
            return _area(a, b, c)
        except ValueError as exc:
            raise CollinearError(str(exc)) from None
    assert _verdict(subclass).correct


@pytest.mark.parametrize("func, words", [
    (_no_check, "has no answer: your function returned a float instead of raising ValueError"),
    (_type_error, "raised TypeError; raise ValueError"),
    (lambda a, b, c: 1 / 0, "your function raised ZeroDivisionError"),
])
def test_a_wrong_outcome_on_either_case_is_named(func, words):
    verdict = _verdict(func)
    assert not verdict.correct and words in verdict.message
    if func is not _type_error and "ZeroDivision" not in words:
        assert "three points are collinear" in verdict.message


def test_the_grader_extraction_reads_a_raised_error(monkeypatch):
    """The batch grader's kernel code reports each case's error as Raised and goes on."""
    import IPython.display

    from photolib.grading.extract import (
        answer_record,
        build_extraction,
        case_to_json,
        decode_item,
    )
    from photolib.grading.sandbox import RESULT_MIME

    sent = [case_to_json(c) for c in CASES]
    for func, correct in ((_area, True), (_no_check, False), (_type_error, False)):
        code, nonce = build_extraction([{"name": "area", "cases": sent}])
        published = []
        monkeypatch.setattr(IPython.display, "publish_display_data",
                            lambda data, published=published: published.append({"data": data}))
        ns = {"area": func, "STUDENT_ID": "s1"}
        exec(code, {"get_ipython": lambda ns=ns: type("Shell", (), {"user_ns": ns})()})  # noqa: S102
        record = answer_record([d["data"][RESULT_MIME] for d in published], nonce)
        answer = decode_item(EX, record["answers"]["area"])
        assert len(answer.outputs) == 2
        assert isinstance(answer.outputs[1], Raised) == (func is not _no_check)
        verdict = judge(EX, Params(), answer, reference_outputs(CASES))
        assert verdict.correct == correct, verdict.message
