"""Task statements that read like a textbook (issue 14 point 2).

* The Markdown :func:`photolib.grading.task` displays keeps every number whole: outside
  maths a number is in a no-wrap span with a proper minus (U+2212); lists are LaTeX arrays.
* Every exercise of every chapter states the precision it asks (in words, or by the line
  derived from the tolerance), and for many students the reference rounded as stated is
  judged correct: the stated precision is never looser than the judge's tolerance.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from photolib.grading.exercises import chapters
from photolib.grading.notebook import parameters_for, precision_line, statement_texts
from photolib.grading.precision import ROUNDED_KINDS, Precision, for_variant, stated_in_words
from photolib.grading.spec import Exercise
from photolib.grading.statement import render

from .chapter_checks import judge_as_grader

ALL = [ex for exs in chapters().values() for ex in exs]
STUDENTS = tuple(f"prec{i:03d}" for i in range(12))


def _outside_maths(markdown: str) -> str:
    """The Markdown less maths, code spans and the no-wrap spans (their numbers are safe)."""
    text = re.sub(r"\$\$.*?\$\$", " ", markdown, flags=re.S)
    text = re.sub(r"(?<!\\)\$[^$]*\$", " ", text)
    text = re.sub(r"`[^`]*`", " ", text)
    return re.sub(r'<span style="white-space:nowrap">[^<]*</span>', " ", text)


@pytest.mark.parametrize("ex", ALL, ids=lambda ex: ex.id)
def test_numbers_are_kept_whole_and_signed_with_a_minus(ex):
    for sid in STUDENTS[:4]:
        params = parameters_for(ex, sid)
        markdown, plain = statement_texts(ex, params)
        rest = _outside_maths(markdown)
        # a hyphen-minus before a digit is where a browser breaks "-" / "1.5"
        assert not re.search(r"(?<![\w])-\d", rest), (ex.id, sid, rest)
        # every number the parameters print outside maths is in a no-wrap span
        for value in params.values():
            if isinstance(value, float) and f"{value}" in plain and value < 0:
                assert f"{value}" not in rest, (ex.id, value)
        assert ex.title in markdown and ex.params_name in markdown


def test_rendering_puts_fields_in_maths_and_lists_in_arrays():
    md = render("Rotate by $\\kappa = {k}$ gon; v = {v} mm; w = {w}.",
                {"k": -263.0354, "v": [-1.5, 2.25], "w": -0.5})
    assert "$\\kappa = -263.0354$" in md
    assert "\\begin{bmatrix} -1.5 & 2.25 \\end{bmatrix}" in md
    assert '<span style="white-space:nowrap">−0.5</span>' in md
    md = render("Points {P}", {"P": [[1.0, 2.0], [3.0, -4.0]]})
    assert "1.0 & 2.0 \\\\ 3.0 & -4.0" in md
    # a printed matrix in a text field becomes a matrix; intra-word * stays text
    md = render("R =\n{m}; x*1 = E", {"m": "[[ 1.0, -2.0],\n [ 3.0,  4.0]]"})
    assert "\\begin{bmatrix} 1.0 & -2.0 \\\\ 3.0 & 4.0 \\end{bmatrix}" in md
    assert "x\\*1" in md


def test_a_name_with_a_numbered_field_stays_whole():
    # the browser broke chapter 12's "aerial2-" / "008" at the hyphen
    md = render("images aerial2-{j:03d} and aerial2-{i:03d}; x = -{k}", {"j": 8, "i": 9, "k": 2})
    outer = r'<span style="white-space:nowrap">{}<span style="white-space:nowrap">{}</span></span>'
    assert outer.format("aerial2-", "008") in md and outer.format("aerial2-", "009") in md, md
    # a hyphen typed before a field after a space is a minus, kept with its number
    assert outer.format("−", "2") in md, md


def test_the_statement_of_a_split_number_of_today_is_whole():
    # issue 14: "v = [-" / "1.5, …" read as +1.5: bun.sigma0 printed v as a plain list
    ex = next(ex for ex in ALL if ex.id == "bun.sigma0")
    markdown, _ = statement_texts(ex, parameters_for(ex, "s1"))
    assert "[-" not in _outside_maths(markdown) and "\\begin{bmatrix}" in markdown


@pytest.mark.parametrize("phrase, precision", [
    ("give x to 0.01 mm", Precision("decimal", 0.01, "mm")),
    ("to 3 significant digits", Precision("significant", 3)),
    ("to 4 significant figures", Precision("significant", 4)),
    ("to 2 decimals", Precision("decimal", 0.01)),
    ("as (x_m, y_m) in mm, to 1e-6 mm.", Precision("decimal", 1e-6, "mm")),
    ("to 0.001°", Precision("decimal", 0.001, "°")),
    ("in µm, to 0.1 µm", Precision("decimal", 0.1, "µm")),
])
def test_precision_in_words_is_read(phrase, precision):
    assert stated_in_words(phrase) == precision


def test_no_precision_in_words_where_there_is_none():
    assert stated_in_words("A camera 20 m above the ground has c = 100 mm.") is None


def _rounded_reference_is_accepted(ex, sid):
    params = parameters_for(ex, sid)
    statement = ex.statement.format(**params)
    precision, in_words = for_variant(ex, params, statement)
    assert precision is not None, f"{ex.id}: no precision stated"
    ref = np.asarray(ex.reference(params), float)
    rtol, atol = ex.tolerances(params)
    tol = np.broadcast_to(np.asarray(atol, float), ref.shape) + rtol * np.abs(ref)
    # not looser than the tolerance: the worst rounding as stated stays within it
    assert np.all(precision.half(ref) <= tol * (1 + 1e-9)), (ex.id, sid, precision)
    answer = precision.round(ref)
    if ex.kind == "number":
        answer = float(answer)
    verdict = judge_as_grader(ex, sid, answer)
    assert verdict.correct, (ex.id, sid, precision.text(), verdict.message)
    return in_words


@pytest.mark.parametrize("ex", [ex for ex in ALL if ex.kind in ROUNDED_KINDS],
                         ids=lambda ex: ex.id)
def test_an_answer_rounded_as_asked_is_accepted(ex):
    for sid in STUDENTS:
        _rounded_reference_is_accepted(ex, sid)


@pytest.mark.parametrize("ex", ALL, ids=lambda ex: ex.id)
def test_every_exercise_states_its_precision(ex):
    params = parameters_for(ex, STUDENTS[0])
    statement = ex.statement.format(**params)
    line = precision_line(ex, params)
    if ex.kind in ("expression", "choice"):
        return                          # a formula or an option is exact
    assert line or stated_in_words(statement), f"{ex.id} states no precision"
    markdown, plain = statement_texts(ex, params)
    if line:
        assert line in plain and line in markdown


def test_a_statement_that_states_its_precision_gets_no_second_line():
    ex = Exercise(id="demo.words", points=1, title="t", kind="number", answer="x",
                  statement="Give x = {a} in mm to 0.01 mm.", parameters=lambda rng: {"a": 1.5},
                  reference=lambda p: p["a"], rtol=0, atol=0.006)
    assert precision_line(ex, ex.parameters(None)) == ""
    precision, in_words = for_variant(ex, ex.parameters(None))
    assert in_words and precision == Precision("decimal", 0.01, "mm")


def test_the_derived_precision_follows_the_tolerance():
    ex = Exercise(id="demo.derived", points=1, title="t", kind="number", answer="x",
                  statement="x in mm", parameters=lambda rng: {"a": 12.3456},
                  reference=lambda p: p["a"], rtol=0, atol=0.0007)
    p = ex.parameters(None)
    assert precision_line(ex, p) == "Give x to 0.001 mm (or more precisely)."
    ex2 = Exercise(id="demo.override", points=1, title="t", kind="number", answer="x",
                   statement="x", parameters=lambda rng: {"a": 12.3456},
                   reference=lambda p: p["a"], rtol=0, atol=0.0007,
                   precision="to 0.01 mm")
    assert for_variant(ex2, p) == (Precision("decimal", 0.01, "mm"), False)


def test_a_precision_in_another_length_unit_is_converted_to_the_answers():
    ex = Exercise(id="demo.units", points=1, title="t", kind="number", answer="x",
                  statement="Give the height in m, to 1 mm.", parameters=lambda rng: {},
                  reference=lambda p: 12.3456, rtol=0, atol=0.0006)
    precision, in_words = for_variant(ex, ex.parameters(None))
    assert in_words and precision == Precision("decimal", 0.001, "m")
    assert precision.round(12.3456) == 12.346
