"""Counting the distinct variants of an exercise: what the student sees and the correct answer.

A variant is what one student id draws. Two variants are the same to a student when the
statement reads the same, and the same to the grader when the correct answer is the same; an
exercise has as many distinct variants as the smaller of the two counts (a statement that
varies in numbers the answer does not depend on, such as a function of its arguments alone,
still has one answer). Answers are compared as the grader would see them:

* numbers and arrays to ten significant digits (far finer than any tolerance);
* expressions by their SymPy ``srepr``; choices by their key;
* functions by their outputs on the same inputs for every variant (the public test inputs
  drawn for a probe student), so a function that ignores the variant counts once.
"""

from __future__ import annotations

import numpy as np

from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

PROBE = "variant-probe"


def _digits(value) -> str:
    values = np.atleast_1d(np.asarray(value, float)).ravel()
    return ",".join(f"{v:.10g}" for v in values) + f"|{np.shape(value)}"


def _probe_cases(ex):
    return ex.cases(rng_for(PROBE, ex.id, "public"), parameters_for(ex, PROBE))


def answer_key(ex, params, probe_cases=None) -> str:
    """The correct answer of one variant, as a string that is equal for equal answers."""
    value = ex.reference(params)
    if ex.kind in ("number", "array", "rotation"):
        return _digits(value)
    if ex.kind == "expression":
        import sympy as sp
        return sp.srepr(value)
    if ex.kind == "function":
        outputs = []
        for case in probe_cases if probe_cases is not None else _probe_cases(ex):
            try:
                outputs.append(_digits(value(*case)))
            except Exception as exc:  # noqa: BLE001 - a function that refuses the input
                outputs.append(type(exc).__name__)
        return ";".join(outputs)
    return str(value)


def distinct_variants(ex, students, enough=None) -> tuple[int, int, int]:
    """``(distinct variants, distinct statements, distinct answers)`` over ``students``.

    With ``enough`` the count stops once both reach it (the tests only ask "at least 50?").
    Answers are computed once per distinct parameter set (symbolic derivations are slow).
    """
    probe = _probe_cases(ex) if ex.kind == "function" else None
    statements, answers, seen = set(), set(), set()
    for sid in students:
        params = parameters_for(ex, sid)
        key = repr(sorted((k, repr(v)) for k, v in params.items()))
        if key in seen:
            continue
        seen.add(key)
        statements.add(ex.statement.format(**params))
        answers.add(answer_key(ex, params, probe))
        if enough is not None and min(len(statements), len(answers)) >= enough:
            break
    return min(len(statements), len(answers)), len(statements), len(answers)
