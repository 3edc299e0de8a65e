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

from photolib.grading.exercises import chapters, exercise
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


# -- an answer of zero -------------------------------------------------------------------------

def test_zero_is_not_called_a_factor_of_1000():
    # im.log-value (reference ≈ −0.05, tolerance 3e-4): the generic "result / 1000" rule
    # gives −5e-5, within the tolerance of 0, so an answer of 0 got "off by a factor of 1000:
    # are mm and m mixed up?"; so did bun.sigma0, prd.occluded-length and others
    for exercise_id in ("im.log-value", "bun.sigma0", "prd.occluded-length"):
        ex = exercise(exercise_id)
        verdict = judge_as_grader(ex, "s1000001", 0.0)
        assert verdict.status == "wrong"
        assert verdict.mistake != "units-mm-m", (exercise_id, verdict.message)
        assert verdict.message == "not correct"


@pytest.mark.parametrize("ex", _by_kind("number", "array"), ids=_ids)
def test_zero_gets_no_hint_of_a_mistake_indistinguishable_from_zero(ex):
    for sid in [f"s{i}" for i in range(12)]:
        ref = np.asarray(ex.reference(parameters_for(ex, sid)), float)
        verdict = judge_as_grader(ex, sid, np.zeros_like(ref) if ref.ndim else 0.0)
        if verdict.mistake in (None, "other", "shape", "type"):
            continue
        # a hint for 0 only from a mistake whose value is exactly zero somewhere it matters
        rule = next(m for m in ex.mistakes if m.tag == verdict.mistake)
        assert not np.any(np.asarray(rule.wrong(parameters_for(ex, sid)), float)), (sid, verdict)


def test_the_mm_m_hint_still_fires_for_a_real_mm_m_mistake():
    ex = exercise("im.log-value")
    ref = ex.reference(parameters_for(ex, "s1000001"))
    assert judge_as_grader(ex, "s1000001", ref * 1000.0).mistake == "units-mm-m"


def test_a_small_mm_m_mistake_keeps_its_hint():
    # prd.relief-displacement, s0000000: Δr = 3.19 mm, tolerance 0.0057 mm; Δr in m (0.00319)
    # lies within the tolerance of 0 and still is recognisably the mm/m mistake
    ex = exercise("prd.relief-displacement")
    ref = ex.reference(parameters_for(ex, "s0000000"))
    assert judge_as_grader(ex, "s0000000", ref * 1e-3).mistake == "units-mm-m"
    assert judge_as_grader(ex, "s0000000", 0.0).mistake == "other"


# -- expressions: NaN, division by zero, typos --------------------------------------------------

@pytest.mark.parametrize("value", [float("nan"), float("inf"), "f/0", "f/(k - k)"])
def test_a_non_finite_expression_is_wrong_not_undecided(value):
    # a NaN answer, or a formula dividing by zero, was "equivalence could not be decided; the
    # instructor will look at it" (tag undecided): the student waits for a review that has
    # nothing to review
    ex = exercise("opt.dof-limit")
    verdict = judge_as_grader(ex, "s1000001", value)
    assert verdict.status == "wrong"
    assert verdict.mistake != "undecided"
    assert "instructor" not in verdict.message
    assert "not finite" in verdict.message


@pytest.mark.parametrize("text", ["f**", "(f*k", "", "f^2"])
def test_a_formula_with_a_typo_is_a_syntax_slip_not_unsafe(text):
    # a typo was tagged "unsafe" in the gradebook summary (as __import__ is) and the student
    # read the parser's class name: "the answer could not be read (UnsafeExpressionError: ..."
    ex = exercise("opt.dof-limit")
    verdict = judge_as_grader(ex, "s1000001", text)
    assert verdict.status == "wrong" and verdict.mistake == "syntax"
    assert verdict.message.startswith("the formula could not be read: ")
    assert "Error" not in verdict.message
    assert run_check(ex, "s1000001", text) == f"✘ {ex.id}: {verdict.message}"


@pytest.mark.parametrize("text", ["__import__('os')", "f.real", "open('x')"])
def test_an_unsafe_formula_stays_unsafe(text):
    verdict = judge_as_grader(exercise("opt.dof-limit"), "s1000001", text)
    assert verdict.status == "wrong" and verdict.mistake == "unsafe"


# -- a function without return ------------------------------------------------------------------

def _no_return(*args):
    args[0] * 2                         # the student computed, but forgot the return


@pytest.mark.parametrize("ex", _by_kind("function"), ids=_ids)
def test_a_function_without_return_is_told_so(ex):
    # a function returning None was "not answered yet", in check() and in the gradebook,
    # though the student had written it: encode_value made None and ... the same
    verdict = judge_as_grader(ex, "s1000001", _no_return)
    assert verdict.status == "wrong"
    assert verdict.message == "not correct: the function returned None: is its return " \
                              "statement missing?"
    assert run_check(ex, "s1000001", _no_return) == f"✘ {ex.id}: {verdict.message}"


@pytest.mark.parametrize("ex", _by_kind("function"), ids=_ids)
def test_the_untouched_function_and_not_implemented_are_not_answered(ex):
    def raises(*args):
        raise NotImplementedError

    for func in (lambda *args: ..., raises):
        assert judge_as_grader(ex, "s1000001", func).status == "not-answered"
        assert run_check(ex, "s1000001", func) == f"… {ex.id}: not answered yet"


@pytest.mark.parametrize("ex", _by_kind("number", "array", "rotation", "expression", "choice"),
                         ids=_ids)
def test_an_answer_set_to_none_is_not_answered(ex):
    assert judge_as_grader(ex, "s1000001", None).status == "not-answered"
    assert run_check(ex, "s1000001", None) == f"… {ex.id}: not answered yet"


# -- an answer the grader cannot read: check() says what the grader says -------------------------

def _as_the_grader_reads(ex, sid, value):
    """The verdict of the batch grader: the kernel's encoding (an exception becomes its type
    name, as the extraction cell reports it), then :func:`judge_item`."""
    import json

    from photolib.grading.encode import encode_value
    from photolib.grading.extract import judge_item
    try:
        item = {"value": json.loads(json.dumps(encode_value(value)))}
    except Exception as exc:  # noqa: BLE001
        item = {"error": type(exc).__name__}
    return judge_item(ex, sid, item, None)


@pytest.mark.parametrize(("exercise_id", "make"), [
    ("opt.dof-limit", lambda sp: sp.nan),
    ("opt.dof-limit", lambda sp: sp.Max(sp.Symbol("f"), sp.Symbol("k"))),
    ("opt.dof-limit", lambda sp: sp.Eq(sp.Symbol("t"), sp.Symbol("f"))),
    ("demo.image-scale", lambda sp: sp.oo),
    ("demo.image-scale", lambda sp: 10 ** 400),
    ("demo.rotation-x", lambda sp: sp.Matrix(3, 3, [sp.nan] * 9)),
])
def test_check_and_the_grader_say_the_same_of_an_unreadable_answer(exercise_id, make):
    # check() printed "opt.dof-limit: the answer could not be read (DecodeError: 'NaN' is not
    # an allowed function)", without the ✘ and in other words than the gradebook's "not
    # correct: expected a SymPy expression, got an unreadable answer (...)"
    import sympy as sp
    ex, value = exercise(exercise_id), make(sp)
    verdict = _as_the_grader_reads(ex, "s1000001", value)
    assert verdict.status == "wrong"
    assert run_check(ex, "s1000001", value) == f"✘ {ex.id}: {verdict.message}"


def test_a_numeric_matrix_for_a_number_is_described_as_it_is():
    # sympy.Matrix([3.19]) for a number was "a SymPy Matrix whose entries are not all real
    # numbers", though its one entry is a real number; sympy.I was "a ImaginaryUnit"
    import sympy as sp
    ex = exercise("demo.image-scale")
    message = judge_as_grader(ex, "s1000001", sp.Matrix([3.19])).message
    assert message == "not correct: expected a number, got a 1×1 SymPy Matrix"
    assert judge_as_grader(ex, "s1000001", sp.I).message == \
        "not correct: expected a number, got an ImaginaryUnit"
    complex_entries = sp.Matrix(3, 3, [sp.I] * 9)
    assert "not all real numbers" in judge_as_grader(exercise("demo.rotation-x"), "s1000001",
                                                     complex_entries).message


# -- a Matrix typed as a formula string -----------------------------------------------------------

@pytest.mark.parametrize("prefix", ["Matrix", "sp.Matrix", "sympy.Matrix"])
def test_a_matrix_formula_string_is_read(prefix):
    # the kind "expression" takes "a SymPy expression or Matrix, or a formula string", but
    # "Matrix([[1, 0, 0], ...])" was "the answer could not be read (UnsafeExpressionError: not
    # allowed: call of 'Matrix'; ...)" with the tag unsafe
    ex = exercise("demo.rotation-x-symbolic")
    text = (prefix + "([[1, 0, 0], [0, cos(omega), -sin(omega)], "
            "[0, sin(omega), cos(omega)]])")
    assert judge_as_grader(ex, "s1000001", text).status == "correct"
    assert run_check(ex, "s1000001", text) == f"✔ {ex.id}: correct"
    transposed = text.replace("-sin", "+X").replace("sin(omega), cos", "-sin(omega), cos") \
        .replace("+X", "sin")
    assert judge_as_grader(ex, "s1000001", transposed).mistake == "transposed"


@pytest.mark.parametrize("text", ["Matrix([[1, 0], [0]])", "Matrix([[__import__('os')]])",
                                  "Matrix([[x.y]])", "Matrix(3, 3, [0]*9)", "os.Matrix([[1]])"])
def test_a_malformed_or_unsafe_matrix_string_is_wrong(text):
    verdict = judge_as_grader(exercise("demo.rotation-x-symbolic"), "s1000001", text)
    assert verdict.status == "wrong"
    if "_" in text or "." in text.split("(")[-1]:
        assert verdict.mistake == "unsafe"


# -- what a student function returns ----------------------------------------------------------

def _returning(ex, sid, convert):
    reference = ex.reference(parameters_for(ex, sid))
    return lambda *args: convert(reference(*args))


@pytest.mark.parametrize("ex", [ex for ex in _by_kind("function")
                                if np.ndim(ex.reference(parameters_for(ex, "s1000001"))(
                                    *ex.cases(np.random.default_rng(0),
                                              parameters_for(ex, "s1000001"))[0])) == 1],
                         ids=_ids)
def test_a_function_returning_a_sympy_matrix_or_a_column(ex):
    # a function returning sympy.Matrix(...) of the right numbers was "not correct" with no
    # reason (a SymPy Matrix is 2-D), though a Matrix is accepted for array answers; a (3, 1)
    # column was "not correct" with no word of the shape
    import sympy as sp
    as_matrix = _returning(ex, "s1000001", lambda v: sp.Matrix(np.asarray(v, float).tolist()))
    assert judge_as_grader(ex, "s1000001", as_matrix).status == "correct"
    column = _returning(ex, "s1000001", lambda v: np.asarray(v, float).reshape(-1, 1))
    verdict = judge_as_grader(ex, "s1000001", column)
    assert verdict.status == "wrong" and "shape" in verdict.message, verdict.message


def test_a_function_returning_a_bool_or_a_symbol_is_wrong_with_a_reason():
    import sympy as sp
    ex = exercise("demo.scale-function")
    assert judge_as_grader(ex, "s1000001", lambda c, h: True).message == \
        "not correct: the function returned a bool"
    verdict = judge_as_grader(ex, "s1000001", lambda c, h: sp.Symbol("m") * h)
    assert verdict.message == "not correct: the function returned a Mul"


# -- multiple choice --------------------------------------------------------------------------

@pytest.mark.parametrize("ex", _by_kind("choice"), ids=_ids)
def test_a_choice_is_read_as_students_write_it(ex):
    # "b." and "'b'" were wrong with no reason; the option's text, or two letters, were a bare
    # "not correct", though the task asks for one letter
    key = ex.reference(parameters_for(ex, "s1000001"))
    for typed in (key, key.upper(), f"({key})", f"{key})", f"{key}.", f"'{key}'", f" {key} "):
        assert judge_as_grader(ex, "s1000001", typed).status == "correct", typed
    for typed in ("its transpose", f"{key}, {key}", "z", ""):
        verdict = judge_as_grader(ex, "s1000001", typed)
        assert verdict.message == "not correct: expected the letter of one option, such as 'a'"


# -- rounded as printed -----------------------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS + ("s3",))
def test_a_height_given_to_the_cm_is_accepted(sid):
    # st.height (Z ≈ −1300 … −5300 m from c to 0.01 mm, B to 0.1 m, px' to 0.001 mm) had rtol
    # 1e-6: Z printed to the cm (e.g. −1285.75) was wrong, though the printed inputs carry only
    # some 0.1 m
    ex = exercise("st.height")
    z = ex.reference(parameters_for(ex, sid))
    assert judge_as_grader(ex, sid, round(z, 2)).status == "correct"
    assert judge_as_grader(ex, sid, round(z, 1)).status == "correct"
    assert judge_as_grader(ex, sid, -z).mistake == "sign-c"


# -- a recognised mistake, rounded to four significant digits --------------------------------
def _four_digits(x):
    """``x`` as a student copies it from a printout: four significant digits per entry."""
    x = np.asarray(x, float)
    exponent = np.floor(np.log10(np.abs(np.where(x == 0, 1.0, x))))
    scale = 10.0 ** (3 - exponent)
    out = np.round(x * scale) / scale
    return float(out) if out.ndim == 0 else out


def test_rounded_mistakes_keep_their_hint_and_rounded_references_get_none():
    from photolib.grading.judge import _expected, judge

    own = total = 0
    for ex in _by_kind("number", "array"):
        for sid in ("s3000001", "s3000002", "s3000003"):
            p = parameters_for(ex, sid)
            # the reference rounded: correct or a plain "not correct", never a mistake's hint
            j = judge(ex, p, _four_digits(ex.reference(p)))
            hints = {f"not correct: {m.message}" for m in ex.mistakes}
            assert j.status == "correct" or j.message not in hints, (ex.id, sid, j.message)
            for m in ex.mistakes:
                wrong = m.wrong(p)
                if wrong is None:
                    continue
                j = judge(ex, p, _four_digits(_expected(ex, wrong, p, None)))
                total += 1
                own += j.message == f"not correct: {m.message}"
    # 2079 of 5341 before the second look at four digits (40 students), 4939 after; the rest
    # are mistakes whose values lie within four digits of another mistake's or of zero
    assert own >= 0.85 * total, (own, total)
