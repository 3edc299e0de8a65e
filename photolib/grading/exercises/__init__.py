"""The exercise registry: one module per chapter, ``chNN_topic.py``.

Each chapter module defines ``CHAPTER`` (the notebook's file stem, e.g. ``"04-rotations"``)
and ``EXERCISES`` (a tuple of :class:`~photolib.grading.spec.Exercise`). Modules are found
by name, so adding a chapter is adding a file.

>>> [ex.id for ex in chapter("00-start")][:2]
['demo.image-scale', 'demo.rotation-2d']
>>> exercise("demo.image-scale").points
2
"""

from __future__ import annotations

import difflib
import functools
import importlib
import pkgutil
import re

__all__ = ["chapter", "chapters", "exercise"]


@functools.cache
def chapters() -> dict:
    """Chapter name -> tuple of exercises, from every ``ch*`` module of this package."""
    found = {}
    seen_ids = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if not info.name.startswith("ch"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        name = getattr(module, "CHAPTER", None)
        exercises = tuple(getattr(module, "EXERCISES", ()))
        if not isinstance(name, str) or not exercises:
            raise ValueError(f"{module.__name__} must define CHAPTER (str) and EXERCISES")
        if name in found:
            raise ValueError(f"chapter {name!r} is defined twice (second in {module.__name__})")
        for ex in exercises:
            if ex.id in seen_ids:
                raise ValueError(f"exercise id {ex.id!r} is used in {seen_ids[ex.id]} and {name}")
            seen_ids[ex.id] = name
        _check_names(name, exercises)
        _check_scenarios(name, exercises)
        found[name] = exercises
    return found


def _check_names(name: str, exercises) -> None:
    """Each task's parameters have a name of their own in the chapter's notebook.

    Two tasks whose parameters share a name (every task's ``p``) overwrite each other's
    numbers: after Run All an answer cell run again reads the last task's numbers. A
    parameter name that is also an answer variable would be overwritten by that answer.
    """
    owner = {}
    answers = {ex.answer: ex.id for ex in exercises}
    for ex in exercises:
        if ex.params_name in owner:
            raise ValueError(f"chapter {name}: {ex.id} and {owner[ex.params_name]} both keep "
                             f"their parameters in {ex.params_name!r}")
        if ex.params_name in answers:
            raise ValueError(f"chapter {name}: {ex.id} keeps its parameters in "
                             f"{ex.params_name!r}, the answer variable of {answers[ex.params_name]}")
        owner[ex.params_name] = ex.id


_STEP = re.compile(r"^Step (\d+) of (\d+)\b")


def scenarios(exercises) -> dict:
    """Scenario id -> its steps (exercises in order), for the multi-step exercises given."""
    found: dict = {}
    for ex in exercises:
        if ex.scenario:
            found.setdefault(ex.scenario, []).append(ex)
    return found


def _check_scenarios(name: str, exercises) -> None:
    """The steps of a multi-step exercise: at least two, in one chapter, titled "Step k of n"."""
    ids = {ex.id for ex in exercises}
    for scenario, steps in scenarios(exercises).items():
        if scenario not in ids:
            raise ValueError(f"chapter {name}: scenario {scenario!r} of {steps[0].id} is not an "
                             f"exercise of this chapter (by convention it is the first step's id)")
        n = len(steps)
        if n < 2:
            raise ValueError(f"chapter {name}: scenario {scenario!r} has one step ({steps[0].id}); "
                             f"a multi-step exercise has at least two")
        for k, ex in enumerate(steps, 1):
            m = _STEP.match(ex.title)
            if not m or (int(m.group(1)), int(m.group(2))) != (k, n):
                raise ValueError(f"chapter {name}: {ex.id} is step {k} of {n} of scenario "
                                 f"{scenario!r}; its title must begin 'Step {k} of {n}', got "
                                 f"{ex.title!r}")


def chapter(name: str) -> tuple:
    """Exercises of chapter ``name`` (a notebook file stem such as ``"00-start"``)."""
    all_ = chapters()
    if name not in all_:
        raise KeyError(f"no exercises for chapter {name!r}; chapters: {sorted(all_)}")
    return all_[name]


def exercise(exercise_id: str):
    """The exercise with this id, from any chapter."""
    for exercises in chapters().values():
        for ex in exercises:
            if ex.id == exercise_id:
                return ex
    known = sorted(ex.id for exs in chapters().values() for ex in exs)
    near = difflib.get_close_matches(exercise_id, known, n=3, cutoff=0.8)
    if near:
        hint = "did you mean " + " or ".join(repr(n) for n in near) + "?"
    else:
        prefix = exercise_id.split(".")[0] + "."
        same = [k for k in known if k.startswith(prefix)]
        hint = (f"the ids beginning {prefix!r} are {same}" if same else
                "the ids are those of the task(...) cells in the chapter notebooks")
    raise KeyError(f"unknown exercise id {exercise_id!r}; {hint}")
