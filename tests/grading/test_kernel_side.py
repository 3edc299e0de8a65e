"""The code run inside the student's kernel (photolib.grading._kernel_side), called directly.

No kernel here: the functions run in the test process (a child process is forked where the
grader's kernel forks one), and the extraction cell is executed with a stand-in for IPython.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import time

import numpy as np
import pytest

from photolib.grading import _kernel_side as ks
from photolib.grading.encode import NONE, NOT_ANSWERED, Raised, Unsupported, encode_value
from photolib.grading.extract import (
    CALL_SECONDS,
    MAX_ANSWER_BYTES,
    VALUE_SECONDS,
    answer_record,
    build_extraction,
    decode_item,
    record_student_id,
)
from photolib.grading.sandbox import RESULT_MIME
from photolib.grading.spec import Exercise

FUNCTION = Exercise(id="t.f", points=1, title="t", kind="function", answer="f", statement="",
                    parameters=lambda rng: {}, cases=lambda rng, p: [], reference=lambda p: None)
VALUE = Exercise(id="t.v", points=1, title="t", kind="number", answer="v", statement="",
                 parameters=lambda rng: {}, reference=lambda p: 1.0)
LIMITS = {"mime": RESULT_MIME, "call_seconds": CALL_SECONDS, "value_seconds": VALUE_SECONDS,
          "max_bytes": MAX_ANSWER_BYTES}


def _extract(ns, requests, seconds=30.0, **limits):
    published = []
    record = ks.extract(ns, "n" * 32, requests, seconds, encode_value,
                        publish=published.append, **{**LIMITS, **limits})
    assert published == [{RESULT_MIME: record}]  # one message, the record itself
    assert json.loads(json.dumps(record, allow_nan=False)) == record  # JSON all through
    return record


def _events(func, cases, call_seconds=1.0):
    events = []
    ks.call_cases(func, cases, events.append, encode_value, call_seconds)
    return events


# -- STUDENT_ID ---------------------------------------------------------------------------
def test_student_id_is_read_only_as_an_exact_str():
    class Sneaky(str):
        def __getitem__(self, item):
            raise AssertionError("a str subclass's method ran")

    assert ks.student_id({"STUDENT_ID": "s1"}) == {"t": "str", "v": "s1"}
    assert ks.student_id({"STUDENT_ID": "x" * 5000})["v"] == "x" * 1000
    assert ks.student_id({"STUDENT_ID": Sneaky("s1")}) == {"t": "none"}
    assert ks.student_id({"STUDENT_ID": 1234}) == {"t": "none"}
    assert ks.student_id({}) == {"t": "none"}


# -- calling student functions -------------------------------------------------------------
def test_the_alarm_stops_a_slow_call_and_the_cases_after_it():
    calls = []

    def slow(x):
        calls.append(x)
        time.sleep(10)

    before = signal.getsignal(signal.SIGALRM)
    t0 = time.monotonic()
    events = _events(slow, [[1.0], [2.0]], call_seconds=0.2)
    assert time.monotonic() - t0 < 2.0
    assert events == [{"error": "your function raised TimeoutError: "
                                "the function took longer than 0.2 s"}]
    assert calls == [1.0]  # the second case is not tried
    assert signal.getsignal(signal.SIGALRM) is before  # the handler is the previous one
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_raising_function_is_reported_per_case():
    def f(x):
        if x == 0:
            raise ValueError("x must not be 0")
        if x == 1:
            raise ZeroDivisionError("by zero")
        if x == 2:
            raise NotImplementedError
        return 2 * x

    assert _events(f, [[0.0], [1.0], [2.0], [3.0]]) == [
        {"output": {"t": "raised", "type": "ValueError", "ve": True, "m": "x must not be 0"}},
        {"output": {"t": "raised", "type": "ZeroDivisionError", "ve": False, "m": "by zero"}},
        {"output": {"t": "none"}},
        {"output": {"t": "num", "v": "6.0"}}]


def test_system_exit_stops_the_cases_with_an_error():
    def f(x):
        sys.exit(f"bye {x:g}")

    assert _events(f, [[1.0], [2.0]]) == [{"error": "your function raised SystemExit: bye 1"}]


def test_array_arguments_arrive_as_float_arrays():
    seen = []
    events = _events(lambda *args: seen.append(args),
                     [[2.0, {"array": [[1, 2], [3, 4]]}], [0.5]])
    assert events == [{"output": {"t": "none", "v": "None"}}] * 2
    (s, a), (t,) = seen
    assert s == 2.0 and t == 0.5
    assert isinstance(a, np.ndarray) and a.dtype == float and a.tolist() == [[1, 2], [3, 4]]


# -- one answer ------------------------------------------------------------------------------
def test_unanswered_variables():
    ns = {"v": ..., "w": None, "g": ...}
    record = _extract(ns, [{"name": "v", "cases": None}, {"name": "w", "cases": None},
                           {"name": "missing", "cases": None}, {"name": "g", "cases": [[1.0]]}])
    answers = record["answers"]
    assert answers["v"] == {"value": {"t": "none"}}
    assert answers["w"] == answers["missing"] == {"value": {"t": "none", "v": "None"}}
    assert answers["g"] == {"value": {"t": "none"}}
    assert decode_item(VALUE, answers["v"]) is NOT_ANSWERED
    assert decode_item(VALUE, answers["missing"]) is NONE
    assert decode_item(FUNCTION, answers["g"]) is NOT_ANSWERED


def test_an_answer_json_cannot_carry():
    class Hostile(list):
        def __len__(self):
            raise RuntimeError("no length")

    ns = {"s": {1, 2}, "z": 1 + 2j, "h": Hostile([1.0]), "f": lambda x: object()}
    record = _extract(ns, [{"name": n, "cases": None} for n in "szh"]
                      + [{"name": "f", "cases": [[1.0]]}])
    answers = record["answers"]
    assert answers["s"] == {"value": {"t": "other", "type": "set"}}
    assert answers["h"] == {"error": "RuntimeError"}  # the encoder raised: named, no value
    assert decode_item(VALUE, answers["s"]).type_name == "set"
    assert "nonzero imaginary part" in decode_item(VALUE, answers["z"]).type_name
    assert "RuntimeError" in decode_item(VALUE, answers["h"]).type_name
    outputs = decode_item(FUNCTION, answers["f"]).outputs
    assert len(outputs) == 1 and isinstance(outputs[0], Unsupported)
    assert outputs[0].type_name == "object"


def test_the_record_decodes_as_the_grader_reads_it():
    def area(a, b):
        if a == 0:
            raise ValueError("degenerate")
        return a * b

    ns = {"STUDENT_ID": "s42", "v": 2.5, "area": area}
    record = _extract(ns, [{"name": "v", "cases": None},
                           {"name": "area", "cases": [[2.0, 3.0], [0.0, 1.0]]}])
    record = answer_record([record], "n" * 32)
    assert record_student_id(record) == "s42"
    assert decode_item(VALUE, record["answers"]["v"]) == 2.5
    answer = decode_item(FUNCTION, record["answers"]["area"])
    assert answer.error is None and answer.outputs[0] == 6.0
    assert isinstance(answer.outputs[1], Raised) and answer.outputs[1].value_error


# -- the child process -------------------------------------------------------------------------
def test_a_function_that_swallows_the_alarm_is_killed():
    def stubborn(x):
        while True:
            try:
                time.sleep(10)
            except TimeoutError:
                pass

    t0 = time.monotonic()
    record = _extract({"f": stubborn, "v": 1.0},
                      [{"name": "f", "cases": [[1.0]]}, {"name": "v", "cases": None}],
                      call_seconds=0.2)
    assert time.monotonic() - t0 < 5.0
    assert record["answers"]["f"] == {
        "outputs": [], "error": "your function took longer than 1.2 s or gave too much data, "
                                "and was stopped"}
    assert record["answers"]["v"] == {"value": {"t": "num", "v": "1.0"}}  # the next one is read


def test_too_much_data_stops_the_answer():
    record = _extract({"a": list(range(1000))}, [{"name": "a", "cases": None}], max_bytes=100)
    assert record["answers"]["a"] == {"error": "reading the answer took longer than 5 s or "
                                               "gave too much data, and was stopped"}


def test_the_whole_time_limit_stops_the_answer_being_read_and_the_rest():
    record = _extract({"f": lambda x: time.sleep(x), "v": 1.0},
                      [{"name": "f", "cases": [[0.0], [3.0]]}, {"name": "v", "cases": None}],
                      seconds=0.5)
    f = record["answers"]["f"]
    assert f["outputs"] == [{"t": "none", "v": "None"}]  # the first call returned None
    assert f["error"] == ("the submission's time limit was reached while this answer was "
                          "read, and it was stopped")
    assert record["answers"]["v"] == {"error": "the submission's time limit was reached "
                                               "before this answer was read"}


def test_the_child_prints_nothing_and_the_parent_lives_on(capfd):
    def noisy(x):
        print("from the student")
        os.write(2, b"")
        return x

    record = _extract({"f": noisy}, [{"name": "f", "cases": [[1.0]]}])
    assert record["answers"]["f"] == {"outputs": [{"t": "num", "v": "1.0"}], "error": None}
    assert "from the student" not in capfd.readouterr().out


def test_without_fork_the_answer_is_read_in_this_process(monkeypatch):
    def no_fork():
        raise OSError("fork: resource temporarily unavailable")

    monkeypatch.setattr(os, "fork", no_fork)
    pid = os.getpid()
    record = _extract({"f": lambda x: os.getpid()}, [{"name": "f", "cases": [[1.0]]}])
    assert record["answers"]["f"]["outputs"] == [{"t": "num", "v": repr(float(pid))}]


# -- the extraction cell ---------------------------------------------------------------------
def _run_cell(ns, requests, monkeypatch, patch=lambda: None):
    """Build the cell, ``patch()`` (the notebook's doing), run the cell as the kernel does."""
    import IPython.display

    code, nonce = build_extraction(requests)
    patch()
    published = []
    monkeypatch.setattr(IPython.display, "publish_display_data",
                        lambda data: published.append(data))
    exec(code, {"get_ipython": lambda: type("Shell", (), {"user_ns": ns})()})  # noqa: S102
    return [d[RESULT_MIME] for d in published], nonce


def test_the_cell_uses_nothing_the_notebook_patched(monkeypatch):
    """The kernel side runs from injected source: patched photolib modules are not used."""
    import photolib.grading.encode as encode

    def patch():  # what a notebook may do to the photolib it imports
        monkeypatch.setattr(encode, "encode_value", lambda v, _depth=0: {"t": "num", "v": "1"})
        monkeypatch.setattr(ks, "extract", lambda *a, **k: pytest.fail("imported code ran"))
        monkeypatch.setitem(sys.modules, "photolib.grading._kernel_side", None)  # no import

    ns = {"STUDENT_ID": "s7", "v": 2.5, "isinstance": lambda *a: True, "json": None}
    payloads, nonce = _run_cell(ns, [{"name": "v", "cases": None}], monkeypatch, patch)
    record = answer_record(payloads, nonce)  # exactly one message, with the nonce
    assert record["nonce"] == nonce and len(payloads) == 1
    assert record["answers"]["v"] == {"value": {"t": "num", "v": "2.5"}}
    assert record_student_id(record) == "s7"
    assert set(ns) == {"STUDENT_ID", "v", "isinstance", "json"}  # nothing left behind


def test_the_cell_passes_its_parameters_as_literals(monkeypatch):
    """Names with quotes and newlines, nested array cases, the time budget: all arrive."""
    requests = [{"name": "a'b\"\n", "cases": None},
                {"name": "g", "cases": [[1.5, {"array": [[1.0, 2.0]]}]]}]
    ns = {"a'b\"\n": "text", "g": lambda s, a: s * a.sum()}
    payloads, nonce = _run_cell(ns, requests, monkeypatch)
    answers = answer_record(payloads, nonce)["answers"]
    assert answers["a'b\"\n"] == {"value": {"t": "str", "v": "text"}}
    assert answers["g"] == {"outputs": [{"t": "num", "v": "4.5"}], "error": None}
    with pytest.raises(ValueError, match="Out of range float"):
        build_extraction([{"name": "g", "cases": [[float("nan")]]}])
