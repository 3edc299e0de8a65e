"""A whole class: collect submissions, return feedback, export grades to the LMS.

``python -m photolib collect``
    gathers one chapter's notebooks from the students' folders — the layout the course's
    JupyterHub creates (``/home/<account>/exercises/<chapter>.ipynb``, see
    ``deploy/jupyterhub``) or any glob with ``{account}`` — into a private folder
    (mode 0700, files 0600) as ``<account>/<chapter>.ipynb``. The student id comes from the
    account name (or from a roster CSV ``account,student_id``) and is checked against the
    notebook's ``STUDENT_ID`` read without running it; a mismatch is not collected but
    reported, so that no one is graded under another's id.
``python -m photolib return``
    puts each feedback file of ``grade --feedback`` into its student's folder
    (``/home/<account>/feedback/<chapter>.md`` by default), owned by that student's user
    and group, mode 0600, never through a symbolic link; the folder is made 0700.
``python -m photolib export``
    writes the gradebook as the CSV that Moodle's grade import or Canvas's gradebook import
    accepts: one chapter = one grade item (:data:`MOODLE_HEADER`, :data:`CANVAS_HEADER`).

The collect report and the export are CSV files written 0600 (:func:`write_private`).
"""

from __future__ import annotations

import csv
import glob
import io
import os
import pwd
import re
import stat
import sys
from dataclasses import dataclass
from pathlib import Path

from photolib.grading.report import csv_cell, write_private

__all__ = ["CANVAS_HEADER", "MOODLE_HEADER", "Collected", "collect", "export_grades",
           "return_feedback"]

#: the default layout of the course's hub: each account's home holds its exercises/ copy
HUB_LAYOUT = "/home/{account}/exercises/{chapter}.ipynb"
#: where ``return`` puts a student's feedback in that layout
HUB_FEEDBACK = "/home/{account}/feedback/{chapter}.md"

#: Moodle, Grades → Import → CSV file: one column identifies the user (mapped in the import
#: form to "ID number", i.e. ``idnumber``), every other column is a grade item, named by
#: its header (mapped to the grade item, or "new grade item"); the header row is required.
MOODLE_HEADER = ("ID number",)
#: Canvas, Grades → Import: the columns Student, ID, SIS User ID, SIS Login ID and Section
#: come first; each following column is an assignment ("Name (id)" for an existing one, a
#: new name creates it); a second row "Points Possible" gives the maximum of each.
CANVAS_HEADER = ("Student", "ID", "SIS User ID", "SIS Login ID", "Section")

_ACCOUNT = re.compile(r"^[a-z_][a-z0-9_.-]{0,31}$")


@dataclass(frozen=True)
class Collected:
    """One account's submission: where it was, where it went, and what was wrong."""

    account: str
    student_id: str
    source: str
    dest: str = ""
    problem: str = ""


def _roster(path) -> dict:
    """``account -> student id`` from a CSV with the header ``account,student_id``."""
    if path is None:
        return {}
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        if not reader.fieldnames or not {"account", "student_id"} <= set(reader.fieldnames):
            raise ValueError(f"roster {path}: the header must name 'account' and "
                             f"'student_id', got {reader.fieldnames}")
        return {row["account"].strip(): row["student_id"].strip() for row in reader}


def _accounts_of(layout: str, chapter: str):
    """``(account, path)`` for every file the layout matches; the account is the path part
    that stands where ``{account}`` stands."""
    if "{account}" not in layout:
        raise ValueError(f"the layout {layout!r} must contain {{account}}")
    pattern = layout.replace("{chapter}", chapter)
    head, tail = pattern.split("{account}", 1)
    found = []
    for path in sorted(glob.glob(head + "*" + tail)):
        account = path[len(head):len(path) - len(tail)] if tail else path[len(head):]
        if "/" in account or not account:
            continue
        found.append((account, path))
    return found


def collect(chapter: str, dest, layout: str = HUB_LAYOUT, roster=None) -> list[Collected]:
    """Copy each account's notebook of ``chapter`` into ``dest/<account>/<chapter>.ipynb``.

    Parameters
    ----------
    chapter : str
        A chapter with exercises, e.g. ``"04-rotations"``.
    dest : path
        The private folder (made 0700; must not be inside a student's folder).
    layout : str
        Where a student's notebook is, with ``{account}`` and ``{chapter}``.
    roster : path, optional
        CSV ``account,student_id``; without it the account name is the student id.

    Returns
    -------
    list of Collected
        One per account found; ``problem`` is empty for those collected.
    """
    from photolib.grading.exercises import chapters
    from photolib.grading.submission import (
        SubmissionError,
        read_submission,
        static_student_id,
    )

    if chapter not in chapters():
        raise ValueError(f"no chapter {chapter!r}; chapters with exercises: "
                         f"{sorted(chapters())}")
    ids = _roster(roster)
    dest = Path(dest)
    dest.mkdir(mode=0o700, parents=True, exist_ok=True)
    os.chmod(dest, 0o700)
    out = []
    for account, source in _accounts_of(layout, chapter):
        expected = ids.get(account, account if roster is None else "")
        if not expected:
            out.append(Collected(account, "", source, problem="not in the roster"))
            continue
        if os.path.islink(source) or not os.path.isfile(source):
            out.append(Collected(account, expected, source,
                                 problem="not a regular file (a symbolic link?)"))
            continue
        try:
            nb = read_submission(Path(source))
        except SubmissionError as exc:
            out.append(Collected(account, expected, source, problem=f"{exc.status}: "
                                 f"{exc.detail}"))
            continue
        claimed = static_student_id(nb)
        if claimed != expected:
            out.append(Collected(account, expected, source,
                                 problem=f"STUDENT_ID is {claimed!r}, the account's id is "
                                         f"{expected!r}: not collected"))
            continue
        folder = dest / account
        folder.mkdir(mode=0o700, exist_ok=True)
        target = folder / f"{chapter}.ipynb"
        write_private(target, Path(source).read_text(encoding="utf-8"))
        out.append(Collected(account, expected, source, str(target)))
    return out


def report_csv(rows) -> str:
    """The collect report: account, student id, source, destination, problem."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["account", "student_id", "source", "dest", "problem"])
    for r in rows:
        w.writerow([csv_cell(r.account), csv_cell(r.student_id), csv_cell(r.source),
                    csv_cell(r.dest), csv_cell(r.problem)])
    return buf.getvalue()


def _owner(account: str):
    try:
        entry = pwd.getpwnam(account)
    except KeyError:
        raise ValueError(f"no user account {account!r} on this machine") from None
    return entry.pw_uid, entry.pw_gid


def return_feedback(chapter: str, gradebook, feedback, collected, layout: str = HUB_FEEDBACK,
                    chown: bool = True) -> list[tuple[str, str]]:
    """Put each student's feedback file into that student's folder.

    Parameters
    ----------
    chapter : str
        The chapter graded.
    gradebook : path
        The gradebook CSV of ``grade``: its ``submission`` column names the collected file
        (``<collected>/<account>/<chapter>.ipynb``), which names the account.
    feedback : path
        The ``--feedback`` folder of ``grade`` (files named by :func:`feedback_name`).
    collected : path
        The folder ``collect`` wrote.
    layout : str
        Where the feedback goes, with ``{account}`` and ``{chapter}``.
    chown : bool
        Give the file and its folder to the account's user and group (needs root).

    Returns
    -------
    list of (account, path)
    """
    from photolib.grading.report import feedback_name

    collected = Path(collected).resolve()
    done = []
    with open(gradebook, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        sub = Path(row["submission"]).resolve()
        if sub.parent.parent != collected or sub.name != f"{chapter}.ipynb":
            continue
        account = sub.parent.name
        graded = type("G", (), {"student_id": row["student_id"], "submission": str(sub)})
        source = Path(feedback) / feedback_name(graded)
        if not source.is_file():
            raise ValueError(f"no feedback file {source} for {account} (grade with --feedback)")
        target = Path(layout.format(account=account, chapter=chapter))
        folder = target.parent
        if folder.is_symlink():
            raise ValueError(f"{folder} is a symbolic link: not writing {account}'s feedback")
        folder.mkdir(mode=0o700, parents=False, exist_ok=True)
        write_private(target, source.read_text(encoding="utf-8"))
        if chown:
            uid, gid = _owner(account)
            for p in (folder, target):
                os.chown(p, uid, gid, follow_symlinks=False)
        os.chmod(folder, 0o700)
        os.chmod(target, stat.S_IRUSR | stat.S_IWUSR)
        done.append((account, str(target)))
    return done


def export_grades(gradebook, fmt: str, item: str | None = None) -> str:
    """The gradebook as Moodle's or Canvas's grade-import CSV (one chapter = one grade item).

    Parameters
    ----------
    gradebook : path
        A gradebook CSV of ``grade`` (columns ``student_id``, ``status``, ``chapter``,
        ``total``, ``max_total``, …).
    fmt : {"moodle", "canvas"}
    item : str, optional
        The grade item's name; default "photolib <chapter>".

    Returns
    -------
    str
        CSV text. Rows whose status is ``duplicate-id`` or has no student id are left out
        (they need the instructor), every other row gives its total.
    """
    if fmt not in ("moodle", "canvas"):
        raise ValueError(f"format must be 'moodle' or 'canvas', got {fmt!r}")
    with open(gradebook, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{gradebook} has no graded rows")
    chapters = {r["chapter"] for r in rows if r.get("chapter")}
    if len(chapters) != 1:
        raise ValueError(f"{gradebook} holds chapters {sorted(chapters)}: one chapter is one "
                         f"grade item, export one gradebook per chapter")
    chapter = chapters.pop()
    name = item or f"photolib {chapter}"
    max_total = max(float(r["max_total"] or 0) for r in rows)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    if fmt == "moodle":
        w.writerow([*MOODLE_HEADER, name])
    else:
        w.writerow([*CANVAS_HEADER, name])
        w.writerow(["Points Possible", "", "", "", "", f"{max_total:g}"])
    for r in rows:
        sid = r.get("student_id", "")
        if not sid or r.get("status") == "duplicate-id":
            continue
        total = f"{float(r['total'] or 0):g}"
        if fmt == "moodle":
            w.writerow([csv_cell(sid), total])
        else:
            w.writerow(["", "", csv_cell(sid), "", "", total])
    return buf.getvalue()


# -- command lines --------------------------------------------------------------------------
def collect_main(argv: list[str]) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="python -m photolib collect",
                                     description="gather one chapter's notebooks from the "
                                                 "students' folders into a private folder")
    parser.add_argument("chapter", help="e.g. 04-rotations")
    parser.add_argument("--to", required=True, type=Path, help="the private folder")
    parser.add_argument("--layout", default=HUB_LAYOUT,
                        help=f"where a student's notebook is (default {HUB_LAYOUT})")
    parser.add_argument("--roster", type=Path, help="CSV account,student_id")
    args = parser.parse_args(argv)
    old = os.umask(0o077)
    try:
        rows = collect(args.chapter, args.to, args.layout, args.roster)
        write_private(args.to / "collect-report.csv", report_csv(rows))
    except (ValueError, OSError) as exc:
        print(f"collect: {exc}", file=sys.stderr)
        return 2
    finally:
        os.umask(old)
    bad = [r for r in rows if r.problem]
    print(f"collect: {len(rows) - len(bad)} of {len(rows)} notebooks collected into {args.to}")
    for r in bad:
        print(f"  {r.account}: {r.problem}")
    return 1 if bad else 0


def return_main(argv: list[str]) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="python -m photolib return",
                                     description="put each feedback file into its student's "
                                                 "folder, owned by the student, mode 0600")
    parser.add_argument("chapter")
    parser.add_argument("--gradebook", required=True, type=Path)
    parser.add_argument("--feedback", required=True, type=Path)
    parser.add_argument("--collected", required=True, type=Path, help="the folder of collect")
    parser.add_argument("--layout", default=HUB_FEEDBACK,
                        help=f"where a student's feedback goes (default {HUB_FEEDBACK})")
    parser.add_argument("--no-chown", action="store_true",
                        help="keep the grader's ownership (testing without root)")
    args = parser.parse_args(argv)
    try:
        done = return_feedback(args.chapter, args.gradebook, args.feedback, args.collected,
                               args.layout, chown=not args.no_chown)
    except (ValueError, OSError) as exc:
        print(f"return: {exc}", file=sys.stderr)
        return 2
    print(f"return: {len(done)} feedback files returned")
    return 0


def export_main(argv: list[str]) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="python -m photolib export",
                                     description="the gradebook as Moodle's or Canvas's "
                                                 "grade-import CSV")
    parser.add_argument("gradebook", type=Path)
    parser.add_argument("--format", required=True, choices=("moodle", "canvas"))
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--item", help="the grade item's name (default: photolib <chapter>)")
    args = parser.parse_args(argv)
    try:
        write_private(args.out, export_grades(args.gradebook, args.format, args.item))
    except (ValueError, OSError, KeyError) as exc:
        print(f"export: {exc}", file=sys.stderr)
        return 2
    print(f"export: wrote {args.out} ({args.format})")
    return 0
