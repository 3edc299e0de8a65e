"""Grading throughput: sandboxed grading versus plain nbclient execution of the same notebooks.

Builds a batch of course-style submissions from the demo master (different student ids,
some answers wrong), then

1. runs each with plain ``nbclient`` (no sandbox, no judging), ``--jobs`` at a time;
2. grades them with :func:`photolib.grading.batch.grade_batch`.

Prints submissions per second of both and the ratio (grading time / plain time).
Run: ``.venv/bin/python benchmarks/bench_grading.py [--n 24] [--jobs 2] [--chapters]``.
The plain run starts one kernel per notebook as nbclient does; the grader keeps a pool of
sandboxed kernels started ahead of need, which is why it can be faster than plain execution.
"""

from __future__ import annotations

import argparse
import copy
import os
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import nbformat  # noqa: E402

from photolib.grading.batch import grade_batch  # noqa: E402
from photolib.grading.sandbox import Limits  # noqa: E402


def make_batch(folder: Path, n: int, masters: list[str] = ("00-start",)) -> list[Path]:
    """``n`` submissions cycling through ``masters``, each with its own student id."""
    books = {m: nbformat.read(ROOT / "solutions" / f"{m}.ipynb", as_version=4) for m in masters}
    paths = []
    for i in range(n):
        name = masters[i % len(masters)]
        nb = copy.deepcopy(books[name])
        for cell in nb.cells:
            if "student-id" in cell.get("metadata", {}).get("tags", []):
                cell.source = f'STUDENT_ID = "s{1000 + i}"'
            if i % 3 == 1 and "answer:demo.image-scale" in cell.metadata.get("tags", []):
                cell.source = cell.source.replace("/ 1000.0", "")
        path = folder / f"s{1000 + i}-{name}.ipynb"
        nbformat.write(nb, path)
        paths.append(path)
    return paths


def plain(paths, jobs: int) -> float:
    from nbclient import NotebookClient

    def run(path):
        nb = nbformat.read(path, as_version=4)
        NotebookClient(nb, timeout=60, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()

    t0 = time.perf_counter()
    with ThreadPoolExecutor(jobs) as ex:
        list(ex.map(run, paths))
    return time.perf_counter() - t0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=24, help="submissions in the batch")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--chapters", action="store_true",
                        help="grade the chapter masters (04-06, heavier SymPy work) in turn "
                             "instead of the demo master")
    args = parser.parse_args(argv)
    from photolib.grading.exercises import chapters
    masters = (sorted(c for c in chapters() if c != "00-start") if args.chapters
               else ["00-start"])
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT),
                                                             os.environ.get("PYTHONPATH")]))
    with tempfile.TemporaryDirectory() as tmp:
        paths = make_batch(Path(tmp), args.n, masters)
        t_plain = plain(paths, args.jobs)
        t0 = time.perf_counter()
        results = grade_batch(paths, Limits(timeout=60), jobs=args.jobs)
        t_grade = time.perf_counter() - t0
    bad = [r for r in results if r.status != "ok"]
    print(f"submissions: {args.n} of {', '.join(masters)}, jobs: {args.jobs}, "
          f"cores: {os.cpu_count()}")
    print(f"plain nbclient : {t_plain:6.2f} s  {args.n / t_plain:5.2f} submissions/s")
    print(f"sandbox+judge  : {t_grade:6.2f} s  {args.n / t_grade:5.2f} submissions/s")
    print(f"ratio grading/plain: {t_grade / t_plain:.2f} "
          f"(overhead {100 * (t_grade / t_plain - 1):+.0f} %)")
    if bad:
        print(f"unexpected statuses: {[(r.submission, r.status) for r in bad]}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
