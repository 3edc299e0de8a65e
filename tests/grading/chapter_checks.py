"""The checks every graded chapter passes, written once and run per chapter by subclassing.

A chapter's test file declares ``class TestChapterNN(ChapterChecks)`` with its module and
students as class attributes; :meth:`ChapterChecks.pytest_generate_tests` parametrises each
check over that chapter's exercises (``ex``: all of them, ``function_ex``: the function
exercises, ``sid``: the first ``reference_students`` students). Add :class:`BatchGradedChecks`
to grade the chapter's solution master and untouched student copy with the batch grader in
a process of its own. What differs between chapters for real (student ids, how many students
must show a mistake or a different variant, the grader's time limit) is a class attribute;
the chapter-specific checks (independent routes to the references, special hints) stay in
the chapter's file.
"""

from __future__ import annotations

import pickle
import subprocess
import sys

import numpy as np
import pytest

from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import chapter
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for

from .conftest import ROOT

STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


def judge_as_grader(ex, sid, value):
    """Judge ``value`` (an answer, or a function) for student ``sid`` as the grader does."""
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def _exercise_id(ex):
    return ex.id


class ChapterChecks:
    """Reference accepted, every mistake recognised with its hint, variants differ, functions
    judged on hidden scalar cases, untouched answers not answered."""

    module = None                   # the chapter's module in photolib.grading.exercises
    chapter_name = ""               # the name it is registered under, e.g. "08-resection-dlt"
    kinds: frozenset = frozenset()  # answer kinds the chapter must use (at least)
    students = STUDENTS
    reference_students = 2          # the first n students whose reference answer is judged
    mistake_students = None         # who may show a mistake (default: ``students``)
    mistake_limit = None            # stop after this many students showed a mistake
    variant_students = 2            # the first n students of whom some must differ ...
    variant_fallback = ()           # ... or, if they do not, one of these from the first
    scalar_cases = True             # function cases are tuples of floats
    slow_mistakes = frozenset()     # ids whose mistake check takes more than ~2 s: marked slow

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.module is not None and all(ex.kind != "function" for ex in cls.module.EXERCISES):
            cls.test_hidden_inputs_differ_from_the_public_ones = None   # nothing to collect

    def pytest_generate_tests(self, metafunc):
        exercises = self.module.EXERCISES
        if "sid" in metafunc.fixturenames:
            metafunc.parametrize("sid", self.students[:self.reference_students])
        if "ex" in metafunc.fixturenames:
            assert self.slow_mistakes <= {ex.id for ex in exercises}, self.slow_mistakes
            slow = (self.slow_mistakes if metafunc.function.__name__
                    == "test_each_mistake_is_recognised_with_its_hint" else ())
            metafunc.parametrize("ex", [pytest.param(ex, marks=pytest.mark.slow) if ex.id in slow
                                        else ex for ex in exercises], ids=_exercise_id)
        if "function_ex" in metafunc.fixturenames:
            metafunc.parametrize("function_ex", [ex for ex in exercises if ex.kind == "function"],
                                 ids=_exercise_id)

    def test_module_is_the_registered_chapter(self):
        exercises = self.module.EXERCISES
        assert self.module.CHAPTER == self.chapter_name
        assert chapter(self.chapter_name) == exercises
        assert len({ex.id for ex in exercises}) == len(exercises) >= 4
        assert set(self.kinds) <= {ex.kind for ex in exercises}

    def test_reference_is_accepted(self, ex, sid):
        verdict = judge_as_grader(ex, sid, ex.reference(parameters_for(ex, sid)))
        assert verdict.status == "correct", verdict.message
        assert verdict.points == ex.points

    def test_each_mistake_is_recognised_with_its_hint(self, ex):
        assert ex.mistakes, f"{ex.id} declares no mistakes"
        students = self.students if self.mistake_students is None else self.mistake_students
        for index, mistake in enumerate(ex.mistakes):
            applied = 0
            for sid in students:
                wrong = mistake.wrong(parameters_for(ex, sid))
                if wrong is None:
                    continue
                applied += 1
                verdict = judge_as_grader(ex, sid, wrong)
                assert verdict.status == "wrong", (ex.id, index, sid)
                assert verdict.mistake == mistake.tag, (ex.id, index, sid, verdict.message)
                assert verdict.message == f"not correct: {mistake.message}", (ex.id, index, sid)
                if self.mistake_limit is not None and applied >= self.mistake_limit:
                    break
            assert applied, f"{ex.id}: mistake {index} ({mistake.tag}) never applies"

    def test_students_get_different_variants(self, ex):
        first = self.students[0]
        variants = [parameters_for(ex, sid) for sid in self.students[:self.variant_students]]
        if self.variant_fallback and all(p == variants[0] for p in variants[1:]):
            # a variant drawn from few options: some pair of students must differ
            variants.append(next(p for p in (parameters_for(ex, s) for s in self.variant_fallback)
                                 if p != variants[0]))
        assert any(p != variants[0] for p in variants[1:])
        assert parameters_for(ex, first) == variants[0]     # the same student, the same numbers
        assert len({ex.statement.format(**p) for p in variants}) >= 2

    def test_hidden_inputs_differ_from_the_public_ones(self, function_ex):
        ex, sid = function_ex, self.students[0]
        params = parameters_for(ex, sid)
        public = ex.cases(rng_for(sid, ex.id, "public"), params)
        hidden = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        assert len(public) == len(hidden) >= 3
        assert not all(np.array_equal(np.asarray(a[0]), np.asarray(b[0]))
                       for a, b in zip(public, hidden))
        if self.scalar_cases:
            # the batch grader sends each argument to the kernel as one float
            assert public != hidden
            for case in public + hidden:
                assert all(np.ndim(arg) == 0 for arg in case)
                assert [float(a) for a in case] == list(case)

    def test_untouched_answer_is_not_answered(self, ex):
        value = (lambda *args: ...) if ex.kind == "function" else ...
        assert judge_as_grader(ex, self.students[0], value).status == "not-answered"


_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[3:], Limits(timeout=int(sys.argv[2])), jobs=1)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""


class BatchGradedChecks:
    """The solution master gets full marks and the untouched student copy zero, graded by the
    batch grader in a process of its own, as an instructor runs it."""

    grade_timeout = 60              # the grader's per-notebook time limit, in seconds

    # both checks share the class fixture ``graded``, about 5 s of kernels: either run alone
    # pays for it, so both are slow

    @pytest.fixture(scope="class")
    @classmethod
    def graded(cls, tmp_path_factory):
        name = cls.chapter_name
        paths = {"master": ROOT / "solutions" / f"{name}.ipynb",
                 "copy": ROOT / "exercises" / f"{name}.ipynb"}
        out = tmp_path_factory.mktemp(name) / "graded.pickle"
        proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), str(cls.grade_timeout),
                               *map(str, paths.values())],
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-3000:]
        with open(out, "rb") as f:
            results = pickle.load(f)
        return {key: results[str(path)] for key, path in paths.items()}

    @pytest.mark.slow
    def test_master_gets_full_marks(self, graded):
        r = graded["master"]
        assert r.status == "ok", r.detail
        assert r.total == r.max_total == sum(ex.points for ex in self.module.EXERCISES)

    @pytest.mark.slow
    def test_untouched_copy_gets_zero(self, graded):
        r = graded["copy"]
        assert r.status == "no-student-id", r.detail
        # ran top to bottom: the empty id is the only note, and nothing is graded for it
        assert r.detail.startswith("STUDENT_ID is empty; not graded"), r.detail
        assert "cell " not in r.detail, r.detail
        assert r.total == 0 and r.max_total > 0
        assert {j.status for j in r.judgements} == {"not-graded"}
        assert r.output.count("not answered yet") == len(self.module.EXERCISES)
        assert "Traceback" not in r.output
