"""A grader an instructor can leave alone with a class: Ctrl-C, stray notebooks, ids, outputs.

Each test runs the grading command as an instructor does (a process of its own) where the
behaviour is the command's: stopping it with SIGINT once and twice, refusing an output path
in a submissions folder, choosing the chapter by majority; the gradebook's duplicate-id flag
is tested on :class:`~photolib.grading.report.Gradebook` itself.
"""

from __future__ import annotations

import copy
import csv
import json
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import nbformat
import pytest

from photolib.grading.batch import Graded
from photolib.grading.judge import Judgement
from photolib.grading.report import Gradebook
from photolib.grading.sandbox import _cgroup_root, sandbox_support

from .conftest import MASTER, ROOT

ENV = dict(os.environ, PYTHONPATH=str(ROOT))


def _grade(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "photolib", "grade", *map(str, args),
                           "--no-progress"], cwd=ROOT, capture_output=True, text=True,
                          env=ENV, timeout=timeout)


def _rows(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


# -- point 6: no output in a submissions folder ----------------------------------------------
@pytest.mark.slow  # grading commands of their own (imports: seconds each)
def test_an_output_path_in_a_submissions_folder_is_refused(tmp_path):
    subs = tmp_path / "subs"
    (subs / "deeper").mkdir(parents=True)
    sub = subs / "s1-00-start.ipynb"
    sub.write_text(MASTER.read_text(encoding="utf-8"), encoding="utf-8")
    for option, path in (("--out", subs / "gb.csv"), ("--out", subs / "deeper" / "x" / "gb.csv"),
                         ("--feedback", subs / "feedback")):
        extra = ["--out", tmp_path / "ok.csv"] if option == "--feedback" else []
        done = _grade(sub, option, path, *extra)
        assert done.returncode == 2, done.stderr
        assert f"refusing {option} {path}: it lies in {subs}" in done.stderr, done.stderr
        assert str(sub) in done.stderr  # names the submission whose folder it is
    assert sorted(p.name for p in subs.rglob("*")) == ["deeper", sub.name]  # nothing written
    assert not (tmp_path / "ok.csv").exists()


# -- point 7: the chapter by majority; duplicate ids -------------------------------------------
@pytest.mark.slow  # grading commands of their own (imports: seconds each)
def test_a_tie_of_chapters_is_refused_with_the_list(tmp_path):
    # missing files: the chapter is decided on the names before anything is read or run
    a, b = tmp_path / "subs" / "a-02-optics.ipynb", tmp_path / "subs" / "b-00-start.ipynb"
    done = _grade(a, b, "--out", tmp_path / "book" / "gb.csv")
    assert done.returncode == 2, done.stderr
    assert "a tie without a chapter named by more than half" in done.stderr, done.stderr
    assert "00-start: 1 (b-00-start.ipynb)" in done.stderr
    assert "02-optics: 1 (a-02-optics.ipynb)" in done.stderr
    assert "--chapter" in done.stderr
    assert not (tmp_path / "book" / "gb.csv").exists()


@pytest.mark.slow
def test_one_stray_notebook_does_not_set_the_chapter(tmp_path):
    """The stray comes first; the class's chapter is the one most file names name."""
    subs = tmp_path / "subs"
    subs.mkdir()
    stray = subs / "a-02-optics.ipynb"
    stray.write_text((ROOT / "solutions" / "02-optics.ipynb").read_text(encoding="utf-8"),
                     encoding="utf-8")
    broken = [subs / "b-00-start.ipynb", subs / "c-00-start.ipynb"]  # no kernel needed
    for p in broken:
        p.write_text("{ not JSON", encoding="utf-8")
    out = tmp_path / "book" / "gb.csv"
    done = _grade(stray, *broken, "--out", out)
    assert done.returncode == 0, done.stderr
    assert "chapter 00-start, named by 2 of the 3" in done.stderr, done.stderr
    assert "a-02-optics.ipynb" in done.stderr
    rows = {Path(r["submission"]).name: r for r in _rows(out)}
    assert {r["chapter"] for r in rows.values()} == {"00-start"}
    assert rows["a-02-optics.ipynb"]["status"] == "wrong-chapter"
    assert rows["b-00-start.ipynb"]["status"] == "invalid-json"
    assert "demo.image-scale" in rows["b-00-start.ipynb"]  # the 00-start columns


def _graded(path, sid, status="ok", detail="", points=2.0):
    return Graded(str(path), sid, status, detail, "00-start",
                  [Judgement("demo.image-scale", "correct", points, 2.0, "")])


def test_duplicate_ids_flag_both_rows_until_one_is_fixed(tmp_path):
    out = tmp_path / "gb.csv"
    a, b, c = (tmp_path / f"{n}-00-start.ipynb" for n in "abc")
    book = Gradebook(out, ["demo.image-scale"])
    book.add(_graded(a, "s1", "cell-errors", "cell 3: NameError: x"))
    book.add(_graded(b, "s2"))
    book.add(_graded(c, "s1", points=1.0))
    rows = {Path(r["submission"]).name: r for r in _rows(out)}
    assert [rows[n]["status"] for n in (a.name, b.name, c.name)] == \
        ["duplicate-id", "ok", "duplicate-id"]
    assert rows[a.name]["detail"] == ("student id s1 is also the id of c-00-start.ipynb: check "
                                      "both against the roster; graded cell-errors: cell 3: "
                                      "NameError: x")
    assert "also the id of a-00-start.ipynb" in rows[c.name]["detail"]
    assert (rows[a.name]["total"], rows[c.name]["total"]) == ("2", "1")  # points kept
    assert sorted(r["status"] for r in book.records()) == ["duplicate-id", "duplicate-id", "ok"]
    # a later run resumes the gradebook; c is regraded with the id corrected (--force)
    book = Gradebook(out, ["demo.image-scale"])
    book.add(_graded(c, "s3"))
    rows = {Path(r["submission"]).name: r for r in _rows(out)}
    assert (rows[a.name]["status"], rows[a.name]["detail"]) == ("cell-errors",
                                                                "cell 3: NameError: x")
    assert rows[c.name]["status"] == "ok"
    assert [r["status"] for r in book.records()] == ["cell-errors", "ok", "ok"]


# -- point 5: Ctrl-C ------------------------------------------------------------------------
#: a cell that runs far longer than the test waits: its submission is running at the SIGINT
SLOW_CELL = "import time\ntime.sleep(60)"


def _class(folder: Path, slow: bool) -> list[Path]:
    """Six submissions of 00-start with ids s0..s5; all but the first two sleep if ``slow``."""
    from photolib.grading.exercises import exercise
    from photolib.grading.notebook import parameters_for
    choice = exercise("demo.inverse-choice")
    master = nbformat.read(MASTER, as_version=4)
    paths = []
    for i in range(6):
        nb = copy.deepcopy(master)
        key = choice.reference(parameters_for(choice, f"s{i}"))
        for cell in nb.cells:
            cell.source = cell.source.replace("demo-student", f"s{i}").replace(
                'choice_inverse = "d"', f'choice_inverse = "{key}"')
        if slow and i >= 2:
            nb.cells.append(nbformat.v4.new_code_cell(SLOW_CELL))
        path = folder / f"s{i}-00-start.ipynb"
        nbformat.write(nb, path)
        paths.append(path)
    return paths


def _children(pid: int) -> dict[int, str]:
    """Processes whose parent is ``pid``: command lines by process id."""
    found = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            ppid = int(Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()[1])
            if ppid == pid:
                found[int(entry)] = Path(f"/proc/{entry}/cmdline").read_bytes().decode(
                    errors="replace").replace("\0", " ")
        except (OSError, IndexError, ValueError):
            continue
    return found


def _alive(pid: int, cmdline: str) -> bool:
    try:
        now = Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace")
    except OSError:
        return False
    return now.replace("\0", " ") == cmdline  # the same process, not a reused id


def _interrupt(tmp_path, signals: int):
    """Start grading the slow class, SIGINT ``signals`` times once two rows are written.

    Returns what the checks need: the process, its stderr, the seconds from the first
    signal to its exit, the gradebook, the submissions and the grader's children (kernels
    and judge workers) seen just before the signal.
    """
    subs = tmp_path / "subs"
    subs.mkdir()
    paths = _class(subs, slow=True)
    out = tmp_path / "book" / "gb.csv"
    args = [*map(str, paths), "--out", str(out), "--jobs", "2", "--timeout", "100",
            "--no-progress"]
    proc = subprocess.Popen([sys.executable, "-m", "photolib", "grade", *args], cwd=ROOT,
                            env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        end = time.monotonic() + 120
        while time.monotonic() < end and proc.poll() is None:
            if out.exists() and len(out.read_text().splitlines()) >= 3:
                break
            time.sleep(0.1)
        assert proc.poll() is None, proc.communicate()[1]
        time.sleep(1.0)  # s2 and s3 are in their sleeping cell now
        children = _children(proc.pid)
        kernels = {p: c for p, c in children.items() if "ipykernel_launcher" in c}
        assert len(kernels) >= 2, children
        t0 = time.monotonic()
        proc.send_signal(signal.SIGINT)
        for _ in range(signals - 1):
            time.sleep(0.3)
            proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=60)
        seconds = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc, stderr, seconds, out, paths, children


def _nothing_left(proc, children):
    for pid, cmdline in children.items():
        assert not _alive(pid, cmdline), f"left running: {pid} {cmdline}"
    for cmdline in children.values():  # each kernel's folder: sockets, working copy, home
        if "ipykernel_launcher" in cmdline:
            folder = Path(cmdline.split(" -f ")[1].split()[0]).parents[1]
            assert not folder.exists(), folder
    if sandbox_support().own_user:
        from photolib.grading.sandbox import UidPool
        assert UidPool().orphans() == []  # no process of a sandbox user nobody holds
    root = _cgroup_root()
    for _, parent in root.parents:
        assert not [n for n in os.listdir(parent)
                    if n.startswith(f"photolib-grading-{proc.pid}-")], parent
    mounts = Path("/proc/self/mountinfo").read_text()
    assert "photolib-grade-" not in mounts and "photolib-sandbox" not in mounts


def _finished_rows_kept(out):
    rows = _rows(out)
    details = [json.loads(line) for line in
               out.with_name(out.name + ".details.jsonl").read_text().splitlines()]
    names = sorted(Path(r["submission"]).name for r in rows)
    # the two quick ones finished; the sleeping ones were abandoned and have no row
    assert names == ["s0-00-start.ipynb", "s1-00-start.ipynb"], rows
    assert [r["status"] for r in rows] == ["ok", "ok"] and {r["total"] for r in rows} == {"11"}
    assert sorted(Path(d["submission"]).name for d in details) == names


@pytest.mark.slow
def test_one_ctrl_c_keeps_the_finished_rows_and_says_how_to_resume(tmp_path):
    proc, stderr, seconds, out, paths, children = _interrupt(tmp_path, 1)
    assert proc.returncode == 130, stderr
    assert seconds < 5.0, (seconds, stderr)
    _nothing_left(proc, children)
    _finished_rows_kept(out)
    assert "2 of 6 submission(s) graded in this run" in stderr
    command = stderr.split("to grade the rest, run the same command again")[1]
    command = shlex.split(command.split(":\n", 1)[1].strip().splitlines()[0])
    # the resumed run grades only the four left (no longer sleeping: a test must end)
    _class(paths[0].parent, slow=False)
    done = subprocess.run(command, cwd=ROOT, env=ENV, capture_output=True, text=True,
                          timeout=180)
    assert done.returncode == 0, done.stderr
    assert "2 submission(s) already in" in done.stderr
    rows = _rows(out)
    assert sorted(Path(r["submission"]).name for r in rows) == [p.name for p in paths]
    assert {r["status"] for r in rows} == {"ok"}


@pytest.mark.slow
def test_a_second_ctrl_c_exits_at_once_and_leaves_nothing(tmp_path):
    proc, stderr, seconds, out, paths, children = _interrupt(tmp_path, 2)
    assert proc.returncode == 130, stderr
    assert seconds < 0.3 + 2.5, (seconds, stderr)  # the second signal came 0.3 s after the first
    assert "interrupted again: abandoning" in stderr
    _nothing_left(proc, children)
    _finished_rows_kept(out)
