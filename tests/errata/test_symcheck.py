"""photolib.symcheck: every verdict kind, the time budget and the safe parser."""

import threading
import time

import mpmath
import pytest
import sympy as sp

from photolib.symcheck import UnsafeExpressionError, Verdict, equivalent, parse_expression

x, y = sp.symbols("x y", real=True)


def test_equal_exact_and_numeric():
    v = equivalent(sp.sin(x) ** 2 + sp.cos(x) ** 2, 1)
    assert v.kind == "equal" and bool(v) and v.method.startswith("exact")
    # atan identity SymPy's cheap routes do not prove: decided by sampling
    v = equivalent(sp.atan(x) + sp.atan(1 / x), sp.pi / 2 * sp.sign(x))
    assert v.kind == "equal"


def test_not_equal_counterexample_reevaluates():
    a, b = (x + y) ** 2, x**2 + y**2
    v = equivalent(a, b)
    assert v.kind == "not-equal" and not v
    with mpmath.workdps(50):
        va = a.evalf(50, subs=v.counterexample)
        vb = b.evalf(50, subs=v.counterexample)
    assert abs(va - vb) > 1e-10
    assert abs(va - v.values[0]) < 1e-30


def test_equal_under_given_condition_and_positive_domain():
    A, F = sp.symbols("A F", real=True)
    v = equivalent(sp.sqrt(1 - A * F) + A, sp.sqrt(1 - F) + 1, assumptions={A: 1})
    assert v.kind == "equal-under-condition" and v.condition == {A: 1} and not v
    v = equivalent(sp.sqrt(x**2), x)
    assert v.kind == "equal-under-condition" and v.condition == "all symbols > 0"
    assert v.counterexample[x] < 0


def test_matrices_and_shapes():
    assert equivalent(sp.Matrix([[x, 1]]), sp.Matrix([[x, 1]])).kind == "equal"
    assert equivalent(sp.Matrix([x, 1]), sp.Matrix([[x, 1]])).kind == "not-equal"


@pytest.mark.slow
def test_undecided_undefined_function_and_budget():
    f = sp.Function("f")
    assert equivalent(f(x), f(x) + x * 0 + sp.sin(x) - sp.sin(x) + f(y) - f(y)).kind in (
        "equal", "undecided")
    assert equivalent(f(x), f(y)).kind == "undecided"
    big_a = sum(sp.cos(k * x) ** k * sp.sin(y) ** (k % 7) for k in range(1, 600))
    # every term times an identity equal to 1 (sin(x + y) − sin x cos y − cos x sin y + 1):
    # added to big_a as one term instead, the 599 terms cancel on subtraction and trigsimp
    # decides the rest at once
    one = sp.sin(x + y) - sp.sin(x) * sp.cos(y) - sp.cos(x) * sp.sin(y) + 1
    big_b = sum(sp.cos(k * x) ** k * sp.sin(y) ** (k % 7) * one for k in range(1, 600))
    t = time.process_time()  # the budget is CPU time: a loaded CI machine must not matter
    v = equivalent(big_a, big_b, time_budget=0.05, samples=50)
    assert v.kind == "undecided"
    assert time.process_time() - t < 5.0


def _new_threads(before):
    return [t for t in threading.enumerate() if t not in before and t.is_alive()]


def test_route_cut_by_the_budget_stops_computing():
    # chapter 06 compares Luhmann's 4.18 with the SymPy Jacobian: trigsimp outlives its budget
    # and must not go on in the background, where it took the GIL from the next cells of the
    # notebook and the CPU-time budget from the next verdicts
    from photolib.derive import collinearity as dc

    L, J = dc.luhmann_418(), dc.jacobian()
    kx, ky, N, zq = dc.luhmann_symbols()
    k = dc.k_vector()
    given = {kx: k[0], ky: k[1], N: k[2], zq: -dc.c}
    luhmann = sp.Matrix([[L[n][i].subs(given) for n in dc.PARAMETERS] for i in range(2)])
    derived = sp.Matrix([[J[n][i] for n in dc.PARAMETERS] for i in range(2)])
    before = set(threading.enumerate())
    v = equivalent(luhmann, derived, samples=6)
    assert v.kind == "equal"
    assert _new_threads(before) == []
    # and the cut-off route leaves the next verdict its whole budget
    t = time.process_time()
    assert equivalent(sp.sin(x) ** 2, 1 - sp.cos(x) ** 2).kind == "equal"
    assert time.process_time() - t < 1.0


def test_cancelled_route_reports_not_done():
    from photolib import symcheck

    def spin():
        while True:
            sum(range(1000))

    before = set(threading.enumerate())
    t = time.monotonic()
    assert symcheck._run_bounded(spin, 0.05) == (False, None)
    assert time.monotonic() - t < 2.0
    assert _new_threads(before) == []
    assert symcheck._run_bounded(lambda: 42, 5.0) == (True, 42)
    assert symcheck._run_bounded(lambda: 1 / 0, 5.0) == (False, None)


def test_bad_arguments():
    with pytest.raises(ValueError, match="time_budget"):
        equivalent(x, x, time_budget=0)
    with pytest.raises(ValueError, match="kind"):
        Verdict("maybe", "none")


@pytest.mark.parametrize("text, word", [
    ("__import__('os')", "__import__"), ("().__class__", "attribute"), ("x.real", "attribute"),
    ("lambda: 1", "lambda"), ("[i for i in x]", "comprehension"), ("'abc'", "str"),
    ("x[0]", "subscript"), ("eval('1')", "eval"), ("open('f')", "open"), ("x if y else 1", "conditional"),
    ("__builtins__", "underscore"), ("x ^ 2", "use **"), ("2**10**10", "too large"),
    ("(x, y)", "tuple"), ("sin(x=1)", "keyword"), ("f(x)(y)", "call"), ("x == y", "comparison"),
])
def test_parser_rejects(text, word):
    with pytest.raises(UnsafeExpressionError, match=word.replace("*", r"\*")):
        parse_expression(text)


def test_parser_accepts_and_binds_symbols():
    c = sp.Symbol("c", positive=True)
    e = parse_expression("-c*sqrt(x**2 + 1)/atan2(y, 2) + pi", {"c": c})
    assert e == -c * sp.sqrt(sp.Symbol("x", real=True) ** 2 + 1) / sp.atan2(
        sp.Symbol("y", real=True), 2) + sp.pi
    assert parse_expression("x'") == sp.Symbol("x_p", real=True)
    assert isinstance(UnsafeExpressionError("m"), ValueError)


@pytest.mark.parametrize("text", ["f**", "(x + 1", "", "x ^ 2", "2 +* x"])
def test_a_typo_is_a_formula_syntax_error(text):
    from photolib.symcheck import FormulaSyntaxError
    with pytest.raises(FormulaSyntaxError):
        parse_expression(text)


@pytest.mark.parametrize("text", ["__import__('os')", "x.real", "open('f')", "x[0]"])
def test_code_is_unsafe_but_not_a_syntax_error(text):
    from photolib.symcheck import FormulaSyntaxError
    with pytest.raises(UnsafeExpressionError) as info:
        parse_expression(text)
    assert not isinstance(info.value, FormulaSyntaxError)
