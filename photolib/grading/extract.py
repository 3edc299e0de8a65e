"""The grader's extraction cell: read the answers out of the kernel as data.

After the notebook has run, the grader executes code it generated itself. It carries a fresh
random nonce, reads ``STUDENT_ID`` and the answer variables, calls student functions on the
hidden inputs (each call under a SIGALRM time limit) and publishes one display message of
MIME type :data:`~photolib.grading.sandbox.RESULT_MIME` holding JSON. The encoder is
injected as source, so nothing the notebook patched in ``photolib`` is used. The grader
accepts exactly one message carrying the nonce, in reply to this very request; anything the
notebook may forge can only report answers, which are then judged like any other answers.
"""

from __future__ import annotations

import inspect
import json
import secrets

import numpy as np

from photolib.grading import encode
from photolib.grading.encode import NOT_ANSWERED, DecodeError, decode_value
from photolib.grading.judge import FunctionOutputs
from photolib.grading.sandbox import RESULT_MIME

__all__ = ["ExtractionError", "answer_record", "build_extraction", "case_from_json",
           "case_to_json", "decode_item", "extraction_seconds", "judge_item",
           "record_student_id"]

CALL_SECONDS = 5.0
VALUE_SECONDS = 5.0
MAX_ANSWER_BYTES = 16 * 1024 * 1024


class ExtractionError(RuntimeError):
    """No trustworthy answer record came back from the kernel."""


def build_extraction(requests: list[dict], seconds: float | None = None) -> tuple[str, str]:
    """Source of the extraction cell and its nonce.

    Parameters
    ----------
    requests : list of dict
        ``{"name": variable, "cases": None or list of argument lists}`` per exercise, the
        arguments as :func:`case_to_json` writes them (numbers, or ``{"array": nested list}``
        which the kernel turns back into a float ``numpy`` array).
    seconds : float, optional
        Time for the whole extraction (default :func:`extraction_seconds`): once it is used
        up, the answers not yet read are reported as not read in time, and the record is
        published with what was read.

    ``STUDENT_ID`` is read only when it is exactly a ``str`` (never a subclass, whose methods
    would run student code), with ``str`` methods.

    Each answer is encoded (and each student function called) in a child process forked from
    the kernel, which the kernel kills when it overruns (:data:`CALL_SECONDS` per call,
    :data:`VALUE_SECONDS` per value): a function that ignores the alarm costs its own
    exercise only. Where ``fork`` fails (e.g. the process limit is used up) the answer is
    read in the kernel itself, under the alarm.
    """
    nonce = secrets.token_hex(16)
    if seconds is None:
        seconds = extraction_seconds(requests)
    source = "\n".join([inspect.getsource(encode.encode_value), inspect.getsource(encode._tree)])
    code = f'''
def _photolib_extract_{nonce}():
    import json as _json, signal as _signal, sys as _sys, os as _os, io as _io
    import select as _select, time as _time
{_indent(source)}
    def _alarm(signum, frame):
        raise TimeoutError("the function took longer than {CALL_SECONDS:g} s")
    try:
        _ns = get_ipython().user_ns
    except NameError:
        _ns = vars(_sys.modules["__main__"])
    _requests = _json.loads({json.dumps(json.dumps(requests))})
    _end = _time.monotonic() + {float(seconds)!r}

    def _encode_one(_r, _emit):
        _value = _ns.get(_r["name"])
        if _r["cases"] is None:
            try:
                _emit({{"value": encode_value(_value)}})
            except Exception as _e:
                _emit({{"error": type(_e).__name__}})
            return
        if not callable(_value):
            _emit({{"value": {{"t": "none"}}}})
            return
        _signal.signal(_signal.SIGALRM, _alarm)
        for _args in _r["cases"]:
            try:
                if any(isinstance(_a, dict) for _a in _args):
                    import numpy as _np
                    _args = [_np.array(_a["array"], dtype=float) if isinstance(_a, dict)
                             else _a for _a in _args]
                _signal.setitimer(_signal.ITIMER_REAL, {CALL_SECONDS})
                try:
                    _res = _value(*_args)
                finally:
                    _signal.setitimer(_signal.ITIMER_REAL, 0)
                _emit({{"output": encode_value(_res)}})
            except NotImplementedError:
                _emit({{"output": {{"t": "none"}}}})
            except TimeoutError as _e:
                _emit({{"error": "your function raised TimeoutError: " + str(_e)[:200]}})
                return
            except Exception as _e:
                # a degenerate input's right answer may be an error (judged as Raised)
                _emit({{"output": {{"t": "raised", "type": type(_e).__name__,
                                   "ve": isinstance(_e, ValueError), "m": str(_e)[:200]}}}})
            except BaseException as _e:
                _emit({{"error": "your function raised " + type(_e).__name__ + ": "
                                 + str(_e)[:200]}})
                return

    def _collect(_events, _r):
        if _r["cases"] is None:
            for _ev in _events:
                return _ev
            return {{"error": "no value"}}
        _outputs, _error = [], None
        for _ev in _events:
            if "value" in _ev:
                return _ev
            if "output" in _ev:
                _outputs.append(_ev["output"])
            elif "error" in _ev:
                _error = _ev["error"]
        return {{"outputs": _outputs, "error": _error}}

    def _in_process(_r):
        _events = []
        _encode_one(_r, _events.append)
        return _collect(_events, _r)

    def _isolated(_r, _seconds):
        try:
            _rfd, _wfd = _os.pipe()
        except OSError:
            return _in_process(_r)
        try:
            _pid = _os.fork()
        except OSError:
            _os.close(_rfd)
            _os.close(_wfd)
            return _in_process(_r)
        if _pid == 0:
            try:
                _os.close(_rfd)
                _sys.stdout = _sys.stderr = _io.StringIO()
                def _emit(_ev):
                    _view = memoryview((_json.dumps(_ev) + "\\n").encode())
                    while _view:
                        _view = _view[_os.write(_wfd, _view):]
                try:
                    _encode_one(_r, _emit)
                except BaseException as _e:
                    _emit({{"error": "reading the answer failed: " + type(_e).__name__}})
            finally:
                _os._exit(0)
        _os.close(_wfd)
        _buf, _events, _late, _size = b"", [], False, 0
        _deadline = min(_time.monotonic() + _seconds, _end)
        try:
            while True:
                _left = _deadline - _time.monotonic()
                if _left <= 0:
                    _late = True
                    break
                _ready, _, _ = _select.select([_rfd], [], [], _left)
                if not _ready:
                    continue
                _chunk = _os.read(_rfd, 1 << 16)
                if not _chunk:
                    break
                _size += len(_chunk)
                if _size > {MAX_ANSWER_BYTES}:
                    _late = True
                    break
                _buf += _chunk
                while b"\\n" in _buf:
                    _line, _buf = _buf.split(b"\\n", 1)
                    _events.append(_json.loads(_line))
                    _deadline = min(_time.monotonic() + _seconds, _end)  # next call afresh
        finally:
            _os.close(_rfd)
            if _late:
                try:
                    _os.kill(_pid, _signal.SIGKILL)
                except OSError:
                    pass
            _os.waitpid(_pid, 0)
        if _late and _time.monotonic() >= _end:
            _events.append({{"error": "the submission's time limit was reached while this "
                                      "answer was read, and it was stopped"}})
        elif _late:
            _what = "your function" if _r["cases"] is not None else "reading the answer"
            _events.append({{"error": _what + " took longer than " + str(_seconds)
                                      + " s or gave too much data, and was stopped"}})
        return _collect(_events, _r)

    _sid = _ns.get("STUDENT_ID")
    _sid = {{"t": "str", "v": str.__getitem__(_sid, slice(0, 1000))}} if type(_sid) is str \
        else {{"t": "none"}}
    _out = {{"nonce": {nonce!r}, "student_id": _sid, "answers": {{}}}}
    for _r in _requests:
        _seconds = {CALL_SECONDS + 1:g} if _r["cases"] is not None else {VALUE_SECONDS:g}
        if _time.monotonic() >= _end:
            _out["answers"][_r["name"]] = {{"error": "the submission's time limit was reached "
                                                     "before this answer was read"}}
            continue
        _out["answers"][_r["name"]] = _isolated(_r, _seconds)
    from IPython.display import publish_display_data
    publish_display_data({{{RESULT_MIME!r}: _out}})
_photolib_extract_{nonce}()
del _photolib_extract_{nonce}
'''
    return code, nonce


def extraction_seconds(requests: list[dict]) -> float:
    """Longest time the extraction cell of ``requests`` can take (kernel execute timeout)."""
    calls = sum(len(r["cases"] or ()) for r in requests)
    values = sum(r["cases"] is None for r in requests)
    return 15 + (CALL_SECONDS + 1) * calls + (VALUE_SECONDS + 1) * (values + len(requests))


def case_to_json(args) -> list:
    """One function case as JSON data: scalars become floats, arrays ``{"array": list}``.

    >>> case_to_json((1, [[0.5, 2]]))
    [1.0, {'array': [[0.5, 2.0]]}]
    """
    out = []
    for a in args:
        arr = np.asarray(a, dtype=float)
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"a function case must be finite, got {a!r}")
        out.append(float(arr) if arr.ndim == 0 else {"array": arr.tolist()})
    return out


def case_from_json(args) -> tuple:
    """Inverse of :func:`case_to_json`: the arguments the reference function is called with."""
    return tuple(np.array(a["array"], dtype=float) if isinstance(a, dict) else a for a in args)


def _indent(source: str) -> str:
    return "\n".join("    " + line for line in source.splitlines())


def answer_record(payloads: list, nonce: str) -> dict:
    """The single record carrying ``nonce``, undecoded.

    Raises
    ------
    ExtractionError
        No record with the nonce, or more than one (the channel was tampered with).
    """
    mine = [p for p in payloads if isinstance(p, dict) and p.get("nonce") == nonce]
    if not mine:
        raise ExtractionError("the kernel returned no answer record")
    if len(mine) > 1 or len(payloads) > 1:
        raise ExtractionError(f"{len(payloads)} answer records came back instead of one: "
                              "the result channel was tampered with")
    record = mine[0]
    if not isinstance(record.get("answers"), dict):
        record = dict(record, answers={})
    return record


def record_student_id(record: dict):
    """``STUDENT_ID`` of a record: a string, or :data:`NOT_ANSWERED` (never decoded further)."""
    item = record.get("student_id")
    if isinstance(item, dict) and item.get("t") == "str" and isinstance(item.get("v"), str):
        return item["v"][:200]
    return NOT_ANSWERED


def decode_item(ex, item):
    """Decode one answer item; any failure becomes :class:`Unsupported` with the reason."""
    return encode.decoded_or_unsupported(lambda: _decode_item(ex, item))


def judge_item(ex, student_id: str, item, cases):
    """Decode and judge one answer item as the grader does; never raises.

    ``cases`` are the JSON argument lists of a function exercise (else None).
    """
    from photolib.grading.judge import Judgement, judge
    from photolib.grading.notebook import parameters_for, reference_outputs
    try:
        params = parameters_for(ex, student_id)
        answer = decode_item(ex, item)
        outputs_of = reference_outputs([case_from_json(c) for c in cases]) if cases else None
        return judge(ex, params, answer, outputs_of)
    except Exception as exc:  # noqa: BLE001
        return Judgement(ex.id, "wrong", 0.0, float(ex.points),
                         f"the answer could not be judged ({type(exc).__name__}: "
                         f"{str(exc)[:200]})", "unjudged")


def _decode_item(ex, item):
    if not isinstance(item, dict):
        return NOT_ANSWERED
    if ex.kind != "function":
        if "error" in item and "value" not in item:
            raise DecodeError(f"encoding failed with {str(item['error'])[:120]}")
        return decode_value(item.get("value"))
    if "value" in item:
        return decode_value(item["value"])
    outputs = item.get("outputs")
    if not isinstance(outputs, list) or len(outputs) > 1000:
        raise DecodeError("bad function outputs")
    error = item.get("error")
    return FunctionOutputs(tuple(decode_value(o) for o in outputs),
                           str(error)[:300] if error else None)
