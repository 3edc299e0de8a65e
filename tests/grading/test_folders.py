"""Every solution master earns full marks; every untouched student copy earns zero."""

from __future__ import annotations

import multiprocessing

import pytest

from photolib.grading.batch import grade_batch
from photolib.grading.exercises import chapters
from photolib.grading.sandbox import Limits

from .conftest import ROOT

MASTERS = sorted(p for p in (ROOT / "solutions").glob("*.ipynb") if p.stem in chapters())
COPIES = sorted(p for p in (ROOT / "exercises").glob("*.ipynb") if p.stem in chapters())


def _grade_in_subprocess(paths, queue):
    results = grade_batch(paths, Limits(timeout=60), jobs=2)
    queue.put({r.submission: r for r in results})


@pytest.fixture(scope="module")
def graded():
    # the grader runs in a process of its own, as an instructor runs it
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_grade_in_subprocess, args=(MASTERS + COPIES, queue))
    proc.start()
    results = queue.get(timeout=240)
    proc.join(timeout=30)
    return results


@pytest.mark.parametrize("path", MASTERS, ids=lambda p: p.name)
def test_master_gets_full_marks(graded, path):
    r = graded[str(path)]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total > 0, [j.message for j in r.judgements]


@pytest.mark.parametrize("path", COPIES, ids=lambda p: p.name)
def test_untouched_copy_gets_zero_without_errors(graded, path):
    r = graded[str(path)]
    assert r.status == "no-student-id", r.detail  # ran top to bottom, only the id is missing
    assert r.detail == ""
    assert r.total == 0 and r.max_total > 0
    assert {j.status for j in r.judgements} == {"not-answered"}


@pytest.mark.parametrize("path", COPIES, ids=lambda p: p.name)
def test_untouched_copy_checks_say_not_answered(graded, path):
    r = graded[str(path)]
    assert r.output.count("not answered yet") == len(chapters()[path.stem])
    assert "Traceback" not in r.output and "Error" not in r.output
