"""Clean-up after a sandboxed kernel: its processes, files and IPC objects.

Every kernel runs as a user id of its own (:class:`photolib.grading.sandbox.UidPool`), so
what it leaves can be found by owner: :func:`kill_user` stops and kills its processes until
none is left, :func:`remove_files_of` removes its files in the shared writable places at any
depth, :func:`remove_ipc_of` its SysV shared memory, message queues and semaphores (where the
kernel had no IPC namespace of its own). Used by :mod:`photolib.grading.sandbox`.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import signal
import stat
import time
from pathlib import Path

__all__ = ["SHARED_TMP", "kill_user", "remove_files_of", "remove_ipc_of"]

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
SHARED_TMP = ("/tmp", "/var/tmp", "/dev/shm", "/run/lock", "/dev/mqueue")


def _open_to_others(places) -> list[str]:
    """``places`` and every folder below them that other users may write to.

    Only folders other users can enter (``o+x``) are searched, without following symbolic
    links or leaving the file system of each place.
    """
    found = []
    for place in places:
        try:
            top = os.stat(place, follow_symlinks=False)
        except OSError:
            continue
        if not stat.S_ISDIR(top.st_mode):
            continue
        found.append(place)
        stack = [place]
        while stack:
            folder = stack.pop()
            try:
                entries = list(os.scandir(folder))
            except OSError:
                continue
            for entry in entries:
                try:
                    info = entry.stat(follow_symlinks=False)
                except OSError:
                    continue
                if not stat.S_ISDIR(info.st_mode) or info.st_dev != top.st_dev:
                    continue
                if info.st_mode & stat.S_IWOTH:
                    found.append(entry.path)
                if info.st_mode & stat.S_IXOTH:
                    stack.append(entry.path)
    return found


def remove_files_of(uid: int, places=SHARED_TMP, recursive: bool = True) -> list[str]:
    """Remove what a sandbox user ``uid`` left in shared writable places.

    A sandbox user can create files only in folders other users may write to (and inside
    its own folders), so with ``recursive`` every such folder below ``places`` is searched
    (:func:`_open_to_others`) and each entry of ``uid`` in it is removed, a folder with all
    it holds (``shutil.rmtree`` does not follow symbolic links). Without ``recursive`` only
    the entries directly in ``places`` are.

    Returns
    -------
    list of str
        The paths removed.
    """
    if uid == os.geteuid() or uid == 0:
        raise ValueError(f"refusing to remove the files of uid {uid}")
    removed = []
    folders = _open_to_others(places) if recursive else list(places)
    for place in folders:
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


#: SysV IPC kinds: /proc/sysvipc file, id column, owner and creator uid columns
_IPC_KINDS = (("shm", 1, 7, 9), ("msg", 1, 7, 9), ("sem", 1, 4, 6))


def remove_ipc_of(uid: int) -> list[str]:
    """Remove the SysV shared memory segments, message queues and semaphores of ``uid``.

    Needed only where kernels cannot get an IPC namespace of their own (``unshare --ipc``),
    which takes its objects with it; a segment otherwise holds memory until reboot.

    Returns
    -------
    list of str
        ``"shm 3"``-style names of the objects removed.
    """
    if uid == os.geteuid() or uid == 0:
        raise ValueError(f"refusing to remove the IPC objects of uid {uid}")
    libc = ctypes.CDLL(None, use_errno=True)
    ipc_rmid = 0
    removed = []
    for kind, id_col, uid_col, cuid_col in _IPC_KINDS:
        try:
            lines = Path(f"/proc/sysvipc/{kind}").read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            cols = line.split()
            try:
                ident, owners = int(cols[id_col]), {int(cols[uid_col]), int(cols[cuid_col])}
            except (IndexError, ValueError):
                continue
            if uid not in owners:  # the owner may hand a segment to another uid (IPC_SET)
                continue
            if kind == "shm":
                rc = libc.shmctl(ident, ipc_rmid, None)
            elif kind == "msg":
                rc = libc.msgctl(ident, ipc_rmid, None)
            else:
                rc = libc.semctl(ident, 0, ipc_rmid)
            if rc == 0:
                removed.append(f"{kind} {ident}")
    return removed
