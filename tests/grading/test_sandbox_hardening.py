"""Hardening of the grader against a kernel that attacks the machine, not the grade.

The batch-level checks (rows of hostile notebooks) are in ``test_hostile.py``; here are the
pieces one by one, including the fallbacks used where a mechanism is not available: writes
that never follow planted symbolic links, private output modes, the refusal of shared output
folders, the clean-up of files and SysV IPC objects, cgroups and the probe's report.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from photolib.grading.report import (
    Gradebook,
    append_private,
    shared_folder_problem,
    write_private,
)
from photolib.grading.sandbox import (
    PRIVATE_PLACES,
    KernelCgroup,
    _cgroup_root,
    _mount_script,
    remove_files_of,
    remove_ipc_of,
    sandbox_support,
)

from photolib.grading import sandbox

from .conftest import ROOT

#: a user id outside the sandbox pool (61000-61511), for files and IPC objects made here
OTHER_UID = 62017
IS_ROOT = os.geteuid() == 0
needs_root = pytest.mark.skipif(not IS_ROOT, reason="needs root (chown, setpriv)")


class _Graded:
    """The fields Gradebook.add reads."""

    def __init__(self, submission, status="ok"):
        self.submission, self.student_id, self.status = str(submission), "s1", status
        self.chapter, self.detail, self.judgements = "00-start", "", []
        self.total = self.max_total = 0.0


# -- D1: no write follows a symbolic link ----------------------------------------------------
def test_a_rewrite_does_not_follow_planted_links(tmp_path):
    out = tmp_path / "gb.csv"
    book = Gradebook(out, ["a"])
    book.add(_Graded(tmp_path / "x.ipynb"))
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    # the names the grader used to write its temporaries to, and a few more
    for name in ("gb.csv.tmp", "gb.csv.details.jsonl.tmp", ".gb.csv.tmp"):
        (tmp_path / name).symlink_to(victim)
    book.add(_Graded(tmp_path / "x.ipynb", status="timeout"))  # replaces the row: a rewrite
    assert victim.read_text() == "precious"
    assert not out.is_symlink() and ",timeout," in out.read_text()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")) == \
        [".gb.csv.tmp", "gb.csv.details.jsonl.tmp", "gb.csv.tmp"]  # no temporary is left


def test_an_append_refuses_a_link(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "gb.csv"
    link.symlink_to(victim)
    with pytest.raises(OSError):
        append_private(link, "row\n")
    assert victim.read_text() == "precious"
    with pytest.raises(ValueError, match="symbolic link"):
        Gradebook(link, ["a"])


def test_written_files_are_private(tmp_path):
    old = os.umask(0o022)  # as an instructor's shell has it
    try:
        write_private(tmp_path / "f.md", "text")
        append_private(tmp_path / "g.csv", "row\n")
    finally:
        os.umask(old)
    for name in ("f.md", "g.csv"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o600


def _grade(*args):
    return subprocess.run([sys.executable, "-m", "photolib", "grade", *map(str, args),
                           "--no-progress"], cwd=ROOT, capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=120)


@pytest.mark.slow
def test_grade_writes_private_files(tmp_path):
    """gradebook, sidecar, feedback folder and summary: 0600 files, 0700 folders."""
    out = tmp_path / "book" / "gb.csv"
    done = _grade(tmp_path / "subs" / "absent-00-start.ipynb", "--out", out,
                  "--feedback", tmp_path / "fb")  # a missing file: a row, no kernel
    assert done.returncode == 0, done.stderr
    for path in (out, tmp_path / "book" / "gb.csv.details.jsonl", tmp_path / "fb" / "summary.md"):
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path
    for folder in (tmp_path / "book", tmp_path / "fb"):
        assert stat.S_IMODE(folder.stat().st_mode) == 0o700, folder


def test_shared_folders_are_recognised(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o1777)
    private = tmp_path / "private"
    private.mkdir(mode=0o700)
    assert "other users may write" in shared_folder_problem(shared)
    assert "other users may write" in shared_folder_problem("/tmp")
    assert shared_folder_problem(private) is None
    mine = shared / "mine"  # ours, in a sticky folder: others cannot rename or replace it
    mine.mkdir(mode=0o700)
    assert shared_folder_problem(mine) is None
    open_ = tmp_path / "open"  # not sticky: anyone may rename what it holds
    open_.mkdir()
    os.chmod(open_, 0o777)
    (open_ / "sub").mkdir(mode=0o700)
    assert "which holds" in shared_folder_problem(open_ / "sub")
    if IS_ROOT:
        theirs = shared / "theirs"
        theirs.mkdir(mode=0o700)
        os.chown(theirs, OTHER_UID, OTHER_UID)
        assert f"belongs to user {OTHER_UID}" in shared_folder_problem(theirs)
        # an instructor's own folder, graded with sudo: theirs, but nobody else may write
        home = tmp_path / "instructor"
        home.mkdir(mode=0o755)
        os.chown(home, OTHER_UID, OTHER_UID)
        assert shared_folder_problem(home) is None


@pytest.mark.slow
def test_grade_refuses_a_shared_output_folder(tmp_path):
    if not sandbox_support().own_user:
        pytest.skip("kernels run as the grader's own user here: a shared folder gives them "
                    "nothing more, so it is not refused (the link-safe writes above still hold)")
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o1777)
    done = _grade(tmp_path / "subs" / "absent-00-start.ipynb", "--out", shared / "gb.csv")
    assert done.returncode == 2 and "refusing --out" in done.stderr, done.stderr
    assert not (shared / "gb.csv").exists()
    done = _grade(tmp_path / "subs" / "absent-00-start.ipynb", "--out", tmp_path / "gb.csv",
                  "--feedback", shared)
    assert done.returncode == 2 and "refusing --feedback" in done.stderr, done.stderr


# -- D3: the fallback clean-up of files and SysV IPC objects ---------------------------------
@needs_root
def test_files_of_a_user_are_removed_at_any_depth(tmp_path):
    place = tmp_path / "place"
    place.mkdir()
    os.chmod(place, 0o1777)
    (place / "open" / "deeper").mkdir(parents=True)
    for d in (place / "open", place / "open" / "deeper"):
        os.chmod(d, 0o777)
    closed = place / "closed"
    closed.mkdir(mode=0o700)
    theirs = place / "open" / "deeper" / "their-dir"
    theirs.mkdir()
    made = [place / "top", place / "open" / "deeper" / "deep", theirs / "inside",
            closed / "unreachable"]
    for path in made:
        path.write_text("x")
    (place / "open" / "link").symlink_to(tmp_path / "target")
    (tmp_path / "target").write_text("keep")
    keep = place / "open" / "root-file"
    keep.write_text("keep")
    for path in [*made, theirs]:
        os.chown(path, OTHER_UID, OTHER_UID)
    os.chown(place / "open" / "link", OTHER_UID, OTHER_UID, follow_symlinks=False)
    removed = remove_files_of(OTHER_UID, places=(str(place),))
    assert sorted(removed) == sorted(map(str, [place / "top", place / "open" / "deeper" / "deep",
                                               theirs, place / "open" / "link"]))
    assert keep.exists() and (tmp_path / "target").read_text() == "keep"
    # a folder the user cannot enter holds nothing it made: not searched
    assert (closed / "unreachable").exists()
    # the top level only (as after a kernel with a private mount namespace)
    (place / "open" / "again").write_text("x")
    os.chown(place / "open" / "again", OTHER_UID, OTHER_UID)
    assert remove_files_of(OTHER_UID, places=(str(place),), recursive=False) == []


@needs_root
def test_ipc_objects_of_a_user_are_removed():
    """The fallback where kernels share the host's IPC namespace (no ``unshare --ipc``)."""
    if not shutil.which("setpriv"):
        pytest.skip("setpriv not found")
    key = int.from_bytes(os.urandom(3), "big") + 0x51000000
    make = ("import ctypes; libc = ctypes.CDLL(None, use_errno=True); "
            f"assert libc.shmget({key}, 1 << 20, 0o1600) >= 0; "
            f"assert libc.msgget({key}, 0o1600) >= 0; "
            f"assert libc.semget({key}, 1, 0o1600) >= 0")
    subprocess.run(["setpriv", f"--reuid={OTHER_UID}", f"--regid={OTHER_UID}",
                    "--clear-groups", "--", sys.executable, "-c", make], check=True,
                   env={"PATH": os.environ["PATH"]}, cwd="/")
    libc = ctypes.CDLL(None, use_errno=True)
    try:
        assert libc.shmget(key, 0, 0) >= 0  # it outlived its process
        removed = remove_ipc_of(OTHER_UID)
        assert {r.split()[0] for r in removed} == {"shm", "msg", "sem"}
        assert libc.shmget(key, 0, 0) < 0 and libc.msgget(key, 0) < 0
        assert libc.semget(key, 0, 0) < 0
    finally:
        for get, rm in ((libc.shmget, lambda i: libc.shmctl(i, 0, None)),
                        (libc.msgget, lambda i: libc.msgctl(i, 0, None)),
                        (libc.semget, lambda i: libc.semctl(i, 0, 0))):
            ident = get(key, 0, 0) if get is not libc.msgget else get(key, 0)
            if ident >= 0:
                rm(ident)


def test_clean_up_refuses_root_and_the_grader():
    for fn in (remove_files_of, remove_ipc_of):
        with pytest.raises(ValueError, match="refusing"):
            fn(0)
        with pytest.raises(ValueError, match="refusing"):
            fn(os.geteuid())


# -- D2: cgroups -------------------------------------------------------------------------
def test_a_kernel_cgroup_limits_and_is_removed():
    root = _cgroup_root()
    if not root.version:
        pytest.skip("no writable cgroup (v2 with memory and pids delegated, or v1 memory and "
                    "pids hierarchies) here: --memory holds per process only")
    group = KernelCgroup(root, 256 << 20, 16)
    folders = list(group.dirs.values())
    try:
        if root.version == "v2":
            assert Path(group.dirs["unified"], "memory.max").read_text().strip() == \
                str(256 << 20)
        else:
            assert Path(group.dirs["memory"], "memory.limit_in_bytes").read_text().strip() == \
                str(256 << 20)
            assert Path(group.dirs["pids"], "pids.max").read_text().strip() == "16"
        # a process that enters it (as the launch chain's sh step does) and grows past it
        enter = " && ".join(f"echo $$ > {f}" for f in group.procs_files)
        hog = subprocess.run(["sh", "-c", enter + ' && exec "$@"', "x", sys.executable, "-c",
                              "b = b'x' * (400 << 20)"], capture_output=True)
        assert hog.returncode != 0  # killed by the OOM killer (SIGKILL)
        assert group.oom_kills() >= 1
        sleeper = subprocess.Popen(["sh", "-c", enter + " && exec sleep 60"])
        time.sleep(0.3)
        assert sleeper.pid in group.pids()
    finally:
        group.remove()
    assert sleeper.wait(timeout=10) == -9
    assert not any(os.path.exists(f) for f in folders)


# -- the launch chain and the probe --------------------------------------------------------
def test_mount_script_binds_the_kernel_folder_back():
    script = _mount_script("/tmp/photolib-grade-x", "/tmp/photolib-grade-x/work",
                           PRIVATE_PLACES, 64, True)
    assert script.startswith("cd /tmp/photolib-grade-x && ")
    assert "mount -t tmpfs -o size=128m,mode=1777,nosuid,nodev photolib-sandbox /tmp" in script
    assert "size=64m,mode=1777,nosuid,nodev photolib-sandbox /dev/shm" in script
    assert "mount --no-canonicalize --bind . /tmp/photolib-grade-x" in script
    assert "hidepid=2" in script and script.endswith("cd /tmp/photolib-grade-x/work")


def test_mount_script_binds_kept_folders_back():
    script = _mount_script("/tmp/photolib-grade-x", "/tmp/photolib-grade-x/work",
                           PRIVATE_PLACES, 64, False, ["/tmp/clone", "/tmp/other env"])
    # opened before the tmpfs goes on, bound back after it, closed before the kernel starts
    opened = script.index("exec 3< /tmp/clone"), script.index("exec 4< '/tmp/other env'")
    mounted = script.index("photolib-sandbox /tmp")
    assert max(opened) < mounted
    assert script.index("mount --no-canonicalize --bind /proc/self/fd/3 /tmp/clone") > mounted
    assert "mount --no-canonicalize --bind /proc/self/fd/4 '/tmp/other env'" in script
    assert "exec 3<&-" in script and "exec 4<&-" in script
    # nothing to keep without private places
    assert "exec 3" not in _mount_script("/b", "/b/w", (), 64, True, ["/tmp/clone"])
    with pytest.raises(ValueError, match="at most"):
        _mount_script("/b", "/b/w", PRIVATE_PLACES, 64, False, [f"/tmp/{i}" for i in range(8)])


def test_kept_folders_are_the_outermost_needed_folders_in_private_places(monkeypatch, tmp_path):
    # a clone made by `git clone . "$(mktemp -d)/c"`: repository and venv both in /tmp
    venv = tmp_path / "c" / ".venv"
    (venv / "bin").mkdir(parents=True)
    (venv / "lib").mkdir()
    monkeypatch.setattr(sys, "prefix", str(venv))
    monkeypatch.setattr(sys, "path", [str(venv / "lib"), "/usr/lib/python3", ""])
    kept = sandbox.kept_folders.__wrapped__(("/tmp",))
    assert str(venv.resolve()) in kept
    assert not any(k == "/usr/lib/python3" for k in kept)
    assert not any(a != b and b.startswith(a + "/") for a in kept for b in kept)


def test_kept_folders_stay_visible_over_the_private_tmp(tmp_path):
    if not sandbox_support().private_tmp:
        pytest.skip("no private mount namespace here: " + " ".join(sandbox_support().notes))
    base, keep, hidden = tmp_path / "base", tmp_path / "env", tmp_path / "hidden"
    (base / "work").mkdir(parents=True)
    keep.mkdir()
    hidden.mkdir()
    (keep / "marker").write_text("kept")
    (hidden / "marker").write_text("hidden")
    places = tuple(p for p in PRIVATE_PLACES if os.path.isdir(p))
    script = _mount_script(str(base), str(base / "work"), places, 1, False, [str(keep)])
    script += f" && test -e {keep}/marker && ! test -e {hidden}/marker && ! test -e /proc/self/fd/3"
    run = subprocess.run(["unshare", "--mount", "--propagation", "private", "--",
                          "sh", "-c", script], capture_output=True, text=True, timeout=30)
    assert run.returncode == 0, run.stderr


def test_sandbox_support_says_what_is_missing():
    s = sandbox_support()
    notes = " ".join(s.notes)
    assert ("prlimit" in notes) != s.prlimit
    assert ("--net" in notes) != s.no_network
    assert ("--ipc" in notes) != s.ipc_namespace
    if s.own_user:
        assert ("mount namespace" in notes) != s.private_tmp
        assert ("hidepid" in notes) != s.hide_processes
        assert ("cgroup" in notes) != bool(s.cgroup)
        assert ("no-new-privs" in notes) != s.no_new_privs
    else:
        assert not (s.private_tmp or s.hide_processes or s.cgroup or s.no_new_privs)


# -- the jupyter_client interfaces the sandbox relies on ---------------------------------------
def test_a_channel_url_is_where_the_client_connected(tmp_path):
    """The address a dropped channel is connected to again: ipc://IP-PORT (jupyter_client's
    naming of an ipc endpoint) of the port in the connection file."""
    km = sandbox._Manager(transport="ipc", ip=str(tmp_path / "k"),
                          connection_file=str(tmp_path / "kernel.json"))
    km.write_connection_file()
    ports = km.get_connection_info()
    kc = km.blocking_client()
    kc.start_channels(hb=False)
    try:
        assert sandbox._channel_url(kc.iopub_channel) == \
            f"ipc://{tmp_path}/k-{ports['iopub_port']}"
        assert sandbox._channel_url(kc.shell_channel) == \
            f"ipc://{tmp_path}/k-{ports['shell_port']}"
    finally:
        kc.stop_channels()
        km.cleanup_resources()


@pytest.mark.parametrize("script, reason", [
    ("import os, signal; os.kill(os.getpid(), signal.SIGKILL)", "kernel killed by SIGKILL"),
    ("import sys; sys.exit(3)", "kernel exited with code 3"),
])
def test_the_kernel_process_and_its_end_are_read(tmp_path, script, reason):
    """The Popen behind the manager (the one private attribute used) and the exit status."""
    km = sandbox._Manager(transport="ipc", ip=str(tmp_path / "k"),
                          connection_file=str(tmp_path / "kernel.json"))
    km.sandbox_cmd = [sys.executable, "-c", "import sys; sys.stdin.read(); " + script]
    assert sandbox._kernel_process(km) is None and sandbox._death_reason(km) == "kernel died"
    km.start_kernel(cwd=str(tmp_path), stdin=subprocess.PIPE)
    try:
        process = sandbox._kernel_process(km)
        assert isinstance(process, subprocess.Popen) and process.args == km.sandbox_cmd
        assert process.poll() is None and sandbox._exit_code(km) is None and km.is_alive()
        process.stdin.close()  # the process goes on to its end
        process.wait(timeout=30)
        assert not km.is_alive()
        assert sandbox._death_reason(km) == reason
    finally:
        km.shutdown_kernel(now=True)


# -- reading a submission without running it ---------------------------------------------------

_STATIC_READ = """
import resource, sys
from nbformat.v4 import new_code_cell, new_notebook
from photolib.grading.submission import static_student_id
big = "x = [" + "0," * 3_000_000 + "]"          # 6 MB of list literal before the id
nb = new_notebook(cells=[new_code_cell(big), new_code_cell("STUDENT_ID = 's1234567'")])
resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
print(static_student_id(nb))
"""


@pytest.mark.slow
def test_a_huge_cell_is_not_parsed_whole_in_the_grader():
    # ast.parse of that cell needs ~3 GB: the grader (root, no limit) read it before any sandbox
    proc = subprocess.run([sys.executable, "-c", _STATIC_READ], capture_output=True, text=True,
                          timeout=120, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip() == "s1234567"


def test_a_regraded_odd_path_replaces_its_row(tmp_path):
    # the CSV cell of such a path is neutralised or shortened, so it cannot be the row's key
    from photolib.grading.batch import Graded
    from photolib.grading.judge import Judgement
    from photolib.grading.report import Gradebook

    folder = tmp_path / "subs"
    folder.mkdir()
    odd = [folder / "'quote.ipynb", folder / "new\nline.ipynb", folder / ("x" * 200 + ".ipynb"),
           folder / "=sum(1).ipynb"]

    def graded(path, total):
        return Graded(str(path), "s1", "ok", "", "00-start",
                      [Judgement("demo.image-scale", "correct", float(total), 2.0, "")])

    out = tmp_path / "gb.csv"
    book = Gradebook(out, ["demo.image-scale"])
    for p in odd:
        book.add(graded(p, 1))
    book = Gradebook(out, ["demo.image-scale"])      # a later run resumes the gradebook
    assert all(book.is_done(p) for p in odd)
    for p in odd:
        book.add(graded(p, 2))                       # regraded (as with --force)
    import csv
    with out.open(newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))[1:]
    assert len(rows) == len(odd), rows
    assert {row[4] for row in rows} == {"2"}
