"""The grader's extraction cell: read the answers out of the kernel as data.

After the notebook has run, the grader executes code it generated itself. It carries a fresh
random nonce, reads ``STUDENT_ID`` and the answer variables, calls student functions on the
hidden inputs (each call under a SIGALRM time limit) and publishes one display message of
MIME type :data:`~photolib.grading.sandbox.RESULT_MIME` holding JSON. What it runs is
:mod:`photolib.grading._kernel_side` and the encoder, injected as source from the grader's
own files and executed in a fresh namespace, so nothing the notebook patched in
``photolib`` is used. The grader accepts exactly one message carrying the nonce, in reply to
this very request; anything the notebook may forge can only report answers, which are then
judged like any other answers.
"""

from __future__ import annotations

import inspect
import json
import secrets
from importlib import resources

import numpy as np

from photolib.grading import encode
from photolib.grading.encode import NOT_ANSWERED, DecodeError, decode_value
from photolib.grading.judge import FunctionOutputs
from photolib.grading.sandbox import RESULT_MIME

__all__ = ["ExtractionError", "answer_record", "build_extraction", "case_from_json",
           "case_to_json", "decode_item", "extraction_seconds", "judge_item",
           "kernel_source", "record_student_id"]

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
    call = json.dumps({"nonce": nonce, "requests": requests, "seconds": float(seconds),
                       "mime": RESULT_MIME, "call_seconds": CALL_SECONDS,
                       "value_seconds": VALUE_SECONDS, "max_bytes": MAX_ANSWER_BYTES},
                      allow_nan=False)
    # the fresh namespace's builtins are the kernel's own; nothing is looked up in the
    # notebook's namespace but exec, compile and get_ipython (to find that namespace)
    code = f'''
def _photolib_extract_{nonce}():
    _kernel_side = {{"__name__": "_photolib_kernel_side"}}
    exec(compile({kernel_source()!r}, "<photolib.grading._kernel_side>", "exec"), _kernel_side)
    try:
        _user_ns = get_ipython().user_ns
    except NameError:
        import sys
        _user_ns = vars(sys.modules["__main__"])
    _kernel_side["run"](_user_ns, {call!r}, _kernel_side["encode_value"])
_photolib_extract_{nonce}()
del _photolib_extract_{nonce}
'''
    return code, nonce


def kernel_source() -> str:
    """Source executed in the kernel: :mod:`._kernel_side` and the encoder it is given.

    Read from the grader's own files (never imported in the kernel): the module, then
    :func:`~photolib.grading.encode.encode_value` and the helper it calls.
    """
    module = resources.files("photolib.grading").joinpath("_kernel_side.py")
    return "\n\n".join([module.read_text(encoding="utf-8"),
                         inspect.getsource(encode.encode_value),
                         inspect.getsource(encode._tree)])


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
