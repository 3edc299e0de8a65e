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
import stat
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
from photolib.grading.worker import JudgePool

__all__ = ["COPY_FILE_BYTES", "COPY_TOTAL_BYTES", "WARM_MODULES", "Graded", "KernelPool",
           "clean_message", "grade_batch", "grade_submission"]

#: imported into every kernel before it is handed a submission
WARM_MODULES = ("numpy", "sympy", "photolib.grading.notebook")
MAX_RESTARTS = 2
#: largest sibling file copied into a kernel's working copy, and most bytes copied in all
COPY_FILE_BYTES = 16 * 1024 * 1024
COPY_TOTAL_BYTES = 64 * 1024 * 1024
COPY_ENTRIES = 2000
#: longest message kept in the gradebook and the feedback
MESSAGE_CHARS = 300
#: seconds the extraction may take beyond what is left of the submission's time limit
EXTRACT_GRACE = 10.0


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


def _copy_folder(src: Path, dst: Path, keep: str, nb) -> list[str]:
    """Copy what the notebook may need from its folder; return the names of skipped files.

    Copied: regular files up to :data:`COPY_FILE_BYTES` each and :data:`COPY_TOTAL_BYTES` in
    all, in sub-folders too. Never copied: other notebooks (``*.ipynb`` in any letter case),
    hidden entries, symbolic links, special files and sparse files (more size than disk
    blocks). The submitted notebook itself is written last.
    """
    skipped, total, seen = [], 0, 0

    def walk(folder: Path, target: Path, rel: str):
        nonlocal total, seen
        try:
            entries = sorted(os.scandir(folder), key=lambda e: e.name)
        except OSError:
            return
        for entry in entries:
            seen += 1
            name = f"{rel}{entry.name}"
            if seen > COPY_ENTRIES:
                skipped.append(f"{name} (more than {COPY_ENTRIES} files)")
                continue
            if entry.name.startswith(".") or entry.name.lower().endswith(".ipynb"):
                continue
            try:
                info = entry.stat(follow_symlinks=False)
            except OSError:
                continue
            if stat.S_ISDIR(info.st_mode):
                (target / entry.name).mkdir(exist_ok=True)
                walk(Path(entry.path), target / entry.name, name + "/")
                continue
            if not stat.S_ISREG(info.st_mode):  # symbolic links, fifos, devices: never
                continue
            size = info.st_size
            if size > COPY_FILE_BYTES:
                skipped.append(f"{name} ({size} bytes > {COPY_FILE_BYTES})")
            elif size > 4096 and info.st_blocks * 512 < size // 2:
                skipped.append(f"{name} (sparse file)")
            elif total + size > COPY_TOTAL_BYTES:
                skipped.append(f"{name} (the copied files would exceed {COPY_TOTAL_BYTES} bytes)")
            else:
                try:
                    shutil.copyfile(entry.path, target / entry.name, follow_symlinks=False)
                    total += size
                except OSError:
                    skipped.append(f"{name} (unreadable)")

    walk(src, dst, "")
    nbformat.write(nb, dst / keep)
    return skipped


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


def _run_cells(pool, path, nb, cells, limits, deadline, skipped_files=None) -> _Run:
    """Run the cells; restart after a kernel death and skip the cell that killed it.

    Copying the folder does not count against the time limit: ``deadline`` moves by the
    time the copy took. ``oom`` counts processes the submission's memory limit (cgroup)
    killed in the kernels discarded here, ``oversized`` kernel messages dropped unread.
    """
    skip, errors, deaths, timed_out, dropped = set(), [], [], False, 0
    oversized = oom = 0
    for _ in range(MAX_RESTARTS + 1):
        kernel = pool.get()
        t_copy = time.monotonic()
        skipped = _copy_folder(path.parent, kernel.workdir, path.name, nb)
        kernel.adopt(kernel.workdir)
        deadline += time.monotonic() - t_copy
        if skipped_files is not None and not skipped_files:
            skipped_files.extend(skipped)
        died = False
        texts = []
        for i, source in enumerate(cells):
            if i in skip:
                continue
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                timed_out = True
                break
            oom_before = kernel.oom_kills()
            result = kernel.execute(source, remaining)
            texts.append(result.text)
            dropped += result.dropped
            oversized += result.oversized
            if result.payloads:
                errors.append((i, "Tampering: the cell published a grading result"))
            if result.status == "error":
                errors.append((i, result.error))
            elif result.status == "timeout":
                timed_out = True
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
        if not died:
            return _Run(kernel, errors, deaths, timed_out, dropped, "".join(texts), deadline,
                        oversized, oom)
        oom += kernel.oom_kills()
        pool.discard(kernel)
        if time.monotonic() >= deadline:
            break
    return _Run(None, errors, deaths, timed_out, dropped, "", deadline, oversized, oom)


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
    skipped_files: list[str] = []
    run = _run_cells(pool, path, nb, code_cells(nb), limits, deadline, skipped_files)
    kernel, errors, deaths, timed_out = run.kernel, run.errors, run.deaths, run.timed_out
    notes = [f"cell {i + 1}: {clean_message(e, 200)}" for i, e in errors[:5]]
    notes += [f"cell {i + 1} killed the kernel ({e}); it was skipped" for i, e in deaths]
    if timed_out:
        notes.append(f"time limit of {limits.timeout:g} s reached; later cells did not run")
    if run.dropped:
        notes.append(f"{run.dropped} characters of output dropped")
    if run.oversized:
        notes.append(f"{run.oversized} kernel message(s) larger than "
                     f"{MAX_MESSAGE_BYTES >> 20} MiB dropped unread (output lost)")
    if skipped_files:
        notes.append(f"{len(skipped_files)} file(s) of the folder not copied: "
                     + ", ".join(skipped_files[:3]))
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
    if sid is None:
        sid = valid_student_id(kernel_sid)
        literal = static_student_id(nb)
        shown = literal if literal else kernel_sid if isinstance(kernel_sid, str) else None
        if sid is None and shown:
            notes.append(f"STUDENT_ID {clean_message(shown, 70)!r} is not a usable id "
                         "(letters, digits and _.@+-, not starting with = + - @ .)")
    elif isinstance(kernel_sid, str) and kernel_sid != sid:
        notes.append(f"STUDENT_ID is changed later in the notebook (to "
                     f"{clean_message(kernel_sid, 70)!r}); graded as {sid!r}, the first literal")
    judgements = []
    for ex in exercises:
        item = None if (tampered or record is None) else record["answers"].get(ex.answer)
        if item in _TRIVIAL:
            judgements.append(judge(ex, parameters_for(ex, sid or ""), NOT_ANSWERED))
        else:
            judgements.append(judges.judge(ex, sid or "", item, params.get(ex.id)))
    judgements = [j if len(j.message) <= MESSAGE_CHARS and "\n" not in j.message
                  else Judgement(j.exercise_id, j.status, j.points, j.max_points,
                                 clean_message(j.message), j.mistake) for j in judgements]
    if oom:
        notes.append(f"the submission's processes together went over the memory limit of "
                     f"{limits.memory_mb} MiB: {oom} process(es) killed")
    status = _status(errors, deaths, timed_out, tampered, kernel is None, sid, lost, oom)
    return Graded(str(path), sid or "", status, clean_message("; ".join(notes), 1000), name,
                  judgements, run.text, time.monotonic() - t0)


def _status(errors, deaths, timed_out, tampered, no_kernel, sid, lost=False, oom=0) -> str:
    if tampered:
        return "tampered"
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
    if sid is None:
        return "no-student-id"
    if errors:
        return "cell-errors"
    return "ok"


def grade_batch(paths, limits: Limits, jobs: int = 1, on_result=None,
                chapter: str | None = None) -> list[Graded]:
    """Grade ``paths`` with ``jobs`` kernels at a time; ``on_result(graded)`` as each finishes.

    The same file given twice (by resolved path) is graded once. With ``chapter``, a
    submission of another chapter gets the status ``wrong-chapter``.
    """
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    unique = {}
    for p in paths:
        unique.setdefault(os.path.realpath(p), p)
    paths = list(unique.values())
    results = []
    if not paths:
        return results
    size = min(jobs, len(paths))
    pool = KernelPool(limits, size=size, total=len(paths))
    judges = JudgePool(size, limits.judge_seconds, limits.judge_memory_mb)
    try:
        with ThreadPoolExecutor(max_workers=jobs) as executor:
            futures = {executor.submit(grade_submission, p, pool, limits, judges, chapter): p
                       for p in paths}
            for future in as_completed(futures):
                try:
                    graded = future.result()
                except Exception as exc:  # noqa: BLE001 - a grader bug must not stop the batch
                    graded = Graded(str(futures[future]), "", "grader-error",
                                    clean_message(f"{type(exc).__name__}: {exc}"))
                results.append(graded)
                if on_result is not None:
                    on_result(graded)
    finally:
        pool.close()
        judges.close()
    return results
