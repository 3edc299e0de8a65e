"""Scan of the tolerance policy of docs/instructors.md over every numeric exercise part.

Two kinds of answers that a careful student may give must be accepted:

* **float32 work**: every input rounded to float32 (parameters and, for functions, the test
  inputs), the result rounded to float32 and then moved by :data:`FLOAT32_SLACK` units of
  float32 round-off (``2**-24`` relative) in either direction for the arithmetic in between;
* **the printed inputs' rounding**: each float input the statement prints, moved by half a
  unit of its last printed digit (one input at a time, both directions), with the answer
  recomputed by the exercise's own reference from the moved inputs.

How an input is printed is read from the statement as the student sees it (the statement's
format fields filled with the variant), independently of the exercise's tolerance code:
a float field gives its text, a list field its elements, and a float (or list element) that is
not a field of its own is looked up among the numbers of the statement's text fields (a matrix
or a list of points printed as text). Integers are counts (pixels, observations, grey values)
and exact; a float the statement does not print (data handed over only as ``p.name``) is exact
too.
"""

from __future__ import annotations

import re
import string

import numpy as np

from photolib.grading.encode import decode_value, encode_value
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.spec import Params
from photolib.grading.variants import rng_for

#: units of float32 round-off (relative 2**-24 each) allowed for the arithmetic between the
#: float32 inputs and the float32 result
FLOAT32_SLACK = 4
EPS32 = 2.0 ** -24
NUMERIC_KINDS = ("number", "array", "rotation", "function")

_NUMBER = re.compile(r"(?<![\w.])[-−]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w])")


def half_unit(text: str) -> float:
    """Half a unit of the last digit of a printed number: ``"12.30"`` → 0.005, ``"1.7e-06"``
    → 5e-08, ``"45"`` → 0.5."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def _is_float(value) -> bool:
    return isinstance(value, float)


def _flat_floats(value):
    """``(index, element)`` of the float elements of a (nested) list, in reading order."""
    array = np.asarray(value, dtype=object)
    return [(index, array[index]) for index in np.ndindex(array.shape)
            if _is_float(array[index])]


def printed_inputs(ex, params) -> list:
    """``(name, index, half_unit, text)`` of every float input as the statement prints it.

    ``index`` is ``None`` for a scalar parameter, else the element's index in its list.
    """
    fields = [(name, spec) for _, name, spec, _ in string.Formatter().parse(ex.statement)
              if name]
    found, pool = {}, []
    for name, spec in fields:
        value = params[name]
        text = format(value, spec or "")
        if name in ex.exact or isinstance(value, bool) or isinstance(value, int):
            continue
        if _is_float(value):
            found[(name, None)] = text
        elif isinstance(value, str):
            pool.extend(m.group().replace("−", "-") for m in _NUMBER.finditer(text))
        elif isinstance(value, (list, tuple, np.ndarray)):
            numbers = [m.group() for m in _NUMBER.finditer(text)]
            elements = _flat_floats(value)
            if len(numbers) == int(np.size(np.asarray(value, dtype=object))):
                flat = list(np.ndindex(np.shape(np.asarray(value, dtype=object))))
                floats = {i for i, _ in elements}
                for index, number in zip(flat, numbers):
                    if index in floats:
                        found[(name, index)] = number
    used = [False] * len(pool)
    printed_names = {name for name, _ in fields}
    for name, value in params.items():
        if name in printed_names or name in ex.exact:
            continue
        items = ([(None, value)] if _is_float(value)
                 else _flat_floats(value) if isinstance(value, (list, tuple)) else [])
        for index, element in items:
            for k, text in enumerate(pool):
                if not used[k] and abs(float(text) - element) <= half_unit(text) * (1 + 1e-9):
                    used[k] = True
                    found[(name, index)] = text
                    break
    return [(name, index, half_unit(text), text) for (name, index), text in found.items()]


def moved(params, name, index, delta):
    """A copy of ``params`` with one input (``index`` None) or one list element moved."""
    changed = Params(params)
    if index is None:
        changed[name] = params[name] + delta
    else:
        array = np.array(params[name], dtype=float)
        array[index] += delta
        changed[name] = array.tolist()
    return changed


def _to_float32(value):
    if isinstance(value, bool) or isinstance(value, (int, str)) or value is None:
        return value
    if isinstance(value, float):
        return float(np.float32(value))
    if isinstance(value, (list, tuple)):
        return type(value)(_to_float32(v) for v in value)
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        return value.astype(np.float32).astype(float)
    return value


def float32_params(params):
    """``params`` with every float (and float list element) rounded to float32."""
    return Params({k: _to_float32(v) for k, v in params.items()})


def _float32_result(value, factor):
    return np.asarray(np.asarray(value, float).astype(np.float32), float) * factor


def judge_answer(ex, sid, params, answer):
    """The grader's verdict on ``answer`` (a value, or a function) of student ``sid``."""
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(answer, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(answer)))


def _as_answer(ex, value):
    value = np.asarray(value, float)
    return float(value) if ex.kind == "number" else value


def integral(ex, params) -> bool:
    """Is the answer a count (every entry a whole number)? A count computed in float32 is
    exact, and a neighbouring count is another answer, so neither the float32 slack nor the
    rounding of the inputs applies to it."""
    if ex.kind == "function":
        return False
    value = np.asarray(ex.reference(params), float)
    return bool(np.all(value == np.round(value)))


def float32_answers(ex, params):
    """``(label, answer)``: float32 work on this variant, result moved up and down."""
    p32 = float32_params(params)
    out = []
    slack = 0 if integral(ex, params) else FLOAT32_SLACK
    for sign in (1.0, -1.0):
        factor = 1.0 + sign * slack * EPS32
        if ex.kind == "function":
            f = ex.reference(p32)

            def answer(*args, f=f, factor=factor):
                return _float32_result(f(*[_to_float32(np.asarray(a, float)) if np.ndim(a)
                                           else float(np.float32(a)) for a in args]), factor)
        else:
            answer = _as_answer(ex, _float32_result(ex.reference(p32), factor))
        out.append((f"float32 work, result x (1 {'+' if sign > 0 else '-'} "
                    f"{slack}*2^-24)", answer))
    return out


def rounding_answers(ex, params):
    """``(label, answer)``: the reference from each printed input moved by ± half a unit."""
    out = []
    if integral(ex, params):
        return out
    for name, index, half, text in printed_inputs(ex, params):
        for sign in (1.0, -1.0):
            changed = moved(params, name, index, sign * half)
            where = name if index is None else f"{name}[{', '.join(map(str, index))}]"
            label = f"{where} = {text} {'+' if sign > 0 else '-'} {half:.3g}"
            try:
                value = ex.reference(changed)
            except Exception as exc:  # noqa: BLE001 - reported as a failure below
                out.append((label, exc))
                continue
            out.append((label, value if ex.kind == "function" else _as_answer(ex, value)))
    return out


def _show(ex, answer):
    if callable(answer):
        return "a function (the reference of the moved inputs)"
    if isinstance(answer, Exception):
        return f"the reference raised {type(answer).__name__}: {answer}"
    return np.array2string(np.asarray(answer, float), precision=12, separator=", ")


def audit(ex, students, which=("float32", "rounding")):
    """Failures ``"exercise, variant: label: answer -> verdict"`` over ``students``."""
    failures = []
    for sid in students:
        params = parameters_for(ex, sid)
        answers = []
        if "float32" in which:
            answers += float32_answers(ex, params)
        if "rounding" in which:
            answers += rounding_answers(ex, params)
        for label, answer in answers:
            if isinstance(answer, Exception):
                failures.append(f"{ex.id}, variant {sid}: {label}: {_show(ex, answer)}")
                continue
            verdict = judge_answer(ex, sid, params, answer)
            if verdict.status != "correct":
                failures.append(f"{ex.id}, variant {sid}: {label}: {_show(ex, answer)} -> "
                                f"{verdict.message}")
    return failures


def numeric_exercises():
    from photolib.grading.exercises import chapters
    return [ex for exs in chapters().values() for ex in exs if ex.kind in NUMERIC_KINDS]

