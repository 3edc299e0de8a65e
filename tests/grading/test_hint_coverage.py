"""Feedback for the near misses (issue 14 point 3), and the share of plausible wrong answers
that get a specific hint (:mod:`tests.grading.hint_coverage`).

Measured with ``python -m tests.grading.hint_coverage`` (3 students, every exercise of every
chapter): 639 of 1764 wrong answers (36.2 %) got a specific hint on the commit this work
started from (8bfb6ae), 1652 of 1764 (93.7 %) after it.
"""

from __future__ import annotations

import numpy as np
import pytest

from photolib.grading.exercises import exercise
from photolib.grading.exercises.ch04_rotations import _derivative
from photolib.grading.exercises.ch10_bundle_adjustment import _contribution
from photolib.grading.notebook import parameters_for

from .chapter_checks import judge_as_grader
from .hint_coverage import FAMILIES, _round_sig, all_exercises, coverage

#: the share measured after this work (93.7 %), less a small margin for new exercises
MEASURED_SHARE = 0.937
MARGIN = 0.03
SID = "s1000001"


def _ref(eid, sid=SID):
    ex = exercise(eid)
    return ex, ex.reference(parameters_for(ex, sid))


@pytest.mark.slow
def test_most_plausible_wrong_answers_get_a_specific_hint():
    hinted, wrong, per_family = coverage(all_exercises())
    assert set(per_family) <= set(FAMILIES)
    assert {"x1000", "x0.001", "x1e6", "x1e-6", "sign", "degrees", "2-digits",
            "unnormalised", "inverse", "x2", "x0.5"} <= set(per_family)
    share = hinted / wrong
    assert share >= MEASURED_SHARE - MARGIN, (
        f"{share:.1%} of {wrong} wrong answers get a specific hint; per family "
        + ", ".join(f"{f}: {h}/{w}" for f, (h, w) in per_family.items()))


def test_two_digits_where_more_are_asked_is_close():
    ex, ref = _ref("col.project")
    verdict = judge_as_grader(ex, SID, _round_sig(ref, 2))
    assert verdict.mistake == "digits", verdict.message
    assert "rounded to 2 significant digits" in verdict.message
    assert "to 0.001 mm" in verdict.message          # the precision the task asks
    ex, ref = _ref("dig.snr-db")
    verdict = judge_as_grader(ex, SID, float(_round_sig(ref, 3)))
    assert verdict.mistake == "digits" and "3 significant digits" in verdict.message


def test_a_slightly_wrong_value_is_not_called_a_rounding():
    ex, ref = _ref("col.project")
    assert judge_as_grader(ex, SID, ref * 1.013).mistake == "other"


def test_a_direction_not_normalised_is_named():
    ex = exercise("rot.ray-direction")
    f = ex.reference(parameters_for(ex, SID))
    verdict = judge_as_grader(ex, SID, lambda *a: 3.7 * np.asarray(f(*a)))
    assert verdict.mistake == "unnormalised", verdict.message
    assert "normalised" in verdict.message


@pytest.mark.slow
def test_the_derivative_of_the_transposed_matrix_is_named():
    ex = exercise("rot.matrix-derivative")
    for sid in ("s1000001", "s1000002", "s1000003"):
        p = parameters_for(ex, sid)
        verdict = judge_as_grader(ex, sid, _derivative(p, transposed=True))
        assert verdict.mistake == "transposed", verdict.message
        assert "derivative of the transposed matrix" in verdict.message


def test_an_inverted_weight_is_named():
    ex = exercise("bun.normal-contribution")
    wrong = _contribution(power=-2)(parameters_for(ex, SID))
    verdict = judge_as_grader(ex, SID, wrong)
    assert verdict.mistake == "weight-inverted", verdict.message
    assert "/σ²" in verdict.message


@pytest.mark.parametrize("eid, factor, words", [
    ("opt.image-distance", 1e3, "in µm where mm are asked"),     # µm for mm, not "mm and m"
    ("opt.image-distance", 1e-3, "in m where mm are asked"),
    ("prd.occluded-length", 1e3, "in mm where m are asked"),
    ("bun.sigma0", 1e-3, "in mm where µm are asked"),
    ("prd.occluded-length", 1e6, "in µm where m are asked"),
])
def test_unit_hints_speak_of_the_answers_unit(eid, factor, words):
    ex, ref = _ref(eid)
    verdict = judge_as_grader(ex, SID, float(np.asarray(ref) * factor))
    assert verdict.mistake in ("units-mm-m", "units-um-m"), verdict.message
    assert words in verdict.message
    if factor == 1e3 and "µm" in words:
        assert "mm and m" not in verdict.message


@pytest.mark.parametrize("factor, tag", [(180 / np.pi, "degrees"), (np.pi / 180, "radians"),
                                         (2.0, "factor-2"), (0.5, "factor-2")])
def test_angle_units_and_factor_two_are_named(factor, tag):
    ex, ref = _ref("opt.image-distance")
    assert judge_as_grader(ex, SID, float(ref * factor)).mistake == tag


def test_the_reciprocal_is_named_only_apart_from_the_reference():
    ex, ref = _ref("bun.critical-t")
    assert judge_as_grader(ex, SID, 1.0 / ref).mistake == "reciprocal"
    from photolib.grading import hints
    rule = next(m for m in hints.generic_mistakes(ex) if m.tag == "reciprocal")
    from photolib.grading.spec import Exercise
    one = Exercise(id="demo.one", points=1, title="", statement="", kind="number", answer="x",
                   parameters=lambda rng: {}, reference=lambda p: 1.01)
    assert next(m for m in hints.generic_mistakes(one) if m.tag == "reciprocal").wrong({}) \
        is None and rule.wrong(parameters_for(ex, SID)) is not None
