"""A Jupyter kernel in a sandbox: own process, rlimits, no network, unprivileged user.

The kernel is launched through a chain of small system tools, each of which ``exec``\\ s the
next, so the kernel's process id is the one jupyter_client watches::

    unshare --net --ipc --mount                          (no network, own IPC and mount namespaces)
      sh -c 'echo $$ > CGROUP/cgroup.procs; mount …'     (as root: enter the submission's cgroup;
                                                          private /tmp, /var/tmp, /run/lock and
                                                          /dev/shm; /proc with hidepid=2)
        prlimit --as=… --nproc=… --cpu=… --fsize=… --nofile=…   (per-process limits)
          setpriv --reuid=U --regid=U --clear-groups --no-new-privs  (a user of its own)
            python -m ipykernel_launcher -f CONNECTION_FILE

The kernel talks to the grader over Unix domain sockets (``transport="ipc"``) in its own
folder, which work without any network interface and stay visible in the private mounts.
Each kernel gets a user id of its own from :class:`UidPool`, so a fork bomb meets
``RLIMIT_NPROC`` for that kernel alone and everything the kernel started can be killed at the
end as that user. The cgroup (v2 ``memory.max``/``pids.max``, or v1
``memory.limit_in_bytes``/``pids.max``) bounds the memory of the kernel's whole process tree,
including what it puts in its private tmpfs folders. The unprivileged user cannot write to the
course repository, the submissions or the grader's files; it writes only to its working copy
and its private temporary folders, which vanish with the kernel. :func:`sandbox_support`
reports which steps this machine permits; the kernel runs with what remains (see
``docs/instructors.md``), and what a kernel leaves behind in shared places is removed
(:func:`remove_files_of`, :func:`remove_ipc_of`).
"""

from __future__ import annotations

import functools
import os
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import zmq
from jupyter_client import KernelManager
from jupyter_core.utils import run_sync
from zmq.utils.monitor import recv_monitor_message

from photolib.grading.cgroups import KernelCgroup, _cgroup_root
from photolib.grading.cleanup import (
    kill_user,
    remove_files_of,
    remove_ipc_of,
)
from photolib.grading.users import _POOL, UidPool, _unprivileged_can_import

__all__ = [
    "MAX_MESSAGE_BYTES",
    "ExecResult",
    "Limits",
    "SandboxSupport",
    "SandboxedKernel",
    "UidPool",
    "remove_files_of",
    "remove_ipc_of",
    "sandbox_support",
]

#: MIME type of the grader's own result messages (see :mod:`photolib.grading.extract`)
RESULT_MIME = "application/x-photolib-grading+json"
#: largest message frame the grader reads from a kernel (``zmq.MAXMSGSIZE``); a larger one is
#: dropped unread (the socket is reconnected), so a kernel cannot inflate the grader's memory
MAX_MESSAGE_BYTES = 16 * 1024 * 1024
#: seconds a kernel interrupted at a time limit has to end the cell; one that is still busy
#: after that (its code swallowed the ``KeyboardInterrupt``) is reported ``stuck``
INTERRUPT_GRACE = 3.0


@dataclass(frozen=True)
class Limits:
    """Resource limits of one submission.

    Parameters
    ----------
    timeout : float
        Wall-clock seconds for running all cells of the notebook.
    memory_mb : int
        Memory of the submission, MiB: the address-space limit of each of its processes
        (``RLIMIT_AS``) and, where cgroups are available, the memory of all its processes
        together, including files in its private tmpfs folders.
    nproc : int
        Processes and threads of the kernel's user (``RLIMIT_NPROC``) and, with cgroups, of
        its process tree (``pids.max``).
    output_bytes : int
        Output text kept per submission; the rest is counted and dropped.
    file_mb : int
        Largest file the kernel may write (``RLIMIT_FSIZE``), MiB; also the size of each of its
        private ``/dev/shm``, ``/var/tmp`` and ``/run/lock`` (``/tmp``: twice that).
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
    #: ``unshare --ipc``: SysV and POSIX IPC objects die with the kernel
    ipc_namespace: bool = False
    #: private tmpfs on /tmp, /var/tmp, /run/lock and /dev/shm (a mount namespace)
    private_tmp: bool = False
    #: /proc mounted with hidepid=2: the kernel sees only its own processes
    hide_processes: bool = False
    #: "v2", "v1" or "": the cgroup interface bounding each submission's memory and processes
    cgroup: str = ""
    #: ``setpriv --no-new-privs``: setuid programs give the kernel no privileges
    no_new_privs: bool = False


def _run_ok(cmd, **kw) -> bool:
    try:
        return subprocess.run(cmd, capture_output=True, timeout=30, **kw).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


#: places whose contents a kernel's private mount namespace replaces with a small tmpfs
PRIVATE_PLACES = ("/tmp", "/var/tmp", "/run/lock", "/dev/shm")


#: at most this many folders of the grader's own (Python, photolib) are bound back into the
#: private places: the shell holds each open on a file descriptor 3…9 while the tmpfs goes on
MAX_KEPT = 7


@functools.cache
def kept_folders(places: tuple = PRIVATE_PLACES) -> tuple[str, ...]:
    """Folders a kernel needs that lie in one of the private ``places``.

    The kernel runs this Python and imports photolib: the virtual environment, photolib's
    root and the folders on ``sys.path`` must stay visible over the private tmpfs. A clone
    made with ``git clone . "$(mktemp -d)/c"`` has both in /tmp, where a private /tmp would
    hide them and every kernel die before it answers. Returns the outermost such folders,
    shallowest first.
    """
    roots = [Path(p).resolve() for p in places if os.path.isdir(p)]
    wanted = [Path(__file__).resolve().parents[2], Path(sys.prefix), Path(sys.exec_prefix),
              Path(sys.base_prefix), Path(sys.executable).parent,
              Path(os.path.realpath(sys.executable)).parent]
    wanted += [Path(p) for p in sys.path if p]
    wanted += [Path(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    found = set()
    for w in wanted:
        try:
            r = w.resolve()
        except OSError:
            continue
        if r.is_dir() and any(r == root or root in r.parents for root in roots):
            found.add(r)
    kept: list[Path] = []
    for r in sorted(found, key=lambda q: (len(q.parts), str(q))):
        if not any(k == r or k in r.parents for k in kept):
            kept.append(r)
    return tuple(str(k) for k in kept)


def _mount_script(base: str, work: str, places, size_mb: int, hide: bool,
                  keep=()) -> str:
    """Shell steps (run as root in the new mount namespace) for private places and /proc.

    ``base`` (the kernel's folder: working copy, IPC sockets, TMPDIR) may lie in one of the
    places: the shell enters it first and binds it back to its path over the new tmpfs.
    ``keep`` (at most :data:`MAX_KEPT` folders, :func:`kept_folders`) are opened on file
    descriptors 3, 4, … before the tmpfs is mounted and bound back the same way; the
    descriptors are closed before the kernel starts.
    """
    q = shlex.quote
    keep = list(keep) if places else []
    if len(keep) > MAX_KEPT:
        raise ValueError(f"{len(keep)} folders to keep visible, at most {MAX_KEPT}: {keep}")
    steps = [f"cd {q(base)}"] + [f"exec {3 + i}< {q(k)}" for i, k in enumerate(keep)]
    for place in places:
        size = 2 * size_mb if place == "/tmp" else size_mb
        steps.append(f"mount -t tmpfs -o size={size}m,mode=1777,nosuid,nodev "
                     f"photolib-sandbox {q(place)}")
    if places:
        # "." is the folder entered above, the original: not canonicalised into the new tmpfs
        # (the parents of base, made in the new tmpfs, must be enterable by the kernel's user);
        # /proc/self/fd/N likewise names the original folder held open on descriptor N
        steps += [f"(umask 022 && mkdir -p {q(base)})",
                  f"mount --no-canonicalize --bind . {q(base)}"]
        for i, k in enumerate(keep):
            steps += [f"(umask 022 && mkdir -p {q(k)})",
                      f"mount --no-canonicalize --bind /proc/self/fd/{3 + i} {q(k)}",
                      f"exec {3 + i}<&-"]
    if hide:
        steps.append("mount -t proc -o hidepid=2,nosuid,nodev,noexec proc /proc")
    steps.append(f"cd {q(work)}")
    return " && ".join(steps)


@functools.cache
def sandbox_support() -> SandboxSupport:
    """Probe once which isolation steps this machine permits.

    Returns
    -------
    SandboxSupport
        ``no_network`` is true when ``unshare --net`` works; ``own_user`` when the grader runs
        as root and ``setpriv`` exists (then each kernel runs as a user id of its own);
        ``ipc_namespace``, ``private_tmp``, ``hide_processes``, ``cgroup`` and ``no_new_privs``
        when those steps work (all but the IPC namespace need ``own_user``). ``notes`` says
        in words what is missing.
    """
    notes = []
    prlimit = shutil.which("prlimit") is not None
    if not prlimit:
        notes.append("prlimit not found: no memory, CPU, process or file-size limits; "
                     "only the wall-clock timeout holds")
    no_network = ipc_ns = False
    if shutil.which("unshare"):
        no_network = _run_ok(["unshare", "--net", "true"])
        ipc_ns = no_network and _run_ok(["unshare", "--net", "--ipc", "true"])
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
    private_tmp = hide = nnp = False
    cgroup = ""
    if own_user:
        nnp = _run_ok(["setpriv", "--no-new-privs", "true"])
        if not nnp:
            notes.append("setpriv --no-new-privs failed: setuid programs keep their privileges")
        private_tmp, hide = _probe_mounts()
        if not private_tmp:
            notes.append("no private mount namespace (unshare --mount + tmpfs): kernels share "
                         "/tmp, /var/tmp, /run/lock and /dev/shm with the host; their files there "
                         "are removed after each kernel")
        if not hide:
            notes.append("/proc cannot be mounted with hidepid=2: a kernel can see other "
                         "processes and their command lines (the gradebook path among them)")
        cgroup = _cgroup_root().version
        if not cgroup:
            notes.append("no writable cgroup with memory and pids controllers: --memory holds "
                         "per process, not for a submission's processes together")
    if not ipc_ns:
        notes.append("unshare --ipc is not permitted: SysV IPC objects a kernel leaves are "
                     "removed after it ends" if own_user else
                     "unshare --ipc is not permitted: SysV IPC objects a kernel leaves may stay")
    return SandboxSupport(prlimit, no_network, own_user, tuple(notes), ipc_ns, private_tmp,
                          hide, cgroup, nnp)


def _probe_mounts() -> tuple[bool, bool]:
    """Whether private tmpfs places (with the kernel folder bound back) and hidepid work."""
    if not shutil.which("unshare") or not shutil.which("mount"):
        return False, False
    base = tempfile.mkdtemp(prefix="photolib-probe-")
    try:
        work = os.path.join(base, "work")
        os.mkdir(work)
        places = tuple(p for p in PRIVATE_PLACES if os.path.isdir(p))
        open(os.path.join(base, "marker"), "w").close()
        keep = kept_folders(places)
        # the kernel folder and this Python must be there over the tmpfs
        script = _mount_script(base, work, places, 1, False, keep[:MAX_KEPT]) + \
            f" && test -e {shlex.quote(base)}/marker && test -x {shlex.quote(sys.executable)}"
        tmp_ok = len(keep) <= MAX_KEPT and _run_ok(
            ["unshare", "--mount", "--propagation", "private", "--", "sh", "-c", script])
        hide_ok = _run_ok(["unshare", "--mount", "--propagation", "private", "--", "sh", "-c",
                           _mount_script(base, work, (), 1, True)])
        return tmp_ok, hide_ok
    finally:
        shutil.rmtree(base, ignore_errors=True)




@dataclass
class ExecResult:
    """Outcome of executing one piece of code in the kernel.

    ``status`` is ``"ok"``, ``"error"`` (the code raised), ``"timeout"`` or ``"dead"`` (the
    kernel died). ``payloads`` are the data of display messages of type :data:`RESULT_MIME`.
    ``dropped`` counts characters of output not kept, ``oversized`` messages over
    :data:`MAX_MESSAGE_BYTES` that were dropped unread. ``stuck`` is true for a timeout
    after which the cell had not ended :data:`INTERRUPT_GRACE` seconds after the interrupt:
    the kernel is still busy with it and will run nothing else.
    """

    status: str
    error: str = ""
    text: str = ""
    dropped: int = 0
    payloads: list = field(default_factory=list)
    oversized: int = 0
    stuck: bool = False



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
        self.cgroup: KernelCgroup | None = None
        self._context = None
        self._monitors = []
        self._kept = 0
        self._killed = False
        self._shutdown_lock = threading.Lock()

    # -- life cycle -----------------------------------------------------------------------
    def _command(self) -> list[str]:
        lim = self.limits
        support = self.support
        cmd, steps = [], []
        flags = ["--net"] if support.no_network else []
        if support.ipc_namespace:
            flags.append("--ipc")
        private = self.uid is not None and (support.private_tmp or support.hide_processes)
        if private:
            flags += ["--mount", "--propagation", "private"]
        if flags:
            cmd += ["unshare", *flags, "--"]
        if self.cgroup is not None:
            steps += [f"echo $$ > {shlex.quote(f)}" for f in self.cgroup.procs_files]
        if private:
            base = str(self.workdir.parent)
            places = [p for p in PRIVATE_PLACES if os.path.isdir(p)] if support.private_tmp \
                else []
            steps.append(_mount_script(base, str(self.workdir), places, lim.file_mb,
                                       support.hide_processes, kept_folders(tuple(places))))
        if steps:  # as root, in the new namespaces: the same process, exec'd on below
            cmd += ["sh", "-c", " && ".join(steps) + ' && exec "$@"', "photolib-sandbox"]
        if support.prlimit:
            mem = lim.memory_mb * 1024 * 1024
            cpu = int(lim.timeout * 2 + 30)
            nproc = f"--nproc={lim.nproc}" if self.uid is not None else None
            cmd += ["prlimit", f"--as={mem}", f"--cpu={cpu}", f"--fsize={lim.file_mb << 20}",
                    "--nofile=256", "--core=0"] + ([nproc] if nproc else []) + ["--"]
        if self.uid is not None:
            cmd += ["setpriv", f"--reuid={self.uid}", f"--regid={self.uid}", "--clear-groups"]
            cmd += ["--no-new-privs"] if support.no_new_privs else []
            cmd += ["--"]
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
        km.write_connection_file()
        self.adopt(home)
        self.adopt(base / "ipc")
        self.adopt(base / "tmp")
        self.adopt(self.workdir)
        for d in (home, base / "ipc", base / "tmp", self.workdir):
            os.chmod(d, 0o700)  # only the kernel's own user (and the grader) may look inside
        if self.uid is not None:
            os.chmod(base, 0o711)
        root = _cgroup_root() if self.uid is not None and self.support.cgroup else None
        if root is not None and root.version:
            self.cgroup = KernelCgroup(root, self.limits.memory_mb << 20, self.limits.nproc)
        km.sandbox_cmd = self._command()
        km.start_kernel(cwd=str(self.workdir), env=self._env(home))
        self.km = km
        if self._killed:  # kill() came while the kernel was being launched
            self.kill()
            raise RuntimeError("the kernel was killed while it started")
        kc = km.blocking_client()
        # a context of our own: every socket it makes refuses frames over MAX_MESSAGE_BYTES
        # (the limit must be set before the socket connects)
        self._context = zmq.Context()
        self._context.setsockopt(zmq.MAXMSGSIZE, MAX_MESSAGE_BYTES)
        kc.context = self._context
        kc.start_channels()
        self._monitors = []
        for channel in (kc.iopub_channel, kc.shell_channel):
            monitor = channel.socket.get_monitor_socket(zmq.EVENT_DISCONNECTED)
            self._monitors.append((channel.socket, _channel_url(channel), monitor))
        self.kc = kc
        kc.wait_for_ready(timeout=ready_timeout)

    def is_alive(self) -> bool:
        return self.km is not None and self.km.is_alive()

    def oom_kills(self) -> int:
        """Processes of this kernel's tree killed by the submission's memory limit so far."""
        return self.cgroup.oom_kills() if self.cgroup is not None else 0

    def _reconnect_dropped(self) -> int:
        """Reconnect each channel whose connection an oversized frame broke; how many."""
        broken = 0
        for sock, url, monitor in self._monitors:
            try:
                while monitor.poll(0):
                    recv_monitor_message(monitor)
                    broken += 1
                    try:
                        sock.disconnect(url)
                    except zmq.ZMQError:
                        pass
                    sock.connect(url)
            except zmq.ZMQError:
                pass
        return broken

    def kill(self) -> None:
        """SIGKILL the kernel and every process of its tree now; callable from any thread.

        For a batch that is stopped (Ctrl-C): whatever the kernel runs ends at once (also a
        cell that swallows interrupts), and the thread using the kernel sees it dead within
        a poll. :meth:`shutdown` still removes the cgroup, the user's leftovers and the
        sockets; a kernel being launched is killed as soon as its process exists.
        """
        self._killed = True
        km = self.km
        process = _kernel_process(km)
        if process is not None and process.poll() is None:
            for kill in (os.killpg, os.kill):  # its own session: the group is the kernel's
                try:
                    kill(process.pid, signal.SIGKILL)
                except OSError:
                    pass
        cgroup, uid = self.cgroup, self.uid
        if cgroup is not None:
            cgroup.kill()
        if uid is not None:  # two rounds, no waiting: shutdown() repeats until none is left
            kill_user(uid, rounds=2)  # (the kernel's zombie stays until its thread reaps it)

    def shutdown(self) -> None:
        """Stop the kernel and every process it left behind; safe to call twice, and from
        two threads at once (the second waits for the first, then has nothing to do)."""
        with self._shutdown_lock:
            self._shutdown()

    def _shutdown(self) -> None:
        for sock, _, monitor in self._monitors:
            try:
                sock.disable_monitor()
                monitor.close(linger=0)
            except Exception:  # noqa: BLE001
                pass
        self._monitors = []
        if self.kc is not None:
            try:
                self.kc.stop_channels()
            except Exception:  # noqa: BLE001 - a broken channel must not stop the clean-up
                pass
            self.kc = None
        if self._context is not None:
            try:
                self._context.destroy(linger=0)
            except Exception:  # noqa: BLE001
                pass
            self._context = None
        if self.km is not None:
            try:
                self.km.shutdown_kernel(now=True)
            except Exception:  # noqa: BLE001
                pass
            self.km = None
        if self.cgroup is not None:
            self.cgroup.kill()
        if self.uid is not None:
            kill_user(self.uid)
            # with a private mount namespace nothing of the kernel is left in shared places
            # but what it left before (a crash), so the top level is enough there
            remove_files_of(self.uid, recursive=not self.support.private_tmp)
            if not self.support.ipc_namespace:
                remove_ipc_of(self.uid)
            _POOL.release(self.uid)
            self.uid = None
        if self.cgroup is not None:
            self.cgroup.remove()
            self.cgroup = None

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

        On timeout the kernel is interrupted (SIGINT) and given :data:`INTERRUPT_GRACE`
        seconds to come back (else the result is ``stuck``). A message
        over :data:`MAX_MESSAGE_BYTES` breaks its connection: the channel is reconnected and
        counted in ``oversized``; as messages sent meanwhile are lost (the final ``idle``
        status among them), the shell's ``execute_reply`` ends the wait as well.
        """
        if not self.is_alive():
            return ExecResult("dead", "kernel is not running")
        kc = self.kc
        msg_id = kc.execute(code, silent=silent, store_history=False, allow_stdin=False)
        result = ExecResult("ok")
        deadline = time.monotonic() + timeout
        interrupted_at = replied_at = None
        while True:
            now = time.monotonic()
            if interrupted_at is None and now > deadline:
                self.km.interrupt_kernel()
                interrupted_at = now
                result.status, result.error = "timeout", f"time limit {timeout:.0f} s"
            if interrupted_at is not None and now > interrupted_at + INTERRUPT_GRACE:
                result.stuck = replied_at is None
                return result
            result.oversized += self._reconnect_dropped()
            if replied_at is None:
                replied_at = self._replied(msg_id, result)
            elif now > replied_at + (0.5 if result.oversized else 5.0):
                return result  # the idle status was lost (a reconnect) or never came
            try:
                msg = kc.get_iopub_msg(timeout=0.1 if replied_at else 0.25)
            except Exception:  # queue.Empty: poll the kernel's life
                if not self.km.is_alive():
                    result.status, result.error = "dead", _death_reason(self.km)
                    return result
                continue
            if msg["parent_header"].get("msg_id") != msg_id:
                continue
            if replied_at is not None:
                replied_at = time.monotonic()  # output still coming: wait on for the idle
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

    def _replied(self, msg_id: str, result: ExecResult) -> float | None:
        """The time the shell's reply to ``msg_id`` came (None: not yet); others are dropped."""
        while True:
            try:
                reply = self.kc.get_shell_msg(timeout=0)
            except Exception:  # noqa: BLE001 - queue.Empty, or a reply that cannot be parsed
                return None
            if reply.get("parent_header", {}).get("msg_id") == msg_id:
                content = reply.get("content", {})
                if content.get("status") == "error" and result.status == "ok":
                    result.status = "error"
                    result.error = f"{content.get('ename', '?')}: {content.get('evalue', '')}"
                return time.monotonic()


def _channel_url(channel) -> str:
    """The address a client channel's socket is connected to (to connect it again).

    pyzmq's public ``LAST_ENDPOINT`` of the socket, where jupyter_client's
    ``KernelClient._make_url`` would be private.
    """
    return channel.socket.get(zmq.LAST_ENDPOINT).decode()


def _kernel_process(km: KernelManager | None):
    """The ``subprocess.Popen`` of the process ``km`` launched, or None.

    The one use of a jupyter_client internal (``LocalProvisioner.process``): its public ways
    to signal a kernel (``KernelManager.signal_kernel``, the provisioner's ``send_signal``
    and ``kill``) are coroutines run on the calling thread's event loop, and
    :meth:`SandboxedKernel.kill` must act at once from any thread while another thread uses
    the manager. ``test_sandbox_hardening.py`` checks it against the installed version.
    """
    return getattr(getattr(km, "provisioner", None), "process", None)


def _exit_code(km: KernelManager) -> int | None:
    """Exit status of the kernel's process (negative: killed by that signal); None while it
    runs or when none was launched. Through the provisioner's public ``poll``."""
    if not km.has_kernel:
        return None
    return run_sync(km.provisioner.poll)()


def _death_reason(km: KernelManager) -> str:
    code = None
    try:
        code = _exit_code(km)
    except Exception:  # noqa: BLE001
        pass
    if code is not None and code < 0:
        name = signal.Signals(-code).name if -code in signal.valid_signals() else str(-code)
        return f"kernel killed by {name}"
    if code is not None:
        return f"kernel exited with code {code}"
    return "kernel died"
