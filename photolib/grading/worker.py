"""Judging under a hard bound: each answer is decoded and judged in a worker process.

Decoding rebuilds SymPy trees and judging samples them with mpmath; an answer crafted to be
expensive (a tower of exponentials, a huge power) must not stall the grader or eat its
memory. :class:`JudgePool` keeps worker processes (``python -m photolib.grading.worker``,
new interpreters that inherit no grader threads or locks) with an address-space limit (``RLIMIT_AS``); each answer gets
``timeout`` wall-clock seconds, after which the worker is killed and replaced and the answer
scores zero with a message. A worker that was left with busy helper threads (symcheck's
bounded exact routes) exits after answering, so the next answer starts in a fresh one.
"""

from __future__ import annotations

import os
import pickle
import queue
import select
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

__all__ = ["Cancelled", "JudgePool"]

_HEADER = struct.Struct("!Q")


class Cancelled(RuntimeError):
    """The batch was stopped (Ctrl-C): the submission being graded is abandoned, no row."""


def _vm_bytes() -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def _write(stream, obj) -> None:
    data = pickle.dumps(obj)
    stream.write(_HEADER.pack(len(data)) + data)
    stream.flush()


def _read_exact(stream, n: int) -> bytes:
    data = stream.read(n)
    if data is None or len(data) < n:
        raise EOFError("the judge worker closed its pipe")
    return data


def _serve(memory_mb: int) -> None:
    """Worker main loop: ``(exercise_id, student_id, item, cases)`` in, Judgement out."""
    out = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)  # whatever prints goes to stderr, not into the protocol
    stdin = sys.stdin.buffer
    from photolib.grading.exercises import exercise
    from photolib.grading.extract import judge_item
    try:
        import photolib.symcheck  # noqa: F401 - imported before the memory limit is set
    except ImportError:
        pass
    try:
        import resource
        limit = _vm_bytes() + memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    except (ImportError, ValueError, OSError):
        pass
    _write(out, "ready")
    while True:
        try:
            (n,) = _HEADER.unpack(_read_exact(stdin, _HEADER.size))
            job = pickle.loads(_read_exact(stdin, n))
        except (EOFError, OSError, pickle.UnpicklingError):
            return
        if job is None:
            return
        ex_id, sid, item, cases = job
        try:
            result = judge_item(exercise(ex_id), sid, item, cases)
        except MemoryError:
            result = "memory"
        leftover = threading.active_count() > 1  # a bounded route left a thread running
        try:
            _write(out, (result, leftover))
        except Exception:  # noqa: BLE001 - the parent reports a dead worker
            return
        if leftover:  # start anew rather than share the CPU with it
            return


class _Worker:
    def __init__(self, memory_mb: int):
        root = str(Path(__file__).resolve().parents[2])
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                   MKL_NUM_THREADS="1")
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [root, env.get("PYTHONPATH")]))
        self.process = subprocess.Popen(
            [sys.executable, "-m", "photolib.grading.worker", str(int(memory_mb))],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env, cwd="/",
            start_new_session=True)
        self._buf = b""
        if self.receive(120) != "ready":
            self.kill()
            raise OSError("the judge worker did not start")

    def alive(self) -> bool:
        return self.process.poll() is None

    def send(self, obj) -> None:
        _write(self.process.stdin, obj)

    def receive(self, timeout: float):
        """The next message, or raise TimeoutError after ``timeout`` s / EOFError."""
        deadline = time.monotonic() + timeout
        fd = self.process.stdout.fileno()
        need = None
        while True:
            if need is None and len(self._buf) >= _HEADER.size:
                (need,) = _HEADER.unpack(self._buf[:_HEADER.size])
            if need is not None and len(self._buf) >= _HEADER.size + need:
                data = self._buf[_HEADER.size:_HEADER.size + need]
                self._buf = self._buf[_HEADER.size + need:]
                return pickle.loads(data)
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            ready, _, _ = select.select([fd], [], [], left)
            if ready:
                chunk = os.read(fd, 1 << 20)
                if not chunk:
                    raise EOFError("the judge worker exited")
                self._buf += chunk

    def kill(self) -> None:
        if self.alive():
            self.process.kill()
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            pass
        for stream in (self.process.stdin, self.process.stdout):
            try:
                stream.close()
            except OSError:
                pass


class JudgePool:
    """Worker processes that judge one answer at a time under ``timeout`` and ``memory_mb``.

    Parameters
    ----------
    size : int
        Workers (use the number of parallel jobs).
    timeout : float
        Wall-clock seconds per answer (decoding, reference, comparison and hints).
    memory_mb : int
        Memory a worker may grow by beyond what it uses after start-up, MiB.
    """

    def __init__(self, size: int = 1, timeout: float = 30.0, memory_mb: int = 2048):
        self.timeout, self.memory_mb = float(timeout), int(memory_mb)
        self._idle: queue.Queue = queue.Queue()
        self._all: list[_Worker] = []
        self._lock = threading.Lock()
        self._closed = False
        for _ in range(max(1, size)):
            self._idle.put(None)  # started on first use

    def _new(self) -> _Worker:
        worker = _Worker(self.memory_mb)
        with self._lock:
            self._all.append(worker)
        return worker

    def _drop(self, worker: _Worker | None) -> None:
        if worker is None:
            return
        worker.kill()
        with self._lock:
            if worker in self._all:
                self._all.remove(worker)

    def judge(self, ex, student_id: str, item, cases):
        """Judgement of one answer item; zero points with a message when it overruns."""
        from photolib.grading.judge import Judgement

        def failed(message, mistake):
            return Judgement(ex.id, "wrong", 0.0, float(ex.points), message, mistake)

        if self._closed:
            raise Cancelled("the batch was stopped")
        worker = self._idle.get()
        keep = None
        try:
            if self._closed:  # aborted while this thread waited for a worker
                raise Cancelled("the batch was stopped")
            if worker is None or not worker.alive():
                self._drop(worker)
                worker = self._new()
            worker.send((ex.id, student_id, item, cases))
            try:
                result, leftover = worker.receive(self.timeout)
            except TimeoutError:
                return failed(f"judging this answer took longer than {self.timeout:g} s "
                              "and was stopped (is the expression unreasonably large?)",
                              "judge-timeout")
            except (EOFError, OSError, pickle.UnpicklingError):
                return failed("judging this answer stopped the judge (memory limit of "
                              f"{self.memory_mb} MiB?)", "judge-died")
            if not leftover:
                keep = worker
            if result == "memory":
                return failed(f"judging this answer exceeded the memory limit of "
                              f"{self.memory_mb} MiB", "judge-memory")
            return result
        except (BrokenPipeError, EOFError, OSError) as exc:
            return failed(f"the judge failed on this answer ({type(exc).__name__})",
                          "judge-died")
        finally:
            if keep is not None and keep.alive() and not self._closed:
                self._idle.put(keep)
            else:
                self._drop(worker)
                self._idle.put(None)

    def abort(self) -> None:
        """Kill every worker now (the batch was stopped); later :meth:`judge` calls raise
        :class:`Cancelled`, one under way ends with a "judge-died" verdict nobody keeps."""
        self._closed = True
        with self._lock:
            workers = list(self._all)
        for worker in workers:
            if worker.alive():
                try:
                    worker.process.kill()
                except OSError:
                    pass

    def close(self) -> None:
        """Stop every worker (those judging an answer too) and wait for each to end."""
        self._closed = True
        with self._lock:
            workers = list(self._all)
            self._all.clear()
        for worker in workers:
            try:
                worker.send(None)
            except (OSError, ValueError):
                pass
            worker.kill()


if __name__ == "__main__":
    _serve(int(sys.argv[1]))
