"""Committed notebook outputs print no raw float reprs.

A float printed at full precision (``-1.0000000000000002``) is a test that passes only on the CPU
and BLAS kernel that wrote it: strict nbval on another machine prints ``-1.0``. The rule (docs/
instructors.md, "Numbers in committed outputs"): a number in a chapter or solution output carries
the digits its meaning justifies, formatted or rounded to its tolerance, never the repr of a float.
This test scans every committed output of ``notebooks/`` and ``solutions/`` (``text/plain`` and
``stdout``) and names notebook and cell of every float with more than 12 significant digits.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted([*ROOT.glob("notebooks/*.ipynb"), *ROOT.glob("solutions/*.ipynb")])
MAX_SIGNIFICANT = 12

# a decimal number with a fraction, not part of a word, an identifier or a longer dotted number
_FLOAT = re.compile(r"(?<![\w.])[-+]?(\d+)\.(\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def significant_digits(integer: str, fraction: str) -> int:
    """Significant digits of ``integer.fraction``: leading zeros do not count, trailing ones do."""
    return len((integer + fraction).lstrip("0"))


def long_floats(text: str) -> list[str]:
    """The floats in ``text`` with more than ``MAX_SIGNIFICANT`` significant digits."""
    return [m.group(0) for m in _FLOAT.finditer(text)
            if significant_digits(m.group(1), m.group(2)) > MAX_SIGNIFICANT]


def output_texts(cell: dict):
    """``(kind, text)`` of each stdout stream and text/plain result of one cell."""
    for out in cell.get("outputs", []):
        if out.get("output_type") == "stream" and out.get("name") == "stdout":
            yield "stdout", "".join(out.get("text", ""))
        plain = out.get("data", {}).get("text/plain")
        if plain is not None:
            yield "text/plain", "".join(plain)


def offending(path: Path, root: Path = ROOT) -> list[str]:
    """One line per cell output of ``path`` that prints a raw float repr (path shown from root)."""
    nb = json.loads(path.read_text(encoding="utf-8"))
    found = []
    for index, cell in enumerate(nb.get("cells", [])):
        for kind, text in output_texts(cell):
            bad = long_floats(text)
            if bad:
                shown = ", ".join(bad[:3]) + (f" and {len(bad) - 3} more" if len(bad) > 3 else "")
                found.append(f"{path.relative_to(root)} cell {index} ({kind}): {shown}")
    return found


@pytest.mark.parametrize("text, expected", [
    ("a2 | -1.0 | -1.0000000000000002 | 1e-12", ["-1.0000000000000002"]),
    ("0.05361241244947067", ["0.05361241244947067"]),
    ("[ 1.23456789012345e-05 2.5 ]", ["1.23456789012345e-05"]),
    ("x0 = 3.829 mm, r = 0.000000000, 1.000000000", []),
    ("0.000000000001234", []),               # 4 significant digits
    ("123456789012.5", ["123456789012.5"]),  # 13 significant digits
    ("version 3.11.7, id 1234567890123456", []),
    ("<Figure size 640x480 with 1 Axes>", []),
])
def test_scanner(text, expected):
    assert long_floats(text) == expected


def test_scanner_names_notebook_and_cell(tmp_path):
    nb = {"cells": [{"cell_type": "code", "source": "", "outputs": []},
                    {"cell_type": "code", "source": "", "outputs": [
                        {"output_type": "stream", "name": "stdout", "text": ["-1.0000000000000002\n"]},
                        {"output_type": "execute_result", "data": {"text/plain": "0.1 + 0.2"}}]}]}
    path = tmp_path / "x.ipynb"
    path.write_text(json.dumps(nb), encoding="utf-8")
    assert offending(path, tmp_path) == ["x.ipynb cell 1 (stdout): -1.0000000000000002"]


def test_notebooks_found():
    assert len(NOTEBOOKS) >= 20


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_raw_float_repr_in_committed_outputs(path):
    bad = offending(path)
    assert not bad, ("committed outputs print floats at full precision (format them to the "
                     "digits their meaning justifies):\n" + "\n".join(bad))
