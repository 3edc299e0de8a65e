"""The exercises of chapters 04-06, judged in this process by calling the registry directly.

For every exercise (:class:`chapter_checks.ChapterChecks`): the reference answer is accepted,
the wrong answer of every declared mistake is recognised with that mistake's hint, students
get different variants, functions are judged on hidden scalar cases and an untouched answer
is not answered. Answers travel through :func:`encode_value`/:func:`decode_value` as they do
from a kernel.
"""

from __future__ import annotations

from photolib.grading.exercises import ch04_rotations, ch05_interior_orientation, ch06_collinearity

from .chapter_checks import ChapterChecks

STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


class TestChapter04(ChapterChecks):
    module = ch04_rotations
    chapter_name = "04-rotations"
    kinds = {"expression", "function"}
    students = STUDENTS


class TestChapter05(ChapterChecks):
    module = ch05_interior_orientation
    chapter_name = "05-interior-orientation"
    kinds = {"expression", "function"}
    students = STUDENTS


class TestChapter06(ChapterChecks):
    module = ch06_collinearity
    chapter_name = "06-collinearity"
    kinds = {"expression", "function"}
    students = STUDENTS


def test_every_answer_kind_is_used():
    modules = (ch04_rotations, ch05_interior_orientation, ch06_collinearity)
    kinds = {ex.kind for module in modules for ex in module.EXERCISES}
    assert {"number", "array", "rotation", "expression", "function"} <= kinds
