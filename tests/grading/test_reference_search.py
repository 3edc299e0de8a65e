"""The instructors' guide's search for notebooks that reach the references matches only those.

Every student copy imports ``check`` and ``task`` from ``photolib.grading``; the search must not
list them (an instructor would read every notebook of the class), and it must list a notebook
that computes an answer from an exercise's reference.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _search_pattern() -> re.Pattern:
    """The extended regex of the guide's ``grep -lE '...' submissions/*.ipynb`` line."""
    guide = (ROOT / "docs" / "instructors.md").read_text(encoding="utf-8")
    found = re.findall(r"^\s*grep -lE '([^']+)' submissions/\*\.ipynb\s*$", guide, re.M)
    assert len(found) == 1, "docs/instructors.md should give exactly one grep -lE line"
    return re.compile(found[0])


def _raw(source: str) -> str:
    """The text grep reads: the notebook file, with the cell source as a JSON string."""
    return json.dumps({"cells": [{"cell_type": "code", "source": source.splitlines(True)}]})


@pytest.mark.parametrize("path", sorted([*ROOT.glob("exercises/*.ipynb"),
                                         *ROOT.glob("solutions/*.ipynb")]),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_course_notebooks_not_listed(path):
    assert not _search_pattern().search(path.read_text(encoding="utf-8"))


@pytest.mark.parametrize("source", [
    'from photolib.grading.spec import exercise\nR = exercise("rot.opk-matrix").reference(p)',
    "import photolib.grading.exercises as ex",
    "from photolib.grading.notebook import parameters_for, reference_outputs",
    "e = get('rot.opk-matrix')\nR = e.reference(parameters_for(e, STUDENT_ID))",
    "from photolib.grading.variants import draw",
    "from photolib.grading import check, task, exercises",
])
def test_reference_use_listed(source):
    assert _search_pattern().search(_raw(source))


@pytest.mark.parametrize("source", [
    "from photolib.grading import check, task",
    'p = task("rot.opk-matrix")\ncheck("rot.opk-matrix")',
    "import photolib as pl\nR = pl.rotation_matrix(p.omega, p.phi, p.kappa)",
])
def test_ordinary_work_not_listed(source):
    assert not _search_pattern().search(_raw(source))
