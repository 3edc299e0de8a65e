"""Chapters that teach (issue 16): objectives first, self-check and further reading last,
errata verdicts in call-outs, and the multi-step share of the graded exercises.

Every chapter notebook 01–14 opens (right after its title) with "Learning objectives /
Lernziele", closes with "Self-check" — three to five questions whose answers are revealed on
demand (``<details>``), not graded — and "Further reading". The verdict ids of the errata
catalogue (``de-summary:…``, ``luhmann:…``) appear in the teaching text only inside
"> **Erratum**" call-outs; chapter 13 keeps the full table.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from photolib.grading.exercises import chapters, scenarios

ROOT = Path(__file__).resolve().parents[1]
CHAPTERS = sorted(p for p in (ROOT / "notebooks").glob("[01][0-9]-*.ipynb")
                  if not p.name.startswith("00-"))
RECORD = re.compile(r"`(?:luhmann|de-summary|hu-article|pl-notes):[^`]+`")


def _markdown(path):
    nb = json.loads(path.read_text(encoding="utf-8"))
    return ["".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown"]


def test_every_chapter_from_01_to_14_is_there():
    numbers = {p.name[:2] for p in CHAPTERS}
    assert {f"{n:02d}" for n in range(1, 15)} <= numbers, sorted(numbers)


_ITEM = re.compile(r"^(?:[*-]|\d+\.) ", re.M)


def _section(text, heading):
    """The part of ``text`` from the ``## heading`` line to the next ``## `` heading."""
    start = re.search(rf"^## {heading}.*$", text, re.M)
    if not start:
        return None
    rest = text[start.end():]
    end = re.search(r"^## ", rest, re.M)
    return rest[:end.start()] if end else rest


@pytest.mark.parametrize("path", CHAPTERS, ids=lambda p: p.stem)
def test_objectives_first_self_check_and_reading_last(path):
    cells = _markdown(path)
    assert cells[0].startswith("# "), "the first cell is the chapter's title"
    head = cells[0] + "\n\n" + cells[1]                    # in the title cell or right after
    assert "Learning objectives" in head, "objectives at the top, with the title"
    assert len(_ITEM.findall(head.split("Learning objectives", 1)[1])) >= 3, \
        "at least three objectives"
    tail = "\n\n".join(cells[-3:])
    checks = _section(tail, "Self-check")
    assert checks is not None, "a self-check among the last three markdown cells"
    questions = checks.count("<details>")
    assert 3 <= questions <= 5 and questions == checks.count("</details>")
    reading = _section(tail, "Further reading")
    assert reading is not None and len(_ITEM.findall(reading)) >= 2


@pytest.mark.parametrize("path", [p for p in CHAPTERS if not p.name.startswith("13-")],
                         ids=lambda p: p.stem)
def test_errata_records_only_in_call_outs(path):
    outside = []
    for cell in _markdown(path):
        for line in cell.splitlines():
            if RECORD.search(line) and not line.lstrip().startswith(">"):
                outside.append(line.strip()[:100])
    assert not outside, f"errata ids in the teaching text (move them into a call-out): {outside}"


def test_a_quarter_of_the_exercises_have_steps_graded_separately():
    """An exercise is counted once per id; the steps of a multi-step scenario each count."""
    all_ids, in_steps = 0, 0
    for exercises in chapters().values():
        all_ids += len(exercises)
        in_steps += sum(len(steps) for steps in scenarios(exercises).values())
    assert in_steps >= 0.25 * all_ids, f"{in_steps} of {all_ids} exercises are steps"
