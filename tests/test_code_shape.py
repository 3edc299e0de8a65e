"""The library stays readable for a new maintainer (issue 18): no function in ``photolib/``
longer than 120 lines (nested functions count in their parent; the generated code of
``photolib/_generated`` is exempt: it is written by ``photolib.codegen``, not by hand)."""

from __future__ import annotations

import ast
from pathlib import Path

PHOTOLIB = Path(__file__).resolve().parents[1] / "photolib"
MAX_LINES = 120


def _long_functions(limit=MAX_LINES):
    found = []
    for path in sorted(PHOTOLIB.rglob("*.py")):
        if "_generated" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > limit:
                    found.append(f"{path.relative_to(PHOTOLIB.parent)}:{node.lineno} "
                                 f"{node.name} ({n} lines)")
    return found


def test_no_function_is_longer_than_120_lines():
    assert not _long_functions(), "split into named stages: " + "; ".join(_long_functions())


def test_the_measure_sees_long_functions():
    assert _long_functions(limit=100), "the scan found no function over 100 lines at all"
