"""Writing grades: the gradebook CSV, one Markdown feedback file per student, a summary.

The gradebook has the columns ``submission, student_id, status, chapter, total, max_total``,
one column per exercise (points) and ``detail`` (why a status is not ``ok``). Two rows with
the same student id both show the status ``duplicate-id`` (points kept, the detail names the
other row and the status graded); the sidecar keeps the graded status. Rows are
appended and flushed as submissions finish; ``<gradebook>.details.jsonl`` keeps each row's
verdicts so a rerun can skip graded submissions and still summarise every mistake. A
regraded submission (``--force``) replaces its own row and keeps all others. Text cells are
one line of bounded length, and a cell that a spreadsheet would read as a formula (starting
with ``= + - @``) gets a leading apostrophe.

Every file is written without following symbolic links: a rewrite goes to a temporary file
of a random name made with ``O_EXCL`` (:func:`tempfile.mkstemp`) in the target's folder and
replaces the target, an append opens the target with ``O_NOFOLLOW``; files are created
0600. :func:`shared_folder_problem` tells whether other users could plant links in a folder.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
import re
import stat
import tempfile
from collections import Counter
from pathlib import Path

__all__ = ["BASE_COLUMNS", "Gradebook", "append_private", "csv_cell", "feedback_markdown",
           "shared_folder_problem", "summary_markdown", "write_private"]

BASE_COLUMNS = ["submission", "student_id", "status", "chapter", "total", "max_total"]


def _fmt(x: float) -> str:
    return f"{x:g}"


def _one_line(text, limit: int = 1000) -> str:
    text = re.sub(r"[\x00-\x1f\x7f\u2028\u2029\x85]+", " ", str(text))
    return text if len(text) <= limit else text[:limit - 1] + "…"


def csv_cell(text, limit: int = 1000) -> str:
    """A text cell that is one line and never a spreadsheet formula.

    >>> csv_cell("=HYPERLINK(1)"), csv_cell("a\\nb"), csv_cell("-1+1")
    ("'=HYPERLINK(1)", 'a b', "'-1+1")
    """
    text = _one_line(text, limit)
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def write_private(path, text: str) -> None:
    """Write ``text`` to ``path`` atomically, mode 0600, never through a symbolic link.

    The text goes to a new file of a random name in the same folder (``O_EXCL``), which then
    replaces ``path``; a symbolic link at ``path`` is replaced, not followed.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name[:60]}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o600)
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def append_private(path, text: str) -> None:
    """Append ``text`` to ``path`` (created 0600); refuses a symbolic link (``O_NOFOLLOW``)."""
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC,
                 0o600)
    with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
        f.write(text)


def shared_folder_problem(folder) -> str | None:
    """Why anyone could replace files in ``folder`` (None: only its owner and root can).

    A folder anyone may write to (``o+w``, as ``/tmp``) is refused, and so is a folder below
    one that is not sticky; in a sticky folder (``/tmp``) the next step must belong to root or
    this user, so that nobody else may rename or replace it. Symbolic links are resolved
    first. Group permissions do not count: a sandboxed kernel belongs to no group.

    >>> shared_folder_problem("/tmp") is None
    False
    """
    real = Path(os.path.realpath(folder))
    parts = [real, *real.parents][::-1]  # "/" first
    mine = (0, os.geteuid())
    for i, part in enumerate(parts):
        try:
            info = os.stat(part)
        except FileNotFoundError:
            break  # will be made by this process, 0700
        except OSError as exc:
            return f"{part} cannot be inspected ({exc.strerror})"
        if not info.st_mode & stat.S_IWOTH:
            continue
        mode = stat.filemode(info.st_mode)
        if part == real:
            return f"other users may write to {part} ({mode})"
        if not info.st_mode & stat.S_ISVTX:
            return f"other users may write to {part} ({mode}), which holds {real}"
        try:
            nxt = os.stat(parts[i + 1])
        except FileNotFoundError:
            break
        if nxt.st_uid not in mine:
            return f"{parts[i + 1]} in the shared folder {part} belongs to user {nxt.st_uid}"
    return None


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
        self._rows: dict[str, list] = {}
        self._ids: dict[str, set] = {}  # student id -> keys of its rows
        for p in (self.path, self.details_path):
            if p.is_symlink():
                raise ValueError(f"{p} is a symbolic link; give the gradebook's real path")
        if self.path.exists():
            with self.path.open(newline="", encoding="utf-8") as f:
                reader = csv.reader(f)
                header = next(reader, [])
                rows = list(reader) if header == self.columns else []
            if header != self.columns and not force:
                raise ValueError(f"{self.path} has columns {header}, this batch needs "
                                 f"{self.columns}; use --force (which starts it afresh) "
                                 "or another --out")
            if header == self.columns:
                rows = [row for row in rows if row]
                records = []
                if self.details_path.exists():
                    for line in self.details_path.read_text(encoding="utf-8").splitlines():
                        if line.strip():
                            records.append(json.loads(line))
                # rows and records are written together, in the same order: key each row by
                # its record's resolved path, not by the CSV cell, which csv_cell may have
                # shortened or neutralised (a leading ', control characters, > 1000 chars)
                if len(records) == len(rows):
                    keys = [record["submission"] for record in records]
                else:
                    keys = [self.key(row[0].removeprefix("'")) for row in rows]
                self._rows = dict(zip(keys, rows))
                self.done = {record["submission"]: record for record in records}
                for key, record in self.done.items():
                    row = self._rows.get(key)
                    if row is not None and "detail" in record:  # as graded, not as flagged
                        row[2] = csv_cell(record["status"], 40)
                        row[-1] = csv_cell(record["detail"])
                    self._index(key, record.get("student_id"))
                return
        self._rewrite()

    def _index(self, key: str, student_id) -> None:
        if student_id:
            self._ids.setdefault(student_id, set()).add(key)

    def _partners(self, key: str) -> list[str]:
        """The other rows with the student id of row ``key``."""
        sid = self.done.get(key, {}).get("student_id")
        return sorted(k for k in self._ids.get(sid, ()) if k != key) if sid else []

    def _shown(self, key: str) -> list:
        """Row ``key`` as written: ``duplicate-id`` when another row has its student id.

        The status and detail it was graded with stay in the sidecar, so the flag goes as
        soon as the other row does (regraded with a corrected id, ``--force``).
        """
        row = self._rows[key]
        partners = self._partners(key)
        if not partners:
            return row
        record = self.done[key]
        names = ", ".join(Path(p).name for p in partners[:3])
        more = f" and {len(partners) - 3} more" if len(partners) > 3 else ""
        detail = record.get("detail", "")
        note = (f"student id {record['student_id']} is also the id of {names}{more}: check "
                f"both against the roster; graded {record['status']}"
                + (f": {detail}" if detail else ""))
        return [*row[:2], "duplicate-id", *row[3:-1], csv_cell(note)]

    def forget(self, submissions) -> None:
        """Remove the rows of ``submissions`` (``--force``: they are graded afresh).

        Removed at the start, not as each is regraded, so that a forced run stopped
        half-way leaves no stale row that a resumed run would skip.
        """
        keys = [k for k in map(self.key, submissions) if k in self._rows or k in self.done]
        if not keys:
            return
        for key in keys:
            record = self.done.pop(key, None)
            if record is not None:
                self._ids.get(record.get("student_id"), set()).discard(key)
            self._rows.pop(key, None)
        self._rewrite()

    def records(self) -> list[dict]:
        """The sidecar records with the status as written (``duplicate-id`` where flagged)."""
        return [dict(r, status="duplicate-id") if self._partners(k) else r
                for k, r in self.done.items()]

    def key(self, submission) -> str:
        return str(Path(submission).resolve())

    def is_done(self, submission) -> bool:
        return self.key(submission) in self.done

    def _rewrite(self) -> None:
        """Write the CSV and the sidecar afresh from the rows and records kept."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        table = io.StringIO(newline="")
        writer = csv.writer(table)
        writer.writerow(self.columns)
        writer.writerows(self._shown(key) for key in self._rows)
        write_private(self.path, table.getvalue())
        write_private(self.details_path,
                      "".join(json.dumps(r) + "\n" for r in self.done.values()))

    def add(self, graded) -> None:
        """Add one graded submission (replacing its earlier row, if any) and flush."""
        points = {j.exercise_id: _fmt(j.points) for j in graded.judgements}
        row = [csv_cell(graded.submission), csv_cell(graded.student_id, 80),
               csv_cell(graded.status, 40), csv_cell(graded.chapter or "", 80),
               _fmt(graded.total), _fmt(graded.max_total)]
        row += [points.get(c, "") for c in self.columns[len(BASE_COLUMNS):-1]]
        row.append(csv_cell(graded.detail))
        key = self.key(graded.submission)
        record = {"submission": key, "student_id": graded.student_id,
                  "status": graded.status, "chapter": graded.chapter,
                  "detail": _one_line(graded.detail),
                  "verdicts": [{"id": j.exercise_id, "status": j.status, "mistake": j.mistake,
                                "points": j.points} for j in graded.judgements]}
        replace = key in self._rows or key in self.done
        if key in self.done:
            self._ids.get(self.done[key].get("student_id"), set()).discard(key)
        self._rows[key] = row
        self.done[key] = record
        self._index(key, graded.student_id)
        if replace or self._partners(key):  # other rows change too: flagged or no longer
            self._rewrite()
            return
        line = io.StringIO(newline="")
        csv.writer(line).writerow(row)
        append_private(self.path, line.getvalue())
        append_private(self.details_path, json.dumps(record) + "\n")


def feedback_markdown(graded) -> str:
    """Feedback for the student: status, points and message per exercise."""
    lines = [f"# Feedback: {_one_line(graded.student_id, 80) or 'unknown student'}", "",
             f"- submission: `{_one_line(Path(graded.submission).name, 200)}`",
             f"- status: **{graded.status}**"]
    if graded.chapter:
        lines.append(f"- chapter: {graded.chapter}")
    lines.append(f"- total: **{_fmt(graded.total)} / {_fmt(graded.max_total)}** points")
    if graded.detail:
        lines.append(f"- notes: {_one_line(graded.detail)}")
    lines += ["", "| exercise | points | feedback |", "|---|---|---|"]
    for j in graded.judgements:
        message = _one_line(j.message, 500).replace("|", "\\|")
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
