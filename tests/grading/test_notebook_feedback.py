"""task() and check() in the student's notebook: a mistyped id, an empty STUDENT_ID."""

from __future__ import annotations

import pytest

from photolib.grading import notebook
from photolib.grading.exercises import chapters, exercise
from photolib.grading.notebook import NO_STUDENT_ID, StudentIdMissing, parameters_for


@pytest.fixture
def namespace(monkeypatch):
    ns = {}
    monkeypatch.setattr(notebook, "_namespace", lambda: ns)
    return ns


@pytest.mark.parametrize("typed, suggested", [
    ("rot.opk-matirx", "'rot.opk-matrix'"),
    ("rot.opk_matrix", "'rot.opk-matrix'"),
    ("bun.sigma-0", "'bun.sigma0'"),
    ("col.projec", "'col.project'"),
])
def test_mistyped_id_suggests_the_nearest(namespace, capsys, typed, suggested):
    notebook.check(typed)
    out = capsys.readouterr().out.strip()
    assert out == f"check: unknown exercise id {typed!r}; did you mean {suggested}?"


def test_unknown_id_lists_at_most_its_prefix(namespace, capsys):
    notebook.check("rot.zzz")
    out = capsys.readouterr().out
    rot = sorted(e.id for exs in chapters().values() for e in exs if e.id.startswith("rot."))
    assert str(rot) in out
    assert "col." not in out                                   # not the 70 other ids
    notebook.check("nope")
    assert capsys.readouterr().out.strip() == (
        "check: unknown exercise id 'nope'; the ids are those of the task(...) cells in the "
        "chapter notebooks")


@pytest.mark.parametrize("sid", ["", "   "])
def test_empty_student_id_issues_no_numbers(namespace, capsys, sid):
    namespace["STUDENT_ID"] = sid
    ex = exercise("rot.opk-matrix")
    p = notebook.task(ex.id)
    out = capsys.readouterr().out
    assert out.strip() == f"✋ rot.opk-matrix: {NO_STUDENT_ID}"      # one line, no statement
    numbers = parameters_for(ex, sid)
    assert not any(f"{v}" in out for v in numbers.values() if isinstance(v, float))
    with pytest.raises(StudentIdMissing, match="STUDENT_ID is empty"):
        _ = p.omega_gon
    with pytest.raises(StudentIdMissing):
        p["omega_gon"]


def test_empty_student_id_check_does_not_judge(namespace, capsys):
    """An answer is not judged against the empty id's numbers; an untouched one is unanswered."""
    ex = exercise("rot.opk-matrix")
    namespace.update(STUDENT_ID="", **{ex.answer: ...})
    notebook.check(ex.id)
    assert capsys.readouterr().out.strip() == "… rot.opk-matrix: not answered yet"
    namespace[ex.answer] = ex.reference(parameters_for(ex, ""))    # right for nobody's numbers
    notebook.check(ex.id)
    assert capsys.readouterr().out.strip() == f"✋ rot.opk-matrix: {NO_STUDENT_ID}"
    namespace["STUDENT_ID"] = "s1000001"
    namespace[ex.answer] = ex.reference(parameters_for(ex, "s1000001"))
    notebook.check(ex.id)
    assert capsys.readouterr().out.strip() == "✔ rot.opk-matrix: correct"
