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

from dataclasses import dataclass

import numpy as np

from photolib.grading.encode import NONE, NOT_ANSWERED, Unsupported, unanswered
from photolib.grading.hints import generic_mistakes

__all__ = ["FunctionOutputs", "Judgement", "compare", "judge", "propagated_atol"]


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
        for index in np.ndindex(base.shape):
            shifted = []
            for sign in (1.0, -1.0):
                element = base.copy()
                element[index] += sign * du
                changed = dict(params)
                changed[name] = element.tolist() if isinstance(value, list) else element
                shifted.append(evaluate(changed))
            total = total + np.abs(shifted[0] - shifted[1]) / 2.0
    total = np.maximum(total, floor)
    return float(total) if total.ndim == 0 else total


def rounding_tolerance(reference, half_units, rtol=1e-6, mistakes=(), share=0.4, floor=1e-12):
    """``tolerance`` of an exercise: the rounding of the printed inputs, kept off the mistakes.

    The absolute tolerance is :func:`propagated_atol` of the printed
    inputs' last digits (``half_units``), so an answer rounded as precisely as the inputs
    allow is accepted, and ``rtol`` (1e-6) accepts float32 results. Where a recognisable
    mistake lies closer than that (a variant with a tiny effect), the absolute tolerance is
    cut to ``share`` of the distance to the nearest mistake, so the mistake still lands
    outside with its hint. Mistakes that coincide with the reference are ignored. ``floor``
    is the smallest absolute tolerance before that cut (an answer's own rounding).

    >>> tol = rounding_tolerance(lambda p: p["a"] / 3, {"a": 0.005},
    ...                          mistakes=(lambda p: p["a"] / 3 + 1e-4,))
    >>> [round(float(t), 8) for t in tol({"a": 1.0})]
    [1e-06, 4e-05]
    """
    def tolerance(p):
        atol = propagated_atol(reference, p, half_units, floor=floor)
        ref = np.asarray(reference(p), float)
        for wrong in mistakes:
            value = wrong(p)
            if value is None:
                continue
            gap = float(np.max(np.abs(np.asarray(value, float) - ref)))
            if gap > 1e-12 * (1.0 + float(np.max(np.abs(ref)))):
                atol = np.minimum(atol, share * gap)
        return rtol, atol
    return tolerance


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


def compare(exercise, answer, expected, params) -> tuple[bool, str]:
    """Does ``answer`` equal ``expected`` for this exercise's kind? Returns ``(ok, reason)``."""
    rtol, atol = exercise.tolerances(params)
    kind = exercise.kind
    if kind == "number":
        answer = _as_number(answer)
        if not isinstance(answer, float):
            return False, f"expected a number, got {_describe(answer)}"
        return _numbers_match(answer, expected, rtol, atol), ""
    if kind in ("array", "rotation"):
        answer = _numeric_matrix(answer, np.ndim(expected))
        if not isinstance(answer, np.ndarray):
            return False, f"expected an array, got {_describe(answer)}"
        expected = np.asarray(expected, float)
        if answer.shape != expected.shape:
            return False, f"expected shape {expected.shape}, got {answer.shape}"
        if not np.all(np.isfinite(answer)):
            return False, "the array contains NaN or infinity"
        if kind == "rotation":
            n = answer.shape[0]
            err = float(np.max(np.abs(answer.T @ answer - np.eye(n))))
            if err > 1e-6:
                return False, f"not a rotation matrix: max |RᵀR − I| = {err:.2g}"
            if np.linalg.det(answer) < 0:
                return False, "det R = −1: a reflection, not a rotation"
        return _numbers_match(answer, expected, rtol, atol), ""
    if kind == "expression":
        import sympy as sp
        if isinstance(answer, str):
            answer = _parse_formula(exercise, answer)
        if not isinstance(answer, (sp.Basic, sp.MatrixBase, float)):
            return False, f"expected a SymPy expression, got {_describe(answer)}"
        if isinstance(answer, float):
            answer = sp.Float(answer)
        if answer.has(sp.nan, sp.zoo, sp.oo, sp.S.NegativeInfinity):
            # not for symcheck, which calls such a comparison undecided (instructor's note)
            return False, "the expression is not finite (NaN or infinity: a division by zero?)"
        positive = {sp.Symbol(name): (0.2, 3.0) for name in exercise.positive}
        verdict = _expression_verdict(plain_symbols(answer), plain_symbols(expected), positive)
        if verdict == "undecided":
            return False, "equivalence could not be decided; the instructor will look at it"
        if verdict == "equal-under-condition":
            names = ", ".join(s for s in exercise.symbols if s not in exercise.positive)
            return False, ("equal only when the symbols are positive, but "
                           + (names or "the symbols") + " may be negative here")
        return verdict == "equal", ""
    if kind == "function":
        if not isinstance(answer, FunctionOutputs):
            return False, "expected a function"
        if answer.error:
            return False, answer.error
        if len(answer.outputs) != len(expected):
            return False, "the function did not answer every test input"
        for got, want in zip(answer.outputs, expected):
            if got is NONE:
                return False, "the function returned None: is its return statement missing?"
            if got is NOT_ANSWERED or isinstance(got, (str, bool, Unsupported, list)):
                return False, f"the function returned {_describe(got)}"
            # a SymPy number or numeric Matrix is read as for number and array answers
            got = _numeric_matrix(_as_number(got), np.ndim(want))
            if not isinstance(got, (float, np.ndarray)):
                return False, f"the function returned {_describe(got)}"
            if np.shape(got) != np.shape(want):
                return False, (f"the function returned shape {np.shape(got)}, "
                               f"expected shape {np.shape(want)}")
            if not _numbers_match(got, want, rtol, atol):
                return False, ""
        return True, ""
    if kind == "choice":
        if not isinstance(answer, str):
            return False, f"expected an option key such as 'a', got {_describe(answer)}"
        # "b", "B", "(b)", "b)", "b." and "'b'" (quotes typed inside the string) are all b
        key = answer.strip().lower().strip("()[].:'\" \t")
        if key not in {str(k).lower() for k in exercise.choices}:
            return False, "expected the letter of one option, such as 'a'"
        return key == str(expected).lower(), ""
    raise ValueError(f"unknown answer kind {kind!r}")


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
        ok, reason = compare(exercise, answer, expected, params)
    except ImportError as exc:
        return verdict("wrong", f"cannot judge this answer here: {exc}", mistake="unjudged")
    except Exception as exc:  # noqa: BLE001 - e.g. UnsafeExpressionError from the parser
        name = type(exc).__name__
        text = str(exc)
        if name == "FormulaSyntaxError":
            # a typo or ^ for ** is a slip of the student's, not an attempt at anything unsafe
            return verdict("wrong", f"the formula could not be read: {text}", mistake="syntax")
        return verdict("wrong", f"the answer could not be read ({name}: {text})",
                       mistake="unreadable" if name != "UnsafeExpressionError" else "unsafe")
    if ok:
        return verdict("correct", "correct", float(exercise.points))
    tried = []
    for mistake, wrong in _mistake_values(exercise, params, outputs_of):
        tried.append((mistake, wrong))
        try:
            hit, _ = compare(exercise, answer, wrong, params)
            if hit and _closer_to_zero(exercise, answer, wrong, params):
                continue
        except Exception:  # noqa: BLE001 - a hint rule that does not apply is skipped
            continue
        if hit:
            return verdict("wrong", f"not correct: {mistake.message}", mistake=mistake.tag)
    rounded = _rounded_mistake(exercise, answer, expected, params, tried)
    if rounded is not None:
        return verdict("wrong", f"not correct: {rounded.message}", mistake=rounded.tag)
    return verdict("wrong", "not correct" + (f": {reason}" if reason else ""),
                   mistake=_reason_tag(reason))


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


def _rounded_mistake(exercise, answer, expected, params, tried):
    """The one mistake a number or array answer matches to four significant digits, or None.

    The hints above compare with the exercise's own tolerance, which a student who made a
    recognised mistake and then rounded to four digits misses: the answer is wrong either
    way, but the hint is lost. This second look accepts :data:`HINT_RTOL` per entry (plus the
    exercise's ``atol``), and names a mistake only when the answer is not as near the correct
    value and no other mistake with a different hint is as near. ``tried`` are the
    ``(mistake, value)`` pairs of :func:`_mistake_values` that the first look compared.
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
    _, atol = exercise.tolerances(params)

    def near(target) -> bool:
        t = np.asarray(target, float)
        return (t.shape == given.shape and bool(np.all(np.isfinite(t)))
                and bool(np.all(np.abs(given - t) <= atol + HINT_RTOL * np.abs(t))))

    if near(expected):
        return None
    found = {}
    for mistake, wrong in tried:
        try:
            if near(wrong) and not _closer_to_zero(exercise, answer, wrong, params):
                found.setdefault(mistake.message, mistake)
        except Exception:  # noqa: BLE001 - a value that cannot be compared gives no hint
            continue
    return next(iter(found.values())) if len(found) == 1 else None


def _closer_to_zero(exercise, answer, wrong, params) -> bool:
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
    if not compare(exercise, zero, values, params)[0]:
        return False
    given = _as_number(answer) if exercise.kind == "number" else _numeric_matrix(answer,
                                                                                 values.ndim)
    given = np.asarray(given, float)
    return float(np.max(np.abs(given - values))) >= float(np.max(np.abs(given)))


def _reason_tag(reason: str) -> str:
    if not reason:
        return "other"
    for key, tag in (("only when the symbols are positive", "sign-domain"),
                     ("rotation matrix", "not-orthonormal"), ("reflection", "reflection"),
                     ("shape", "shape"), ("expected", "type"), ("raised", "raised"),
                     ("decided", "undecided")):
        if key in reason:
            return tag
    return "other"
