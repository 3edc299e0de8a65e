"""Student copies from solution masters (``solutions/NN-topic.ipynb`` → ``exercises/``).

In a master:

- the cell tagged ``student-id`` sets ``STUDENT_ID``; the copy gets an empty id to fill in;
- an answer cell is tagged ``answer:EXERCISE_ID``; the lines between ``### BEGIN SOLUTION`` and
  ``### END SOLUTION`` become ``NAME = ...`` (or ``return ...`` in a function exercise), with
  the indentation of the marker;
- cells tagged ``solution-only`` are left out of the copy;
- outputs and execution counts are removed; ``metadata.photolib.chapter`` is set.

:func:`make_student_copy` checks that every exercise of the chapter has exactly one answer
cell and a ``check("ID")`` call, and that no tag names an unknown exercise.
"""

from __future__ import annotations

import copy
import re
from pathlib import Path

import nbformat

from photolib.grading.exercises import chapter as chapter_exercises

__all__ = ["STUDENT_ID_LINE", "AssignError", "assign_folder", "make_student_copy"]

STUDENT_ID_LINE = 'STUDENT_ID = ""  # your student id, e.g. "s1234567"'
_BEGIN, _END = "### BEGIN SOLUTION", "### END SOLUTION"


class AssignError(ValueError):
    """A solution master that breaks the exercise format."""


def _strip_solution(source: str, stub: str, where: str) -> str:
    out, inside = [], False
    for line in source.splitlines():
        if line.strip() == _BEGIN:
            if inside:
                raise AssignError(f"{where}: nested {_BEGIN}")
            inside = True
            out.append(line[: len(line) - len(line.lstrip())] + stub)
        elif line.strip() == _END:
            if not inside:
                raise AssignError(f"{where}: {_END} without {_BEGIN}")
            inside = False
        elif not inside:
            out.append(line)
    if inside:
        raise AssignError(f"{where}: {_BEGIN} without {_END}")
    return "\n".join(out)


def make_student_copy(master, chapter: str):
    """The student copy of the master notebook ``master`` (an nbformat 4 node)."""
    exercises = {ex.id: ex for ex in chapter_exercises(chapter)}
    nb = copy.deepcopy(master)
    cells, answered, checked = [], {}, set()
    for index, cell in enumerate(nb.cells):
        tags = list(cell.get("metadata", {}).get("tags", []))
        where = f"{chapter} cell {index + 1}"
        if "solution-only" in tags:
            continue
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
            cell.metadata.pop("execution", None)
            checked.update(re.findall(r"""check\(\s*["']([^"']+)["']\s*\)""", cell.source))
            ids = [t.split(":", 1)[1] for t in tags if t.startswith("answer:")]
            for ex_id in ids:
                if ex_id not in exercises:
                    raise AssignError(f"{where}: tag answer:{ex_id} names no exercise of "
                                      f"{chapter}; known: {sorted(exercises)}")
                if ex_id in answered:
                    raise AssignError(f"{where}: second answer cell for {ex_id} "
                                      f"(first in cell {answered[ex_id] + 1})")
                answered[ex_id] = index
            if "student-id" in tags:
                cell.source = STUDENT_ID_LINE
            elif _BEGIN in cell.source:
                if len(ids) != 1:
                    raise AssignError(f"{where}: a solution cell needs exactly one answer: tag")
                ex = exercises[ids[0]]
                stub = ("return ...  # your code here" if ex.kind == "function"
                        else f"{ex.answer} = ...  # your answer here")
                cell.source = _strip_solution(cell.source, stub, where)
        cells.append(cell)
    missing = sorted(set(exercises) - set(answered))
    if missing:
        raise AssignError(f"{chapter}: no cell tagged answer:ID for {missing}")
    unchecked = sorted(set(exercises) - checked)
    if unchecked:
        raise AssignError(f"{chapter}: no check(\"ID\") cell for {unchecked}")
    nb.cells = cells
    nb.metadata["photolib"] = {"chapter": chapter, "student-copy": True}
    return nb


def render(nb) -> str:
    """Notebook JSON text as committed (stable, trailing newline)."""
    text = nbformat.writes(nb)
    return text if text.endswith("\n") else text + "\n"


def assign_folder(source: Path, dest: Path, check: bool = False) -> list[Path]:
    """Write (or with ``check``, compare) the copy of every master with exercises.

    Returns
    -------
    list of Path
        Copies written, or with ``check`` the copies that are missing or out of date.
    """
    from photolib.grading.exercises import chapters
    source, dest = Path(source), Path(dest)
    if not source.is_dir():
        raise AssignError(f"no folder {source}")
    changed = []
    for master_path in sorted(source.glob("*.ipynb")):
        name = master_path.stem
        if name not in chapters():
            continue
        master = nbformat.read(master_path, as_version=4)
        text = render(make_student_copy(master, name))
        target = dest / master_path.name
        old = target.read_text(encoding="utf-8") if target.exists() else None
        if old != text:
            changed.append(target)
            if not check:
                dest.mkdir(parents=True, exist_ok=True)
                target.write_text(text, encoding="utf-8")
    return changed
