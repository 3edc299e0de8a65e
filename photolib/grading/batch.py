"""Grading submissions: run each in a sandboxed kernel, extract answers, judge them here.

:func:`grade_submission` grades one notebook; :class:`KernelPool` keeps kernels started ahead
of time (kernel start-up dominates the cost of a submission); :func:`grade_batch` grades many
in parallel and hands each result to a callback as soon as it is done.
"""

from __future__ import annotations

import queue
import shutil
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import nbformat

from photolib.grading.encode import NOT_ANSWERED
from photolib.grading.exercises import chapter as chapter_exercises
from photolib.grading.exercises import chapters
from photolib.grading.extract import (
    ExtractionError,
    build_extraction,
    case_from_json,
    case_to_json,
    parse_extraction,
)
from photolib.grading.judge import Judgement, judge
from photolib.grading.notebook import parameters_for, reference_outputs
from photolib.grading.sandbox import Limits, SandboxedKernel
from photolib.grading.submission import (
    SubmissionError,
    chapter_of,
    code_cells,
    read_submission,
    static_student_id,
    valid_student_id,
)
from photolib.grading.variants import rng_for

__all__ = ["WARM_MODULES", "Graded", "KernelPool", "grade_batch", "grade_submission"]

#: imported into every kernel before it is handed a submission
WARM_MODULES = ("numpy", "sympy", "photolib.grading.notebook")
MAX_RESTARTS = 2


@dataclass
class Graded:
    """The result of grading one submission."""

    submission: str
    student_id: str
    status: str
    detail: str = ""
    chapter: str | None = None
    judgements: list = field(default_factory=list)
    output: str = ""
    seconds: float = 0.0

    @property
    def total(self) -> float:
        return sum(j.points for j in self.judgements)

    @property
    def max_total(self) -> float:
        return sum(j.max_points for j in self.judgements)


class KernelPool:
    """Sandboxed kernels started ahead of time, each used for one submission only.

    Parameters
    ----------
    limits : Limits
    size : int
        Kernels kept ready (use the number of parallel jobs).
    """

    def __init__(self, limits: Limits, size: int, total: int | None = None):
        self.limits = limits
        self._ready: queue.Queue = queue.Queue()
        self._closed = False
        self._lock = threading.Lock()
        self._threads = []
        self._pending = 0
        self._waiting = 0
        first = size if total is None else min(size, total)
        self._remaining = None if total is None else total - first
        for _ in range(first):
            self._spawn()

    def _spawn(self):
        thread = threading.Thread(target=self._start_one, daemon=True)
        with self._lock:
            self._threads.append(thread)
            self._pending += 1
        thread.start()

    def _start_one(self):
        base = Path(tempfile.mkdtemp(prefix="photolib-grade-"))
        kernel = SandboxedKernel(base / "work", self.limits)
        try:
            kernel.start()
            code = "".join(f"__import__({m!r});" for m in WARM_MODULES)
            kernel.execute(code, timeout=60, silent=True)
            item = kernel
        except Exception as exc:  # noqa: BLE001 - reported to whoever takes this kernel
            kernel.shutdown()
            shutil.rmtree(base, ignore_errors=True)
            item = exc
        if self._closed and isinstance(item, SandboxedKernel):
            self.discard(item)
            item = RuntimeError("pool closed")
        with self._lock:
            self._pending -= 1
            self._ready.put(item)

    def get(self) -> SandboxedKernel:
        """A started kernel; a new one is started in the background to replace it."""
        spawn = False
        with self._lock:
            self._waiting += 1
            if self._remaining is None or self._remaining > 0:
                spawn = not self._closed
                if self._remaining is not None:
                    self._remaining -= 1
            elif self._pending + self._ready.qsize() < self._waiting:
                spawn = True  # a restart beyond the planned number of kernels
        if spawn:
            self._spawn()
        item = self._ready.get()
        with self._lock:
            self._waiting -= 1
        if isinstance(item, Exception):
            raise RuntimeError(f"could not start a sandboxed kernel: {item}") from item
        return item

    @staticmethod
    def discard(kernel: SandboxedKernel) -> None:
        """Shut a kernel down and remove its temporary folder."""
        kernel.shutdown()
        shutil.rmtree(kernel.workdir.parent, ignore_errors=True)

    def close(self) -> None:
        self._closed = True
        with self._lock:
            threads = list(self._threads)
        for thread in threads:
            thread.join(timeout=60)
        while not self._ready.empty():
            item = self._ready.get()
            if isinstance(item, SandboxedKernel):
                self.discard(item)


def _copy_folder(src: Path, dst: Path, keep: str, nb) -> None:
    """Copy the submission's folder (without the other notebooks) and the notebook."""
    for entry in src.iterdir():
        if entry.suffix == ".ipynb" or entry.name.startswith("."):
            continue
        try:
            if entry.is_symlink():
                continue
            if entry.is_dir():
                shutil.copytree(entry, dst / entry.name, symlinks=True,
                                ignore=shutil.ignore_patterns("*.ipynb"))
            elif entry.is_file():
                shutil.copy2(entry, dst / entry.name)
        except OSError:
            continue
    nbformat.write(nb, dst / keep)


def _run_cells(pool, path, nb, cells, limits, deadline):
    """Run the cells; restart after a kernel death and skip the cell that killed it."""
    skip, errors, deaths, timed_out, dropped = set(), [], [], False, 0
    for _ in range(MAX_RESTARTS + 1):
        kernel = pool.get()
        _copy_folder(path.parent, kernel.workdir, path.name, nb)
        kernel.adopt(kernel.workdir)
        died = False
        texts = []
        for i, source in enumerate(cells):
            if i in skip:
                continue
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                timed_out = True
                break
            result = kernel.execute(source, remaining)
            texts.append(result.text)
            dropped += result.dropped
            if result.payloads:
                errors.append((i, "Tampering: the cell published a grading result"))
            if result.status == "error":
                errors.append((i, result.error))
            elif result.status == "timeout":
                timed_out = True
                break
            elif result.status == "dead":
                deaths.append((i, result.error))
                skip.add(i)
                died = True
                break
        if not died:
            return kernel, errors, deaths, timed_out, dropped, "".join(texts)
        pool.discard(kernel)
        if time.monotonic() >= deadline:
            break
    return None, errors, deaths, timed_out, dropped, ""


def _failed(path, status, detail, exercises, sid="", chapter=None, t0=None):
    judgements = [Judgement(ex.id, "not-answered", 0.0, float(ex.points), detail)
                  for ex in exercises]
    return Graded(str(path), sid, status, detail, chapter, judgements,
                  seconds=time.monotonic() - (t0 or time.monotonic()))


def grade_submission(path, pool: KernelPool, limits: Limits) -> Graded:
    """Grade one notebook; never raises for anything the submission does."""
    t0 = time.monotonic()
    path = Path(path)
    known = chapters()
    guess = next((c for c in known if c in path.name), None)
    try:
        nb = read_submission(path)
    except SubmissionError as exc:
        return _failed(path, exc.status, exc.detail, known.get(guess, ()), chapter=guess, t0=t0)
    name = chapter_of(nb, path, known)
    if name is None:
        return _failed(path, "unknown-chapter", "no chapter in metadata or file name", (),
                       t0=t0)
    exercises = chapter_exercises(name)
    sid = valid_student_id(static_student_id(nb))
    deadline = t0 + limits.timeout
    kernel, errors, deaths, timed_out, dropped, text = _run_cells(
        pool, path, nb, code_cells(nb), limits, deadline)
    notes = [f"cell {i + 1}: {e}" for i, e in errors[:5]]
    notes += [f"cell {i + 1} killed the kernel ({e}); it was skipped" for i, e in deaths]
    if timed_out:
        notes.append(f"time limit of {limits.timeout:g} s reached; later cells did not run")
    if dropped:
        notes.append(f"{dropped} characters of output dropped")
    tampered = any(e.startswith("Tampering") for _, e in errors)
    answers, kernel_sid = {}, NOT_ANSWERED
    params = {}
    try:
        if kernel is None:
            raise ExtractionError("the kernel died; no answers could be read")
        requests = []
        for ex in exercises:
            cases = None
            if ex.kind == "function":
                p = parameters_for(ex, sid or "")
                cases = [case_to_json(c) for c in ex.cases(rng_for(sid or "", ex.id,
                                                                       "hidden"), p)]
                params[ex.id] = (p, cases)
            requests.append({"name": ex.answer, "cases": cases})
        code, nonce = build_extraction(requests)
        n_calls = sum(len(r["cases"] or ()) for r in requests)
        result = kernel.execute(code, timeout=15 + 5 * n_calls)
        if result.status not in ("ok",):
            raise ExtractionError(f"reading the answers failed ({result.status}: "
                                  f"{result.error})")
        kernel_sid, answers = parse_extraction(result.payloads, nonce, exercises)
    except ExtractionError as exc:
        notes.append(str(exc))
        tampered = tampered or "tampered" in str(exc)
        answers = {}
    finally:
        if kernel is not None:
            pool.discard(kernel)
    if sid is None:
        sid = valid_student_id(kernel_sid)
    judgements = []
    for ex in exercises:
        p, cases = params.get(ex.id, (parameters_for(ex, sid or ""), None))
        outputs_of = reference_outputs([case_from_json(c) for c in cases]) if cases else None
        answer = answers.get(ex.id, NOT_ANSWERED)
        if tampered:
            answer = NOT_ANSWERED
        judgements.append(judge(ex, p, answer, outputs_of))
    status = _status(errors, deaths, timed_out, tampered, kernel is None, sid)
    return Graded(str(path), sid or "", status, "; ".join(notes), name, judgements,
                  text, time.monotonic() - t0)


def _status(errors, deaths, timed_out, tampered, no_kernel, sid) -> str:
    if tampered:
        return "tampered"
    if no_kernel:
        return "kernel-died"
    if timed_out:
        return "timeout"
    if any("MemoryError" in e for _, e in errors):
        return "memory-limit"
    if deaths:
        return "kernel-restarted"
    if sid is None:
        return "no-student-id"
    if errors:
        return "cell-errors"
    return "ok"


def grade_batch(paths, limits: Limits, jobs: int = 1, on_result=None) -> list[Graded]:
    """Grade ``paths`` with ``jobs`` kernels at a time; ``on_result(graded)`` as each finishes."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    paths = list(paths)
    results = []
    if not paths:
        return results
    pool = KernelPool(limits, size=min(jobs, len(paths)), total=len(paths))
    try:
        with ThreadPoolExecutor(max_workers=jobs) as executor:
            futures = {executor.submit(grade_submission, p, pool, limits): p for p in paths}
            for future in as_completed(futures):
                try:
                    graded = future.result()
                except Exception as exc:  # noqa: BLE001 - a grader bug must not stop the batch
                    graded = Graded(str(futures[future]), "", "grader-error",
                                    f"{type(exc).__name__}: {exc}")
                results.append(graded)
                if on_result is not None:
                    on_result(graded)
    finally:
        pool.close()
    return results
