"""collect, return and export (photolib.grading.classroom), without a hub: folders laid out
as the course's JupyterHub lays them out, in a temporary directory."""

from __future__ import annotations

import csv
import io
import os
import pwd
import stat

import nbformat
import pytest

from photolib.__main__ import main
from photolib.grading import classroom
from photolib.grading.report import BASE_COLUMNS, feedback_name

CHAPTER = "04-rotations"


def _notebook(path, student_id):
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(f"STUDENT_ID = {student_id!r}"),
                                         nbformat.v4.new_code_cell("x = 1")])
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(nbformat.writes(nb), encoding="utf-8")


@pytest.fixture
def homes(tmp_path):
    home = tmp_path / "home"
    _notebook(home / "s1000001" / "exercises" / f"{CHAPTER}.ipynb", "s1000001")
    _notebook(home / "s1000002" / "exercises" / f"{CHAPTER}.ipynb", "s1000002")
    _notebook(home / "s1000003" / "exercises" / f"{CHAPTER}.ipynb", "s1000002")  # another's id
    (home / "s1000004" / "exercises").mkdir(parents=True)
    os.symlink(home / "s1000001" / "exercises" / f"{CHAPTER}.ipynb",
               home / "s1000004" / "exercises" / f"{CHAPTER}.ipynb")
    (home / "s1000005").mkdir()                                          # no notebook at all
    return home


def test_collect_checks_the_id_and_keeps_the_copies_private(homes, tmp_path):
    layout = str(homes) + "/{account}/exercises/{chapter}.ipynb"
    rows = {r.account: r for r in classroom.collect(CHAPTER, tmp_path / "in", layout)}
    assert sorted(rows) == ["s1000001", "s1000002", "s1000003", "s1000004"]
    assert not rows["s1000001"].problem and not rows["s1000002"].problem
    assert "STUDENT_ID is 's1000002'" in rows["s1000003"].problem
    assert "symbolic link" in rows["s1000004"].problem
    dest = tmp_path / "in"
    assert stat.S_IMODE(dest.stat().st_mode) == 0o700
    copy = dest / "s1000001" / f"{CHAPTER}.ipynb"
    assert stat.S_IMODE(copy.stat().st_mode) == 0o600
    assert copy.read_text() == (homes / "s1000001" / "exercises" / f"{CHAPTER}.ipynb").read_text()
    assert not (dest / "s1000003").exists()


def test_collect_with_a_roster_and_from_the_command_line(homes, tmp_path, capsys):
    roster = tmp_path / "roster.csv"
    roster.write_text("account,student_id\ns1000001,s1000001\ns1000003,s1000002\n")
    layout = str(homes) + "/{account}/exercises/{chapter}.ipynb"
    code = main(["collect", CHAPTER, "--to", str(tmp_path / "in"), "--layout", layout,
                 "--roster", str(roster)])
    out = capsys.readouterr().out
    assert code == 1 and "2 of 4 notebooks collected" in out          # s1000002, s1000004 out
    assert "s1000002: not in the roster" in out
    with open(tmp_path / "in" / "collect-report.csv", newline="") as f:
        report = list(csv.DictReader(f))
    assert {r["account"]: r["student_id"] for r in report}["s1000003"] == "s1000002"
    with pytest.raises(ValueError, match="no chapter '99-nothing'"):
        classroom.collect("99-nothing", tmp_path / "x", layout)
    with pytest.raises(ValueError, match="must contain"):
        classroom.collect(CHAPTER, tmp_path / "x", str(homes) + "/exercises/{chapter}.ipynb")


def _gradebook(path, rows):
    columns = BASE_COLUMNS + ["rot.opk-matrix", "detail"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in rows:
            w.writerow([r.get(c, "") for c in columns])


def test_export_moodle_and_canvas(tmp_path):
    book = tmp_path / "book.csv"
    _gradebook(book, [
        {"submission": "a", "student_id": "s1000001", "status": "ok", "chapter": CHAPTER,
         "total": "7.5", "max_total": "12"},
        {"submission": "b", "student_id": "s1000002", "status": "duplicate-id",
         "chapter": CHAPTER, "total": "3", "max_total": "12"},
        {"submission": "c", "student_id": "=cmd", "status": "ok", "chapter": CHAPTER,
         "total": "0", "max_total": "12"}])
    moodle = list(csv.reader(io.StringIO(classroom.export_grades(book, "moodle"))))
    # Moodle's CSV grade import: a user-identifying column (mapped to "ID number") and one
    # column per grade item, header row first
    assert moodle[0] == ["ID number", f"photolib {CHAPTER}"]
    assert moodle[1] == ["s1000001", "7.5"] and moodle[2] == ["'=cmd", "0"]
    assert len(moodle) == 3                                      # the duplicate id left out
    canvas = list(csv.reader(io.StringIO(classroom.export_grades(book, "canvas", "Rotations"))))
    # Canvas's gradebook import: Student, ID, SIS User ID, SIS Login ID, Section, then one
    # column per assignment; the optional second row "Points Possible"
    assert canvas[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Rotations"]
    assert canvas[1] == ["Points Possible", "", "", "", "", "12"]
    assert canvas[2] == ["", "", "s1000001", "", "", "7.5"]
    with pytest.raises(ValueError, match="'moodle' or 'canvas'"):
        classroom.export_grades(book, "blackboard")
    _gradebook(book, [{"student_id": "s1", "chapter": CHAPTER, "total": "1", "max_total": "2"},
                      {"student_id": "s2", "chapter": "05-x", "total": "1", "max_total": "2"}])
    with pytest.raises(ValueError, match="one chapter is one grade item"):
        classroom.export_grades(book, "moodle")


@pytest.mark.skipif(os.geteuid() != 0, reason="giving files to another user needs root")
def test_return_gives_each_student_their_own_feedback(tmp_path):
    accounts = [a for a in ("nobody", "daemon", "bin") if _exists(a)][:2]
    if len(accounts) < 2:
        pytest.skip("needs two system accounts (nobody, daemon or bin)")
    collected = tmp_path / "in"
    feedback = tmp_path / "fb"
    feedback.mkdir()
    rows = []
    for account in accounts:
        sub = collected / account / f"{CHAPTER}.ipynb"
        sub.parent.mkdir(parents=True)
        sub.write_text("{}")
        rows.append({"submission": str(sub), "student_id": account, "status": "ok",
                     "chapter": CHAPTER, "total": "1", "max_total": "2"})
        graded = type("G", (), {"student_id": account, "submission": str(sub)})
        (feedback / feedback_name(graded)).write_text(f"# Feedback: {account}\n")
        (tmp_path / "homes" / account).mkdir(parents=True)
    book = tmp_path / "book.csv"
    _gradebook(book, rows)
    layout = str(tmp_path / "homes") + "/{account}/feedback/{chapter}.md"
    done = classroom.return_feedback(CHAPTER, book, feedback, collected, layout)
    assert [a for a, _ in done] == accounts
    for account, path in done:
        info = os.stat(path)
        assert info.st_uid == pwd.getpwnam(account).pw_uid
        assert stat.S_IMODE(info.st_mode) == 0o600
        assert stat.S_IMODE(os.stat(os.path.dirname(path)).st_mode) == 0o700
        with open(path) as f:
            assert f.read() == f"# Feedback: {account}\n"


def _exists(account):
    try:
        pwd.getpwnam(account)
        return True
    except KeyError:
        return False
