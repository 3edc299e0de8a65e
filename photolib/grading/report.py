"""Writing grades: the gradebook CSV, one Markdown feedback file per student, a summary.

The gradebook has the columns ``submission, student_id, status, total, max_total``, one column
per exercise (points) and ``detail`` (why a status is not ``ok``). Rows are appended and
flushed as submissions finish; ``<gradebook>.details.jsonl`` keeps each row's verdicts so a
rerun can skip graded submissions and still summarise every mistake.
"""

from __future__ import annotations

import csv
import hashlib
import json
import re
from collections import Counter
from pathlib import Path

__all__ = ["BASE_COLUMNS", "Gradebook", "feedback_markdown", "summary_markdown"]

BASE_COLUMNS = ["submission", "student_id", "status", "total", "max_total"]


def _fmt(x: float) -> str:
    return f"{x:g}"


class Gradebook:
    """An append-only gradebook CSV with its JSON-lines sidecar.

    Parameters
    ----------
    path : Path
    exercise_ids : list of str
        The exercise columns.
    force : bool
        Start afresh instead of resuming an existing gradebook.
    """

    def __init__(self, path, exercise_ids, force: bool = False):
        self.path = Path(path)
        self.details_path = self.path.with_name(self.path.name + ".details.jsonl")
        self.columns = BASE_COLUMNS + list(exercise_ids) + ["detail"]
        self.done: dict[str, dict] = {}
        if force or not self.path.exists():
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with self.path.open("w", newline="", encoding="utf-8") as f:
                csv.writer(f).writerow(self.columns)
            self.details_path.write_text("", encoding="utf-8")
            return
        with self.path.open(newline="", encoding="utf-8") as f:
            header = next(csv.reader(f), [])
        if header != self.columns:
            raise ValueError(f"{self.path} has columns {header}, this batch needs "
                             f"{self.columns}; use --force or another --out")
        if self.details_path.exists():
            for line in self.details_path.read_text(encoding="utf-8").splitlines():
                if line.strip():
                    record = json.loads(line)
                    self.done[record["submission"]] = record

    def key(self, submission) -> str:
        return str(Path(submission).resolve())

    def is_done(self, submission) -> bool:
        return self.key(submission) in self.done

    def add(self, graded) -> None:
        """Append one graded submission and flush."""
        points = {j.exercise_id: _fmt(j.points) for j in graded.judgements}
        row = [graded.submission, graded.student_id, graded.status, _fmt(graded.total),
               _fmt(graded.max_total)]
        row += [points.get(c, "") for c in self.columns[len(BASE_COLUMNS):-1]]
        row.append(graded.detail)
        with self.path.open("a", newline="", encoding="utf-8") as f:
            csv.writer(f).writerow(row)
        record = {"submission": self.key(graded.submission), "student_id": graded.student_id,
                  "status": graded.status,
                  "verdicts": [{"id": j.exercise_id, "status": j.status, "mistake": j.mistake,
                                "points": j.points} for j in graded.judgements]}
        with self.details_path.open("a", encoding="utf-8") as f:
            f.write(json.dumps(record) + "\n")
        self.done[record["submission"]] = record


def feedback_markdown(graded) -> str:
    """Feedback for the student: status, points and message per exercise."""
    lines = [f"# Feedback: {graded.student_id or 'unknown student'}", "",
             f"- submission: `{Path(graded.submission).name}`",
             f"- status: **{graded.status}**",
             f"- total: **{_fmt(graded.total)} / {_fmt(graded.max_total)}** points"]
    if graded.detail:
        lines.append(f"- notes: {graded.detail}")
    lines += ["", "| exercise | points | feedback |", "|---|---|---|"]
    for j in graded.judgements:
        message = j.message.replace("|", "\\|").replace("\n", " ")
        lines.append(f"| `{j.exercise_id}` | {_fmt(j.points)} / {_fmt(j.max_points)} | "
                     f"{message} |")
    return "\n".join(lines) + "\n"


def feedback_name(graded) -> str:
    """File name of the feedback file: student id and a short hash of the submission path."""
    stem = graded.student_id or "unknown"
    tag = hashlib.sha1(str(Path(graded.submission).resolve()).encode()).hexdigest()[:6]
    return re.sub(r"[^A-Za-z0-9_.@+-]", "_", stem)[:80] + f"-{tag}.md"


def summary_markdown(records) -> str:
    """Most common mistakes per exercise, with counts, over gradebook ``records``."""
    statuses = Counter(r["status"] for r in records)
    per_ex: dict[str, Counter] = {}
    correct: Counter = Counter()
    for r in records:
        for v in r["verdicts"]:
            per_ex.setdefault(v["id"], Counter())
            if v["status"] == "correct":
                correct[v["id"]] += 1
            else:
                per_ex[v["id"]][v["mistake"] or v["status"]] += 1
    lines = ["# Grading summary", "", f"{len(records)} submissions; status: "
             + ", ".join(f"{k} {n}" for k, n in statuses.most_common()), ""]
    for ex_id, counter in sorted(per_ex.items()):
        lines.append(f"## {ex_id}: {correct[ex_id]} correct")
        for tag, n in counter.most_common(5):
            lines.append(f"- {tag}: {n}")
        lines.append("")
    return "\n".join(lines)
