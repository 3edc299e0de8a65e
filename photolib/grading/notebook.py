"""Immediate feedback in the student's notebook: :func:`task` and :func:`check`.

Both read ``STUDENT_ID`` and the answer variables from the notebook's namespace. ``check``
judges exactly as the grader does (same decoding, same judge, same hints), but in the
student's own kernel, so it is feedback, not a grade: the grader re-runs the notebook in a
sandbox and judges in its own process. The public test inputs of function exercises differ
from the grader's hidden ones, and no message shows test inputs.
"""

from __future__ import annotations

import sys

from photolib.grading.encode import (NOT_ANSWERED, Unsupported, decode_value,
                                      decoded_or_unsupported, encode_value)
from photolib.grading.exercises import exercise as _exercise
from photolib.grading.judge import FunctionOutputs, judge
from photolib.grading.spec import Params
from photolib.grading.variants import rng_for

__all__ = ["check", "function_outputs", "parameters_for", "reference_outputs", "task"]


def _namespace() -> dict:
    try:
        ip = get_ipython()
        return ip.user_ns
    except NameError:
        return vars(sys.modules["__main__"])


def _student_id(ns: dict) -> str:
    sid = ns.get("STUDENT_ID", "")
    return sid if isinstance(sid, str) else str(sid)


#: what task() and check() say, instead of numbers, while STUDENT_ID is empty
NO_STUDENT_ID = ("STUDENT_ID is empty: set it in the first cell to your student id, then run "
                 "the notebook again (your numbers depend on it; no numbers are issued without it).")


class StudentIdMissing(RuntimeError):
    """Raised by the parameters of a task read while ``STUDENT_ID`` is empty."""


class NoParameters:
    """What :func:`task` returns while ``STUDENT_ID`` is empty: any parameter read raises.

    >>> NoParameters().c_mm
    Traceback (most recent call last):
    ...
    photolib.grading.notebook.StudentIdMissing: STUDENT_ID is empty: ...
    """

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise StudentIdMissing(NO_STUDENT_ID)

    __getitem__ = __getattr__

    def __repr__(self):
        return "NoParameters(STUDENT_ID is empty)"


def parameters_for(exercise, student_id: str) -> Params:
    """The variant of ``exercise`` for ``student_id``."""
    return Params(exercise.parameters(rng_for(student_id, exercise.id)))


def task(exercise_id: str) -> Params | NoParameters:
    """Print the exercise with this student's numbers and return them.

    While ``STUDENT_ID`` is empty it prints one line saying so and issues no numbers: the
    statement is not printed and the returned :class:`NoParameters` raises on any read, so no
    one works on the numbers of the empty id (which are nobody's and graded as nobody's).

    Returns
    -------
    Params
        The parameters, readable as attributes (``p.c_mm``).
    """
    ex = _exercise(exercise_id)
    sid = _student_id(_namespace())
    if not sid.strip():
        print(f"✋ {ex.id}: {NO_STUDENT_ID}")
        return NoParameters()
    params = parameters_for(ex, sid)
    unit = "point" if ex.points == 1 else "points"
    print(f"{ex.id} ({ex.points:g} {unit}) {ex.title}\n{ex.statement.format(**params)}")
    return params


def function_outputs(func, cases) -> FunctionOutputs:
    """Call ``func`` on each argument tuple; outputs as data (encoded then decoded)."""
    outputs = []
    for args in cases:
        try:
            value = func(*args)
        except NotImplementedError:
            value = ...                 # untouched, as the grader's extraction reports it
        except Exception as exc:  # noqa: BLE001 - the student's function may raise anything
            return FunctionOutputs((), f"your function raised {type(exc).__name__}: {exc}")
        outputs.append(decode_value(encode_value(value)))
    return FunctionOutputs(tuple(outputs))


def reference_outputs(cases):
    """``outputs_of`` for :func:`~photolib.grading.judge.judge`: any function on ``cases``."""
    def outputs_of(func):
        return tuple(decode_value(encode_value(func(*args))) for args in cases)
    return outputs_of


def _read(value):
    """``value`` as the grader reads it, including what it makes of an unreadable one.

    The grader turns an answer its encoder or decoder rejects (``sympy.nan``, ``Max(a, b)``,
    an int of 400 digits) into :class:`~photolib.grading.encode.Unsupported` with the reason
    (:func:`photolib.grading.extract.decode_item`), which the judge then calls wrong; ``check``
    says the same, with the same words.
    """
    try:
        data = encode_value(value)
    except Exception as exc:  # noqa: BLE001 - the grader's kernel reports the type only
        return Unsupported(f"unreadable answer (encoding failed with {type(exc).__name__})")
    return decoded_or_unsupported(lambda: decode_value(data))


def check(exercise_id: str) -> None:
    """Judge the current answer of ``exercise_id`` and print one line of feedback.

    While ``STUDENT_ID`` is empty an answer is not judged (it would be judged against the
    numbers of the empty id, which are nobody's): check says so instead.
    """
    try:
        ex = _exercise(exercise_id)
    except KeyError as exc:
        print(f"check: {exc.args[0]}")
        return
    ns = _namespace()
    sid = _student_id(ns)
    params = parameters_for(ex, sid)
    value = ns.get(ex.answer, None)
    outputs_of = None
    if ex.kind == "function":
        if not callable(value):
            answer = NOT_ANSWERED
        else:
            cases = ex.cases(rng_for(sid, ex.id, "public"), params)
            answer = function_outputs(value, cases)
            outputs_of = reference_outputs(cases)
    else:
        answer = _read(value)
    verdict = judge(ex, params, answer, outputs_of)
    if not sid.strip() and verdict.status != "not-answered":    # judged against nobody's numbers
        print(f"✋ {ex.id}: {NO_STUDENT_ID}")
        return
    mark = {"correct": "✔", "not-answered": "…"}.get(verdict.status, "✘")
    print(f"{mark} {ex.id}: {verdict.message}")
