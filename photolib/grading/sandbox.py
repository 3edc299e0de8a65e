"""A Jupyter kernel in a sandbox: own process, rlimits, no network, unprivileged user.

The kernel is launched through a chain of small system tools, each of which ``exec``\\ s the
next, so the kernel's process id is the one jupyter_client watches::

    prlimit --as=… --nproc=… --cpu=… --fsize=… --nofile=…   (memory, processes, CPU time)
      unshare --net                                           (an empty network namespace)
        setpriv --reuid=U --regid=U --clear-groups            (a user of its own, no privileges)
          python -m ipykernel_launcher -f CONNECTION_FILE

The kernel talks to the grader over Unix domain sockets (``transport="ipc"``), which work
without any network interface. Each kernel gets a user id of its own from :class:`UidPool`, so
a fork bomb meets ``RLIMIT_NPROC`` for that kernel alone and everything the kernel started
can be killed at the end with ``kill(-1)`` as that user. The unprivileged user cannot write
to the course repository, the submissions or the grader's files; it writes only to its
working copy (and world-writable places such as ``/tmp``).

Where a step is not permitted (not root, no ``unshare``), :func:`sandbox_support` reports it
and the kernel runs with what remains: see ``docs/instructors.md``.
"""

from __future__ import annotations

import fcntl
import functools
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from jupyter_client import KernelManager

__all__ = [
    "ExecResult",
    "Limits",
    "SandboxSupport",
    "SandboxedKernel",
    "UidPool",
    "remove_files_of",
    "sandbox_support",
]

#: MIME type of the grader's own result messages (see :mod:`photolib.grading.extract`)
RESULT_MIME = "application/x-photolib-grading+json"


@dataclass(frozen=True)
class Limits:
    """Resource limits of one submission.

    Parameters
    ----------
    timeout : float
        Wall-clock seconds for running all cells of the notebook.
    memory_mb : int
        Address-space limit of the kernel (``RLIMIT_AS``), MiB.
    nproc : int
        Processes and threads of the kernel's user (``RLIMIT_NPROC``).
    output_bytes : int
        Output text kept per submission; the rest is counted and dropped.
    file_mb : int
        Largest file the kernel may write (``RLIMIT_FSIZE``), MiB.
    judge_seconds : float
        Wall-clock seconds for decoding and judging one answer in the grader
        (:class:`photolib.grading.worker.JudgePool`); an answer over it scores zero.
    judge_memory_mb : int
        Memory a judge worker may grow by while judging, MiB.
    """

    timeout: float = 60.0
    memory_mb: int = 1536
    nproc: int = 64
    output_bytes: int = 20_000
    file_mb: int = 64
    judge_seconds: float = 30.0
    judge_memory_mb: int = 2048

    def __post_init__(self):
        for name in ("timeout", "memory_mb", "nproc", "output_bytes", "file_mb",
                     "judge_seconds", "judge_memory_mb"):
            value = getattr(self, name)
            if not value > 0:
                raise ValueError(f"Limits.{name} must be positive, got {value!r}")


@dataclass(frozen=True)
class SandboxSupport:
    """What the sandbox can do on this machine: see :func:`sandbox_support`."""

    prlimit: bool
    no_network: bool
    own_user: bool
    notes: tuple[str, ...] = ()


@functools.cache
def sandbox_support() -> SandboxSupport:
    """Probe once which isolation steps this machine permits.

    Returns
    -------
    SandboxSupport
        ``no_network`` is true when ``unshare --net`` works; ``own_user`` when the grader runs
        as root and ``setpriv`` exists (then each kernel runs as a user id of its own).
    """
    notes = []
    prlimit = shutil.which("prlimit") is not None
    if not prlimit:
        notes.append("prlimit not found: no memory, CPU, process or file-size limits; "
                     "only the wall-clock timeout holds")
    no_network = False
    if shutil.which("unshare"):
        probe = subprocess.run(["unshare", "--net", "true"], capture_output=True)
        no_network = probe.returncode == 0
    if not no_network:
        notes.append("unshare --net is not permitted: kernels keep the network")
    own_user = os.geteuid() == 0 and shutil.which("setpriv") is not None
    if not own_user:
        notes.append("not root (or no setpriv): kernels run as the grader's own user")
    elif not _unprivileged_can_import():
        own_user = False
        notes.append("an unprivileged user cannot run this Python or import photolib (is the "
                     "repository or the virtual environment inside a folder only its owner may "
                     "enter, e.g. one made by mktemp -d?): kernels run as the grader's own user")
    return SandboxSupport(prlimit, no_network, own_user, tuple(notes))


def _unprivileged_can_import(uid: int = 65534) -> bool:
    """Whether user ``uid`` (nobody) can start this interpreter and import photolib."""
    root = str(Path(__file__).resolve().parents[2])
    env = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": root, "HOME": "/",
           "PYTHONDONTWRITEBYTECODE": "1"}
    cmd = ["setpriv", f"--reuid={uid}", f"--regid={uid}", "--clear-groups", "--",
           sys.executable, "-c", "import photolib, ipykernel"]
    try:
        probe = subprocess.run(cmd, capture_output=True, env=env, cwd="/", timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return probe.returncode == 0


class UidPool:
    """Hand out user ids for kernels, one per running kernel, across grader processes.

    An id is taken by holding an exclusive ``flock`` on ``LOCK_DIR/<uid>.lock``; the lock dies
    with the process that holds it, so two graders on one machine never share an id and a
    crashed grader's ids come free. Leftover processes of an id are killed on acquiring it.

    Parameters
    ----------
    first : int
        First user id of the pool; ids ``first … first + size − 1`` must not belong to anyone.
    size : int
        Number of ids.
    """

    def __init__(self, first: int = 61000, size: int = 512):
        self.ids = range(first, first + size)
        self._held: dict[int, int] = {}
        self._lock = threading.Lock()

    @staticmethod
    def _lock_dir() -> Path:
        path = Path(tempfile.gettempdir()) / "photolib-grading-uids"
        path.mkdir(mode=0o700, exist_ok=True)
        return path

    def _try(self, uid: int) -> int | None:
        fd = os.open(self._lock_dir() / f"{uid}.lock", os.O_CREAT | os.O_RDWR, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            return None
        return fd

    def acquire(self) -> int:
        with self._lock:
            for uid in self.ids:
                if uid in self._held:
                    continue
                fd = self._try(uid)
                if fd is not None:
                    self._held[uid] = fd
                    kill_user(uid)
                    return uid
        raise RuntimeError(f"all {len(self.ids)} sandbox user ids are in use")

    def release(self, uid: int) -> None:
        with self._lock:
            fd = self._held.pop(uid, None)
        if fd is not None:
            os.close(fd)

    def orphans(self) -> list[int]:
        """Processes of pool ids that no grader holds (should always be empty)."""
        found = []
        for uid in self.ids:
            pids = _processes_of(uid) if uid not in self._held else []
            if pids:
                fd = self._try(uid)
                if fd is not None:
                    os.close(fd)
                    found += pids
        return found


_POOL = UidPool()


@dataclass
class ExecResult:
    """Outcome of executing one piece of code in the kernel.

    ``status`` is ``"ok"``, ``"error"`` (the code raised), ``"timeout"`` or ``"dead"`` (the
    kernel died). ``payloads`` are the data of display messages of type :data:`RESULT_MIME`.
    """

    status: str
    error: str = ""
    text: str = ""
    dropped: int = 0
    payloads: list = field(default_factory=list)


def _processes_of(uid: int) -> list[int]:
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if os.stat(f"/proc/{entry}").st_uid == uid:
                    pids.append(int(entry))
            except OSError:
                pass
    return pids


def kill_user(uid: int, rounds: int = 100) -> None:
    """Kill every process of ``uid`` (a sandbox user), repeating until none is left.

    Each round first stops (SIGSTOP) every process found, so a fork bomb cannot outrun the
    scan, then kills them. Signals come from the grader (root); nothing runs as ``uid``.
    """
    if uid == os.geteuid() or uid == 0:
        raise ValueError(f"refusing to kill all processes of uid {uid}")
    for _ in range(rounds):
        pids = _processes_of(uid)
        if not pids:
            return
        for sig in (signal.SIGSTOP, signal.SIGKILL):
            for pid in pids:
                try:
                    os.kill(pid, sig)
                except ProcessLookupError:
                    pass
        time.sleep(0.01)


#: shared writable places searched for files a sandbox user left behind
SHARED_TMP = ("/tmp", "/var/tmp", "/dev/shm")


def remove_files_of(uid: int, places=SHARED_TMP) -> list[str]:
    """Remove the entries directly in ``places`` owned by ``uid`` (a sandbox user)."""
    if uid == os.geteuid() or uid == 0:
        raise ValueError(f"refusing to remove the files of uid {uid}")
    removed = []
    for place in places:
        try:
            entries = list(os.scandir(place))
        except OSError:
            continue
        for entry in entries:
            try:
                if entry.stat(follow_symlinks=False).st_uid != uid:
                    continue
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path, ignore_errors=True)
                else:
                    os.unlink(entry.path)
                removed.append(entry.path)
            except OSError:
                pass
    return removed


class _Manager(KernelManager):
    """A KernelManager whose command line is the sandbox chain, not the kernel spec's."""

    sandbox_cmd: list = []

    def format_kernel_cmd(self, extra_arguments=None):
        return [a.replace("{connection_file}", os.path.realpath(self.connection_file))
                for a in self.sandbox_cmd]


class SandboxedKernel:
    """A Python kernel started in ``workdir`` under :class:`Limits`.

    Parameters
    ----------
    workdir : Path
        Empty directory that becomes the kernel's working directory; created if missing and
        handed to the kernel's user. Files copied into it later must be passed to
        :meth:`adopt` so the kernel can write them.
    limits : Limits
        Resource limits.
    """

    def __init__(self, workdir: Path, limits: Limits):
        self.workdir = Path(workdir)
        self.limits = limits
        self.support = sandbox_support()
        self.uid = _POOL.acquire() if self.support.own_user else None
        self.km: KernelManager | None = None
        self.kc = None
        self._kept = 0

    # -- life cycle -----------------------------------------------------------------------
    def _command(self) -> list[str]:
        lim = self.limits
        cmd = []
        if self.support.prlimit:
            mem = lim.memory_mb * 1024 * 1024
            cpu = int(lim.timeout * 2 + 30)
            nproc = f"--nproc={lim.nproc}" if self.uid is not None else None
            cmd += ["prlimit", f"--as={mem}", f"--cpu={cpu}", f"--fsize={lim.file_mb << 20}",
                    "--nofile=256", "--core=0"] + ([nproc] if nproc else []) + ["--"]
        if self.support.no_network:
            cmd += ["unshare", "--net", "--"]
        if self.uid is not None:
            cmd += ["setpriv", f"--reuid={self.uid}", f"--regid={self.uid}", "--clear-groups",
                    "--"]
        return cmd + [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]

    def _env(self, home: Path) -> dict:
        keep = ("PATH", "LANG", "LC_ALL", "PYTHONPATH", "VIRTUAL_ENV", "TZ")
        env = {k: os.environ[k] for k in keep if k in os.environ}
        env.update(HOME=str(home), IPYTHONDIR=str(home / ".ipython"),
                   MPLCONFIGDIR=str(home / ".mpl"), MPLBACKEND="Agg",
                   JUPYTER_PLATFORM_DIRS="1", JUPYTER_RUNTIME_DIR=str(home / "runtime"),
                   OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1",
                   MALLOC_ARENA_MAX="2", PYDEVD_DISABLE_FILE_VALIDATION="1",
                   PYTHONDONTWRITEBYTECODE="1", PHOTOLIB_GRADING_SANDBOX="1",
                   TMPDIR=str(self.workdir.parent / "tmp"))
        # the kernel imports the same photolib as the grader, installed or not
        root = str(Path(__file__).resolve().parents[2])
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [root, env.get("PYTHONPATH")]))
        return env

    def adopt(self, path: Path) -> None:
        """Give ``path`` (recursively) to the kernel's user; folders ``path`` itself 0700."""
        path = Path(path)
        if path.is_dir():
            os.chmod(path, 0o700)
        if self.uid is None:
            return
        os.chown(path, self.uid, self.uid)
        if path.is_dir():
            for root, dirs, files in os.walk(path):
                for name in dirs + files:
                    os.chown(os.path.join(root, name), self.uid, self.uid, follow_symlinks=False)

    def start(self, ready_timeout: float = 30.0) -> None:
        """Launch the kernel and wait until it answers."""
        base = self.workdir.parent
        self.workdir.mkdir(parents=True, exist_ok=True)
        home = base / "home"
        for d in (home, base / "ipc", base / "tmp"):
            d.mkdir(exist_ok=True)
        km = _Manager(transport="ipc", ip=str(base / "ipc" / "k"),
                           connection_file=str(base / "ipc" / "kernel.json"))
        km.sandbox_cmd = self._command()
        km.write_connection_file()
        self.adopt(home)
        self.adopt(base / "ipc")
        self.adopt(base / "tmp")
        self.adopt(self.workdir)
        for d in (home, base / "ipc", base / "tmp", self.workdir):
            os.chmod(d, 0o700)  # only the kernel's own user (and the grader) may look inside
        if self.uid is not None:
            os.chmod(base, 0o711)
        km.start_kernel(cwd=str(self.workdir), env=self._env(home))
        self.km = km
        kc = km.blocking_client()
        kc.start_channels()
        kc.wait_for_ready(timeout=ready_timeout)
        self.kc = kc

    def is_alive(self) -> bool:
        return self.km is not None and self.km.is_alive()

    def shutdown(self) -> None:
        """Stop the kernel and every process it left behind; safe to call twice."""
        if self.kc is not None:
            try:
                self.kc.stop_channels()
            except Exception:  # noqa: BLE001 - a broken channel must not stop the clean-up
                pass
            self.kc = None
        if self.km is not None:
            try:
                self.km.shutdown_kernel(now=True)
            except Exception:  # noqa: BLE001
                pass
            self.km = None
        if self.uid is not None:
            kill_user(self.uid)
            remove_files_of(self.uid)
            _POOL.release(self.uid)
            self.uid = None

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.shutdown()

    # -- execution --------------------------------------------------------------------------
    def _keep(self, text: str, result: ExecResult) -> None:
        room = self.limits.output_bytes - self._kept
        if room > 0:
            result.text += text[:room]
            self._kept += min(room, len(text))
        result.dropped += max(0, len(text) - max(room, 0))

    def execute(self, code: str, timeout: float, silent: bool = False) -> ExecResult:
        """Run ``code``; collect at most ``output_bytes`` of text and the result payloads.

        On timeout the kernel is interrupted (SIGINT) and given 3 s to come back.
        """
        if not self.is_alive():
            return ExecResult("dead", "kernel is not running")
        kc = self.kc
        msg_id = kc.execute(code, silent=silent, store_history=False, allow_stdin=False)
        result = ExecResult("ok")
        deadline = time.monotonic() + timeout
        interrupted_at = None
        while True:
            now = time.monotonic()
            if interrupted_at is None and now > deadline:
                self.km.interrupt_kernel()
                interrupted_at = now
                result.status, result.error = "timeout", f"time limit {timeout:.0f} s"
            if interrupted_at is not None and now > interrupted_at + 3.0:
                return result
            try:
                msg = kc.get_iopub_msg(timeout=0.25)
            except Exception:  # queue.Empty: poll the kernel's life
                if not self.km.is_alive():
                    result.status, result.error = "dead", _death_reason(self.km)
                    return result
                continue
            if msg["parent_header"].get("msg_id") != msg_id:
                continue
            kind, content = msg["msg_type"], msg["content"]
            if kind == "status" and content.get("execution_state") == "idle":
                return result
            if kind == "stream":
                self._keep(content.get("text", ""), result)
            elif kind in ("display_data", "execute_result", "update_display_data"):
                data = content.get("data", {})
                if RESULT_MIME in data:
                    result.payloads.append(data[RESULT_MIME])
                else:
                    self._keep(str(data.get("text/plain", "")) + "\n", result)
            elif kind == "error":
                if result.status == "ok":
                    result.status = "error"
                    result.error = f"{content.get('ename', '?')}: {content.get('evalue', '')}"
                self._keep(f"{content.get('ename')}: {content.get('evalue')}\n", result)


def _death_reason(km: KernelManager) -> str:
    code = None
    try:
        code = km.provisioner.process.poll() if km.provisioner else None
    except Exception:  # noqa: BLE001
        pass
    if code is not None and code < 0:
        name = signal.Signals(-code).name if -code in signal.valid_signals() else str(-code)
        return f"kernel killed by {name}"
    if code is not None:
        return f"kernel exited with code {code}"
    return "kernel died"
