"""What real students type, judged as ``check()`` and the grader judge it.

Each test here comes from a sweep that fed every exercise of every chapter the answers students
actually give (the reference, rounded, float32, lists, other shapes, None, NaN, strings, the
recognised mistakes, a neighbour's answer) and read the message. The judge is called directly
(no kernel): :func:`judge_as_grader` decodes and judges like the batch grader; ``check`` is run
on a namespace of its own.
"""

from __future__ import annotations

import contextlib
import io
import sys

import numpy as np
import pytest

from photolib.grading.exercises import chapters
from photolib.grading.notebook import check, parameters_for

from .chapter_checks import judge_as_grader

ALL = [ex for exs in chapters().values() for ex in exs]
STUDENTS = ("s1000001", "s2345678")


def _by_kind(*kinds):
    return [ex for ex in ALL if ex.kind in kinds]


def _ids(ex):
    return ex.id


def _as_float32(ex, reference):
    """The reference computed by a student who works in float32 (inputs and result)."""
    if ex.kind != "function":
        return np.asarray(reference, np.float32)

    def func(*args):
        return np.asarray(reference(*[np.asarray(a, np.float32) for a in args]), np.float32)
    return func


def run_check(ex, sid, value) -> str:
    """What ``check(ex.id)`` prints when the answer variable holds ``value``."""
    ns = vars(sys.modules["__main__"])
    saved = {k: ns[k] for k in ("STUDENT_ID", ex.answer) if k in ns}
    ns["STUDENT_ID"], ns[ex.answer] = sid, value
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            check(ex.id)
    finally:
        for k in ("STUDENT_ID", ex.answer):
            ns.pop(k, None)
        ns.update(saved)
    return out.getvalue().strip()


# -- float32 -----------------------------------------------------------------------------------

@pytest.mark.parametrize("ex", _by_kind("number", "array", "rotation", "function"), ids=_ids)
@pytest.mark.parametrize("sid", STUDENTS)
def test_a_float32_answer_is_accepted(ex, sid):
    # the policy of docs/instructors.md: tolerances never tighter than float32 (relative ~1e-6);
    # demo.scale-function, dig.gsd-function, st.height and st.intersection (rtol 1e-9),
    # col.ground-point and plane.helmert-angle (rtol 0, atol 1e-6 on values of 1e3 m and
    # 400 gon) and plane.bilinear-function (rtol 1e-12) rejected a float32 result
    reference = ex.reference(parameters_for(ex, sid))
    verdict = judge_as_grader(ex, sid, _as_float32(ex, reference))
    assert verdict.status == "correct", verdict.message
    assert run_check(ex, sid, _as_float32(ex, reference)) == f"✔ {ex.id}: correct"
