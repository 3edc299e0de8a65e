"""``python -m photolib assign`` and ``python -m photolib grade``."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from photolib.grading.sandbox import Limits

__all__ = ["assign_main", "grade_main"]


def assign_main(argv: list[str]) -> int:
    """Generate student copies from solution masters; ``--check`` only reports differences."""
    from photolib.grading.assign import AssignError, assign_folder
    parser = argparse.ArgumentParser(prog="python -m photolib assign",
                                     description="generate exercises/ from solutions/")
    parser.add_argument("--source", default="solutions", help="folder of solution masters")
    parser.add_argument("--dest", default="exercises", help="folder of student copies")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if a student copy is out of date, write nothing")
    args = parser.parse_args(argv)
    try:
        stale = assign_folder(Path(args.source), Path(args.dest), check=args.check)
    except AssignError as exc:  # exit 2, not 1: with --check, 1 means "copies out of date"
        print(f"assign: {exc} (run from the course's root folder or pass --source/--dest)",
              file=sys.stderr)
        return 2
    for path in stale:
        print(("out of date: " if args.check else "wrote ") + str(path))
    return 1 if args.check and stale else 0


def grade_main(argv: list[str]) -> int:
    """Grade submissions into a gradebook; see ``docs/instructors.md``."""
    from photolib.grading.batch import grade_batch
    from photolib.grading.exercises import chapters
    from photolib.grading.report import (
        Gradebook,
        feedback_markdown,
        feedback_name,
        summary_markdown,
    )
    from photolib.grading.sandbox import sandbox_support
    parser = argparse.ArgumentParser(prog="python -m photolib grade",
                                     description="grade submitted notebooks")
    parser.add_argument("submissions", nargs="+", type=Path)
    parser.add_argument("--out", required=True, type=Path, help="gradebook CSV")
    parser.add_argument("--feedback", type=Path, help="folder for one Markdown file per student")
    parser.add_argument("--jobs", type=int, default=1, help="submissions graded at once")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per submission")
    parser.add_argument("--memory", type=int, default=1536, help="MiB per kernel")
    parser.add_argument("--judge-timeout", type=float, default=30.0,
                        help="seconds for judging one answer in the grader")
    parser.add_argument("--chapter", help="the gradebook's chapter (default: the chapter "
                        "named by the first submission's file name)")
    parser.add_argument("--force", action="store_true",
                        help="regrade the given submissions, replacing only their rows")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs must be at least 1, got {args.jobs}")
    try:
        limits = Limits(timeout=args.timeout, memory_mb=args.memory,
                        judge_seconds=args.judge_timeout)
    except ValueError as exc:
        parser.error(str(exc))
    unique = {}
    for p in args.submissions:  # the same file given twice is graded once
        unique.setdefault(os.path.realpath(p), p)
    if len(unique) < len(args.submissions):
        print(f"grade: {len(args.submissions) - len(unique)} duplicate path(s) ignored",
              file=sys.stderr)
    args.submissions = list(unique.values())
    missing = [p for p in args.submissions if not p.is_file()]
    for p in missing:
        print(f"grade: {p} is not a file; it gets a 'missing' row", file=sys.stderr)
    for note in sandbox_support().notes:
        print(f"grade: warning: {note}", file=sys.stderr)
    chapter = args.chapter or _first_chapter(args.submissions, missing)
    if chapter is None:
        parser.error("no submission names a chapter in its file name; give --chapter")
    if chapter not in chapters():
        parser.error(f"unknown chapter {chapter!r}; chapters: {', '.join(chapters())}")
    ids = [ex.id for ex in chapters()[chapter]]
    try:
        book = Gradebook(args.out, ids, force=args.force)
    except ValueError as exc:
        print(f"grade: {exc}", file=sys.stderr)
        return 2
    todo = [p for p in args.submissions
            if p not in missing and (args.force or not book.is_done(p))]
    skipped = len(args.submissions) - len(missing) - len(todo)
    if skipped:
        print(f"grade: {skipped} submission(s) already in {args.out} skipped (--force regrades)",
              file=sys.stderr)
    from photolib.grading.batch import Graded
    from photolib.grading.judge import Judgement
    for p in missing:
        if args.force or not book.is_done(p):
            book.add(Graded(str(p), "", "missing", "file not found", chapter,
                            [Judgement(ex.id, "not-answered", 0.0, float(ex.points),
                                       "file not found") for ex in chapters()[chapter]]))
    if args.feedback:
        args.feedback.mkdir(parents=True, exist_ok=True)
    from tqdm import tqdm
    bar = tqdm(total=len(todo), unit="nb", desc="grading", disable=args.no_progress)

    def done(graded):
        book.add(graded)
        if args.feedback:
            (args.feedback / feedback_name(graded)).write_text(feedback_markdown(graded),
                                                               encoding="utf-8")
        bar.update(1)

    grade_batch(todo, limits, jobs=args.jobs, on_result=done, chapter=chapter)
    bar.close()
    summary = summary_markdown(list(book.done.values()))
    summary_path = (args.feedback / "summary.md" if args.feedback
                    else args.out.with_name(args.out.stem + ".summary.md"))
    summary_path.write_text(summary, encoding="utf-8")
    print(summary)
    return 0


def _first_chapter(paths, missing) -> str | None:
    """The chapter named by the first submission's file name (else its metadata)."""
    from photolib.grading.exercises import chapters
    from photolib.grading.submission import SubmissionError, chapter_claims, read_submission
    known = chapters()
    for p in paths:
        by_name = next((c for c in known if c in Path(p).name), None)
        if by_name:
            return by_name
    for p in paths:
        if p in missing:
            continue
        try:
            by_meta, _ = chapter_claims(read_submission(p), p, known)
        except SubmissionError:
            continue
        if by_meta:
            return by_meta
    return None
