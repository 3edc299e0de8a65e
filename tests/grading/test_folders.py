"""Every solution master earns full marks; every untouched student copy earns zero."""

from __future__ import annotations

import pickle
import subprocess
import sys

import pytest

from photolib.grading.exercises import chapters

from .conftest import ROOT

# every test reads the module fixture ``graded``, which grades all masters and copies in
# sandboxed kernels (about 20 s): the module is slow
pytestmark = pytest.mark.slow

MASTERS = sorted(p for p in (ROOT / "solutions").glob("*.ipynb") if p.stem in chapters())
COPIES = sorted(p for p in (ROOT / "exercises").glob("*.ipynb") if p.stem in chapters())


_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[2:], Limits(timeout=60), jobs=2)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    # the grader runs in a process of its own, as an instructor runs it
    out = tmp_path_factory.mktemp("folders") / "graded.pickle"
    proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), *map(str, MASTERS + COPIES)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out, "rb") as f:
        return pickle.load(f)


@pytest.mark.parametrize("path", MASTERS, ids=lambda p: p.name)
def test_master_gets_full_marks(graded, path):
    r = graded[str(path)]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total > 0, [j.message for j in r.judgements]


@pytest.mark.parametrize("path", COPIES, ids=lambda p: p.name)
def test_untouched_copy_gets_zero_without_errors(graded, path):
    r = graded[str(path)]
    assert r.status == "no-student-id", r.detail  # ran top to bottom, only the id is missing
    assert r.detail.startswith("STUDENT_ID is empty; not graded"), r.detail
    assert "cell " not in r.detail, r.detail
    assert r.total == 0 and r.max_total > 0
    assert {j.status for j in r.judgements} == {"not-graded"}


@pytest.mark.parametrize("path", COPIES, ids=lambda p: p.name)
def test_untouched_copy_checks_say_not_answered(graded, path):
    r = graded[str(path)]
    assert r.output.count("not answered yet") == len(chapters()[path.stem])
    assert "Traceback" not in r.output and "Error" not in r.output
