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
    """Grade submissions into a gradebook; see ``docs/instructors.md``.

    Everything it writes is private: created under umask 077 (files 0600, folders 0700).
    """
    # imported before the umask changes, so that no byte-code file is written 0600
    import tqdm  # noqa: F401

    import photolib.grading.batch
    import photolib.grading.report  # noqa: F401
    old_umask = os.umask(0o077)
    try:
        return _grade(argv)
    finally:
        os.umask(old_umask)


def _grade(argv: list[str]) -> int:
    from photolib.grading.batch import Graded, grade_batch
    from photolib.grading.exercises import chapters
    from photolib.grading.judge import Judgement
    from photolib.grading.report import (
        Gradebook,
        feedback_markdown,
        feedback_name,
        shared_folder_problem,
        summary_markdown,
        write_private,
    )
    from photolib.grading.sandbox import sandbox_support
    parser = argparse.ArgumentParser(prog="python -m photolib grade",
                                     description="grade submitted notebooks")
    parser.add_argument("submissions", nargs="+", type=Path)
    parser.add_argument("--out", required=True, type=Path, help="gradebook CSV")
    parser.add_argument("--feedback", type=Path, help="folder for one Markdown file per student")
    parser.add_argument("--jobs", type=int, default=1, help="submissions graded at once")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per submission")
    parser.add_argument("--memory", type=int, default=1536,
                        help="MiB per submission: the address space of each of its processes "
                        "and, with cgroups, all its processes together")
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
    folders = [args.out.parent] + ([args.feedback] if args.feedback else [])
    for folder in folders:
        folder.mkdir(parents=True, exist_ok=True)
    if sandbox_support().own_user:  # kernels run as other users: they must not reach these
        for option, folder in zip(("--out", "--feedback"), folders):
            problem = shared_folder_problem(folder)
            if problem:
                print(f"grade: refusing {option} {folder}: {problem}. Kernels run as other "
                      "users and could plant symbolic links or read the grades there; use a "
                      "private folder (e.g. mkdir -m 700 ~/grading)", file=sys.stderr)
                return 2
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
    for p in missing:
        if args.force or not book.is_done(p):
            book.add(Graded(str(p), "", "missing", "file not found", chapter,
                            [Judgement(ex.id, "not-answered", 0.0, float(ex.points),
                                       "file not found") for ex in chapters()[chapter]]))
    from tqdm import tqdm
    bar = tqdm(total=len(todo), unit="nb", desc="grading", disable=args.no_progress)

    def done(graded):
        book.add(graded)
        if args.feedback:
            write_private(args.feedback / feedback_name(graded), feedback_markdown(graded))
        bar.update(1)

    grade_batch(todo, limits, jobs=args.jobs, on_result=done, chapter=chapter)
    bar.close()
    summary = summary_markdown(list(book.done.values()))
    summary_path = (args.feedback / "summary.md" if args.feedback
                    else args.out.with_name(args.out.stem + ".summary.md"))
    write_private(summary_path, summary)
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
