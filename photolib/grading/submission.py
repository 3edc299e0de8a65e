"""Reading a submitted notebook defensively: JSON, nbformat 3, duplicate ids, student id.

>>> nb = read_submission_text('{"cells": [], "metadata": {}, "nbformat": 4, "nbformat_minor": 5}')
>>> len(nb.cells)
0
>>> read_submission_text("not json")
Traceback (most recent call last):
...
photolib.grading.submission.SubmissionError: invalid-json: not a JSON file (Expecting value: line 1 column 1 (char 0))
"""

from __future__ import annotations

import ast
import json
import re
import uuid
import warnings
from pathlib import Path

import nbformat

__all__ = [
    "MAX_BYTES",
    "SubmissionError",
    "chapter_claims",
    "code_cells",
    "read_submission",
    "read_submission_text",
    "static_student_id",
]

MAX_BYTES = 20 * 1024 * 1024
# a letter, digit or underscore first: ids never start like a spreadsheet formula (= + - @)
# or a command-line option
_ID_OK = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.@+-]{0,63}")


class SubmissionError(ValueError):
    """A submission that cannot be run; ``status`` is the gradebook status."""

    def __init__(self, status: str, detail: str):
        super().__init__(f"{status}: {detail}")
        self.status, self.detail = status, detail


def read_submission_text(text: str):
    """Parse notebook JSON into an nbformat 4 notebook with unique cell ids."""
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, RecursionError) as exc:
        raise SubmissionError("invalid-json", f"not a JSON file ({exc})") from None
    if not isinstance(data, dict) or "nbformat" not in data:
        raise SubmissionError("invalid-notebook", "JSON without an nbformat version")
    try:
        with warnings.catch_warnings():  # duplicate ids and the like are repaired below
            warnings.simplefilter("ignore")
            nb = nbformat.reads(json.dumps(data), as_version=4)
    except Exception as exc:  # noqa: BLE001 - nbformat raises many kinds
        raise SubmissionError("invalid-notebook", f"nbformat cannot read it ({exc})") from None
    cells = nb.get("cells")
    if not isinstance(cells, list):
        raise SubmissionError("invalid-notebook", "no list of cells")
    seen = set()
    for cell in cells:
        if not isinstance(cell, dict) or not isinstance(cell.get("source", ""), (str, list)):
            raise SubmissionError("invalid-notebook", "a cell is not a cell")
        if isinstance(cell.get("source"), list):
            cell["source"] = "".join(map(str, cell["source"]))
        cid = cell.get("id")
        if not isinstance(cid, str) or cid in seen:
            cell["id"] = uuid.uuid4().hex[:12]
        seen.add(cell["id"])
    return nb


def read_submission(path: Path):
    """Read ``path`` (at most :data:`MAX_BYTES`) with :func:`read_submission_text`."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise SubmissionError("too-large", f"{size} bytes > {MAX_BYTES}")
        raw = path.read_bytes()
    except OSError as exc:
        raise SubmissionError("unreadable", str(exc)) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise SubmissionError("invalid-json", "not UTF-8 text") from None
    return read_submission_text(text)


def code_cells(nb) -> list[str]:
    """Sources of the code cells, in file order."""
    return [c["source"] for c in nb.cells if c.get("cell_type") == "code"]


#: code cells longer than this are not parsed whole in the grader: ``ast.parse`` needs some
#: 500 bytes of memory per byte of source (a 6 MB list literal took the grader to 3 GB)
PARSE_BYTES = 100_000
_ID_LINE = re.compile(r"^STUDENT_ID[ \t]*=[^=].*$", re.MULTILINE)


def _literal_id(tree) -> str | None:
    for node in tree.body:
        if (isinstance(node, ast.Assign) and len(node.targets) == 1
                and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id == "STUDENT_ID"
                and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)):
            return node.value.value
    return None


def static_student_id(nb) -> str | None:
    """The first ``STUDENT_ID = "literal"`` among the code cells, read without running.

    Only cells that mention ``STUDENT_ID`` are parsed; of a cell longer than
    :data:`PARSE_BYTES`, only its top-level lines ``STUDENT_ID = ...`` are (one line each).

    >>> from nbformat.v4 import new_code_cell, new_notebook
    >>> big = "x = [" + "0," * 200_000 + "]\\nSTUDENT_ID = 's123'"
    >>> static_student_id(new_notebook(cells=[new_code_cell(big)]))
    's123'
    """
    for source in code_cells(nb):
        if not isinstance(source, str) or "STUDENT_ID" not in source:
            continue
        pieces = [source] if len(source) <= PARSE_BYTES else \
            [m.group(0) for m in _ID_LINE.finditer(source) if len(m.group(0)) <= 1000]
        for piece in pieces:
            try:
                found = _literal_id(ast.parse(piece))
            except (SyntaxError, ValueError, RecursionError, MemoryError):
                continue
            if found is not None:
                return found
    return None


def valid_student_id(value) -> str | None:
    """``value`` if it is a usable student id, else None.

    Letters, digits and ``_.@+-``, at most 64, starting with a letter, digit or ``_``.

    >>> valid_student_id("s1234567"), valid_student_id("s1\\n"), valid_student_id("+B2")
    ('s1234567', None, None)
    """
    return value if isinstance(value, str) and _ID_OK.fullmatch(value) else None


def chapter_claims(nb, path: Path, known) -> tuple[str | None, str | None]:
    """``(chapter in metadata photolib.chapter, chapter in the file name)``; None if absent."""
    meta = nb.metadata.get("photolib", {}) if isinstance(nb.metadata, dict) else {}
    name = meta.get("chapter") if isinstance(meta, dict) else None
    by_meta = name if isinstance(name, str) and name in known else None
    by_name = next((c for c in known if c in Path(path).name), None)
    return by_meta, by_name
