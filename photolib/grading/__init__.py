"""Auto-grading of the course's exercise notebooks.

In a notebook, ``from photolib.grading import check, task`` gives immediate feedback. The
instructor's side is ``python -m photolib assign`` and ``python -m photolib grade``
(:mod:`photolib.grading.cli`); ``docs/instructors.md`` describes the exercise format.
"""

from __future__ import annotations

__all__ = ["check", "task"]


def __getattr__(name):
    if name in __all__:
        from photolib.grading import notebook
        return getattr(notebook, name)
    raise AttributeError(f"module 'photolib.grading' has no attribute {name!r}")
