"""Grading submissions: run each in a sandboxed kernel, extract answers, judge them here.

:func:`grade_submission` grades one notebook; :class:`KernelPool` keeps kernels started ahead
of time (kernel start-up dominates the cost of a submission); :func:`grade_batch` grades many
in parallel and hands each result to a callback as soon as it is done.
"""

from __future__ import annotations

import os
import queue
import re
import shutil
import tempfile
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path

import nbformat

from photolib.grading.encode import NOT_ANSWERED
from photolib.grading.exercises import chapter as chapter_exercises
from photolib.grading.exercises import chapters
from photolib.grading.extract import (
    ExtractionError,
    answer_record,
    build_extraction,
    case_to_json,
    extraction_seconds,
    record_student_id,
)
from photolib.grading.judge import Judgement, judge
from photolib.grading.notebook import parameters_for
from photolib.grading.sandbox import MAX_MESSAGE_BYTES, Limits, SandboxedKernel
from photolib.grading.submission import (
    SubmissionError,
    chapter_claims,
    code_cells,
    read_submission,
    static_student_id,
    valid_student_id,
)
from photolib.grading.variants import rng_for
from photolib.grading.worker import Cancelled, JudgePool

__all__ = ["WARM_MODULES", "Cancelled", "Graded", "KernelPool", "StopRequest", "clean_message",
           "grade_batch", "grade_submission"]

#: imported into every kernel before it is handed a submission
WARM_MODULES = ("numpy", "sympy", "photolib.grading.notebook")
MAX_RESTARTS = 2
#: longest message kept in the gradebook and the feedback
MESSAGE_CHARS = 300
#: seconds the extraction may take beyond what is left of the submission's time limit
EXTRACT_GRACE = 10.0
#: seconds the re-run of the cells before one that swallowed the interrupt may take beyond
#: twice the time they took the first time (see :func:`_run_cells`)
RERUN_GRACE = 10.0


def clean_message(text, limit: int = MESSAGE_CHARS) -> str:
    """One line of at most ``limit`` characters: control characters become spaces.

    >>> clean_message("a\\nb,ok\\r" + "x" * 400)[:12]
    'a b,ok xxxxx'
    >>> len(clean_message("x" * 400))
    300
    """
    text = re.sub(r"[\x00-\x1f\x7f\u2028\u2029\x85]+", " ", str(text))
    return text if len(text) <= limit else text[:limit - 1] + "…"


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
    total : int, optional
        Kernels the batch needs (restarts aside): no more are started ahead of time.

    :meth:`stop` starts no kernel any more and kills the ones nobody took; :meth:`abort`
    kills all of them, also those in use (their submissions are abandoned). Every kernel is
    still shut down and removed by whoever holds it (:meth:`discard`, :meth:`close`).
    """

    def __init__(self, limits: Limits, size: int, total: int | None = None):
        self.limits = limits
        self._ready: queue.Queue = queue.Queue()
        self._closed = False
        self._lock = threading.Lock()
        self._threads = []
        self._pending = 0
        self._waiting = 0
        self._kernels: set = set()  # made and not yet discarded: starting, ready or in use
        self._taken: set = set()
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
        kernel = None
        try:
            kernel = SandboxedKernel(base / "work", self.limits)
            with self._lock:
                self._kernels.add(kernel)
            if self._closed:
                raise Cancelled("the batch was stopped")
            kernel.start()
            code = "".join(f"__import__({m!r});" for m in WARM_MODULES)
            kernel.execute(code, timeout=60, silent=True)
            item = kernel
        except Exception as exc:  # noqa: BLE001 - reported to whoever takes this kernel
            if kernel is not None:
                self.discard(kernel)
            shutil.rmtree(base, ignore_errors=True)
            item = exc
        if self._closed and isinstance(item, SandboxedKernel):
            self.discard(item)
            item = Cancelled("the batch was stopped")
        with self._lock:
            self._pending -= 1
            self._ready.put(item)

    def get(self) -> SandboxedKernel:
        """A started kernel; a new one is started in the background to replace it.

        Raises :class:`Cancelled` once the pool is stopped or closed.
        """
        spawn = False
        with self._lock:
            if self._closed:
                raise Cancelled("the batch was stopped")
            self._waiting += 1
            if self._remaining is None or self._remaining > 0:
                spawn = True
                if self._remaining is not None:
                    self._remaining -= 1
            elif self._pending + self._ready.qsize() < self._waiting:
                spawn = True  # a restart beyond the planned number of kernels
        if spawn:
            self._spawn()
        try:
            while True:
                try:
                    item = self._ready.get(timeout=0.1)
                    break
                except queue.Empty:
                    if self._closed:
                        raise Cancelled("the batch was stopped") from None
        finally:
            with self._lock:
                self._waiting -= 1
        if isinstance(item, SandboxedKernel) and self._closed:
            self.discard(item)
            raise Cancelled("the batch was stopped")
        if isinstance(item, Cancelled):
            raise item
        if isinstance(item, Exception):
            raise RuntimeError(f"could not start a sandboxed kernel: {item}") from item
        with self._lock:
            self._taken.add(item)
        return item

    def discard(self, kernel: SandboxedKernel) -> None:
        """Shut a kernel down and remove its temporary folder."""
        kernel.shutdown()
        shutil.rmtree(kernel.workdir.parent, ignore_errors=True)
        with self._lock:
            self._kernels.discard(kernel)
            self._taken.discard(kernel)

    def stop(self) -> None:
        """Start no more kernels; kill those starting or waiting (nobody will take them)."""
        self._closed = True
        with self._lock:
            idle = [k for k in self._kernels if k not in self._taken]
        for kernel in idle:
            kernel.kill()

    def abort(self) -> None:
        """:meth:`stop`, and kill the kernels in use too: their submissions end at once."""
        self.stop()
        with self._lock:
            kernels = list(self._kernels)
        for kernel in kernels:
            kernel.kill()

    def close(self, wait: float = 60.0) -> None:
        """Stop, wait up to ``wait`` s for kernels being started, shut the idle ones down."""
        self._closed = True
        with self._lock:
            threads = list(self._threads)
        end = time.monotonic() + wait
        for thread in threads:
            thread.join(timeout=max(end - time.monotonic(), 0.0))
        while not self._ready.empty():
            item = self._ready.get()
            if isinstance(item, SandboxedKernel):
                self.discard(item)

    def leftovers(self) -> list:
        """Kernels not yet discarded (after :meth:`close`: those of abandoned threads)."""
        with self._lock:
            return list(self._kernels)


def _write_submission(dst: Path, name: str, nb) -> None:
    """Write the submitted notebook, and nothing else, into a kernel's working folder.

    No other file of the submission's folder reaches a kernel: with 300 submissions in one
    folder, a sibling file is another student's work (or a gradebook left there), and the
    course notebooks read their data from the course package, never from their folder.
    """
    nbformat.write(nb, dst / name)


@dataclass
class _Run:
    """What running a submission's cells left: see :func:`_run_cells`."""

    kernel: SandboxedKernel | None
    errors: list
    deaths: list
    timed_out: bool
    dropped: int
    text: str
    deadline: float
    oversized: int = 0
    oom: int = 0
    #: index of the cell that ignored the interrupt at the time limit (None: none did)
    stuck: int | None = None
    #: the re-run of the cells before ``stuck`` could not give a kernel to read
    rerun_failed: bool = False


def _noted(errors: list, item: tuple) -> None:
    """Append ``(cell, message)`` unless a run before this one noted it already."""
    if item not in errors:
        errors.append(item)


def _run_cells(pool, path, nb, cells, limits, deadline) -> _Run:
    """Run the cells; restart after a kernel death and skip the cell that killed it.

    Writing the notebook into the kernel's folder does not count against the time limit:
    ``deadline`` moves by the time it took. ``oom`` counts processes the submission's memory
    limit (cgroup) killed in the kernels discarded here, ``oversized`` kernel messages
    dropped unread.

    A cell that is still running :data:`~photolib.grading.sandbox.INTERRUPT_GRACE` seconds
    after the interrupt at the time limit (a loop around a bare ``except:`` swallows
    ``KeyboardInterrupt``) holds the kernel: no extraction could ever run in it. That
    kernel is killed (the student's code cannot swallow ``SIGKILL``) and the cells before
    the stuck one are run again in a fresh kernel, within twice the time they took plus
    :data:`RERUN_GRACE`, so that the answers they defined are read as after any timeout.
    """
    skip, errors, deaths, timed_out, dropped = set(), [], [], False, 0
    oversized = oom = 0
    stop, stuck, restarts = len(cells), None, 0
    while True:
        kernel = pool.get()
        t_write = time.monotonic()
        _write_submission(kernel.workdir, path.name, nb)
        kernel.adopt(kernel.workdir)
        deadline += time.monotonic() - t_write
        died = held = False
        texts = []
        started = time.monotonic()
        for i, source in enumerate(cells[:stop]):
            if i in skip:
                continue
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                timed_out = True
                break
            oom_before = kernel.oom_kills()
            t_cell = time.monotonic()
            result = kernel.execute(source, remaining)
            texts.append(result.text)
            dropped += result.dropped
            oversized += result.oversized
            if result.payloads:
                _noted(errors, (i, "Tampering: the cell published a grading result"))
            if result.status == "error":
                _noted(errors, (i, result.error))
            elif result.status == "timeout":
                timed_out = True
                if result.stuck:
                    held, stop, spent = True, i, t_cell - started
                break
            elif result.status == "dead":
                reason = result.error
                if kernel.oom_kills() > oom_before:
                    reason = f"memory limit of {limits.memory_mb} MiB for all its processes; " \
                             + reason
                deaths.append((i, reason))
                skip.add(i)
                died = True
                break
        if not died and not held:
            return _Run(kernel, errors, deaths, timed_out, dropped, "".join(texts), deadline,
                        oversized, oom, stuck)
        oom += kernel.oom_kills()
        pool.discard(kernel)
        if held:
            if stuck is not None:  # a cell that had finished before held the re-run too
                return _Run(None, errors, deaths, timed_out, dropped, "", deadline, oversized,
                            oom, stuck, rerun_failed=True)
            stuck = stop
            deadline = time.monotonic() + min(limits.timeout, 2 * spent + RERUN_GRACE)
            continue
        restarts += 1
        if restarts > MAX_RESTARTS or time.monotonic() >= deadline:
            break
    return _Run(None, errors, deaths, timed_out, dropped, "", deadline, oversized, oom, stuck)


def _failed(path, status, detail, exercises, sid="", chapter=None, t0=None):
    detail = clean_message(detail)
    judgements = [Judgement(ex.id, "not-answered", 0.0, float(ex.points), detail)
                  for ex in exercises]
    return Graded(str(path), sid, status, detail, chapter, judgements,
                  seconds=time.monotonic() - (t0 or time.monotonic()))


_TRIVIAL = ({"value": {"t": "none"}}, None)


def grade_submission(path, pool: KernelPool, limits: Limits, judges: JudgePool | None = None,
                     chapter: str | None = None) -> Graded:
    """Grade one notebook; never raises for anything the submission does.

    Parameters
    ----------
    judges : JudgePool, optional
        Where answers are decoded and judged (one of its own if not given).
    chapter : str, optional
        The batch's chapter: a submission of another chapter gets ``wrong-chapter``.
    """
    if judges is None:
        judges = JudgePool(1, limits.judge_seconds, limits.judge_memory_mb)
        try:
            return grade_submission(path, pool, limits, judges, chapter)
        finally:
            judges.close()
    t0 = time.monotonic()
    path = Path(path)
    known = chapters()
    guess = chapter or next((c for c in known if c in path.name), None)
    try:
        nb = read_submission(path)
    except SubmissionError as exc:
        return _failed(path, exc.status, exc.detail, known.get(guess, ()), chapter=guess, t0=t0)
    by_meta, by_name = chapter_claims(nb, path, known)
    name = by_meta or by_name
    if name is None:
        return _failed(path, "unknown-chapter", "no chapter in metadata or file name",
                       known.get(chapter, ()), chapter=chapter, t0=t0)
    sid = valid_student_id(static_student_id(nb))
    if by_meta and by_name and by_meta != by_name:
        return _failed(path, "wrong-chapter",
                       f"the notebook's metadata says chapter {by_meta}, its file name "
                       f"{by_name}", known.get(chapter or by_name, ()), sid or "",
                       chapter or by_name, t0)
    if chapter is not None and name != chapter:
        return _failed(path, "wrong-chapter",
                       f"a notebook of chapter {name} in a gradebook of chapter {chapter}",
                       known.get(chapter, ()), sid or "", chapter, t0)
    exercises = chapter_exercises(name)
    deadline = t0 + limits.timeout
    run = _run_cells(pool, path, nb, code_cells(nb), limits, deadline)
    kernel, errors, deaths, timed_out = run.kernel, run.errors, run.deaths, run.timed_out
    notes = _run_notes(run, limits)
    tampered = any(e.startswith("Tampering") for _, e in errors)
    record, kernel_sid, lost = None, NOT_ANSWERED, False
    params = {}
    oom = run.oom
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
                params[ex.id] = cases
            requests.append({"name": ex.answer, "cases": cases})
        # the extraction may run a little past the submission's time limit, never far
        budget = min(extraction_seconds(requests),
                     max(run.deadline - time.monotonic(), 0.0) + EXTRACT_GRACE)
        code, nonce = build_extraction(requests, budget)
        result = kernel.execute(code, timeout=budget + 5)
        if result.status not in ("ok",):
            raise ExtractionError(f"reading the answers failed ({result.status}: "
                                  f"{clean_message(result.error, 200)})")
        record = answer_record(result.payloads, nonce)
        kernel_sid = record_student_id(record)
    except ExtractionError as exc:
        notes.append(str(exc))
        tampered = tampered or "tampered" in str(exc)
        lost = kernel is not None and not tampered
        record = None
    finally:
        if kernel is not None:
            oom += kernel.oom_kills()
            pool.discard(kernel)
    no_id = None
    if sid is None:
        sid = valid_student_id(kernel_sid)
        literal = static_student_id(nb)
        shown = literal if literal else kernel_sid if isinstance(kernel_sid, str) else None
        if sid is None:
            no_id = _missing_id_reason(shown, literal, record)
            notes.append(no_id)
    elif isinstance(kernel_sid, str) and kernel_sid != sid:
        notes.append(f"STUDENT_ID is changed later in the notebook (to "
                     f"{clean_message(kernel_sid, 70)!r}); graded as {sid!r}, the first literal")
    judgements = []
    for ex in exercises:
        item = None if (tampered or record is None) else record["answers"].get(ex.answer)
        if no_id is not None:  # never graded against the variant of the empty id, shared by all
            judgements.append(Judgement(ex.id, "not-graded", 0.0, float(ex.points),
                                        f"not graded: {no_id}"))
        elif item in _TRIVIAL:
            judgements.append(judge(ex, parameters_for(ex, sid), NOT_ANSWERED))
        else:
            judgements.append(judges.judge(ex, sid, item, params.get(ex.id)))
    judgements = [j if len(j.message) <= MESSAGE_CHARS and "\n" not in j.message
                  else Judgement(j.exercise_id, j.status, j.points, j.max_points,
                                 clean_message(j.message), j.mistake) for j in judgements]
    if oom:
        notes.append(f"the submission's processes together went over the memory limit of "
                     f"{limits.memory_mb} MiB: {oom} process(es) killed")
    status = _status(errors, deaths, timed_out, tampered, kernel is None, sid, lost, oom)
    return Graded(str(path), sid or "", status, clean_message("; ".join(notes), 1000), name,
                  judgements, run.text, time.monotonic() - t0)


def _run_notes(run, limits: Limits) -> list[str]:
    """The gradebook notes on how the submission's cells ran: their errors (the first five),
    cells that killed the kernel, the time limit, a cell that ignored the interrupt, dropped
    output."""
    notes = [f"cell {i + 1}: {clean_message(e, 200)}" for i, e in run.errors[:5]]
    notes += [f"cell {i + 1} killed the kernel ({e}); it was skipped" for i, e in run.deaths]
    if run.timed_out:
        notes.append(f"time limit of {limits.timeout:g} s reached; later cells did not run")
    if run.stuck is not None:
        notes.append(f"cell {run.stuck + 1} went on after the interrupt (a bare except:?): "
                     f"its kernel was stopped and cells 1-{run.stuck} run again to read the "
                     "answers" + ("; that re-run did not end either" if run.rerun_failed
                                  else ""))
    if run.dropped:
        notes.append(f"{run.dropped} characters of output dropped")
    if run.oversized:
        notes.append(f"{run.oversized} kernel message(s) larger than "
                     f"{MAX_MESSAGE_BYTES >> 20} MiB dropped unread (output lost)")
    return notes


def _missing_id_reason(shown, literal, record) -> str:
    """Why a notebook has no usable student id, in words for the gradebook and the student."""
    how = 'write yours as STUDENT_ID = "..." in the first cell'
    if shown:
        what = (f"STUDENT_ID {clean_message(shown, 70)!r} is not a usable id (letters, digits "
                "and _.@+-, not starting with = + - @ .)")
    elif literal == "" or (record is not None and record_student_id(record) == ""):
        what = "STUDENT_ID is empty"
    elif record is None:
        what = "the notebook has no STUDENT_ID literal and none could be read from the kernel"
    else:
        what = "the notebook defines no STUDENT_ID (or not as a string)"
    return f"{what}; not graded, as every student's numbers come from the id: {how}"


def _status(errors, deaths, timed_out, tampered, no_kernel, sid, lost=False, oom=0) -> str:
    if tampered:
        return "tampered"
    if sid is None and not (no_kernel or lost):  # nothing was graded: the id is what to fix
        return "no-student-id"
    if oom:  # the cgroup killed a process of the submission: whatever followed came of it
        return "memory-limit"
    if no_kernel:
        return "kernel-died"
    if lost:
        return "answers-lost"
    if timed_out:
        return "timeout"
    if any("MemoryError" in e for _, e in errors):
        return "memory-limit"
    if deaths:
        return "kernel-restarted"
    if errors:
        return "cell-errors"
    return "ok"


class StopRequest:
    """Ctrl-C for :func:`grade_batch`, safe to call from a signal handler.

    The first :meth:`request` stops the batch: no submission is started any more, the
    running ones get :data:`STOP_GRACE` seconds to finish (their results are kept), the
    others are abandoned (their kernels killed; no result). The second abandons the running
    ones at once. Plain attributes, no locks: a signal handler may run while the main thread
    holds any lock.
    """

    def __init__(self):
        self.stopping = False
        self.abandoning = False

    def request(self) -> int:
        """Ask for the next step; returns 1 (stop) or 2 (abandon)."""
        if self.stopping:
            self.abandoning = True
            return 2
        self.stopping = True
        return 1


#: seconds the running submissions get to finish after a first stop request (Ctrl-C)
STOP_GRACE = 1.5
#: seconds abandoned submissions' threads get to end once their kernels are killed
ABANDON_WAIT = 3.0


def grade_batch(paths, limits: Limits, jobs: int = 1, on_result=None,
                chapter: str | None = None, stop: StopRequest | None = None) -> list[Graded]:
    """Grade ``paths`` with ``jobs`` kernels at a time; ``on_result(graded)`` as each finishes.

    The same file given twice (by resolved path) is graded once. With ``chapter``, a
    submission of another chapter gets the status ``wrong-chapter``. ``stop`` (see
    :class:`StopRequest`) ends the batch early: the results returned (and handed to
    ``on_result``, always from the calling thread) are those of the submissions that
    finished; nothing of the others is kept, and no kernel, judge worker, cgroup or
    temporary folder of the batch is left when this returns.
    """
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    unique = {}
    for p in paths:
        unique.setdefault(os.path.realpath(p), p)
    paths = list(unique.values())
    results = []
    stop = stop if stop is not None else StopRequest()
    if not paths or stop.stopping:
        return results
    size = min(jobs, len(paths))
    pool = KernelPool(limits, size=size, total=len(paths))
    judges = JudgePool(size, limits.judge_seconds, limits.judge_memory_mb)
    executor = ThreadPoolExecutor(max_workers=jobs)

    def finished(done):
        for future in done:
            try:
                graded = future.result()
            except Cancelled:  # abandoned after a stop request: graded by the next run
                continue
            except Exception as exc:  # noqa: BLE001 - a grader bug must not stop the batch
                graded = Graded(str(futures[future]), "", "grader-error",
                                clean_message(f"{type(exc).__name__}: {exc}"))
            results.append(graded)
            if on_result is not None:
                on_result(graded)

    try:
        futures = {executor.submit(grade_submission, p, pool, limits, judges, chapter): p
                   for p in paths}
        pending = set(futures)
        while pending and not stop.stopping:
            done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            finished(done)
        if pending:  # stopped: nothing new starts, the running ones may finish in the grace
            for future in pending:
                future.cancel()
            pending = {f for f in pending if not f.cancelled()}
            pool.stop()
            end = time.monotonic() + STOP_GRACE
            while pending and time.monotonic() < end and not stop.abandoning:
                done, pending = wait(pending, timeout=0.1, return_when=FIRST_COMPLETED)
                finished(done)
            pool.abort()
            judges.abort()
            wait(pending, timeout=ABANDON_WAIT)  # their threads end once the kernels are gone
    finally:
        executor.shutdown(wait=False, cancel_futures=True)
        pool.close(wait=ABANDON_WAIT if stop.stopping else 60.0)
        judges.close()
        for kernel in pool.leftovers():  # held by a thread that did not end in time
            kernel.kill()
            pool.discard(kernel)
    return results
