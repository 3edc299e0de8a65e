"""Hostile and broken submissions, graded in one batch next to a normal one.

Each fixture notebook is built here with nbformat from the demo master (full marks) or its
untouched student copy (zero). Every one must end as a clear gradebook row, and the normal
submission in the same batch must still get full marks.
"""

from __future__ import annotations

import copy
import csv
import os
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest

from photolib.grading.sandbox import RESULT_MIME, sandbox_support

from .conftest import MASTER, ROOT, cell_index, with_cell

TIMEOUT = 12
JUDGE = ROOT / "photolib" / "grading" / "judge.py"

MONKEYPATCH = """
import numpy as np
import photolib.grading.judge as j, photolib.grading.encode as e, photolib.grading as g
np.isclose = lambda *a, **k: True
np.allclose = lambda *a, **k: True
j.judge = lambda *a, **k: None
j._numbers_match = lambda *a, **k: True
e.decode_value = lambda d: 1.0
g.check = lambda *a: print("correct")
"""

FORGE = f"""
from IPython.display import publish_display_data
fake = {{"nonce": "0" * 32, "student_id": {{"t": "str", "v": "demo-student"}},
        "answers": {{"scale_number": {{"value": {{"t": "num", "v": "1.0"}}}}}}}}
publish_display_data({{{RESULT_MIME!r}: fake}})
def forge(info):
    import re
    m = re.search(r"_photolib_extract_([0-9a-f]+)", info.raw_cell or "")
    if m:
        publish_display_data({{{RESULT_MIME!r}: dict(fake, nonce=m.group(1))}})
get_ipython().events.register("pre_run_cell", forge)
"""


def _variants(master, untouched, sandbox_dir: Path):
    """name -> notebook (or raw text) of the hostile corpus."""
    out = {}
    out["normal"] = master
    out["infinite-loop"] = with_cell(master, "while True:\n    pass")
    out["memory-bomb"] = with_cell(master, "hog = bytearray(64 * 1024 ** 3)")
    if sandbox_support().own_user:  # only a user of its own gets a process limit
        out["fork-bomb"] = with_cell(
            master, "import os, time\nwhile True:\n    if os.fork() == 0:\n"
                    "        time.sleep(600)\n        os._exit(0)", at=3)
    out["os-exit"] = with_cell(master, "import os\nos._exit(1)", at=5)
    out["sys-exit"] = with_cell(master, "import sys\nsys.exit(3)", at=5)
    out["segfault"] = with_cell(master, "import ctypes\nctypes.string_at(0)", at=5)
    out["network"] = with_cell(
        master, "import socket\nsocket.create_connection(('1.1.1.1', 80), timeout=3)")
    out["write-outside"] = with_cell(
        master, f"open({str(sandbox_dir / 'pwned.txt')!r}, 'w').write('x')\n"
                f"open({str(JUDGE)!r}, 'a').write('# pwned')")
    out["monkeypatch"] = with_cell(untouched, 'STUDENT_ID = "demo-student"\n' + MONKEYPATCH
                                   + "scale_number = 1.0\nR2 = [[1, 0], [0, 2]]")
    out["forge"] = with_cell(untouched, 'STUDENT_ID = "demo-student"\n' + FORGE)
    out["huge-output"] = with_cell(master, "print('x' * 30_000_000)\nfor i in range(3000):\n"
                                           "    print('spam', i)")
    out["not-json"] = "{ this is not JSON"
    out["nbformat3"] = nbformat.writes(nbformat.convert(copy.deepcopy(master), 3))
    deleted = copy.deepcopy(master)
    del deleted.cells[cell_index(deleted, "answer:demo.rotation-x")]
    out["deleted-cell"] = deleted
    reordered = copy.deepcopy(master)
    first = cell_index(reordered, "## 1 ·")
    last = cell_index(reordered, "## 6 ·")
    reordered.cells = reordered.cells[:first] + reordered.cells[last:] + \
        reordered.cells[first:last]
    out["reordered"] = reordered
    duplicated = copy.deepcopy(master)
    i = cell_index(duplicated, "answer:demo.rotation-2d")
    duplicated.cells.insert(i, copy.deepcopy(duplicated.cells[i]))
    duplicated.cells[i]["id"] = "a-copy"
    out["duplicated-cell"] = duplicated
    out["duplicate-ids"] = "DUPLICATE-IDS"
    out["import-formula"] = with_cell(
        untouched, 'STUDENT_ID = "demo-student"\n'
                   f"R_omega_sym = \"__import__('os').system('touch {sandbox_dir}/formula')\"")
    return out


@pytest.fixture(scope="module")
def corpus(tmp_path_factory, master, untouched):
    folder = tmp_path_factory.mktemp("submissions")
    outside = tmp_path_factory.mktemp("outside")
    os.chmod(outside, 0o700)
    paths = {}
    for name, nb in _variants(master, untouched, outside).items():
        path = folder / f"{name}-00-grading-demo.ipynb"
        if nb == "DUPLICATE-IDS":
            text = MASTER.read_text(encoding="utf-8").replace('"id": "demo-', '"id": "same')
            text = __import__("re").sub(r'"id": "same\d+"', '"id": "same"', text)
            path.write_text(text, encoding="utf-8")
        elif isinstance(nb, str):
            path.write_text(nb, encoding="utf-8")
        else:
            nbformat.write(nb, path)
        paths[name] = path
    judge_before = JUDGE.read_text(encoding="utf-8")
    out = folder / "gradebook.csv"
    # a separate grader process, as an instructor runs it
    done = subprocess.run([sys.executable, "-m", "photolib", "grade", *map(str, paths.values()),
                           "--out", str(out), "--jobs", "2", "--timeout", str(TIMEOUT),
                           "--memory", "1536", "--feedback", str(folder / "feedback"),
                           "--no-progress"], cwd=ROOT, capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=240)
    assert done.returncode == 0, done.stderr
    with out.open(newline="") as f:
        rows = {Path(r["submission"]).name.split("-00-")[0]: r for r in csv.DictReader(f)}
    return {"rows": rows, "outside": outside, "judge_before": judge_before, "folder": folder,
            "paths": paths}


def row(corpus, name):
    return corpus["rows"][name]


FULL, ZERO = "11", "0"


@pytest.mark.parametrize("name, status, total, detail", [
    ("normal", "ok", FULL, ""),
    ("infinite-loop", "timeout", FULL, "time limit"),
    ("memory-bomb", "memory-limit", FULL, "MemoryError"),
    ("fork-bomb", "cell-errors", FULL, "BlockingIOError"),
    ("os-exit", "kernel-restarted", FULL, "killed the kernel"),
    ("sys-exit", "cell-errors", FULL, "SystemExit"),
    ("segfault", "kernel-restarted", FULL, "SIGSEGV"),
    ("network", "cell-errors", FULL, "Network is unreachable"),
    ("monkeypatch", "ok", ZERO, ""),
    ("forge", "tampered", ZERO, "tampered"),
    ("huge-output", "ok", FULL, "characters of output dropped"),
    ("not-json", "invalid-json", ZERO, "not a JSON file"),
    ("nbformat3", "ok", FULL, ""),
    ("deleted-cell", "ok", "9", ""),
    ("reordered", "ok", FULL, ""),
    ("duplicated-cell", "ok", FULL, ""),
    ("duplicate-ids", "ok", FULL, ""),
    ("import-formula", "ok", ZERO, ""),
])
def test_each_submission_ends_as_a_clear_row(corpus, name, status, total, detail):
    if name == "fork-bomb" and not sandbox_support().own_user:
        pytest.skip("kernels run as the grader's user here: no per-user process limit, "
                    "so the fork bomb is not run")
    r = row(corpus, name)
    if name == "network" and not sandbox_support().no_network:
        pytest.skip("unshare --net is not permitted here")
    assert (r["status"], r["total"]) == (status, total), r["detail"]
    assert detail in r["detail"]
    assert r["max_total"] == FULL


def test_monkeypatching_changes_nothing(corpus):
    r = row(corpus, "monkeypatch")
    assert r["demo.image-scale"] == "0" and r["demo.rotation-2d"] == "0"


def test_writing_outside_the_working_copy_fails(corpus):
    if not sandbox_support().own_user:
        pytest.skip("kernels run as the grader's user: the sandbox cannot stop these writes")
    r = row(corpus, "write-outside")
    assert (r["status"], r["total"]) == ("cell-errors", FULL)
    assert "PermissionError" in r["detail"]
    assert not (corpus["outside"] / "pwned.txt").exists()
    assert JUDGE.read_text(encoding="utf-8") == corpus["judge_before"]


def test_formula_with_import_is_not_run(corpus):
    r = row(corpus, "import-formula")
    assert r["demo.rotation-x-symbolic"] == "0"
    assert not (corpus["outside"] / "formula").exists()
    feedback = "".join(p.read_text() for p in (corpus["folder"] / "feedback").glob("demo-*"))
    assert "UnsafeExpressionError" in feedback or "symcheck" in feedback


def test_no_sandbox_process_survives(corpus):
    if not sandbox_support().own_user:
        pytest.skip("no sandbox users here")
    from photolib.grading.sandbox import UidPool
    assert UidPool().orphans() == []


def test_summary_and_feedback_written(corpus):
    summary = (corpus["folder"] / "feedback" / "summary.md").read_text()
    assert "demo.rotation-x: " in summary and "not-answered" in summary
    assert len(list((corpus["folder"] / "feedback").glob("*.md"))) == len(corpus["paths"]) + 1


def _grade(*args):
    return subprocess.run([sys.executable, "-m", "photolib", "grade", *map(str, args),
                           "--no-progress"], cwd=ROOT, capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=120)


def test_rerun_skips_graded_and_force_regrades(corpus):
    folder = corpus["folder"]
    out = folder / "gradebook.csv"
    before = out.read_text()
    done = _grade(corpus["paths"]["normal"], "--out", out)
    assert done.returncode == 0 and "already in" in done.stderr
    assert out.read_text() == before
    fresh = folder / "fresh.csv"
    assert _grade(corpus["paths"]["not-json"], "--out", fresh, "--force").returncode == 0
    lines = fresh.read_text().splitlines()
    assert len(lines) == 2 and ",invalid-json," in lines[1]
