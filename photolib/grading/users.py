"""Sandbox users of the grader: one user id per kernel, and whether such a user can work.

:class:`UidPool` hands out user ids 61000… (a lock file per id, so that parallel graders
never share one) and finds ids left locked by a grader that died;
:func:`_unprivileged_can_import` checks that an unprivileged user can start this
interpreter and import photolib (a course folder of mode 700 cannot be used by one: then
kernels run as the grader's own user, see ``docs/instructors.md``). Used by
:mod:`photolib.grading.sandbox`.
"""

from __future__ import annotations

import fcntl
import os
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

from photolib.grading.cleanup import _processes_of, kill_user

__all__ = ["UidPool"]


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
