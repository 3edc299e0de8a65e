"""Student copies are generated from the masters: regenerate and diff, and format errors."""

from __future__ import annotations

import copy

import pytest

from photolib.grading.assign import AssignError, assign_folder, make_student_copy, render
from photolib.grading.cli import assign_main
from photolib.grading.exercises import chapters

from .conftest import ROOT, cell_index


@pytest.mark.parametrize("name", sorted(chapters()))
def test_committed_student_copy_is_up_to_date(name):
    import nbformat
    master = nbformat.read(ROOT / "solutions" / f"{name}.ipynb", as_version=4)
    committed = (ROOT / "exercises" / f"{name}.ipynb").read_text(encoding="utf-8")
    assert render(make_student_copy(master, name)) == committed, \
        "exercises/ is stale: run python -m photolib assign"


def test_student_copy_has_no_solution_and_no_outputs(untouched):
    text = render(untouched)
    assert "BEGIN SOLUTION" not in text and "demo-student" not in text
    assert all(c.outputs == [] for c in untouched.cells if c.cell_type == "code")
    assert untouched.metadata["photolib"]["chapter"] == "00-start"


def test_assign_check_mode(tmp_path):
    assert assign_main(["--source", str(ROOT / "solutions"), "--dest", str(tmp_path),
                        "--check"]) == 1
    assert not list(tmp_path.iterdir())
    written = assign_folder(ROOT / "solutions", tmp_path)
    assert written == [tmp_path / f"{name}.ipynb" for name in sorted(chapters())]
    assert assign_main(["--source", str(ROOT / "solutions"), "--dest", str(tmp_path),
                        "--check"]) == 0


def test_format_errors_name_the_problem(master):
    nb = copy.deepcopy(master)
    i = cell_index(nb, "answer:demo.rotation-x")
    nb.cells[i].metadata["tags"] = ["answer:demo.no-such"]
    with pytest.raises(AssignError, match="answer:demo.no-such names no exercise"):
        make_student_copy(nb, "00-start")
    nb = copy.deepcopy(master)
    del nb.cells[cell_index(nb, "answer:demo.rotation-x")]
    with pytest.raises(AssignError, match=r"no cell tagged answer:ID for \['demo.rotation-x'\]"):
        make_student_copy(nb, "00-start")
    nb = copy.deepcopy(master)
    i = cell_index(nb, "answer:demo.rotation-x")
    nb.cells[i].source = nb.cells[i].source.replace("### END SOLUTION", "")
    with pytest.raises(AssignError, match="BEGIN SOLUTION without"):
        make_student_copy(nb, "00-start")
