"""``python -m photolib assign`` and ``python -m photolib grade``."""

from __future__ import annotations

import argparse
import os
import shlex
import signal
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
        code = _grade(argv)
    finally:
        os.umask(old_umask)
    if code == 130:  # interrupted (Ctrl-C): every row, the summary and the hint are written
        sys.stdout.flush()
        sys.stderr.flush()
        # the interpreter's own teardown (NumPy, SymPy, ZeroMQ; seconds on a loaded machine)
        # is skipped, so that the command ends when it says it does
        os._exit(130)
    return code


def _grade(argv: list[str]) -> int:
    from photolib.grading.batch import StopRequest
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
                        "named by more than half of the submissions' file names)")
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
    stop = StopRequest()
    old_handler = signal.signal(signal.SIGINT, lambda signum, frame: _on_interrupt(stop))
    try:
        return _grade_with(args, argv, limits, stop)
    finally:
        signal.signal(signal.SIGINT, old_handler)


def _on_interrupt(stop) -> None:
    """SIGINT: the first stops the batch, the second abandons the running submissions.

    Written with ``os.write``: the handler may run while the progress bar writes to stderr
    (a reentrant buffered write raises).
    """
    if stop.request() == 1:
        text = ("\ngrade: interrupted: no further submission is started; the running ones "
                "get a few seconds to finish (Ctrl-C again abandons them at once)\n")
    else:
        text = "\ngrade: interrupted again: abandoning the running submissions\n"
    try:
        os.write(2, text.encode())
    except OSError:
        pass


def _grade_with(args, argv, limits, stop) -> int:
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
    unique = {}
    for p in args.submissions:  # the same file given twice is graded once
        unique.setdefault(os.path.realpath(p), p)
    if len(unique) < len(args.submissions):
        print(f"grade: {len(args.submissions) - len(unique)} duplicate path(s) ignored",
              file=sys.stderr)
    args.submissions = list(unique.values())
    inside = _outputs_in_submission_folders(args)
    if inside:
        print(f"grade: refusing {inside}", file=sys.stderr)
        return 2
    missing = [p for p in args.submissions if not p.is_file()]
    for p in missing:
        print(f"grade: {p} is not a file; it gets a 'missing' row", file=sys.stderr)
    if args.chapter:
        chapter = args.chapter
    else:
        chapter, message = _batch_chapter(args.submissions, missing)
        if chapter is None:
            print(f"grade: {message}", file=sys.stderr)
            return 2
        if message:
            print(f"grade: {message}", file=sys.stderr)
    if chapter not in chapters():
        print(f"grade: unknown chapter {chapter!r}; chapters: {', '.join(chapters())}",
              file=sys.stderr)
        return 2
    for note in sandbox_support().notes:
        print(f"grade: warning: {note}", file=sys.stderr)
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
    if args.force:  # their old rows go now: a run stopped half-way is resumed without --force
        book.forget(args.submissions)
    todo = [p for p in args.submissions if p not in missing and not book.is_done(p)]
    skipped = len(args.submissions) - len(missing) - len(todo)
    if skipped:
        print(f"grade: {skipped} submission(s) already in {args.out} skipped (--force regrades)",
              file=sys.stderr)
    for p in missing:
        if not book.is_done(p):
            book.add(Graded(str(p), "", "missing", "file not found", chapter,
                            [Judgement(ex.id, "not-answered", 0.0, float(ex.points),
                                       "file not found") for ex in chapters()[chapter]]))
    from tqdm import tqdm
    bar = tqdm(total=len(todo), unit="nb", desc="grading", disable=args.no_progress)
    graded_now = []

    def done(graded):
        book.add(graded)
        if args.feedback:
            write_private(args.feedback / feedback_name(graded), feedback_markdown(graded))
        graded_now.append(graded)
        bar.update(1)

    grade_batch(todo, limits, jobs=args.jobs, on_result=done, chapter=chapter, stop=stop)
    bar.close()
    summary = summary_markdown(book.records())
    summary_path = (args.feedback / "summary.md" if args.feedback
                    else args.out.with_name(args.out.stem + ".summary.md"))
    write_private(summary_path, summary)
    if not stop.stopping:
        print(summary)
        return 0
    rest = len(todo) - len(graded_now)
    again = [a for a in argv if a != "--force"]
    print(f"grade: interrupted: {len(graded_now)} of {len(todo)} submission(s) graded in "
          f"this run, every finished row kept in {args.out}; {rest} not graded.\n"
          f"grade: to grade the rest, run the same command again from this folder"
          + (" without --force" if args.force else "") + " (graded submissions are "
          f"skipped):\n  {shlex.join([sys.executable, '-m', 'photolib', 'grade', *again])}",
          file=sys.stderr)
    return 130


def _outputs_in_submission_folders(args) -> str | None:
    """Why an output path lies in (or below) the folder of a submission (None: none does).

    Kernels get only their notebook, but a gradebook or feedback next to the submissions
    is one copying mistake (or one future feature) away from every kernel: never allowed.
    """
    folders = {}
    for p in args.submissions:
        folders.setdefault(Path(os.path.realpath(Path(p).parent)), p)
    outputs = [("--out", args.out, Path(os.path.realpath(args.out)).parent)]
    if args.feedback:
        outputs.append(("--feedback", args.feedback, Path(os.path.realpath(args.feedback))))
    for option, given, where in outputs:
        for folder, submission in folders.items():
            if where == folder or folder in where.parents:
                return (f"{option} {given}: it lies in {folder}, the folder of the submission "
                        f"{submission}. Gradebook, details and feedback must stay out of the "
                        "submissions' folders, so that no kernel ever sees them; give a path "
                        "outside them (e.g. ~/grading/gradebook.csv for "
                        "~/grading/submissions/*.ipynb)")
    return None


def _batch_chapter(paths, missing) -> tuple[str | None, str]:
    """The chapter named by more than half of the submissions, and what to tell about it.

    File names count (a notebook's metadata only where no file name names a chapter): one
    stray notebook of another chapter, sorted first, must not turn a whole class into
    ``wrong-chapter`` rows. A tie or a mixture without such a majority is refused: returns
    ``(None, message listing the chapters and their files)``.
    """
    from photolib.grading.exercises import chapters
    from photolib.grading.submission import SubmissionError, chapter_claims, read_submission
    known = chapters()
    named: dict[str, list] = {}
    for p in paths:
        by_name = next((c for c in known if c in Path(p).name), None)
        if by_name:
            named.setdefault(by_name, []).append(p)
    how = "file names"
    if not named:
        how = "notebooks' metadata"
        for p in paths:
            if p in missing:
                continue
            try:
                by_meta, _ = chapter_claims(read_submission(p), p, known)
            except SubmissionError:
                continue
            if by_meta:
                named.setdefault(by_meta, []).append(p)
    if not named:
        return None, "no submission names a chapter in its file name or metadata; give --chapter"
    ranked = sorted(named.items(), key=lambda item: (-len(item[1]), item[0]))
    total = sum(len(v) for v in named.values())

    def listing(items):
        return "; ".join(f"{c}: {len(v)} ({', '.join(Path(p).name for p in v[:5])}"
                         + (", …" if len(v) > 5 else "") + ")" for c, v in items)

    top, files = ranked[0]
    if 2 * len(files) <= total:
        kind = "a tie" if len(ranked) > 1 and len(ranked[1][1]) == len(files) else "a mixture"
        return None, (f"the submissions' {how} name {len(ranked)} chapters, {kind} without a "
                      f"chapter named by more than half of them: {listing(ranked)}. Give "
                      "--chapter, or grade each chapter into a gradebook of its own")
    if len(ranked) == 1:
        return top, ""
    return top, (f"chapter {top}, named by {len(files)} of the {total} submissions' {how}; "
                 f"these get 'wrong-chapter' rows: {listing(ranked[1:])}")
