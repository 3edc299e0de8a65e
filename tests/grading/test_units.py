"""Judging, hints, encoding and variants in the grader's process (no kernel)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from photolib.grading import hints
from photolib.grading.encode import (
    NOT_ANSWERED,
    DecodeError,
    Unsupported,
    decode_value,
    encode_value,
)
from photolib.grading.exercises import chapter, chapters, exercise
from photolib.grading.judge import FunctionOutputs, judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.spec import Exercise, Mistake, Params
from photolib.grading.variants import rng_for


def _judge(ex_id, answer, sid="s0001"):
    ex = exercise(ex_id)
    p = parameters_for(ex, sid)
    value = answer(p) if callable(answer) and ex.kind != "function" else answer
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), p)
        return judge(ex, p, function_outputs(answer, cases), reference_outputs(cases))
    return judge(ex, p, decode_value(encode_value(value)))


def test_variants_differ_between_students_and_repeat_for_one():
    ex = exercise("demo.image-scale")
    a, b = parameters_for(ex, "s1"), parameters_for(ex, "s2")
    assert a == parameters_for(ex, "s1")
    assert a != b


@pytest.mark.parametrize("sid", [f"s{i}" for i in range(40)])
def test_parameters_are_realistic(sid):
    p = parameters_for(exercise("demo.image-scale"), sid)
    assert 8 <= p.c_mm <= 310 and 1 <= p.h_m <= 6000
    assert 5 <= parameters_for(exercise("demo.rotation-2d"), sid).kappa_gon <= 395


def test_hidden_cases_depend_on_secret(monkeypatch):
    a = rng_for("s1", "demo.scale-function", "hidden").uniform()
    monkeypatch.setenv("PHOTOLIB_GRADING_SECRET", "course-2026")
    assert rng_for("s1", "demo.scale-function", "hidden").uniform() != a
    assert rng_for("s1", "demo.scale-function", "public").uniform() == \
        rng_for("s1", "demo.scale-function", "public").uniform()


def _rot2(p, k=None):
    k = p.kappa_gon * math.pi / 200 if k is None else k
    return np.array([[math.cos(k), -math.sin(k)], [math.sin(k), math.cos(k)]])


@pytest.mark.parametrize("ex_id, answer, status, mistake", [
    ("demo.image-scale", lambda p: p.h_m / p.c_mm * 1000, "correct", None),
    ("demo.image-scale", lambda p: round(p.h_m / p.c_mm * 1000), "correct", None),
    ("demo.image-scale", lambda p: p.h_m / p.c_mm, "wrong", "units-mm-m"),
    ("demo.image-scale", lambda p: -p.h_m / p.c_mm * 1000, "wrong", "sign-c"),
    ("demo.image-scale", lambda p: p.h_m / p.c_mm * 1100, "wrong", "other"),
    ("demo.image-scale", lambda p: "12000", "wrong", "type"),
    ("demo.rotation-2d", _rot2, "correct", None),
    ("demo.rotation-2d", lambda p: _rot2(p).T, "wrong", "transposed"),
    ("demo.rotation-2d", lambda p: _rot2(p, p.kappa_gon), "wrong", "gon"),
    ("demo.rotation-2d", lambda p: _rot2(p, math.radians(p.kappa_gon)), "wrong", "degrees"),
    ("demo.rotation-2d", lambda p: 2 * _rot2(p), "wrong", "not-orthonormal"),
    ("demo.rotation-2d", lambda p: np.diag([1.0, -1.0]), "wrong", "reflection"),
    ("demo.rotation-2d", lambda p: np.eye(3), "wrong", "shape"),
    ("demo.rotation-x", lambda p: np.array([[1, 0, 0], [0, math.cos(p.omega_deg),
                                                        -math.sin(p.omega_deg)],
                                            [0, math.sin(p.omega_deg), math.cos(p.omega_deg)]]),
     "wrong", "degrees"),
    ("demo.rotation-x", lambda p: None, "not-answered", None),
    ("demo.inverse-choice", lambda p: p.correct.upper(), "correct", None),
    ("demo.inverse-choice", lambda p: "a" if p.correct != "a" else "b", "wrong", "other"),
])
def test_judge_and_hints(ex_id, answer, status, mistake):
    verdict = _judge(ex_id, answer)
    assert verdict.status == status, verdict.message
    assert verdict.mistake == mistake
    assert verdict.points == (verdict.max_points if status == "correct" else 0)


def test_symbolic_answers():
    w = sp.Symbol("omega")
    good = sp.Matrix([[1, 0, 0], [0, sp.cos(w), -sp.sin(w)], [0, sp.sin(w), sp.cos(w)]])
    rewritten = good.applyfunc(lambda e: sp.expand_trig(sp.sin(sp.pi / 2 - w))
                               if e == sp.cos(w) else e)
    assert _judge("demo.rotation-x-symbolic", rewritten).correct
    assert _judge("demo.rotation-x-symbolic", good.T).mistake == "transposed"
    assert _judge("demo.rotation-x-symbolic", good[:2, :2]).status == "wrong"


def test_function_answers():
    assert _judge("demo.scale-function", lambda c, h: h / c * 1000).correct
    assert _judge("demo.scale-function", lambda c, h: h / c).mistake == "units-mm-m"
    assert _judge("demo.scale-function", lambda c, h: -h / c * 1000).mistake == "sign-c"
    raised = _judge("demo.scale-function", lambda c, h: 1 / 0)
    assert "ZeroDivisionError" in raised.message and raised.points == 0
    assert _judge("demo.scale-function", lambda c, h: ...).status == "not-answered"


def test_public_messages_never_show_hidden_inputs():
    ex = exercise("demo.scale-function")
    p = parameters_for(ex, "s1")
    cases = ex.cases(rng_for("s1", ex.id, "hidden"), p)
    for answer in (lambda c, h: h / c, lambda c, h: 1 / 0, lambda c, h: "x"):
        msg = judge(ex, p, function_outputs(answer, cases), reference_outputs(cases)).message
        for args in cases:
            for value in args:
                assert f"{value:g}" not in msg and repr(value) not in msg


@pytest.mark.parametrize("bad", [
    {"t": "sympy", "v": {"f": "__import__", "a": [{"s": "os"}]}},
    {"t": "sympy", "v": {"f": "Function", "a": []}},
    {"t": "sympy", "v": {"s": "__class__"}},
    {"t": "sympy", "v": {"f": "Pow", "a": [{"i": "10"}, {"i": "100000"}]}},
    {"t": "sympy", "v": {"i": "1" * 500}},
    {"t": "num", "v": "__import__('os')"},
    {"t": "array", "shape": [2, 2], "v": ["1"]},
    {"t": "matrix", "shape": [1, 1], "v": [{"c": "oo"}]},
    {"t": "eval", "v": "1"},
    "1 + 1",
])
def test_decoder_whitelist_rejects(bad):
    with pytest.raises(DecodeError):
        decode_value(bad)


def test_encode_round_trips():
    x = sp.Symbol("x")
    for value in (1.5, np.float32(2.0), np.arange(6.0).reshape(2, 3), sp.atan2(x, 2) * sp.pi,
                  sp.Matrix([[x, 1], [sp.Rational(1, 3), sp.E]]), "b", True):
        back = decode_value(encode_value(value))
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(back, value)
        else:
            assert back == value or float(back) == float(value)
    assert decode_value(encode_value(...)) is NOT_ANSWERED
    assert isinstance(decode_value(encode_value(object())), Unsupported)


def test_formula_strings_are_parsed_by_symcheck():
    symcheck = pytest.importorskip("photolib.symcheck")
    assert _judge("demo.rotation-x-symbolic", "__import__('os').system('true')").mistake == \
        "unsafe"
    assert symcheck.UnsafeExpressionError


def test_erratum_hint_uses_the_catalogue(monkeypatch):
    import sys
    import types
    h, c = sp.symbols("h c")

    class Record:
        versions = {"old": h * c, "new": h / c}

    fake = types.ModuleType("photolib.errata")
    fake.get = lambda rid: Record()
    monkeypatch.setitem(sys.modules, "photolib.errata", fake)
    import photolib
    monkeypatch.setattr(photolib, "errata", fake, raising=False)
    rule = hints.erratum_version("luhmann:4.18b",
                                 lambda e, p: float(e.subs({h: p["h"], c: p["c"]})))
    ex = Exercise(id="t.err", points=1, title="", statement="", kind="number", answer="a",
                  parameters=lambda rng: {"h": 2.0, "c": 4.0},
                  reference=lambda p: p["h"] / p["c"], mistakes=(rule,))
    verdict = judge(ex, Params(h=2.0, c=4.0), 8.0)
    assert verdict.mistake == "erratum" and "luhmann:4.18b" in verdict.message


def test_erratum_hint_degrades_without_catalogue(monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "photolib.errata", None)
    rule = hints.erratum_version("luhmann:4.18b", lambda e, p: 1.0)
    assert rule.wrong(Params()) is None


def test_every_erratum_hint_names_a_record_and_version_that_exist():
    """A mistyped record id or version is caught here, not silently dropped by the judge
    (which skips a rule that raises)."""
    chapters()                                    # imports every exercise module
    assert hints.check_erratum_rules() >= 7
    assert ("luhmann:4.18b", "old") in hints.ERRATUM_RULES


def test_an_unknown_erratum_record_or_version_raises_naming_it(monkeypatch):
    monkeypatch.setattr(hints, "ERRATUM_RULES", [])
    bad = hints.erratum_version("luhmann:4.18b", lambda e, p: 1.0, version="olld")
    with pytest.raises(KeyError, match="'olld'.*'corrected'"):
        bad.wrong(Params())
    with pytest.raises(KeyError, match="olld"):
        hints.check_erratum_rules()
    bad = hints.erratum_version("luhmann:4.18x", lambda e, p: 1.0)
    with pytest.raises(KeyError, match="luhmann:4.18x"):
        bad.wrong(Params())
    assert hints.ERRATUM_RULES == [("luhmann:4.18b", "olld"), ("luhmann:4.18x", "old")]


def test_registry_is_consistent():
    ids = [ex.id for exs in chapters().values() for ex in exs]
    assert len(ids) == len(set(ids))
    assert {ex.kind for ex in chapter("00-start")} >= {"number", "rotation",
                                                               "expression", "function",
                                                               "choice"}
    with pytest.raises(KeyError, match="unknown exercise id 'nope'"):
        exercise("nope")


def test_exercise_declaration_errors_name_the_bad_value():
    kw = dict(points=1, title="", statement="", answer="a", parameters=lambda r: {},
              reference=lambda p: 1)
    with pytest.raises(ValueError, match="'Bad Id'"):
        Exercise(id="Bad Id", kind="number", **kw)
    with pytest.raises(ValueError, match="'vector'"):
        Exercise(id="t.x", kind="vector", **kw)
    with pytest.raises(ValueError, match="needs cases"):
        Exercise(id="t.x", kind="function", **kw)
    assert Mistake("t", "m", lambda p: None).tag == "t"
    assert FunctionOutputs((1.0,)).error is None


def test_formula_string_answers():
    pytest.importorskip("photolib.symcheck")
    ex = Exercise(id="t.formula", points=1, title="", statement="", kind="expression",
                  answer="f", symbols=("h", "c"), parameters=lambda rng: {},
                  reference=lambda p: sp.Symbol("h") / sp.Symbol("c"))
    assert judge(ex, Params(), "h/c").correct
    assert judge(ex, Params(), "1/(c/h)").correct
    assert judge(ex, Params(), "c/h").status == "wrong"


def test_extraction_passes_array_cases_as_arrays(monkeypatch):
    """A function exercise may take arrays: the kernel sees float arrays, the grader too."""
    import IPython.display

    from photolib.grading.extract import (
        answer_record,
        build_extraction,
        case_from_json,
        case_to_json,
        decode_item,
        record_student_id,
    )
    from photolib.grading.sandbox import RESULT_MIME

    cases = [(2.0, np.array([[1.0, 2.0], [3.0, 4.0]])), (0.5, [1, 2, 3])]
    sent = [case_to_json(c) for c in cases]
    assert sent[0] == [2.0, {"array": [[1.0, 2.0], [3.0, 4.0]]}]
    with pytest.raises(ValueError, match="finite"):
        case_to_json((np.nan,))
    code, nonce = build_extraction([{"name": "scaled_norm", "cases": sent}])
    published = []
    monkeypatch.setattr(IPython.display, "publish_display_data",
                        lambda data: published.append({"data": data}))

    def scaled_norm(s, xy):  # fails on a list: xy.shape exists only for arrays
        assert isinstance(xy, np.ndarray) and xy.dtype == float, type(xy)
        return s * np.linalg.norm(xy.reshape(-1, xy.shape[-1]), axis=1)

    namespace = {"get_ipython": lambda: type("Shell", (), {"user_ns": {
        "scaled_norm": scaled_norm, "STUDENT_ID": "s1"}})()}
    exec(code, namespace)  # noqa: S102 - the grader's own generated code
    ex = Exercise(id="t.norm", points=1, title="t", kind="function", answer="scaled_norm",
                  statement="", parameters=lambda rng: {}, cases=lambda rng, p: cases,
                  reference=lambda p: lambda s, xy: s * np.linalg.norm(
                      np.asarray(xy, float).reshape(-1, np.shape(xy)[-1]), axis=1))
    payloads = [d["data"][RESULT_MIME] for d in published]
    record = answer_record(payloads, nonce)
    sid, answer = record_student_id(record), decode_item(ex, record["answers"].get(ex.answer))
    assert sid == "s1" and answer.error is None
    verdict = judge(ex, Params({}), answer,
                    reference_outputs([case_from_json(c) for c in sent]))
    assert verdict.correct, verdict.message


def test_expression_references_with_assumptions_match_plain_answers():
    """Answers arrive without assumptions; a reference with real=True must still match."""
    w = sp.Symbol("omega", real=True)
    ex = Exercise(id="t.sin", points=1, title="t", kind="expression", answer="e",
                  statement="", parameters=lambda rng: {},
                  reference=lambda p: sp.Matrix([[sp.sin(w) ** 2 + sp.cos(w)], [w]]))
    plain = sp.Symbol("omega")
    answer = decode_value(encode_value(sp.Matrix([[1 - sp.cos(plain) ** 2 + sp.cos(plain)],
                                                  [plain]])))
    assert judge(ex, Params({}), answer).correct
    assert not judge(ex, Params({}), sp.Matrix([[sp.cos(plain)], [plain]])).correct


def _pow_tower(n):
    e = sp.Integer(2)
    for _ in range(n):
        e = sp.Pow(e, 64, evaluate=False)
    return e


@pytest.mark.parametrize("value", [
    sp.Pow(2, sp.Rational(10**12 + 1, 3), evaluate=False),
    sp.Pow(sp.Symbol("x"), sp.Float(1e9), evaluate=False),
    _pow_tower(5),
    sp.exp(sp.exp(sp.exp(sp.exp(sp.Symbol("omega"))))),
])
def test_decoder_bounds_expensive_expressions(value):
    with pytest.raises(DecodeError):
        decode_value(encode_value(value))


def test_decoder_errors_of_any_kind_are_decode_errors():
    class sin(sp.Function):  # noqa: N801 - a student's own function named like SymPy's
        nargs = 2
    with pytest.raises(DecodeError, match="sin cannot take"):
        decode_value(encode_value(sin(sp.Symbol("x"), 1)))


def test_honest_powers_and_exponentials_decode():
    x, r = sp.symbols("x r")
    for value in (sp.exp(sp.exp(x)), (sp.sqrt(x**2 + r**2)) ** 7, (x + 1) ** 64,
                  sp.Pow(x, sp.Rational(3, 2))):
        assert decode_value(encode_value(value)) == value


def test_numbers_as_sympy_numbers_and_zero_d_arrays():
    ex = exercise("demo.image-scale")
    p = parameters_for(ex, "s0001")
    right = p.h_m / p.c_mm * 1000
    assert _judge("demo.image-scale", lambda p: sp.nsimplify(right, rational=True)).correct
    assert _judge("demo.image-scale", lambda p: np.array(right)).correct
    assert _judge("demo.image-scale", lambda p: complex(right, 0)).correct
    bad = _judge("demo.image-scale", lambda p: complex(right, 1))
    assert not bad.correct and "complex" in bad.message
    arr = _judge("demo.rotation-2d", lambda p: _rot2(p) + 1j)
    assert not arr.correct and "complex" in arr.message


@pytest.mark.parametrize("entry", [
    lambda w: sp.Abs(sp.sin(w)), lambda w: sp.sin(sp.Abs(w)),
    lambda w: sp.sqrt(w**2) / w * sp.sin(w)])
def test_symbolic_answers_are_judged_over_signed_angles(entry):
    w = sp.Symbol("omega")
    s = entry(w)
    answer = sp.Matrix([[1, 0, 0], [0, sp.cos(w), -s], [0, s, sp.cos(w)]])
    verdict = _judge("demo.rotation-x-symbolic", answer)
    assert verdict.points == 0 and verdict.mistake == "sign-domain", verdict.message


def test_declared_positive_symbols_are_sampled_positive():
    f = sp.Symbol("f")
    kw = dict(points=1, title="", statement="", kind="expression", answer="e", symbols=("f",),
              parameters=lambda rng: {}, reference=lambda p: f)
    assert not judge(Exercise(id="t.real", **kw), Params(), sp.Abs(f)).correct
    assert judge(Exercise(id="t.pos", positive=("f",), **kw), Params(), sp.Abs(f)).correct


def test_student_ids_are_whole_and_never_formulas():
    from photolib.grading.submission import valid_student_id
    assert valid_student_id("s-normal") == "s-normal"
    for bad in ("s-normal\n", "+B2", "-1+1", "=HYPERLINK(1)", "@x", "", "x" * 65):
        assert valid_student_id(bad) is None


# -- numeric SymPy matrices answer array and rotation exercises --------------------------------

def _sympy_rotation_opk(omega, phi, kappa):
    w, f, k = sp.symbols("omega phi kappa")
    R = (sp.Matrix([[1, 0, 0], [0, sp.cos(w), -sp.sin(w)], [0, sp.sin(w), sp.cos(w)]])
         * sp.Matrix([[sp.cos(f), 0, sp.sin(f)], [0, 1, 0], [-sp.sin(f), 0, sp.cos(f)]])
         * sp.Matrix([[sp.cos(k), -sp.sin(k), 0], [sp.sin(k), sp.cos(k), 0], [0, 0, 1]]))
    values = {w: omega, f: phi, k: kappa}
    return R.subs({s: v for s, v in values.items() if v is not None})


def _opk_answer(sid, free_omega=False):
    p = parameters_for(exercise("rot.opk-matrix"), sid)
    gon = sp.pi / 200
    return _sympy_rotation_opk(None if free_omega else sp.Float(p.omega_gon) * gon,
                               sp.Float(p.phi_gon) * gon, sp.Float(p.kappa_gon) * gon).evalf()


@pytest.mark.parametrize("free_omega, printed", [
    (False, "✔ rot.opk-matrix: correct"),
    (True, "✘ rot.opk-matrix: not correct: expected an array, got a SymPy Matrix with free "
           "symbols (omega): substitute numbers for them"),
])
def test_sympy_matrix_is_judged_alike_by_check_and_the_grader(monkeypatch, capsys, free_omega,
                                                              printed):
    """check() in the notebook and the batch grader's extraction give the same verdict."""
    import IPython.display

    from photolib.grading import notebook
    from photolib.grading.extract import answer_record, build_extraction, judge_item
    from photolib.grading.sandbox import RESULT_MIME

    sid = "s1000001"
    ns = {"STUDENT_ID": sid, "R": _opk_answer(sid, free_omega)}
    monkeypatch.setattr(notebook, "_namespace", lambda: ns)
    notebook.check("rot.opk-matrix")
    assert capsys.readouterr().out.strip() == printed

    code, nonce = build_extraction([{"name": "R", "cases": None}])
    published = []
    monkeypatch.setattr(IPython.display, "publish_display_data",
                        lambda data: published.append({"data": data}))
    exec(code, {"get_ipython": lambda: type("Shell", (), {"user_ns": ns})()})  # noqa: S102
    record = answer_record([d["data"][RESULT_MIME] for d in published], nonce)
    verdict = judge_item(exercise("rot.opk-matrix"), sid, record["answers"]["R"], None)
    assert f"{'✔' if verdict.correct else '✘'} rot.opk-matrix: {verdict.message}" == printed
    assert verdict.mistake == (None if not free_omega else "type")


def test_sympy_matrix_answers_to_array_exercises():
    ex = Exercise(id="t.vector", points=1, title="t", kind="array", answer="v", statement="",
                  parameters=lambda rng: {}, reference=lambda p: np.array([1.0, 2.0, 3.0]),
                  rtol=0.0, atol=1e-9)
    judged = lambda value: judge(ex, Params({}), decode_value(encode_value(value)))  # noqa: E731
    assert judged(sp.Matrix([1, 2, 3])).correct                      # a column
    assert judged(sp.Matrix([[1.0, 2.0, 3.0]])).correct              # a row
    assert judged(sp.Matrix([sp.sqrt(1), sp.Rational(4, 2), 3])).correct
    assert judged(sp.Matrix([1000, 2000, 3000])).mistake == "units-mm-m"
    assert judged(sp.Matrix([[1, 2, 3], [1, 2, 3]])).mistake == "shape"
    assert judged(sp.Matrix([1, 2, 3 * sp.I])).mistake == "type"
    assert judged(sp.Matrix([1, 2, sp.Symbol("x")])).mistake == "type"


def test_propagated_atol_of_arrays_and_list_parameters():
    from photolib.grading.judge import propagated_atol

    # f = (u0 + u1, 3·u1) with u rounded to ±0.5: Σ |∂f/∂u_i|·0.5 per entry
    tol = propagated_atol(lambda p: np.array([p["u"][0] + p["u"][1], 3.0 * p["u"][1]]),
                          {"u": [1.0, 2.0]}, {"u": 0.5})
    np.testing.assert_allclose(tol, [1.0, 1.5])
    assert isinstance(propagated_atol(lambda p: p["a"] ** 2, {"a": 3.0}, {"a": 0.01}), float)


def test_each_answer_kind_has_one_comparator_that_returns_its_tag():
    """The gradebook tag comes from the comparator with its verdict and message (it was
    searched for in the student-facing message)."""
    from photolib.grading.judge import COMPARATORS, Comparison, compare
    assert set(COMPARATORS) == {"number", "array", "rotation", "expression", "function",
                                "choice"}
    rot = exercise("demo.rotation-x")
    p = parameters_for(rot, "s1000001")
    mirror = np.diag([1.0, 1.0, -1.0])
    result = compare(rot, mirror, rot.reference(p), p)
    assert isinstance(result, Comparison)
    assert (result.ok, result.tag) == (False, "reflection")
    assert result.message.startswith("det R = −1")
    ok, reason = result                                     # the old (ok, reason) form
    assert (ok, reason) == (False, result.message)
    shape = compare(rot, np.eye(2), rot.reference(p), p)
    assert (shape.tag, shape.message) == ("shape", "expected shape (3, 3), got (2, 2)")
    assert compare(rot, rot.reference(p), rot.reference(p), p) == Comparison(True, "", "")
    bad = Exercise(id="t.kind", points=1, title="", statement="", kind="number", answer="a",
                   parameters=lambda rng: {}, reference=lambda p: 1.0)
    object.__setattr__(bad, "kind", "vector")
    with pytest.raises(ValueError, match="unknown answer kind 'vector'"):
        compare(bad, 1.0, 1.0, Params())


def test_a_message_that_mentions_shape_does_not_become_the_shape_tag():
    """A function's degenerate-input message may contain any word ("shape", "expected"): the
    tag is the comparator's, "degenerate", not the first keyword found in the text."""
    from photolib.grading.encode import Raised
    from photolib.grading.judge import FunctionOutputs, compare
    ex = exercise("demo.scale-function")
    want = [Raised("ValueError", True, "expected shape (n, 2)")]
    result = compare(ex, FunctionOutputs((1.0,)), want, parameters_for(ex, "s1000001"),
                     (1e-9, [1e-9]))
    assert (result.ok, result.tag) == (False, "degenerate")
