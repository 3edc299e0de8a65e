"""The committed verdict table: every record's verdicts and evidence, computed once.

Why: recomputing every verdict of the catalogue takes some 20 s (SymPy derivations, sampling at
50 digits, the checks of the examples), and the errata chapter must open in seconds. So the
verdicts are computed once, by ``python -m photolib errata --write-table`` (or ``make regen``),
into the package data ``photolib/data/errata-verdicts.json``, which is committed and read by the
chapter and its interactive table (:class:`photolib.nb.errata.VerdictExplorer`).

How it is kept honest, as ``photolib/_generated`` is (``tests/test_codegen.py``):
``tests/errata/test_verdict_table.py`` recomputes every verdict and its evidence from the
records and diffs the result against the committed file (marked slow), and a fast test compares
the SHA-256 of the sources the verdicts come from (:func:`source_hash`: ``photolib/errata``,
``photolib/derive``, ``photolib/symcheck.py``) with the one the file was written from, so an
edit of a record or a derivation without a refresh fails at once. The file never replaces the
evidence: ``python -m photolib errata`` and ``--id`` still recompute everything.

Each record's entry holds the id, the source key (:data:`ORIGINS`) and the chapter of the book
(:func:`chapter_of`), the item, its kind and note, per printed version the source's claim, our
recomputed verdict, its one-line reason and the counterexample (4 significant digits), and the
full text of ``python -m photolib errata --id ID`` (:func:`photolib.errata.cli.describe`) as a
list of lines. Numbers in it are formatted as the CLI prints them (never a float's repr), so the
file is the same on every CPU.

Examples
--------
>>> t = load_table()
>>> len(t["records"]) == len(__import__("photolib.errata").errata.catalogue())
True
>>> entry("luhmann:2.86")["versions"]["corrected"]["verdict"]
'right'
"""

from __future__ import annotations

import difflib
import functools
import hashlib
import json
import re
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[1]
TABLE_PATH = PACKAGE_DIR / "data" / "errata-verdicts.json"
#: what the verdicts are computed from (hashed by :func:`source_hash`), relative to the package
SOURCE_GLOBS = ("errata/*.py", "derive/**/*.py", "symcheck.py")
#: source key (the prefix of a record id) → the source
ORIGINS = {"luhmann": "Luhmann, errata list of Nahbereichsphotogrammetrie",
           "de-summary": "German lecture summary",
           "hu-wiki": "Hungarian Wikipedia article",
           "pl-notes": "Polish exercise notes"}
#: Luhmann items whose id carries a page, not a formula number: their chapter of the book
PAGE_CHAPTER = {"p48-T11": "2", "p90-t-distribution": "2", "p425-figure-ref": "5"}
FORMAT = 1


def source_hash() -> str:
    """SHA-256 of the sources the verdicts are computed from (paths and contents, sorted).

    >>> len(source_hash())
    64
    """
    h = hashlib.sha256()
    paths = sorted({p for g in SOURCE_GLOBS for p in PACKAGE_DIR.glob(g)})
    for path in paths:
        h.update(path.relative_to(PACKAGE_DIR).as_posix().encode() + b"\0")
        h.update(path.read_bytes().replace(b"\r\n", b"\n") + b"\0")
    return h.hexdigest()


def origin_of(record_id: str) -> str:
    """The source key of a record id: ``luhmann:4.18b`` → ``luhmann``.

    >>> origin_of("pl-notes:bilinear")
    'pl-notes'
    """
    key = record_id.partition(":")[0]
    if key not in ORIGINS:
        raise ValueError(f"record id {record_id!r} has no known source prefix; "
                         f"expected one of {list(ORIGINS)}")
    return key


def chapter_of(record_id: str) -> str:
    """The chapter of Luhmann's book a Luhmann record belongs to, ``""`` for other sources.

    The chapter is the first number of the item (``example-4.8`` → 4, ``fig-8.67b`` → 8);
    items named by their page have it in :data:`PAGE_CHAPTER`.

    >>> chapter_of("luhmann:example-4.8"), chapter_of("luhmann:p48-T11"), chapter_of("hu-wiki:history")
    ('4', '2', '')
    """
    if origin_of(record_id) != "luhmann":
        return ""
    rest = record_id.partition(":")[2]
    if rest in PAGE_CHAPTER:
        return PAGE_CHAPTER[rest]
    m = re.search(r"[0-9]+", rest)
    if m is None:
        raise ValueError(f"{record_id}: no chapter number in the id; add it to PAGE_CHAPTER")
    return m.group()


def record_entry(rec) -> dict:
    """The table's entry of one record (recomputes its verdicts: slow for some records)."""
    from photolib.errata.cli import describe, format_point

    versions = {}
    for name, spec in rec.specs.items():
        ev = rec.evaluate(name)
        versions[name] = {"claim": spec.claim, "verdict": ev.verdict, "why": ev.detail,
                          "counterexample": format_point(ev.counterexample)
                          if ev.counterexample else ""}
    return {"id": rec.id, "origin": origin_of(rec.id), "chapter": chapter_of(rec.id),
            "item": rec.item, "kind": rec.kind, "source": rec.source, "note": rec.note,
            "versions": versions, "describe": describe(rec).splitlines()}


def build_table(records=None, progress=None) -> dict:
    """The whole table, recomputed from the records (the catalogue by default).

    ``progress`` wraps the records (a progress bar); the order is the catalogue's.
    """
    from photolib.errata import catalogue

    recs = catalogue() if records is None else list(records)
    if progress is not None:
        recs = progress(recs)
    return {"format": FORMAT,
            "generated_by": "python -m photolib errata --write-table (make regen); do not edit",
            "source_sha256": source_hash(),
            "records": [record_entry(r) for r in recs]}


def render(table: dict) -> str:
    """The file's text: JSON, one key per line, UTF-8 letters kept (stable diffs)."""
    return json.dumps(table, ensure_ascii=False, indent=1) + "\n"


def write_table(path: Path | str = TABLE_PATH, progress=None) -> Path:
    """Recompute the table and write it to ``path``; returns the path."""
    path = Path(path)
    text = render(build_table(progress=progress))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


#: how symcheck decided an equality ("exact: trigsimp", "numeric: 12 points at 50 digits"): which
#: route finishes first depends on its CPU-time budget, so on the load of the machine; the
#: verdict does not, and the sync test compares the tables without it
_EQUALITY_ROUTE = re.compile(r"\b(?:exact: [\w-]+|numeric: \d+ points at \d+ digits)")


def diff(committed: str, recomputed: str, path: str = "photolib/data/errata-verdicts.json",
         context: int = 1) -> str:
    """A unified diff of two table texts (:func:`render`), ``""`` when they are equal.

    The sync test shows it when the committed table is out of date; it names the changed
    verdicts and the record ids around them. The route by which an equality was decided
    (``exact: trigsimp`` on an idle machine, ``numeric: 12 points at 50 digits`` when trigsimp ran
    out of its time budget) is not a difference:

    >>> diff('"(equal, exact: trigsimp)"', '"(equal, numeric: 12 points at 50 digits)"')
    ''

    >>> diff('{"a": 1}\\n', '{"a": 1}\\n')
    ''
    >>> print(diff('{\\n "verdict": "right"\\n}\\n', '{\\n "verdict": "wrong"\\n}\\n'), end="")
    --- photolib/data/errata-verdicts.json
    +++ recomputed
    @@ -1,3 +1,3 @@
     {
    - "verdict": "right"
    + "verdict": "wrong"
     }
    """
    if _EQUALITY_ROUTE.sub("ROUTE", committed) == _EQUALITY_ROUTE.sub("ROUTE", recomputed):
        return ""
    return "".join(difflib.unified_diff(committed.splitlines(True), recomputed.splitlines(True),
                                        path, "recomputed", n=context))


@functools.lru_cache(maxsize=4)
def load_table(path: Path | str = TABLE_PATH) -> dict:
    """The committed table (read once per process).

    Raises
    ------
    FileNotFoundError
        If the file is missing, saying how to write it.
    ValueError
        If it is not a table of this format.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path} missing: run `python -m photolib errata --write-table` "
                                "or `make regen`")
    data = json.loads(path.read_text(encoding="utf-8"))
    if not isinstance(data, dict) or data.get("format") != FORMAT or "records" not in data:
        raise ValueError(f"{path} is not an errata verdict table of format {FORMAT} "
                         f"(format {data.get('format') if isinstance(data, dict) else None!r}); "
                         "rewrite it with `python -m photolib errata --write-table`")
    return data


def is_current(table: dict | None = None) -> bool:
    """Whether the table was written from the sources as they are now (:func:`source_hash`)."""
    table = load_table() if table is None else table
    return table.get("source_sha256") == source_hash()


def entry(record_id: str, table: dict | None = None) -> dict:
    """The committed entry of one record; ``KeyError`` names the close matches."""
    table = load_table() if table is None else table
    for e in table["records"]:
        if e["id"] == record_id:
            return e
    near = [e["id"] for e in table["records"] if record_id.split(":")[-1] in e["id"]]
    raise KeyError(f"no record {record_id!r} in the committed verdict table"
                   + (f"; did you mean {near}?" if near else ""))


def describe(record_id: str, table: dict | None = None) -> str:
    """The committed text of ``python -m photolib errata --id ID``: versions, derivation, steps,
    verdicts and evidence, as :func:`photolib.errata.cli.describe` printed it when the table
    was written (no recomputation).

    >>> describe("luhmann:2.86").splitlines()[0]
    'luhmann:2.86: circle radius from the general conic'
    """
    return "\n".join(entry(record_id, table)["describe"])
