"""The code the grader runs inside the student's kernel: read the answers out as data.

The kernel never imports this module. :func:`photolib.grading.extract.build_extraction` reads
its source (the grader's own file) and the source of
:func:`photolib.grading.encode.encode_value`, and the extraction cell executes both in a
fresh namespace in the kernel and calls :func:`run`: nothing the notebook patched in
``photolib``, nor a name it rebound in its own namespace, is used here. Only the standard
library is imported (``numpy`` when a function case has array arguments, ``IPython`` to
publish the record). The grader's tests import the module and call its functions directly.

An answer is read as a stream of *events*, JSON-ready dicts, reduced by :func:`collect` to
one answer item of the record:

- ``{"value": encoded}``: a value answer (or a function answer that is not callable);
- ``{"output": encoded}``: a student function's outcome on one hidden input, an encoded
  value or ``{"t": "raised", ...}``;
- ``{"error": text}``: reading stopped (the time limit, ``SystemExit``, too much data).

The record published (one display message of MIME type ``mime``) is
``{"nonce": nonce, "student_id": {...}, "answers": {name: item}}``.
"""

import io
import json
import os
import select
import signal
import sys
import time

#: characters of a message kept from an exception raised by student code
MESSAGE_CHARS = 200


def student_id(ns) -> dict:
    """``STUDENT_ID`` of the namespace, encoded: its first 1000 characters, else none.

    Only an exact ``str`` is read (a subclass's methods would run student code), and with
    ``str``'s own methods.
    """
    sid = ns.get("STUDENT_ID")
    if type(sid) is str:
        return {"t": "str", "v": str.__getitem__(sid, slice(0, 1000))}
    return {"t": "none"}


def arguments(case: list) -> list:
    """The arguments of one function case: each ``{"array": nested list}`` a float array."""
    if not any(isinstance(a, dict) for a in case):
        return case
    import numpy as np
    return [np.array(a["array"], dtype=float) if isinstance(a, dict) else a for a in case]


def call_cases(func, cases: list, emit, encode, call_seconds: float) -> None:
    """Call ``func`` on each case, each call under a SIGALRM limit of ``call_seconds``.

    Emits one ``output`` event per case: the encoded result, ``{"t": "none"}`` for
    ``NotImplementedError`` (not answered yet), or the raised exception's type and message
    (a degenerate input's right answer may be a ``ValueError``, judged as ``Raised``). A
    ``TimeoutError`` (the alarm, or the function's own) or a ``BaseException`` that is no
    ``Exception`` (``SystemExit``, ``KeyboardInterrupt``) emits an ``error`` event and stops
    the remaining cases. The previous SIGALRM handler is restored at the end.
    """
    def alarm(signum, frame):
        raise TimeoutError(f"the function took longer than {call_seconds:g} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    try:
        for case in cases:
            try:
                args = arguments(case)
                signal.setitimer(signal.ITIMER_REAL, call_seconds)
                try:
                    result = func(*args)
                finally:
                    signal.setitimer(signal.ITIMER_REAL, 0)
                emit({"output": encode(result)})
            except NotImplementedError:
                emit({"output": {"t": "none"}})
            except TimeoutError as exc:
                emit({"error": "your function raised TimeoutError: "
                               + str(exc)[:MESSAGE_CHARS]})
                return
            except Exception as exc:  # noqa: BLE001 - the outcome on a degenerate input
                emit({"output": {"t": "raised", "type": type(exc).__name__,
                                 "ve": isinstance(exc, ValueError),
                                 "m": str(exc)[:MESSAGE_CHARS]}})
            except BaseException as exc:
                emit({"error": "your function raised " + type(exc).__name__ + ": "
                               + str(exc)[:MESSAGE_CHARS]})
                return
    finally:
        signal.signal(signal.SIGALRM, previous)


def encode_answer(ns, request: dict, emit, encode, call_seconds: float) -> None:
    """Emit the events of one answer: ``request`` is ``{"name": …, "cases": …}``.

    A value answer (``cases`` None) is the encoded variable, or an ``error`` event naming
    the exception the encoding raised. A function answer that is not callable (missing,
    ``...``) is the value ``{"t": "none"}``: not answered; else :func:`call_cases`.
    """
    value = ns.get(request["name"])
    if request["cases"] is None:
        try:
            emit({"value": encode(value)})
        except Exception as exc:  # noqa: BLE001 - the answer's failure, reported by name
            emit({"error": type(exc).__name__})
        return
    if not callable(value):
        emit({"value": {"t": "none"}})
        return
    call_cases(value, request["cases"], emit, encode, call_seconds)


def collect(events: list, request: dict) -> dict:
    """The answer item of one answer's events.

    A value answer is its first event (``{"error": "no value"}`` for none); a function
    answer is ``{"outputs": [...], "error": text or None}``, or its ``value`` event.
    """
    if request["cases"] is None:
        for event in events:
            return event
        return {"error": "no value"}
    outputs, error = [], None
    for event in events:
        if "value" in event:
            return event
        if "output" in event:
            outputs.append(event["output"])
        elif "error" in event:
            error = event["error"]
    return {"outputs": outputs, "error": error}


def read_in_process(work, request: dict) -> dict:
    """``work(emit)`` run here, its events collected (where no child process can be made)."""
    events = []
    work(events.append)
    return collect(events, request)


def _child(work, rfd: int, wfd: int) -> None:
    """In the forked child: run ``work``, writing each event as a JSON line; never returns."""
    try:
        os.close(rfd)
        sys.stdout = sys.stderr = io.StringIO()

        def emit(event):
            view = memoryview((json.dumps(event) + "\n").encode())
            while view:
                view = view[os.write(wfd, view):]

        try:
            work(emit)
        except BaseException as exc:  # noqa: BLE001 - the child reports and ends
            emit({"error": "reading the answer failed: " + type(exc).__name__})
    finally:
        os._exit(0)


def _read_events(rfd: int, seconds: float, end: float, max_bytes: int) -> tuple[list, bool]:
    """Events read from the child's pipe until it closes; ``late`` when it must be killed.

    Each event restarts the ``seconds`` allowed (the next call afresh), never past ``end``
    (``time.monotonic()``); more than ``max_bytes`` is late too.
    """
    buf, events, size = b"", [], 0
    deadline = min(time.monotonic() + seconds, end)
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return events, True
        ready, _, _ = select.select([rfd], [], [], left)
        if not ready:
            continue
        chunk = os.read(rfd, 1 << 16)
        if not chunk:
            return events, False
        size += len(chunk)
        if size > max_bytes:
            return events, True
        buf += chunk
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            events.append(json.loads(line))
            deadline = min(time.monotonic() + seconds, end)


def read_isolated(work, request: dict, seconds: float, end: float, max_bytes: int) -> dict:
    """The answer item of ``work(emit)`` run in a child process forked from this one.

    The child is killed (SIGKILL) when it stays silent for ``seconds``, reaches ``end``
    (``time.monotonic()``) or writes more than ``max_bytes``; its answer then says so, with
    the events it sent before. A function that ignores the alarm costs its own exercise
    only. Where ``pipe`` or ``fork`` fails (e.g. the process limit is used up), ``work`` runs
    here (:func:`read_in_process`).
    """
    try:
        rfd, wfd = os.pipe()
    except OSError:
        return read_in_process(work, request)
    try:
        pid = os.fork()
    except OSError:
        os.close(rfd)
        os.close(wfd)
        return read_in_process(work, request)
    if pid == 0:
        _child(work, rfd, wfd)
    os.close(wfd)
    late = False
    try:
        events, late = _read_events(rfd, seconds, end, max_bytes)
    finally:
        os.close(rfd)
        if late:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        os.waitpid(pid, 0)
    if late and time.monotonic() >= end:
        events.append({"error": "the submission's time limit was reached while this "
                                "answer was read, and it was stopped"})
    elif late:
        what = "your function" if request["cases"] is not None else "reading the answer"
        events.append({"error": f"{what} took longer than {seconds:g} s or gave too much "
                                "data, and was stopped"})
    return collect(events, request)


def extract(ns, nonce: str, requests: list, seconds: float, encode, *, mime: str,
            call_seconds: float, value_seconds: float, max_bytes: int, publish=None) -> dict:
    """Read every answer of ``requests`` out of ``ns`` and publish the record once.

    Parameters
    ----------
    ns : dict
        The notebook's namespace.
    nonce : str
        The grader's nonce, carried by the record.
    requests : list of dict
        ``{"name": variable, "cases": None or list of argument lists}`` per exercise.
    seconds : float
        Time for the whole extraction, s: an answer not begun by then is reported as not
        read in time, one being read is stopped.
    encode : callable
        :func:`photolib.grading.encode.encode_value` (the copy injected in the kernel).
    mime : str
        MIME type of the one display message published.
    call_seconds, value_seconds : float
        Time of one function call (SIGALRM), of reading one value, s; a function answer's
        child process is given ``call_seconds + 1`` s per call.
    max_bytes : int
        Most data one answer may send, bytes.
    publish : callable, optional
        ``publish({mime: record})``; default ``IPython.display.publish_display_data``.

    Returns
    -------
    dict
        The record published.
    """
    end = time.monotonic() + seconds
    record = {"nonce": nonce, "student_id": student_id(ns), "answers": {}}
    for request in requests:
        if time.monotonic() >= end:
            record["answers"][request["name"]] = {
                "error": "the submission's time limit was reached before this answer was read"}
            continue

        def work(emit, request=request):
            encode_answer(ns, request, emit, encode, call_seconds)

        limit = call_seconds + 1 if request["cases"] is not None else value_seconds
        record["answers"][request["name"]] = read_isolated(work, request, limit, end,
                                                           max_bytes)
    if publish is None:
        from IPython.display import publish_display_data as publish
    publish({mime: record})
    return record


def run(ns, call: str, encode) -> None:
    """The extraction cell's entry point: :func:`extract` with the JSON text ``call``.

    ``call`` holds ``nonce``, ``requests``, ``seconds``, ``mime``, ``call_seconds``,
    ``value_seconds`` and ``max_bytes`` as :func:`photolib.grading.extract.build_extraction`
    wrote them.
    """
    extract(ns, encode=encode, **json.loads(call))
