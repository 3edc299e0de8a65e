"""Student copies from solution masters (``solutions/NN-topic.ipynb`` → ``exercises/``).

In a master:

- the cell tagged ``student-id`` sets ``STUDENT_ID``; the copy gets an empty id to fill in;
- an answer cell is tagged ``answer:EXERCISE_ID``; the lines between ``### BEGIN SOLUTION`` and
  ``### END SOLUTION`` become ``NAME = ...`` (or ``return ...`` in a function exercise), with
  the indentation of the marker;
- each exercise's task cell assigns its parameters to the exercise's own name,
  ``p_opk = task("rot.opk-matrix")`` (``Exercise.params_name``), and no other cell assigns
  that name: one name per task, so that cells can run in any order;
- cells tagged ``solution-only`` are left out of the copy;
- outputs and execution counts are removed; ``metadata.photolib.chapter`` is set.

:func:`make_student_copy` checks that every exercise of the chapter has exactly one answer
cell, one task cell assigning to its ``params_name`` and a ``check("ID")`` call, and that no
tag or ``task`` call names an unknown exercise.
"""

from __future__ import annotations

import ast
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


def _task_calls(tree):
    """``(target or None, exercise id)`` of each ``task("ID")`` call, with its assignment."""
    found, assigned = [], set()
    for node in ast.walk(tree):
        if (isinstance(node, ast.Assign) and len(node.targets) == 1
                and isinstance(node.targets[0], ast.Name)):
            assigned.add(id(node.value))
            call = node.value
            target = node.targets[0].id
        elif isinstance(node, ast.Call) and id(node) not in assigned:
            call, target = node, None
        else:
            continue
        if (isinstance(call, ast.Call) and isinstance(call.func, ast.Name)
                and call.func.id == "task" and call.args
                and isinstance(call.args[0], ast.Constant) and isinstance(call.args[0].value, str)):
            found.append((target, call.args[0].value))
    return found


def _check_task_cells(nb, chapter: str, exercises: dict) -> None:
    """Each exercise has one task cell ``params_name = task("ID")``; no other cell assigns it."""
    from photolib.grading.notebook import _analyse
    owners = {ex.params_name: ex for ex in exercises.values()}
    answers = {ex.answer: ex for ex in exercises.values()}
    tasks = {}
    for index, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        where = f"{chapter} cell {index + 1}"
        try:
            tree = ast.parse(cell.source)
        except SyntaxError as exc:
            if "task(" in cell.source:
                raise AssignError(f"{where}: a task cell must be plain Python ({exc})") from None
            continue
        calls = _task_calls(tree)
        for target, ex_id in calls:
            ex = exercises.get(ex_id)
            if ex is None:
                raise AssignError(f"{where}: task({ex_id!r}) names no exercise of {chapter}; "
                                  f"known: {sorted(exercises)}")
            if target != ex.params_name:
                got = f"to {target}" if target else "to no name"
                raise AssignError(f"{where}: task({ex_id!r}) is assigned {got}; write "
                                  f"{ex.params_name} = task({ex_id!r}) (the exercise's "
                                  f"params_name)")
            if ex_id in tasks:
                raise AssignError(f"{where}: second task cell for {ex_id} "
                                  f"(first in cell {tasks[ex_id] + 1})")
            tasks[ex_id] = index
        own = {target for target, _ in calls}
        assigned = _analyse(cell.source).assigned
        for name in sorted((assigned & set(owners)) - own):
            raise AssignError(f"{where}: assigns {name}, which holds the parameters of "
                              f"{owners[name].id}; only its task cell may")
        # a later cell that reuses an answer's name (a helper variable `radial`) overwrites
        # that answer after its check() said ✔: the grader, reading the namespace after Run
        # All, would mark a right answer wrong
        tags = set(cell.metadata.get("tags", []))
        if any(t.startswith("answer:") and t[7:] not in exercises for t in tags):
            continue                    # an unknown answer tag: make_student_copy names it
        for name in sorted(assigned & set(answers)):
            if f"answer:{answers[name].id}" not in tags:
                raise AssignError(f"{where}: assigns {name}, the answer of {answers[name].id}; "
                                  f"only its answer cell may (rename the helper variable)")
    missing = sorted(set(exercises) - set(tasks))
    if missing:
        names = ", ".join(f"{exercises[i].params_name} = task({i!r})" for i in missing)
        raise AssignError(f"{chapter}: no task cell for {missing}: write {names}")


def make_student_copy(master, chapter: str):
    """The student copy of the master notebook ``master`` (an nbformat 4 node)."""
    exercises = {ex.id: ex for ex in chapter_exercises(chapter)}
    nb = copy.deepcopy(master)
    _check_task_cells(nb, chapter, exercises)
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
