"""Per-submission cgroups of the grading sandbox: memory (with swap) and process limits.

:class:`KernelCgroup` creates one memory and one pids cgroup per kernel below the grader's
own (cgroup v1, one folder per controller) or one cgroup (v2: ``memory.max``,
``memory.swap.max``, ``pids.max``, ``cgroup.kill``); the kernel's launch chain writes its
process id into ``cgroup.procs`` before it execs the kernel, so every process the kernel
starts is counted together. :func:`_cgroup_root` finds where this grader may create them
("" when nowhere: then ``--memory`` holds per process only, see ``docs/instructors.md``).
Used by :mod:`photolib.grading.sandbox`.
"""

from __future__ import annotations

import functools
import itertools
import os
import signal
import time
from dataclasses import dataclass
from pathlib import Path

__all__ = ["KernelCgroup"]

@dataclass(frozen=True)
class _CgroupRoot:
    """Where this grader may create kernel cgroups: ``version`` "" when nowhere."""

    version: str = ""
    parents: tuple[tuple[str, str], ...] = ()  # (controller or "unified", folder)


def _own_cgroups() -> tuple[dict, str | None]:
    """This process's cgroup v1 paths by controller, and its cgroup v2 path."""
    v1, v2 = {}, None
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
    except OSError:
        return v1, v2
    for line in lines:
        num, _, rest = line.partition(":")
        controllers, _, path = rest.partition(":")
        if num == "0" and controllers == "":
            v2 = path
        for c in controllers.split(","):
            if c:
                v1[c] = path
    return v1, v2


def _cgroup_mounts() -> list[tuple[str, str, str, set]]:
    """(fstype, mount root, mount point, super options) of the cgroup file systems."""
    found = []
    try:
        lines = Path("/proc/self/mountinfo").read_text().splitlines()
    except OSError:
        return found
    for line in lines:
        left, _, right = line.partition(" - ")
        fields, rfields = left.split(), right.split()
        if len(fields) >= 5 and len(rfields) >= 3 and rfields[0] in ("cgroup", "cgroup2"):
            found.append((rfields[0], fields[3], fields[4], set(rfields[2].split(","))))
    return found


def _join(mount: str, root: str, path: str) -> str:
    if root != "/" and path.startswith(root):
        path = path[len(root):]
    return os.path.normpath(mount + "/" + path.lstrip("/"))


def _writable_cgroup(folder: str, files: tuple[str, ...]) -> bool:
    """Whether a child cgroup can be made in ``folder`` with ``files`` written; cleans up."""
    probe = os.path.join(folder, f"photolib-probe-{os.getpid()}")
    try:
        os.mkdir(probe)
    except OSError:
        return False
    try:
        for name in files:
            Path(probe, name).write_text("max\n" if name.endswith(".max") else "-1\n")
        return True
    except OSError:
        return False
    finally:
        try:
            os.rmdir(probe)
        except OSError:
            pass


def _remove_stale(folder: str) -> None:
    """Remove empty kernel cgroups left by graders that are no longer running."""
    try:
        entries = os.listdir(folder)
    except OSError:
        return
    for name in entries:
        parts = name.split("-")
        if name.startswith("photolib-grading-") and len(parts) > 2 and parts[2].isdigit():
            if not os.path.exists(f"/proc/{parts[2]}"):
                try:
                    os.rmdir(os.path.join(folder, name))
                except OSError:
                    pass


@functools.cache
def _cgroup_root() -> _CgroupRoot:
    """Find a cgroup (v2 preferred, else v1) in which this grader may create kernel cgroups.

    Kernel cgroups are created below the grader's own cgroup, so every limit above it still
    holds. cgroup v2 needs ``memory`` and ``pids`` enabled for children (delegation), v1 a
    writable ``memory`` and ``pids`` hierarchy.
    """
    if os.geteuid() != 0:
        return _CgroupRoot()
    v1, v2 = _own_cgroups()
    mounts = _cgroup_mounts()
    if v2 is not None:
        for fstype, root, mount, _ in mounts:
            if fstype != "cgroup2":
                continue
            folder = _join(mount, root, v2)
            try:
                available = Path(folder, "cgroup.controllers").read_text().split()
                enabled = Path(folder, "cgroup.subtree_control").read_text().split()
            except OSError:
                continue
            if not {"memory", "pids"} <= set(available):
                continue
            if not {"memory", "pids"} <= set(enabled):
                try:  # refused (EBUSY) when processes live in the grader's own cgroup
                    Path(folder, "cgroup.subtree_control").write_text("+memory +pids\n")
                except OSError:
                    continue
            if _writable_cgroup(folder, ("memory.max", "pids.max")):
                _remove_stale(folder)
                return _CgroupRoot("v2", (("unified", folder),))
    parents = {}
    for controller, limit in (("memory", "memory.limit_in_bytes"), ("pids", "pids.max")):
        for fstype, root, mount, opts in mounts:
            if fstype == "cgroup" and controller in opts and controller in v1:
                folder = _join(mount, root, v1[controller])
                if _writable_cgroup(folder, (limit,)):
                    parents[controller] = folder
                    break
    if set(parents) == {"memory", "pids"}:
        for folder in parents.values():
            _remove_stale(folder)
        return _CgroupRoot("v1", tuple(parents.items()))
    return _CgroupRoot()


_CGROUP_SERIAL = itertools.count()


class KernelCgroup:
    """The cgroup(s) of one kernel's process tree: memory and process limits, OOM count.

    Parameters
    ----------
    root : _CgroupRoot
    memory_bytes : int
        Memory of all processes together (and no swap), bytes.
    pids : int
        Processes and threads of the tree.
    """

    def __init__(self, root: _CgroupRoot, memory_bytes: int, pids: int):
        self.version = root.version
        name = f"photolib-grading-{os.getpid()}-{next(_CGROUP_SERIAL)}-{os.urandom(3).hex()}"
        self.dirs = {}
        try:
            for controller, parent in root.parents:
                folder = os.path.join(parent, name)
                os.mkdir(folder)
                self.dirs[controller] = folder
            if self.version == "v2":
                d = self.dirs["unified"]
                self._write(d, "memory.max", memory_bytes)
                self._write(d, "memory.swap.max", 0, optional=True)
                self._write(d, "pids.max", pids)
            else:
                d = self.dirs["memory"]
                self._write(d, "memory.limit_in_bytes", memory_bytes)
                self._write(d, "memory.memsw.limit_in_bytes", memory_bytes, optional=True)
                self._write(self.dirs["pids"], "pids.max", pids)
        except OSError:
            self.remove()
            raise

    @staticmethod
    def _write(folder, name, value, optional=False):
        try:
            Path(folder, name).write_text(f"{value}\n")
        except OSError:
            if not optional:
                raise

    @property
    def procs_files(self) -> list[str]:
        """The files a process writes its pid to, to enter the cgroup(s)."""
        return [os.path.join(d, "cgroup.procs") for d in self.dirs.values()]

    def oom_kills(self) -> int:
        """How many processes of the tree the memory limit has killed so far."""
        d = self.dirs.get("unified") or self.dirs.get("memory")
        name = "memory.events" if self.version == "v2" else "memory.oom_control"
        try:
            for line in Path(d, name).read_text().splitlines():
                key, _, value = line.partition(" ")
                if key == "oom_kill":
                    return int(value)
        except (OSError, ValueError, TypeError):
            pass
        return 0

    def pids(self) -> list[int]:
        found = set()
        for d in self.dirs.values():
            try:
                found.update(int(x) for x in Path(d, "cgroup.procs").read_text().split())
            except (OSError, ValueError):
                pass
        return sorted(found)

    def kill(self) -> None:
        """SIGKILL every process in the cgroup(s) (v2: ``cgroup.kill``)."""
        d = self.dirs.get("unified")
        if d and os.path.exists(os.path.join(d, "cgroup.kill")):
            try:
                Path(d, "cgroup.kill").write_text("1\n")
                return
            except OSError:
                pass
        for _ in range(100):
            pids = [p for p in self.pids() if p != os.getpid()]
            if not pids:
                return
            for pid in pids:
                try:
                    os.kill(pid, signal.SIGKILL)
                except OSError:
                    pass
            time.sleep(0.01)

    def remove(self, wait: float = 5.0) -> None:
        """Kill what is left and remove the cgroup(s); safe to call twice."""
        if self.dirs:
            self.kill()
        end = time.monotonic() + wait
        for key, d in list(self.dirs.items()):
            while True:
                try:
                    os.rmdir(d)
                    break
                except FileNotFoundError:
                    break
                except OSError:  # dying processes still counted (EBUSY)
                    if time.monotonic() > end:
                        break
                    self.kill()
                    time.sleep(0.02)
            if not os.path.exists(d):
                del self.dirs[key]
