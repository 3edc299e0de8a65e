"""Fixtures of the grading tests: the demo master, its student copy and notebook surgery."""

from __future__ import annotations

import copy
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[2]
MASTER = ROOT / "solutions" / "00-start.ipynb"
COPY = ROOT / "exercises" / "00-start.ipynb"


def load(path: Path):
    return nbformat.read(path, as_version=4)


def cell_index(nb, needle: str) -> int:
    """Index of the first cell whose source or tags contain ``needle``."""
    for i, cell in enumerate(nb.cells):
        if needle in cell.source or needle in cell.get("metadata", {}).get("tags", []):
            return i
    raise LookupError(needle)


def with_cell(nb, source: str, at: int | None = None):
    """A copy of ``nb`` with a code cell inserted (appended by default)."""
    nb = copy.deepcopy(nb)
    cell = nbformat.v4.new_code_cell(source)
    nb.cells.insert(len(nb.cells) if at is None else at, cell)
    return nb


@pytest.fixture(scope="session")
def master():
    return load(MASTER)


@pytest.fixture(scope="session")
def untouched():
    return load(COPY)
