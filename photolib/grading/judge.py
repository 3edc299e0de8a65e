"""Judging a decoded answer against the reference, by answer kind, in the grader's process.

>>> from photolib.grading.spec import Exercise, Params
>>> ex = Exercise(id="demo.half", points=2, title="", statement="", kind="number",
...               answer="half", parameters=lambda rng: {"a": 3.0},
...               reference=lambda p: p["a"] / 2, rtol=1e-3)
>>> judge(ex, Params(a=3.0), 1.5).status
'correct'
>>> judge(ex, Params(a=3.0), 1500.0).mistake
'units-mm-m'
"""

from __future__ import annotations

import math
import re
import string
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from photolib.grading.encode import NONE, NOT_ANSWERED, Raised, Unsupported, unanswered
from photolib.grading.hints import MESSAGES, generic_mistakes

__all__ = ["COMPARATORS", "Comparison", "FunctionOutputs", "Judgement", "compare", "judge", "printed_half_units",
           "printed_tolerance", "propagated_atol", "rounding_tolerance"]


@dataclass(frozen=True)
class Judgement:
    """Verdict on one answer.

    ``status`` is ``"correct"``, ``"wrong"``, ``"not-answered"`` or ``"not-graded"`` (the
    notebook has no usable student id, hence no variant of its own); ``mistake`` is the tag
    of a recognised mistake (or ``None``); ``message`` is what the student reads.
    """

    exercise_id: str
    status: str
    points: float
    max_points: float
    message: str
    mistake: str | None = None

    @property
    def correct(self) -> bool:
        return self.status == "correct"


@dataclass(frozen=True)
class FunctionOutputs:
    """What a student function returned on the test inputs: decoded values, or an error."""

    outputs: tuple
    error: str | None = None


def propagated_atol(reference, params: dict, half_units: dict, floor: float = 1e-12):
    """Absolute tolerance from rounding the inputs: ``Σ |∂f/∂p|·Δp`` by central differences.

    Parameters
    ----------
    reference : callable
        ``reference(params)`` returning a number or an array of numbers.
    params : dict
    half_units : dict
        Parameter name -> half of its last printed digit (``0.005`` for a value printed to 0.01).
        A parameter that is a list or array (e.g. point coordinates) has every element
        rounded alike: each element is perturbed on its own and contributes its own term.
        For such a parameter the half unit may also be an array of its shape, one per
        element (0 for an element that is exact).
    floor : float
        Smallest tolerance returned.

    Returns
    -------
    float or ndarray
        A float for a number-valued reference; for an array-valued one an array of the
        reference's shape, one tolerance per entry (``judge`` compares entry by entry).

    >>> round(propagated_atol(lambda p: p["h"] / p["c"], {"h": 1000.0, "c": 0.1}, {"h": 0.5}), 6)
    5.0
    >>> propagated_atol(lambda p: 2.0 * np.asarray(p["xy"]), {"xy": [1.0, 2.0]}, {"xy": 0.5})
    array([1., 1.])
    """
    def evaluate(changed):
        return np.asarray(reference(changed), dtype=float)

    total = np.zeros_like(evaluate(params))
    for name, du in half_units.items():
        value = params[name]
        if np.ndim(value) == 0:
            up, down = dict(params), dict(params)
            up[name] = value + du
            down[name] = value - du
            total = total + np.abs(evaluate(up) - evaluate(down)) / 2.0
            continue
        base = np.asarray(value, dtype=float)
        steps = np.broadcast_to(np.asarray(du, dtype=float), base.shape)
        for index in np.ndindex(base.shape):
            if not steps[index]:
                continue
            shifted = []
            for sign in (1.0, -1.0):
                element = base.copy()
                element[index] += sign * steps[index]
                changed = dict(params)
                changed[name] = element.tolist() if isinstance(value, list) else element
                shifted.append(evaluate(changed))
            total = total + np.abs(shifted[0] - shifted[1]) / 2.0
    total = np.maximum(total, floor)
    return float(total) if total.ndim == 0 else total


def rounding_tolerance(reference, half_units, rtol=1e-6, mistakes=(), share=0.4, floor=1e-12,
                       margin=1.0):
    """``tolerance`` of an exercise: the rounding of the printed inputs, kept off the mistakes.

    The absolute tolerance is :func:`propagated_atol` of the printed
    inputs' last digits (``half_units``), so an answer rounded as precisely as the inputs
    allow is accepted, and ``rtol`` (1e-6) accepts float32 results. Where a recognisable
    mistake lies closer than that (a variant with a tiny effect), the absolute tolerance is
    cut to ``share`` of the distance to the nearest mistake, so the mistake still lands
    outside with its hint. Mistakes that coincide with the reference are ignored. ``floor``
    is the smallest absolute tolerance before that cut (an answer's own rounding).
    ``half_units`` may also be a function of the parameters returning that dict
    (:func:`printed_half_units`). ``margin`` multiplies the propagated part: an input moved by
    a whole half unit reaches the first-order sum exactly, and the second-order term may
    carry it just over.

    >>> tol = rounding_tolerance(lambda p: p["a"] / 3, {"a": 0.005},
    ...                          mistakes=(lambda p: p["a"] / 3 + 1e-4,))
    >>> [round(float(t), 8) for t in tol({"a": 1.0})]
    [1e-06, 4e-05]
    """
    def tolerance(p):
        units = half_units(p) if callable(half_units) else half_units
        atol = margin * propagated_atol(reference, p, units, floor=floor)
        ref = np.asarray(reference(p), float)
        for wrong in mistakes:
            try:
                value = wrong(p)
            except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
                continue
            if value is None or np.shape(value) != ref.shape:
                continue
            gap = float(np.max(np.abs(np.asarray(value, float) - ref)))
            if gap > 1e-12 * (1.0 + float(np.max(np.abs(ref)))):
                atol = np.minimum(atol, share * gap)
        return rtol, atol
    return tolerance


#: relative rounding of a float32 number (half a unit of its 24-bit significand)
FLOAT32_ROUNDING = 2.0 ** -24
#: a printed number: optional sign (also the typographic minus), digits, decimals, exponent
_PRINTED_NUMBER = re.compile(r"(?<![\w.])[-−]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?!\w)")


def _half_unit(text: str) -> float:
    """Half a unit of the last digit of the printed number ``text`` (``"2.50"`` → 0.005)."""
    mantissa, _, exponent = text.lower().partition("e")
    return 0.5 * 10.0 ** (int(exponent or 0) - len(mantissa.partition(".")[2]))


def printed_half_units(statement: str, params, exact=()) -> dict:
    """Half a unit of the last printed digit of every float input, as ``statement`` prints it.

    What the student reads is ``statement.format(**params)``, and Python prints a float by
    its shortest repr: a value drawn to 0.01 as 57.0 reads "57.0" and is good to 0.05 only,
    so the half units come from the text, not from how the value was drawn. A float field
    gives its own text; a list field its elements; a float parameter that is no field (or a
    list printed through a text field, such as a matrix or a list of points) is looked up
    among the numbers of the statement's text fields, in order. Integers are counts and
    exact; so are the names in ``exact`` and floats the statement does not print.

    Each half unit is at least the float32 rounding of the value, so a tolerance built on
    them also accepts inputs kept in float32.

    Returns
    -------
    dict
        Parameter name -> half unit (float), or for a list an array of its shape (0 where an
        element is exact).

    >>> printed_half_units("c = {c} mm, h = {h:.2f} m, n = {n}", {"c": 57.0, "h": 3.0, "n": 4})
    {'c': 0.05, 'h': 0.005}
    >>> printed_half_units("X = {text}", {"X": [1.25, 2.0], "text": "(1.25, 2.00)"})["X"]
    array([0.005, 0.005])
    """
    fields = [(name, spec) for _, name, spec, _ in string.Formatter().parse(statement) if name]
    named = {name for name, _ in fields}
    units, pool = {}, []

    def floor32(value, half):
        return max(half, FLOAT32_ROUNDING * abs(float(value)))

    for name, spec in fields:
        value = params[name]
        if name in exact or isinstance(value, (bool, int)):
            continue
        text = format(value, spec or "")
        if isinstance(value, float):
            units[name] = floor32(value, _half_unit(text))
        elif isinstance(value, str):
            pool.extend(m.group().replace("−", "-") for m in _PRINTED_NUMBER.finditer(text))
        elif isinstance(value, (list, tuple, np.ndarray)):
            cells = np.asarray(value, dtype=object)
            numbers = [m.group() for m in _PRINTED_NUMBER.finditer(text)]
            if len(numbers) != cells.size:
                continue
            half = np.zeros(cells.shape)
            for index, number in zip(np.ndindex(cells.shape), numbers):
                if isinstance(cells[index], float):
                    half[index] = floor32(cells[index], _half_unit(number))
            if np.any(half):
                units[name] = half
    used = [False] * len(pool)

    def lookup(element):
        for k, number in enumerate(pool):
            if not used[k] and abs(float(number) - element) <= _half_unit(number) * (1 + 1e-9):
                used[k] = True
                return floor32(element, _half_unit(number))
        return 0.0

    for name, value in params.items():
        if name in named or name in exact or isinstance(value, (bool, int, str)):
            continue
        if isinstance(value, float):
            half = lookup(value)
            if half:
                units[name] = half
        elif isinstance(value, (list, tuple)):
            cells = np.asarray(value, dtype=object)
            half = np.zeros(cells.shape)
            for index in np.ndindex(cells.shape):
                if isinstance(cells[index], float):
                    half[index] = lookup(cells[index])
            if np.any(half):
                units[name] = half
    return units


#: recently computed PRINTED tolerances: (exercise id, parameters, ...) -> tolerance; one
#: judgement compares an answer with the reference and every mistake, and a check or a batch
#: judges the same variant again, each time re-evaluating the reference per printed input
_PRINTED_CACHE: OrderedDict = OrderedDict()
_PRINTED_CACHE_SIZE = 512


def _cached(key, compute):
    if key in _PRINTED_CACHE:
        _PRINTED_CACHE.move_to_end(key)
        return _PRINTED_CACHE[key]
    value = compute()
    _PRINTED_CACHE[key] = value
    if len(_PRINTED_CACHE) > _PRINTED_CACHE_SIZE:
        _PRINTED_CACHE.popitem(last=False)
    return value


def _params_key(params) -> str:
    return repr(sorted((str(k), repr(v)) for k, v in params.items()))


#: a PRINTED tolerance is this many times the first-order sum of the rounding effects: room
#: for the second-order term of an input moved by a whole half unit
PRINTED_MARGIN = 1.1


def _all_mistakes(exercise):
    """The mistakes a ``PRINTED`` tolerance is kept off (hint-only ones left out)."""
    return tuple(m for m in tuple(exercise.mistakes) + generic_mistakes(exercise)
                 if m.shapes_tolerance)


def printed_tolerance(exercise, share=0.4):
    """``tolerance(params)`` of ``Exercise(tolerance=PRINTED)``: the printed inputs' rounding.

    :func:`rounding_tolerance` of :func:`printed_half_units` (the exercise's ``exact``
    parameters left alone), the exercise's ``rtol`` (1e-6 by default: float32) and its
    ``atol`` as the floor, cut to ``share`` of the distance to the nearest declared or
    generic mistake and of the distance between two mistakes with different hints. For a function exercise it returns ``(rtol, atol)`` only: the absolute
    tolerance of each test input is :func:`function_atols`.
    """
    rtol = float(exercise.rtol)
    if exercise.kind == "function":
        return lambda p: (rtol, float(exercise.atol))

    def half_units(p):
        return printed_half_units(exercise.statement, p, exercise.exact)

    mistakes = _all_mistakes(exercise)
    compute = rounding_tolerance(exercise.reference, half_units, rtol=rtol,
                                 mistakes=[m.wrong for m in mistakes],
                                 share=share, floor=float(exercise.atol), margin=PRINTED_MARGIN)

    def apart(p):
        # two declared mistakes with different hints stay apart as well: an answer within
        # the tolerance of one must not match the other first (the generic ones are tried
        # after them and give way)
        r, atol = compute(p)
        if exercise.mistakes:
            atol = np.minimum(atol, share * _hint_gap(exercise.mistakes, p))
        return r, atol

    def tolerance(p):
        return _cached((exercise.id, share, _params_key(p)), lambda: apart(p))
    return tolerance


def _hint_gap(mistakes, params):
    """The smallest distance between the values of two mistakes with different hints
    (mistakes that coincide, or do not apply, are left out); ``inf`` if there is none."""
    values = []
    for mistake in mistakes:
        try:
            value = mistake.wrong(params)
        except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
            continue
        if value is not None and not callable(value):
            values.append((mistake.message, np.asarray(value, float)))
    gap = np.inf
    for i, (text_a, a) in enumerate(values):
        for text_b, b in values[i + 1:]:
            if text_a == text_b or a.shape != b.shape:
                continue
            d = float(np.max(np.abs(a - b)))
            if d > 1e-12 * (1.0 + float(np.max(np.abs(a)))):
                gap = min(gap, d)
    return gap


def function_atols(exercise, params, outputs_of, share=0.4):
    """Absolute tolerances of a function exercise with ``tolerance=PRINTED``, one per input.

    For each test input: what half a unit of each printed digit changes in the reference's
    output (:func:`printed_half_units`, moved one at a time), at least the exercise's
    ``atol``, cut to ``share`` of the distance to each mistake's output on that input.
    """
    base = [_numeric(v) for v in outputs_of(exercise.reference(params))]
    key = (exercise.id, share, _params_key(params), tuple(v.tobytes() for v in base))
    return _cached(key, lambda: _function_atols(exercise, params, outputs_of, share, base))


def _function_atols(exercise, params, outputs_of, share, base):
    total = [np.zeros_like(v) for v in base]
    units = printed_half_units(exercise.statement, params, exercise.exact)
    for name, du in units.items():
        value = params[name]
        indices = [None] if np.ndim(value) == 0 else list(np.ndindex(np.shape(value)))
        for index in indices:
            step = float(du) if index is None else float(np.asarray(du)[index])
            if not step:
                continue
            shifted = []
            for sign in (1.0, -1.0):
                changed = dict(params)
                if index is None:
                    changed[name] = value + sign * step
                else:
                    element = np.array(value, dtype=float)
                    element[index] += sign * step
                    changed[name] = element.tolist()
                shifted.append(outputs_of(exercise.reference(type(params)(changed))))
            for k, (up, down) in enumerate(zip(*shifted)):
                total[k] = total[k] + np.abs(_numeric(up) - _numeric(down)) / 2
    atols = [np.maximum(PRINTED_MARGIN * t, float(exercise.atol)) for t in total]
    for mistake in _all_mistakes(exercise):
        try:
            wrong = mistake.wrong(params)
            values = None if wrong is None else outputs_of(wrong)
        except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
            continue
        if values is None:
            continue
        for k, (value, ref) in enumerate(zip(values, base)):
            value = _numeric(value)
            if value.shape != ref.shape or not np.all(np.isfinite(value)):
                continue
            gap = float(np.max(np.abs(value - ref)))
            if gap > 1e-12 * (1.0 + float(np.max(np.abs(ref)))):
                atols[k] = np.minimum(atols[k], share * gap)
    return [float(a) if a.ndim == 0 else a for a in atols]


def _numeric(value):
    """An output as a float array; a raised error (a degenerate input) as 0, whose tolerance
    is never used (:class:`~photolib.grading.encode.Raised` is judged by its type)."""
    return np.zeros(()) if isinstance(value, Raised) else np.asarray(value, float)


def _numbers_match(answer, expected, rtol, atol) -> bool:
    a, e = np.asarray(answer, float), np.asarray(expected, float)
    if a.shape != e.shape or not np.all(np.isfinite(a)):
        return False
    return bool(np.all(np.abs(a - e) <= atol + rtol * np.abs(e)))


def plain_symbols(expr):
    """``expr`` with every symbol replaced by an assumption-free symbol of the same name.

    Answers reach the judge as JSON trees whose symbols carry no assumptions
    (:mod:`photolib.grading.encode`), so the judge compares both sides by symbol *name*: a
    reference built with ``Symbol("omega", real=True)`` matches a student's ``omega``.

    >>> import sympy as sp
    >>> plain_symbols(sp.Symbol("w", real=True) + 1) == sp.Symbol("w") + 1
    True
    """
    import sympy as sp
    if not isinstance(expr, (sp.Basic, sp.MatrixBase)):
        return expr
    return expr.xreplace({s: sp.Symbol(s.name) for s in expr.free_symbols
                          if isinstance(s, sp.Symbol) and s.assumptions0})


def _expression_verdict(answer, expected, domain=None) -> str:
    """Verdict kind of ``answer == expected`` from :mod:`photolib.symcheck` when present.

    ``domain`` maps symbols to sampling intervals; symbols not in it range over the reals.
    """
    import sympy as sp
    try:
        from photolib.symcheck import equivalent
    except ImportError:
        equivalent = None
    pairs = [(answer, expected)]
    if isinstance(expected, sp.MatrixBase):
        if not isinstance(answer, sp.MatrixBase) or answer.shape != expected.shape:
            return "not-equal"
        pairs = list(zip(answer, expected))
    elif isinstance(answer, sp.MatrixBase):
        return "not-equal"
    kinds = []
    for a, e in pairs:
        if equivalent is not None:
            kinds.append(equivalent(a, e, symbols_domain=domain).kind)
        else:
            kinds.append("equal" if sp.simplify(a - e) == 0 else "not-equal")
    for kind in ("not-equal", "undecided", "equal-under-condition"):
        if kind in kinds:
            return kind
    return "equal"


def _parse_formula(exercise, text: str):
    import sympy as sp

    from photolib.symcheck import parse_expression
    symbols = [sp.Symbol(s) for s in exercise.symbols] or None
    cells = _matrix_cells(text)
    if cells is not None:
        return sp.Matrix([[parse_expression(c, symbols=symbols) for c in row] for row in cells])
    return parse_expression(text, symbols=symbols)


def _matrix_cells(text: str):
    """The cells of a Matrix typed as text, ``"Matrix([[a, b], [c, d]])"``, as source strings.

    ``sympy.Matrix(...)`` and ``sp.Matrix(...)`` too; a flat list is a column, as in SymPy.
    ``None`` for anything else (then the text is one formula). Each cell is later parsed by
    :func:`photolib.symcheck.parse_expression`, without ``eval``.
    """
    import ast
    if len(text) > 20_000 or "Matrix" not in text:
        return None
    try:
        node = ast.parse(text.strip(), mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return None
    if not (isinstance(node, ast.Call) and len(node.args) == 1 and not node.keywords):
        return None
    func = node.func
    named = isinstance(func, ast.Name) and func.id == "Matrix"
    dotted = (isinstance(func, ast.Attribute) and func.attr == "Matrix"
              and isinstance(func.value, ast.Name) and func.value.id in ("sp", "sympy"))
    if not (named or dotted) or not isinstance(node.args[0], (ast.List, ast.Tuple)):
        return None
    rows = node.args[0].elts
    if rows and all(isinstance(r, (ast.List, ast.Tuple)) for r in rows):
        cells = [[ast.unparse(c) for c in r.elts] for r in rows]
    elif not any(isinstance(r, (ast.List, ast.Tuple)) for r in rows):
        cells = [[ast.unparse(c)] for c in rows]
    else:
        return None
    width = {len(r) for r in cells}
    if len(cells) == 0 or len(width) != 1 or 0 in width or len(cells) * width.pop() > 400:
        return None
    return cells


def _as_number(answer):
    """A real SymPy number or a 0-d array as a float; anything else unchanged."""
    if isinstance(answer, np.ndarray) and answer.ndim == 0:
        return float(answer)
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover - SymPy ships with the course
        return answer
    if (isinstance(answer, sp.Basic) and answer.is_number and answer.is_real
            and not answer.free_symbols):
        try:
            return float(answer)
        except (TypeError, ValueError, OverflowError):
            return answer
    return answer


def _numeric_matrix(answer, expected_ndim: int):
    """A numeric ``sympy.Matrix`` as a float array; anything else unchanged.

    Answers to array and rotation exercises may be built with SymPy (chapter 04 derives R
    symbolically and substitutes the angles): the kernel encodes a Matrix as a matrix of
    expression trees (:func:`photolib.grading.encode.encode_value`, which cannot know the
    exercise's kind), so the conversion happens here, for ``check()`` and the batch grader
    alike. A SymPy matrix is always 2-D; one row or one column answers a 1-D array. A matrix
    with free symbols, or with complex entries, is returned as it is and judged a type error.
    """
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover - SymPy ships with the course
        return answer
    if not isinstance(answer, sp.MatrixBase) or answer.free_symbols:
        return answer
    try:
        values = np.asarray(answer.evalf(), dtype=float)
    except (TypeError, ValueError, OverflowError):
        return answer
    if expected_ndim == 1 and 1 in values.shape:
        values = values.ravel()
    return values


@dataclass(frozen=True)
class Comparison:
    """One comparison of an answer with a value: the verdict, the gradebook tag of a wrong
    answer and the reason the student reads, decided together by the comparator.

    It unpacks as ``ok, reason`` (the form :func:`compare` always returned).

    >>> ok, reason = Comparison(False, "shape", "expected shape (3,), got (2,)")
    >>> ok, reason
    (False, 'expected shape (3,), got (2,)')
    """

    ok: bool
    tag: str = "other"
    message: str = ""

    def __iter__(self):
        return iter((self.ok, self.message))


_SAME = Comparison(True, "", "")


def _wrong(tag: str, message: str = "") -> Comparison:
    return Comparison(False, tag, message)


def _match(ok: bool) -> Comparison:
    return _SAME if ok else _wrong("other")


def _compare_number(exercise, answer, expected, rtol, atol) -> Comparison:
    answer = _as_number(answer)
    if not isinstance(answer, float):
        return _wrong("type", f"expected a number, got {_describe(answer)}")
    return _match(_numbers_match(answer, expected, rtol, atol))


def _compare_array(exercise, answer, expected, rtol, atol) -> Comparison:
    answer = _numeric_matrix(answer, np.ndim(expected))
    if not isinstance(answer, np.ndarray):
        return _wrong("type", f"expected an array, got {_describe(answer)}")
    expected = np.asarray(expected, float)
    if answer.shape != expected.shape:
        return _wrong("shape", f"expected shape {expected.shape}, got {answer.shape}")
    if not np.all(np.isfinite(answer)):
        return _wrong("other", "the array contains NaN or infinity")
    if exercise.kind == "rotation":
        n = answer.shape[0]
        err = float(np.max(np.abs(answer.T @ answer - np.eye(n))))
        if err > 1e-6:
            return _wrong("not-orthonormal", f"not a rotation matrix: max |RᵀR − I| = {err:.2g}")
        if np.linalg.det(answer) < 0:
            return _wrong("reflection", "det R = −1: a reflection, not a rotation")
    return _match(_numbers_match(answer, expected, rtol, atol))


def _compare_expression(exercise, answer, expected, rtol, atol) -> Comparison:
    import sympy as sp
    if isinstance(answer, str):
        answer = _parse_formula(exercise, answer)
    if not isinstance(answer, (sp.Basic, sp.MatrixBase, float)):
        return _wrong("type", f"expected a SymPy expression, got {_describe(answer)}")
    if isinstance(answer, float):
        answer = sp.Float(answer)
    if answer.has(sp.nan, sp.zoo, sp.oo, sp.S.NegativeInfinity):
        # not for symcheck, which calls such a comparison undecided (instructor's note)
        return _wrong("other", "the expression is not finite (NaN or infinity: a division by "
                               "zero?)")
    positive = {sp.Symbol(name): (0.2, 3.0) for name in exercise.positive}
    verdict = _expression_verdict(plain_symbols(answer), plain_symbols(expected), positive)
    if verdict == "undecided":
        return _wrong("undecided",
                      "equivalence could not be decided; the instructor will look at it")
    if verdict == "equal-under-condition":
        names = ", ".join(s for s in exercise.symbols if s not in exercise.positive)
        return _wrong("sign-domain", "equal only when the symbols are positive, but "
                      + (names or "the symbols") + " may be negative here")
    return _match(verdict == "equal")


def _compare_output(got, want, rtol, atol) -> Comparison | None:
    """One test input of a function answer; ``None`` when it is right."""
    if isinstance(want, Raised):      # a degenerate input: the answer is an error
        if isinstance(got, Raised) and got.value_error:
            return None
        if isinstance(got, Raised):
            return _wrong("raised", f"for a degenerate input ({want.message}) your function "
                                    f"raised {got.type_name}; raise ValueError saying what is "
                                    f"wrong with the input")
        return _wrong("degenerate", f"a degenerate input ({want.message}) has no answer: "
                                    f"your function returned {_describe(got)} instead of "
                                    f"raising ValueError")
    if isinstance(got, Raised):
        return _wrong("raised", f"your function raised {got.type_name}: {got.message}")
    if got is NONE:
        return _wrong("type", "the function returned None: is its return statement missing?")
    if got is NOT_ANSWERED or isinstance(got, (str, bool, Unsupported, list)):
        return _wrong("type", f"the function returned {_describe(got)}")
    # a SymPy number or numeric Matrix is read as for number and array answers
    got = _numeric_matrix(_as_number(got), np.ndim(want))
    if not isinstance(got, (float, np.ndarray)):
        return _wrong("type", f"the function returned {_describe(got)}")
    if np.shape(got) != np.shape(want):
        return _wrong("shape", f"the function returned shape {np.shape(got)}, "
                               f"expected shape {np.shape(want)}")
    if not _numbers_match(got, want, rtol, atol):
        return _wrong("other")
    return None


def _compare_function(exercise, answer, expected, rtol, atol) -> Comparison:
    if not isinstance(answer, FunctionOutputs):
        return _wrong("type", "expected a function")
    if answer.error:
        # the kernel side reports what went wrong as text: "your function raised …", a time
        # limit, an unreadable value
        tag = "raised" if answer.error.startswith("your function raised") else "other"
        return _wrong(tag, answer.error)
    if len(answer.outputs) != len(expected):
        return _wrong("other", "the function did not answer every test input")
    per_input = atol if isinstance(atol, list) else [atol] * len(expected)
    for got, want, atol_k in zip(answer.outputs, expected, per_input):
        wrong = _compare_output(got, want, rtol, atol_k)
        if wrong is not None:
            return wrong
    return _SAME


def _compare_choice(exercise, answer, expected, rtol, atol) -> Comparison:
    if not isinstance(answer, str):
        return _wrong("type", f"expected an option key such as 'a', got {_describe(answer)}")
    # "b", "B", "(b)", "b)", "b." and "'b'" (quotes typed inside the string) are all b
    key = answer.strip().lower().strip("()[].:'\" \t")
    if key not in {str(k).lower() for k in exercise.choices}:
        return _wrong("type", "expected the letter of one option, such as 'a'")
    return _match(key == str(expected).lower())


#: one comparator per answer kind: ``(exercise, answer, expected, rtol, atol) → Comparison``
COMPARATORS = {
    "number": _compare_number,
    "array": _compare_array,
    "rotation": _compare_array,
    "expression": _compare_expression,
    "function": _compare_function,
    "choice": _compare_choice,
}


def compare(exercise, answer, expected, params, tolerances=None) -> Comparison:
    """Does ``answer`` equal ``expected`` for this exercise's kind? A :class:`Comparison`
    (unpacks as ``ok, reason``) from the kind's comparator in :data:`COMPARATORS`.

    ``tolerances`` is ``(rtol, atol)`` when the caller has it already (default: the
    exercise's for ``params``); for a function ``atol`` may be a list, one per test input.
    """
    comparator = COMPARATORS.get(exercise.kind)
    if comparator is None:
        raise ValueError(f"unknown answer kind {exercise.kind!r}")
    rtol, atol = exercise.tolerances(params) if tolerances is None else tolerances
    return comparator(exercise, answer, expected, rtol, atol)


def _describe(value) -> str:
    if getattr(value, "is_Matrix", False) and not isinstance(value, np.ndarray):
        free = value.free_symbols
        if free:
            names = ", ".join(sorted(str(s) for s in free))
            return f"a SymPy Matrix with free symbols ({names}): substitute numbers for them"
        try:
            np.asarray(value.evalf(), dtype=float)
        except (TypeError, ValueError, OverflowError):
            return "a SymPy Matrix whose entries are not all real numbers"
        return f"a {value.rows}×{value.cols} SymPy Matrix"
    if isinstance(value, Unsupported):
        if value.type_name.startswith("unreadable"):
            return f"an {value.type_name}"
        return f"a {value.type_name}"
    if value is NOT_ANSWERED:
        return "nothing"
    name = type(value).__name__
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _expected(exercise, value, params, outputs_of):
    """For function exercises turn a reference function into its outputs on the cases."""
    if exercise.kind == "function":
        return outputs_of(value)
    return value


def judge(exercise, params, answer, outputs_of=None) -> Judgement:
    """Judge one decoded answer, with a hint when the mistake is recognisable.

    Parameters
    ----------
    exercise : Exercise
    params : Params
        The student's variant.
    answer : object
        Decoded answer (:func:`photolib.grading.encode.decode_value`), or
        :class:`FunctionOutputs` for function exercises.
    outputs_of : callable, optional
        For function exercises: maps a reference or mistaken function to its outputs on the
        same test inputs the student's function was called with.
    """
    def verdict(status, message, points=0.0, mistake=None):
        return Judgement(exercise.id, status, points, float(exercise.points), message, mistake)

    if unanswered(answer) or (isinstance(answer, FunctionOutputs)
                                  and answer.outputs and all(o is NOT_ANSWERED
                                                             for o in answer.outputs)):
        return verdict("not-answered", "not answered yet")
    expected = _expected(exercise, exercise.reference(params), params, outputs_of)
    try:
        tolerances = _tolerances(exercise, params, outputs_of)
        result = compare(exercise, answer, expected, params, tolerances)
    except ImportError as exc:
        return verdict("wrong", f"cannot judge this answer here: {exc}", mistake="unjudged")
    except Exception as exc:  # noqa: BLE001 - an answer the comparator cannot read
        kind = _parser_error_kind(exc)
        if kind == "syntax":
            # a typo or ^ for ** is a slip of the student's, not an attempt at anything unsafe
            return verdict("wrong", f"the formula could not be read: {exc}", mistake="syntax")
        return verdict("wrong", f"the answer could not be read ({type(exc).__name__}: {exc})",
                       mistake=kind)
    ok, reason = result
    if ok:
        return verdict("correct", "correct", float(exercise.points))
    tried = []
    for mistake, wrong in _mistake_values(exercise, params, outputs_of):
        tried.append((mistake, wrong))
        try:
            hit, _ = compare(exercise, answer, wrong, params, tolerances)
            if hit and _closer_to_zero(exercise, answer, wrong, params, tolerances):
                continue
        except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
            continue
        if hit:
            return verdict("wrong", f"not correct: {mistake.message}", mistake=mistake.tag)
    rounded = _rounded_mistake(exercise, answer, expected, params, tried, tolerances)
    if rounded is not None:
        return verdict("wrong", f"not correct: {rounded.message}", mistake=rounded.tag)
    near = _near_miss(exercise, answer, expected, params)
    if near is not None:
        return verdict("wrong", f"not correct: {near[1]}", mistake=near[0])
    return verdict("wrong", "not correct" + (f": {reason}" if reason else ""),
                   mistake=result.tag)


def _parser_error_kind(exc: Exception) -> str:
    """``"syntax"``, ``"unsafe"`` or ``"unreadable"`` for an exception of the comparison, by
    the classes of :mod:`photolib.symcheck` (the formula parser). Its exceptions exist only
    once it is imported, so a comparison that never parsed a formula does not import SymPy
    here."""
    import sys

    symcheck = sys.modules.get("photolib.symcheck")
    if symcheck is not None and isinstance(exc, symcheck.FormulaSyntaxError):
        return "syntax"
    if symcheck is not None and isinstance(exc, symcheck.UnsafeExpressionError):
        return "unsafe"
    return "unreadable"


def _tolerances(exercise, params, outputs_of):
    """``(rtol, atol)`` of this variant, computed once per judgement (a ``PRINTED``
    tolerance re-evaluates the reference for every printed input); for a function exercise
    with ``tolerance=PRINTED`` ``atol`` is the list of :func:`function_atols`."""
    rtol, atol = exercise.tolerances(params)
    if exercise.kind == "function" and exercise.tolerance == "printed" and outputs_of:
        atol = function_atols(exercise, params, outputs_of)
    return rtol, atol


#: relative tolerance at which a rounded answer still shows which mistake it is: four
#: significant digits, as students copy numbers from a printout
HINT_RTOL = 5e-4


def _mistake_values(exercise, params, outputs_of):
    """``(mistake, value)`` for every hint rule that applies, computed as they are asked for.

    ``value`` is what a student who made the mistake answers; a rule that raises or returns
    None does not apply to these parameters and is skipped.
    """
    for mistake in tuple(exercise.mistakes) + generic_mistakes(exercise):
        try:
            wrong = mistake.wrong(params)
            value = None if wrong is None else _expected(exercise, wrong, params, outputs_of)
        except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
            continue
        if value is not None:
            yield mistake, value


def _rounded_mistake(exercise, answer, expected, params, tried, tolerances):
    """The one mistake a number or array answer matches to four significant digits, or None.

    The hints above compare with the exercise's own tolerance, which a student who made a
    recognised mistake and then rounded to four digits misses: the answer is wrong either
    way, but the hint is lost. This second look accepts :data:`HINT_RTOL` per entry (plus the
    exercise's ``atol``), and names a mistake only when the answer is not as near the correct
    value and no other mistake with a different hint is as near. ``tried`` are the
    ``(mistake, value)`` pairs of :func:`_mistake_values` that the first look compared;
    ``tolerances`` the exercise's ``(rtol, atol)`` for these parameters.
    """
    if exercise.kind not in ("number", "array"):
        return None
    given = (_as_number(answer) if exercise.kind == "number"
             else _numeric_matrix(answer, np.ndim(expected)))
    if not isinstance(given, (float, np.ndarray)):
        return None
    given = np.asarray(given, float)
    if not np.all(np.isfinite(given)):
        return None
    _, atol = tolerances

    def near(target) -> bool:
        t = np.asarray(target, float)
        return (t.shape == given.shape and bool(np.all(np.isfinite(t)))
                and bool(np.all(np.abs(given - t) <= atol + HINT_RTOL * np.abs(t))))

    if near(expected):
        return None
    found = {}
    for mistake, wrong in tried:
        try:
            if near(wrong) and not _closer_to_zero(exercise, answer, wrong, params,
                                                   tolerances):
                found.setdefault(mistake.message, mistake)
        except Exception:  # noqa: BLE001 - a value that cannot be compared gives no hint
            continue
    return next(iter(found.values())) if len(found) == 1 else None


#: the roundings (significant digits, or decimals) an answer is compared with as a near miss
NEAR_DIGITS = range(1, 11)


def _rounded_digits(pairs):
    """The fewest significant digits to which some entry of the answers is the reference
    rounded or cut off (every entry being such a rounding, to any digits or decimals), or None.

    >>> _rounded_digits([(np.array(1.23), np.array(1.23456))])
    3
    >>> _rounded_digits([(np.array(1.2469), np.array(1.23456))]) is None
    True
    """
    fewest = None
    for given, want in pairs:
        for g, e in zip(np.ravel(given), np.ravel(want)):
            if g == e or e == 0:
                continue
            exponent = math.floor(math.log10(abs(e)))
            found = None
            for k in NEAR_DIGITS:
                step = 10.0 ** (exponent - k + 1)
                for r in (round(e / step) * step, math.trunc(e / step) * step):
                    if abs(g - r) <= 1e-9 * abs(e) + 1e-300:
                        found = k
                        break
                if found:
                    break
            if found is None:
                return None
            fewest = found if fewest is None else min(fewest, found)
    return fewest


def _given_values(exercise, answer, expected):
    """``[(given, expected)]`` float arrays of a number, array or function answer, or []."""
    if exercise.kind == "number":
        given = _as_number(answer)
        return [(np.asarray(given, float), np.asarray(expected, float))] \
            if isinstance(given, float) else []
    if exercise.kind in ("array", "rotation"):
        given = _numeric_matrix(answer, np.ndim(expected))
        return [(given, np.asarray(expected, float))] if isinstance(given, np.ndarray) else []
    if exercise.kind == "function" and isinstance(answer, FunctionOutputs) and not answer.error:
        pairs = []
        for got, want in zip(answer.outputs, expected):
            if isinstance(want, Raised) or isinstance(got, Raised):
                continue
            got = _numeric_matrix(_as_number(got), np.ndim(want))
            if not isinstance(got, (float, np.ndarray)):
                return []
            pairs.append((np.asarray(got, float), np.asarray(want, float)))
        return pairs
    return []


def _near_miss(exercise, answer, expected, params):
    """``(tag, message)`` of a near miss no mistake rule explains, or None.

    * ``"unnormalised"``: the answer (or each output) is a vector parallel to a unit vector
      expected, with another length;
    * ``"digits"``: every entry agrees with the reference to :data:`NEAR_DIGITS` significant
      digits of the largest entry, but not within the tolerance: the message says how many
      digits agree and the precision the task asks for
      (:func:`photolib.grading.precision.for_variant`).
    """
    try:
        pairs = _given_values(exercise, answer, expected)
    except Exception:  # noqa: BLE001 - an answer that cannot be read gives no hint
        return None
    pairs = [(g, e) for g, e in pairs if g.shape == e.shape and np.all(np.isfinite(g))
             and e.size and np.all(np.isfinite(e))]
    if not pairs:
        return None

    def unnormalised(g, e):
        ne, ng = np.linalg.norm(e), np.linalg.norm(g)
        return (e.ndim == 1 and e.size > 1 and abs(ne - 1.0) < 1e-6 and ng > 0
                and abs(ng - 1.0) > 1e-3 and np.allclose(g / ng, e, rtol=0, atol=1e-3))

    if all(unnormalised(g, e) for g, e in pairs):
        return "unnormalised", MESSAGES["unnormalised"]
    agree = _rounded_digits(pairs)
    if agree is None:
        return None
    from photolib.grading.precision import for_variant
    try:
        asked, _ = for_variant(exercise, params, _filled(exercise, params))
    except Exception:  # noqa: BLE001 - no precision to name: the hint without it
        asked = None
    wanted = f"; give it {asked.text()}" if asked is not None and asked.value else ""
    return "digits", (f"close: your answer is the correct value rounded to {agree} "
                      f"significant digit{'s' if agree > 1 else ''}, which is not the "
                      f"precision asked{wanted}")


def _filled(exercise, params) -> str:
    try:
        return exercise.statement.format(**params)
    except (KeyError, IndexError, ValueError):
        return exercise.statement


def _closer_to_zero(exercise, answer, wrong, params, tolerances=None) -> bool:
    """Does a mistake whose value is within tolerance of zero match ``answer`` only as zero does?

    A result 1000 times too small (mm for m) of a small reference can be 0 within the
    tolerance: then an answer of 0, or one nearer to 0 than to the mistake's value, matches
    the mistake as well as the mistake itself, and "off by a factor of 1000" would be a
    guess. The hint stays for an answer nearer to the mistake's value than to zero, and for a
    mistake that really gives zero. Numbers and arrays only.
    """
    if exercise.kind not in ("number", "array"):
        return False
    values = np.asarray(wrong, float)
    if not np.any(values):
        return False
    zero = np.zeros_like(values) if values.ndim else 0.0
    if not compare(exercise, zero, values, params, tolerances).ok:
        return False
    given = _as_number(answer) if exercise.kind == "number" else _numeric_matrix(answer,
                                                                                 values.ndim)
    given = np.asarray(given, float)
    return float(np.max(np.abs(given - values))) >= float(np.max(np.abs(given)))
