"""Hostile and broken submissions, graded in one batch next to a normal one.

Each fixture notebook is built here with nbformat from the demo master (full marks) or its
untouched student copy (zero). Every one must end as a clear gradebook row, and the normal
submission in the same batch must still get full marks.
"""

from __future__ import annotations

import copy
import csv
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest

from photolib.grading.sandbox import RESULT_MIME, sandbox_support

from .conftest import MASTER, ROOT, cell_index, with_cell

TIMEOUT = 12
#: written to /tmp by the private-tmp notebook; unique per run, so that a file another run
#: left behind (where kernels run as the grader's user, nothing removes it) cannot fail this one
LEFT_BEHIND = Path(f"/tmp/photolib-hostile-left-behind-{os.getpid()}-{os.urandom(4).hex()}")
JUDGE = ROOT / "photolib" / "grading" / "judge.py"
#: what the leftovers notebook leaves in shared places: a SysV segment (by key) and files
LEFT_KEY = int.from_bytes(os.urandom(3), "big") + 0x50000000
LEFT_NAME = f"photolib-hostile-left-{os.getpid()}-{os.urandom(4).hex()}"
LEFT_FILES = [Path("/run/lock") / LEFT_NAME, Path("/var/tmp") / LEFT_NAME / "deep" / "file",
              Path("/dev/shm") / LEFT_NAME, Path("/tmp") / LEFT_NAME / "a" / "b"]

LEFTOVERS = f"""
import ctypes, os
libc = ctypes.CDLL(None, use_errno=True)
assert libc.shmget({LEFT_KEY}, 8 << 20, 0o1600) >= 0, ctypes.get_errno()  # IPC_CREAT | 0600
for name in {[str(f) for f in LEFT_FILES]!r}:
    try:
        os.makedirs(os.path.dirname(name), mode=0o777, exist_ok=True)
        open(name, "w").write("left behind")
    except OSError:
        pass
"""

RECON = """
import os
visible = [p for p in os.listdir("/proc") if p.isdigit()]
assert not os.path.exists(f"/proc/{os.getppid()}/cmdline"), "the grader is visible"
assert all(os.stat(f"/proc/{p}").st_uid == os.getuid() for p in visible if
           os.path.exists(f"/proc/{p}")), "processes of other users are visible"
status = open("/proc/self/status").read()
assert "NoNewPrivs:\t1" in status, "no no_new_privs"
"""

#: three children of 600 MiB each (pages touched): over --memory 1536 together, not alone
FORK_MEMORY = """
import os, time
kids = []
for _ in range(3):
    pid = os.fork()
    if pid == 0:
        try:
            hog = b"x" * (600 << 20)
            time.sleep(3)
        finally:
            os._exit(0)
    kids.append(pid)
for pid in kids:
    os.waitpid(pid, 0)
"""

#: unique per run, and removed by the corpus fixture where the kernel wrote the host's /dev/shm
SHM_FILES = [Path("/dev/shm") / f"photolib-hostile-fill-{os.getpid()}-{os.urandom(4).hex()}-{i}"
             for i in range(20)]
SHM_FILL = f"""
for name in {[str(f) for f in SHM_FILES]!r}:
    with open(name, "wb") as f:
        f.write(b"x" * (60 << 20))
"""

#: a loop that swallows the KeyboardInterrupt of the time limit (a bare except)
SWALLOW = """
import time
while True:
    try:
        time.sleep(1)
    except:
        pass
"""

HUGE_MESSAGES = """
from IPython.display import publish_display_data
for _ in range(3):
    publish_display_data({"text/plain": "x" * (40 << 20)})
"""

SID_STRSUB = """
class S(str):
    def __getitem__(self, key):
        import time
        time.sleep(10 ** 6)
STUDENT_ID = S("demo-student")
"""

#: every value answer makes the encoder run student code that sleeps (5 s each, stopped)
SLOW_ANSWERS = """
import time
class Slow(sp.Basic):
    @property
    def is_number(self):
        time.sleep(10 ** 6)
scale_number = R2 = R_omega = R_omega_sym = choice_inverse = Slow()
image_scale_number = None
"""

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
        master, "errors = []\n"
                f"for path, mode in (({str(sandbox_dir / 'pwned.txt')!r}, 'w'), "
                f"({str(JUDGE)!r}, 'a')):\n"
                "    try:\n        open(path, mode).write('# pwned')\n"
                "    except OSError as e:\n        errors.append(type(e).__name__)\n"
                "raise OSError('writes failed: ' + ' '.join(errors))")
    out["monkeypatch"] = with_cell(untouched, 'STUDENT_ID = "demo-student"\n' + MONKEYPATCH
                                   + "scale_number = 1.0\nR2 = [[1, 0], [0, 2]]")
    out["forge"] = with_cell(untouched, 'STUDENT_ID = "demo-student"\n' + FORGE)
    out["huge-output"] = with_cell(master, "print('x' * 10_000_000)\nfor i in range(3000):\n"
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
    text = MASTER.read_text(encoding="utf-8").replace('"id": "demo-', '"id": "same')
    out["duplicate-ids"] = __import__("re").sub(r'"id": "same\d+"', '"id": "same"', text)
    out["import-formula"] = with_cell(
        untouched, 'STUDENT_ID = "demo-student"\n'
                   f"R_omega_sym = \"__import__('os').system('touch {sandbox_dir}/formula')\"")
    # answers built to stall the grader's decoder or judge: each costs its own exercise
    rx = "R_omega_sym = sp.Matrix([[1, 0, 0], [0, sp.cos(omega), -sp.sin(omega)], [0, {}, {}]])"
    out["exp-tower"] = with_cell(master, rx.format(
        "sp.sin(omega)", "sp.exp(sp.exp(sp.exp(sp.exp(omega))))"))
    out["rational-exponent"] = with_cell(master, rx.format(
        "sp.sin(omega)", "sp.Pow(2, sp.Rational(10**12 + 1, 3), evaluate=False)"))
    out["nested-pow"] = with_cell(master, "e = sp.Integer(2)\nfor _ in range(6):\n"
                                          "    e = sp.Pow(e, 64, evaluate=False)\n"
                                  + rx.format("sp.sin(omega)", "e"))
    out["abs-trick"] = with_cell(master, rx.format("sp.Abs(sp.sin(omega))", "sp.cos(omega)")
                                 .replace("-sp.sin(omega)", "-sp.Abs(sp.sin(omega))"))
    out["custom-sin"] = with_cell(master, "class sin(sp.Function):\n    nargs = 2\n"
                                  + rx.format("sin(omega, omega)", "sp.cos(omega)"))
    out["complex"] = with_cell(master, "scale_number = complex(scale_number, 1.0)")
    out["exact-number"] = with_cell(master, "scale_number = sp.nsimplify(scale_number, "
                                            "rational=True)")
    out["zero-d-array"] = with_cell(master, "scale_number = np.array(scale_number)")
    out["sleepy-function"] = with_cell(
        master, "import time\ndef image_scale_number(c_mm, h_m):\n    while True:\n"
                "        try:\n            time.sleep(100)\n        except BaseException:\n"
                "            pass")
    out["huge-error"] = with_cell(
        master, 'raise Exception("\\nfake.ipynb,victim,ok,11,11,2,2,2,2,2,1,\\n" + "x" * 200_000)')
    out["sid-newline"] = _with_id(master, "demo-student\\n")
    out["sid-formula"] = _with_id(master, "+B2")
    out["sid-change"] = with_cell(master, 'STUDENT_ID = "someone-else"')
    # the kernel's folder holds its own notebook and nothing else of the submissions' folder
    out["sibling-files"] = with_cell(master, "import os\nassert os.listdir('.') == "
                                             "['sibling-files-00-start.ipynb'], os.listdir('.')")
    out["swallowed-interrupt"] = with_cell(master, SWALLOW)
    empty = copy.deepcopy(master)
    empty.cells[cell_index(empty, "student-id")].source = 'STUDENT_ID = ""'
    out["empty-id"] = empty
    no_id = copy.deepcopy(master)
    del no_id.cells[cell_index(no_id, "student-id")]
    out["missing-id"] = no_id
    out["twin-a"] = copy.deepcopy(master)  # two submissions under one id: both rows flagged
    out["twin-b"] = copy.deepcopy(master)
    wrong = copy.deepcopy(master)
    wrong.metadata["photolib"] = {"chapter": "02-optics"}
    out["wrong-chapter"] = wrong
    out["leftovers"] = with_cell(master, LEFTOVERS)
    out["recon"] = with_cell(master, RECON)
    if sandbox_support().cgroup:
        out["fork-memory"] = with_cell(master, FORK_MEMORY)
    out["shm-fill"] = with_cell(master, SHM_FILL)
    out["huge-messages"] = with_cell(master, HUGE_MESSAGES)
    strsub = copy.deepcopy(master)  # the only id: no literal, the kernel's value is read
    strsub.cells[cell_index(strsub, "student-id")].source = SID_STRSUB
    out["sid-strsub"] = strsub
    out["slow-answers"] = with_cell(master, SLOW_ANSWERS)
    out["private-tmp"] = with_cell(
        master, "import os, stat, tempfile\n"
                "assert stat.S_IMODE(os.stat('.').st_mode) == 0o700, oct(os.stat('.').st_mode)\n"
                "assert tempfile.gettempdir().startswith(os.path.dirname(os.getcwd()))\n"
                f"open({str(LEFT_BEHIND)!r}, 'w').write('x')")
    return out


def _own_ids(variants):
    """Each variant under an id of its own (``demo-<name>``), with its correct choice.

    One gradebook flags every row whose student id occurs twice (``duplicate-id``), so the
    corpus may share an id only where that is tested (the twins). The demo master's choice
    answer is that of ``demo-student``; each id gets the letter its own variant needs.
    """
    from photolib.grading.exercises import exercise
    from photolib.grading.notebook import parameters_for
    choice = exercise("demo.inverse-choice")
    out = {}
    for name, nb in variants.items():
        sid = "demo-twin" if name.startswith("twin-") else f"demo-{name}"
        key = choice.reference(parameters_for(choice, sid))
        if isinstance(nb, str):
            nb = nb.replace("demo-student", sid).replace('choice_inverse = \\"d\\"',
                                                         f'choice_inverse = \\"{key}\\"')
        else:
            nb = copy.deepcopy(nb)
            for cell in nb.cells:
                cell.source = cell.source.replace("demo-student", sid).replace(
                    'choice_inverse = "d"', f'choice_inverse = "{key}"')
        out[name] = nb
    return out


def _with_id(nb, sid):
    nb = copy.deepcopy(nb)
    nb.cells[cell_index(nb, "student-id")].source = f'STUDENT_ID = "{sid}"'
    return nb


@pytest.fixture(scope="module")
def corpus(tmp_path_factory, master, untouched):
    folder = tmp_path_factory.mktemp("submissions")
    outside = tmp_path_factory.mktemp("outside")
    os.chmod(outside, 0o700)
    paths = {}
    for name, nb in _own_ids(_variants(master, untouched, outside)).items():
        path = folder / f"{name}-00-start.ipynb"
        if isinstance(nb, str):
            path.write_text(nb, encoding="utf-8")
        else:
            nbformat.write(nb, path)
        paths[name] = path
    # siblings in the submissions' folder: a sparse 1 GiB file (no disk blocks), another
    # student's notebook with an upper-case suffix and other students' files; none may reach
    # a kernel
    with open(folder / "big.bin", "wb") as f:
        f.truncate(1 << 30)
    nbformat.write(master, folder / "other-student.IPYNB")
    (folder / "other-student-data.csv").write_text("x,y\n1,2\n")
    (folder / "notes").mkdir()
    (folder / "notes" / "other-student.md").write_text("answers")
    judge_before = JUDGE.read_text(encoding="utf-8")
    book = tmp_path_factory.mktemp("book")  # never in the submissions' folder (refused)
    out = book / "gradebook.csv"
    # the same file twice, by another path: graded once
    twice = folder / ".." / folder.name / paths["normal"].name
    # a separate grader process, as an instructor runs it
    grader = subprocess.Popen([sys.executable, "-m", "photolib", "grade",
                               *map(str, paths.values()), str(twice),
                               "--out", str(out), "--jobs", "2", "--timeout", str(TIMEOUT),
                               "--memory", "1536", "--feedback", str(book / "feedback"),
                               "--no-progress"], cwd=ROOT, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True,
                              env=dict(os.environ, PYTHONPATH=str(ROOT)))
    try:
        _, stderr = grader.communicate(timeout=240)
    except subprocess.TimeoutExpired:
        grader.kill()
        raise
    done = subprocess.CompletedProcess(grader.args, grader.returncode, "", stderr)
    assert done.returncode == 0, done.stderr
    with out.open(newline="") as f:
        listed = list(csv.DictReader(f))
    rows = {Path(r["submission"]).name.split("-00-")[0]: r for r in listed}
    yield {"rows": rows, "outside": outside, "judge_before": judge_before, "folder": folder,
           "book": book,
           "paths": paths, "listed": listed, "stderr": done.stderr, "pid": grader.pid}
    LEFT_BEHIND.unlink(missing_ok=True)  # where the sandbox could not remove it
    for path in LEFT_FILES + SHM_FILES:  # the same (1.2 GB of RAM in /dev/shm)
        path.unlink(missing_ok=True)
    for top in (Path("/tmp") / LEFT_NAME, Path("/var/tmp") / LEFT_NAME):
        shutil.rmtree(top, ignore_errors=True)
    _remove_segment(LEFT_KEY)


def _shm_keys() -> set[int]:
    lines = Path("/proc/sysvipc/shm").read_text().splitlines()[1:]
    return {int(line.split()[0]) for line in lines if line.strip()}


def _remove_segment(key: int) -> None:
    import ctypes
    libc = ctypes.CDLL(None, use_errno=True)
    ident = libc.shmget(key, 0, 0)
    if ident >= 0:
        libc.shmctl(ident, 0, None)  # IPC_RMID


# every test but the last reads the module fixture ``corpus`` (the CLI grader on the hostile
# corpus, 90 s and more); the last starts a judge pool, about 2 s alone: the module is slow
pytestmark = pytest.mark.slow


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
    ("exp-tower", "ok", "9", ""),
    ("rational-exponent", "ok", "9", ""),
    ("nested-pow", "ok", "9", ""),
    ("abs-trick", "ok", "9", ""),
    ("custom-sin", "ok", "9", ""),
    ("complex", "ok", "9", ""),
    ("exact-number", "ok", FULL, ""),
    ("zero-d-array", "ok", FULL, ""),
    ("sleepy-function", "ok", "9", ""),
    ("huge-error", "cell-errors", FULL, "fake.ipynb"),
    ("sid-newline", "no-student-id", ZERO, "not a usable id"),
    ("sid-formula", "no-student-id", ZERO, "not a usable id"),
    ("empty-id", "no-student-id", ZERO, "STUDENT_ID is empty; not graded"),
    ("missing-id", "no-student-id", ZERO, "defines no STUDENT_ID"),
    ("twin-a", "duplicate-id", FULL, "is also the id of twin-b-00-start.ipynb"),
    ("twin-b", "duplicate-id", FULL, "is also the id of twin-a-00-start.ipynb"),
    ("swallowed-interrupt", "timeout", FULL, "went on after the interrupt"),
    ("sid-change", "ok", FULL, "changed later"),
    ("sibling-files", "ok", FULL, ""),
    ("wrong-chapter", "wrong-chapter", ZERO, "02-optics"),
    ("private-tmp", "ok", FULL, ""),
    ("leftovers", "ok", FULL, ""),
    ("recon", "ok", FULL, ""),
    ("fork-memory", "memory-limit", FULL, "went over the memory limit of 1536 MiB"),
    ("shm-fill", "cell-errors", FULL, "No space left on device"),
    ("huge-messages", "ok", FULL, "larger than 16 MiB dropped unread"),
    ("sid-strsub", "no-student-id", ZERO, "defines no STUDENT_ID"),
    ("slow-answers", "ok", ZERO, ""),
])
def test_each_submission_ends_as_a_clear_row(corpus, name, status, total, detail):
    support = sandbox_support()
    if name == "fork-bomb" and not support.own_user:
        pytest.skip("kernels run as the grader's user here: no per-user process limit, "
                    "so the fork bomb is not run")
    if name == "fork-memory" and not support.cgroup:
        pytest.skip("no writable cgroup here: --memory holds per process only (the "
                    "memory-bomb row tests that limit)")
    if name == "recon" and not (support.hide_processes and support.no_new_privs):
        pytest.skip("/proc with hidepid=2 or setpriv --no-new-privs is not available here")
    if name == "shm-fill" and not support.private_tmp:
        pytest.skip("no private size-limited /dev/shm here (no mount namespace): files there "
                    "are removed after the kernel (test_sandbox_hardening tests that)")
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
    # with a private /tmp the outside folder (in the host's /tmp) is not even there
    outside = "FileNotFoundError" if sandbox_support().private_tmp else "PermissionError"
    assert f"writes failed: {outside} PermissionError" in r["detail"]
    assert not (corpus["outside"] / "pwned.txt").exists()
    assert JUDGE.read_text(encoding="utf-8") == corpus["judge_before"]


def test_formula_with_import_is_not_run(corpus):
    r = row(corpus, "import-formula")
    assert r["demo.rotation-x-symbolic"] == "0"
    assert not (corpus["outside"] / "formula").exists()
    feedback = "".join(p.read_text() for p in (corpus["book"] / "feedback").glob("demo-*"))
    assert "UnsafeExpressionError" in feedback or "symcheck" in feedback


def test_no_sandbox_process_survives(corpus):
    if not sandbox_support().own_user:
        pytest.skip("no sandbox users here")
    from photolib.grading.sandbox import UidPool
    assert UidPool().orphans() == []


def test_summary_and_feedback_written(corpus):
    summary = (corpus["book"] / "feedback" / "summary.md").read_text()
    assert "demo.rotation-x: " in summary and "not-answered" in summary
    assert len(list((corpus["book"] / "feedback").glob("*.md"))) == len(corpus["paths"]) + 1


def _grade(*args):
    return subprocess.run([sys.executable, "-m", "photolib", "grade", *map(str, args),
                           "--no-progress"], cwd=ROOT, capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=120)


def test_rerun_skips_graded_and_force_regrades(corpus):
    folder = corpus["book"]
    out = folder / "gradebook.csv"
    before = out.read_text()
    done = _grade(corpus["paths"]["normal"], "--out", out)
    assert done.returncode == 0 and "already in" in done.stderr
    assert out.read_text() == before
    fresh = folder / "fresh.csv"
    assert _grade(corpus["paths"]["not-json"], "--out", fresh, "--force").returncode == 0
    lines = fresh.read_text().splitlines()
    assert len(lines) == 2 and ",invalid-json," in lines[1]


# the messages each answer of the corpus above that stalled the grader before must show
@pytest.mark.parametrize("name, exercise, message", [
    ("exp-tower", "demo.rotation-x-symbolic", "exponentials nested deeper"),
    ("rational-exponent", "demo.rotation-x-symbolic", "larger than 64"),
    ("nested-pow", "demo.rotation-x-symbolic", "nested powers"),
    ("abs-trick", "demo.rotation-x-symbolic", "equal only when the symbols are positive"),
    ("custom-sin", "demo.rotation-x-symbolic", "sin cannot take these arguments"),
    ("complex", "demo.image-scale", "complex number"),
    ("sleepy-function", "demo.scale-function", "was stopped"),
])
def test_one_bad_answer_costs_its_own_exercise(corpus, name, exercise, message):
    from types import SimpleNamespace

    from photolib.grading.report import feedback_name
    r = row(corpus, name)
    assert r["student_id"] == f"demo-{name}" and r[exercise] == "0"
    graded = SimpleNamespace(student_id=r["student_id"], submission=r["submission"])
    text = (corpus["book"] / "feedback" / feedback_name(graded)).read_text()
    lines = [line for line in text.splitlines() if f"`{exercise}`" in line and message in line]
    assert lines, f"no feedback line on {exercise} with {message!r}:\n{text}"


def test_gradebook_rows_are_clean(corpus):
    listed = corpus["listed"]
    assert len(listed) == len(corpus["paths"])  # the path given twice is graded once
    assert "duplicate path" in corpus["stderr"]
    assert all(len(r["detail"]) <= 1000 for r in listed)
    assert not any(r["submission"] == "fake.ipynb" for r in listed)
    assert {r["chapter"] for r in listed} == {"00-start"}
    assert row(corpus, "wrong-chapter")["max_total"] == FULL
    assert not any(r["student_id"] == "demo-twin" and r["status"] != "duplicate-id"
                   for r in listed)


def test_nothing_is_left_in_shared_places(corpus):
    """SysV segments and files anywhere in /tmp, /var/tmp, /run/lock, /dev/shm do not stay."""
    if not sandbox_support().own_user:
        pytest.skip("kernels run as the grader's user: their files cannot be told apart")
    assert LEFT_KEY not in _shm_keys()
    for path in LEFT_FILES:
        assert not path.exists()
        assert not Path(*path.parts[:path.parts.index(LEFT_NAME) + 1]).exists()


def test_kernel_cgroups_are_removed(corpus):
    from photolib.grading.sandbox import _cgroup_root
    root = _cgroup_root()
    if not root.version:
        pytest.skip("no writable cgroup here: kernels get none")
    tag = f"photolib-grading-{corpus['pid']}-"
    for _, parent in root.parents:
        assert not [n for n in os.listdir(parent) if n.startswith(tag)]


def test_gradebook_and_feedback_are_private(corpus):
    folder = corpus["book"]
    for path in [folder / "gradebook.csv", folder / "gradebook.csv.details.jsonl",
                 *(folder / "feedback").iterdir()]:
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path
    assert stat.S_IMODE((folder / "feedback").stat().st_mode) == 0o700


def test_the_extraction_is_bounded_by_the_time_limit(corpus):
    """Answers whose reading hangs cost at most the rest of the time limit plus a grace."""
    from types import SimpleNamespace

    from photolib.grading.report import feedback_name
    r = row(corpus, "slow-answers")
    graded = SimpleNamespace(student_id=r["student_id"], submission=r["submission"])
    text = (corpus["book"] / "feedback" / feedback_name(graded)).read_text()
    assert "the submission's time limit was reached" in text, text
    assert "took longer than 5 s" in text


def test_sandbox_files_in_tmp_are_removed(corpus):
    if not sandbox_support().own_user:
        pytest.skip("kernels run as the grader's user: their files cannot be told apart")
    assert not LEFT_BEHIND.exists()


def test_force_regrades_only_the_given_rows(corpus, tmp_path):
    import shutil
    out = tmp_path / "forced.csv"
    shutil.copy(corpus["book"] / "gradebook.csv", out)
    shutil.copy(corpus["book"] / "gradebook.csv.details.jsonl",
                tmp_path / "forced.csv.details.jsonl")
    before = list(csv.DictReader(out.read_text().splitlines()))
    done = _grade(corpus["paths"]["not-json"], "--out", out, "--force")
    assert done.returncode == 0, done.stderr
    after = list(csv.DictReader(out.read_text().splitlines()))
    assert sorted(r["submission"] for r in after) == sorted(r["submission"] for r in before)
    assert [r for r in after if "not-json" in r["submission"]][0]["status"] == "invalid-json"
    details = (tmp_path / "forced.csv.details.jsonl").read_text().splitlines()
    assert len(details) == len(before)


def test_judging_has_a_hard_time_limit():
    """An answer whose judging overruns is stopped; the pool goes on with the next one."""
    import sympy as sp

    from photolib.grading.encode import encode_value
    from photolib.grading.exercises import exercise
    from photolib.grading.worker import JudgePool
    ex = exercise("demo.rotation-x-symbolic")
    w = sp.Symbol("omega")
    good = sp.Matrix([[1, 0, 0], [0, sp.cos(w), -sp.sin(w)], [0, sp.sin(w), sp.cos(w)]])
    wrong = {"value": encode_value(good.T * sp.exp(sp.exp(10**30 * w)))}
    pool = JudgePool(1, timeout=0.01)
    try:
        slow = pool.judge(ex, "s1", wrong, None)
        assert (slow.points, slow.mistake) == (0.0, "judge-timeout"), slow.message
        assert "took longer" in slow.message
        pool.timeout = 30.0
        assert pool.judge(ex, "s1", {"value": encode_value(good)}, None).correct
    finally:
        pool.close()
