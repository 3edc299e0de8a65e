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
from photolib.grading.encode import NOT_ANSWERED, DecodeError, Unsupported, decode_value
from photolib.grading.judge import FunctionOutputs
from photolib.grading.sandbox import RESULT_MIME

__all__ = ["ExtractionError", "build_extraction", "case_from_json", "case_to_json",
           "parse_extraction"]

CALL_SECONDS = 5.0


class ExtractionError(RuntimeError):
    """No trustworthy answer record came back from the kernel."""


def build_extraction(requests: list[dict]) -> tuple[str, str]:
    """Source of the extraction cell and its nonce.

    Parameters
    ----------
    requests : list of dict
        ``{"name": variable, "cases": None or list of argument lists}`` per exercise, the
        arguments as :func:`case_to_json` writes them (numbers, or ``{"array": nested list}``
        which the kernel turns back into a float ``numpy`` array).
    """
    nonce = secrets.token_hex(16)
    source = "\n".join([inspect.getsource(encode.encode_value), inspect.getsource(encode._tree)])
    code = f'''
def _photolib_extract_{nonce}():
    import json as _json, signal as _signal, sys as _sys
{_indent(source)}
    def _alarm(signum, frame):
        raise TimeoutError("the function took longer than {CALL_SECONDS:g} s")
    try:
        _ns = get_ipython().user_ns
    except NameError:
        _ns = vars(_sys.modules["__main__"])
    _requests = _json.loads({json.dumps(json.dumps(requests))})
    _out = {{"nonce": {nonce!r}, "student_id": encode_value(_ns.get("STUDENT_ID")), "answers": {{}}}}
    for _r in _requests:
        _value = _ns.get(_r["name"])
        if _r["cases"] is None:
            try:
                _out["answers"][_r["name"]] = {{"value": encode_value(_value)}}
            except Exception as _e:
                _out["answers"][_r["name"]] = {{"error": type(_e).__name__}}
            continue
        if not callable(_value):
            _out["answers"][_r["name"]] = {{"value": {{"t": "none"}}}}
            continue
        _outputs, _error = [], None
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
                _outputs.append(encode_value(_res))
            except NotImplementedError:
                _outputs.append({{"t": "none"}})
            except BaseException as _e:
                _error = "your function raised " + type(_e).__name__ + ": " + str(_e)[:200]
                break
        _out["answers"][_r["name"]] = {{"outputs": _outputs, "error": _error}}
    from IPython.display import publish_display_data
    publish_display_data({{{RESULT_MIME!r}: _out}})
_photolib_extract_{nonce}()
del _photolib_extract_{nonce}
'''
    return code, nonce


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


def parse_extraction(payloads: list, nonce: str, exercises) -> tuple[object, dict]:
    """Decode the single record carrying ``nonce``.

    Returns
    -------
    student_id : object
        The kernel's ``STUDENT_ID`` (decoded), or :data:`NOT_ANSWERED`.
    answers : dict
        Exercise id -> decoded answer, :class:`FunctionOutputs` or :data:`NOT_ANSWERED`.

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
    answers = {}
    raw = record.get("answers") if isinstance(record.get("answers"), dict) else {}
    for ex in exercises:
        item = raw.get(ex.answer)
        try:
            answers[ex.id] = _decode_item(ex, item)
        except DecodeError as exc:
            answers[ex.id] = Unsupported(f"unreadable answer ({exc})")
    try:
        student_id = decode_value(record.get("student_id"))
    except DecodeError:
        student_id = NOT_ANSWERED
    return student_id, answers


def _decode_item(ex, item):
    if not isinstance(item, dict):
        return NOT_ANSWERED
    if ex.kind != "function":
        if "error" in item and "value" not in item:
            raise DecodeError(f"encoding failed with {str(item['error'])[:60]}")
        return decode_value(item.get("value"))
    if "value" in item:
        return decode_value(item["value"])
    outputs = item.get("outputs")
    if not isinstance(outputs, list) or len(outputs) > 1000:
        raise DecodeError("bad function outputs")
    error = item.get("error")
    return FunctionOutputs(tuple(decode_value(o) for o in outputs),
                           str(error)[:300] if error else None)
