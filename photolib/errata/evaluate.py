"""The errata notebook's callbacks: evaluate printed versions and the derivation at chosen values,
and the rows of the committed verdict table.

The callback :func:`evaluate_versions` is a plain function (unit-tested); :func:`photolib.nb.errata.build_widget`
wires it to ipywidgets sliders (``continuous_update=False``, since a SymPy substitution takes
milliseconds, not microseconds). Plain functions only: the widgets are in :mod:`photolib.nb.errata`.

Only formula records can be evaluated at numbers: at least one printed version and the
derivation must be SymPy expressions. For the others (figures, text statements, examples whose
verdict comes from a check, formulas checked by a function instead of a derivation)
:func:`not_evaluable_reason` says why; :func:`evaluate_versions` raises ``ValueError`` with that
reason and :func:`~photolib.nb.errata.build_widget` shows it instead of sliders.

:class:`photolib.nb.errata.VerdictExplorer` is the chapter's interactive verdict table: a search box and filters
by source, chapter of Luhmann's book and verdict over the committed verdict table
(:mod:`photolib.errata.table`), showing every verdict in full. Its callback
:func:`verdict_table_html` (rows: :func:`verdict_rows`) is a plain function, tested in
``tests/errata/test_verdict_table.py``; it is built like the glossary's explorer
(:class:`photolib.nb.glossary.GlossaryExplorer`, the same :class:`photolib.nb.live.Panel`).

A record whose derivation is the residual of an invariance (``luhmann:2.21``: the cross ratio
is valid iff λ(projected points) − λ(points) ≡ 0) is evaluated as that residual under a fixed
projectivity of the line, so each version is compared with the derivation's 0; the printed
values and the course's λ are shown beside them.

Examples
--------
>>> vals = evaluate_versions("luhmann:2.86", {"A": 2, "D": 3, "E": 4, "F": 1})
>>> sorted(vals)
['corrected', 'derived', 'old']
>>> round(vals["corrected"], 6) == round(vals["derived"], 6)
True
>>> evaluate_versions("de-summary:reflection", {})
Traceback (most recent call last):
...
ValueError: de-summary:reflection cannot be evaluated at numbers: no derivation to evaluate (its verdict is recomputed by a check); no printed version is a formula
"""

from __future__ import annotations

import random
from fractions import Fraction

import sympy as sp

from photolib.derive import plane
from photolib.errata import get


def _is_sym(e) -> bool:
    return isinstance(e, (sp.Basic, sp.MatrixBase))


def _resolve(v):
    return v() if callable(v) else v


# ------------------------------------------------------------------ invariance records (2.21)
def _fixed_projectivity(seed: int = 21) -> dict:
    """``{p, q, r, s: rationals}`` of t ↦ (pt + q)/(rt + s), drawn once at random (``seed``)."""
    rng = random.Random(seed)
    while True:
        p, q, r, s = (sp.Rational(Fraction(rng.randint(-40, 40), rng.randint(7, 19)))
                      for _ in range(4))
        if abs(p * s - q * r) > sp.Rational(1, 2):          # far from degenerate
            return dict(zip(plane.proj_line, (p, q, r, s)))


PROJECTIVITY = _fixed_projectivity()
#: records whose derivation is an invariance residual: id -> (what is invariant, its map)
INVARIANCE_RECORDS = {"luhmann:2.21": "cross ratio"}


def _projected(expr):
    """``expr`` of the points t_A … t_D at the projected points (p t + q)/(r t + s)."""
    image = {t: plane.line_projectivity(t).subs(PROJECTIVITY) for t in plane.t_line}
    return expr.xreplace(image)


def _map_text() -> str:
    p, q, r, s = (PROJECTIVITY[k] for k in plane.proj_line)
    return f"t ↦ ({p}·t + {q})/({r}·t + {s})"


# ----------------------------------------------------------------------------- evaluability
def not_evaluable_reason(rec) -> str | None:
    """Why ``rec`` cannot be evaluated at numbers, or ``None`` if it can.

    >>> not_evaluable_reason(get("luhmann:5.42")) is None
    True
    >>> not_evaluable_reason(get("luhmann:fig-3.45"))
    'a figure record (not-checkable: figure only); no derivation to evaluate; no printed version is a formula'
    """
    why = []
    derived = rec.derived()
    if rec.kind == "figure":
        why.append(f"a figure record ({next(iter(rec.specs.values())).verdict})")
    if derived is None:
        checked = any(s.check is not None for s in rec.specs.values())
        why.append("no derivation to evaluate" + (" (its verdict is recomputed by a check)"
                                                   if checked else ""))
    elif not _is_sym(derived):
        why.append(f"its derivation is not a formula (a Python {type(derived).__name__}: "
                   "input of the check that recomputes the verdict)")
    if not any(_is_sym(e) for e in rec.versions.values()):
        why.append("no printed version is a formula")
    return "; ".join(why) if why else None


def _targets(rec) -> dict:
    """``{version: target}`` of the versions compared with their own target, not the derivation."""
    out = {}
    for name, spec in rec.specs.items():
        t = _resolve(spec.target)
        if _is_sym(t) and name in rec.versions:
            out[name] = t
    return out


def _free_symbols(rec) -> list:
    if not_evaluable_reason(rec) is not None:
        return []
    given = rec.given_substitution()
    syms = set()
    for e in list(rec.versions.values()) + [rec.derived()] + list(_targets(rec).values()):
        if _is_sym(e):
            e = e.subs(given) if given else e
            syms |= e.free_symbols
    return sorted(syms, key=lambda s: s.name)


def evaluate_versions(record_id: str, values: dict) -> dict:
    """Evaluate every printed version and the derivation of a formula record.

    Parameters
    ----------
    record_id : str
        A formula record, e.g. ``"luhmann:5.42"``.
    values : dict
        ``{symbol name: number}``; every free symbol must be given.

    Returns
    -------
    dict
        ``{version: float or list of float, "derived": …}``: each printed version as
        printed (no condition applied), and the derivation. A version compared with its own
        target instead of the derivation (``VersionSpec.target``) adds ``"target (version)"``.
        For an invariance record (:data:`INVARIANCE_RECORDS`, the cross ratio 2.21) each
        version is its residual λ(projected points) − λ(points) under the fixed projectivity
        :data:`PROJECTIVITY` (compare with ``"derived"``, the derivation's residual 0), and
        ``"λ as printed (version)"`` and ``"λ course"`` (``photolib.transforms.cross_ratio``)
        are the values at the given points.

    Raises
    ------
    ValueError
        If a symbol has no value, naming the missing ones; or if the record cannot be
        evaluated at numbers (no SymPy derivation or no printed formula), naming the record
        and the reason.
    """
    rec = get(record_id)
    reason = not_evaluable_reason(rec)
    if reason is not None:
        raise ValueError(f"{record_id} cannot be evaluated at numbers: {reason}")
    syms = _free_symbols(rec)
    missing = [s.name for s in syms if s.name not in values]
    if missing:
        raise ValueError(f"{record_id}: no value for {missing}")
    sub = {s: sp.Float(values[s.name], 30) for s in syms}
    given = rec.given_substitution()

    def num(e):
        e = e.subs(given) if given else e
        v = e.subs(sub)
        if isinstance(v, sp.MatrixBase):
            return [complex(x.evalf(20)).real for x in v]
        return complex(sp.N(v, 20)).real

    out = {}
    if record_id in INVARIANCE_RECORDS:
        from photolib.transforms import cross_ratio

        for name, expr in rec.versions.items():
            out[name] = num(_projected(expr) - expr)
            out[f"λ as printed ({name})"] = num(expr)
        out["λ course"] = cross_ratio(*(float(values[t.name]) for t in plane.t_line))
        out["derived"] = num(rec.derived())
        return out
    for name, expr in rec.versions.items():
        out[name] = num(expr)
    for name, target in _targets(rec).items():
        out[f"target ({name})"] = num(target)
    out["derived"] = num(rec.derived())
    return out


def _fmt(v) -> str:
    if isinstance(v, list):
        return "[" + ", ".join(_fmt(e) for e in v) + "]"
    return f"{v:.12g}"


def _explanation(rec) -> str:
    if rec.id in INVARIANCE_RECORDS:
        return (f"The derivation of the {INVARIANCE_RECORDS[rec.id]} is an invariance: a "
                "definition λ is valid iff λ(projected points) − λ(points) ≡ 0, so "
                "<b>derived</b> is that residual, 0. <b>old</b>, <b>corrected</b>: each print's "
                f"residual under the fixed projectivity {_map_text()} (drawn once at random); "
                "<b>λ as printed</b>: each print's value at the points; <b>λ course</b>: "
                "photolib.transforms.cross_ratio (the corrected print). Both prints are "
                "invariant (residual 0) but give different numbers.")
    if _targets(rec):
        names = ", ".join(_targets(rec))
        return (f"<b>{names}</b> is compared with its own target, shown as <b>target (…)</b>, "
                "not with <b>derived</b>.")
    return ""


# ------------------------------------------------------------- the committed verdict table
#: the verdict filter's choices: each kind, and the versions where we differ from the source
VERDICT_FILTERS = {"all": "all verdicts", "right": "right", "wrong": "wrong",
                   "right-under-condition": "right under a condition",
                   "not-checkable": "not checkable",
                   "differs": "differs from the source's claim"}
_COLUMNS = ("record", "item", "version", "source claims", "our verdict", "why")


def _kind(verdict: str) -> str:
    return verdict.split(":")[0]


def verdict_rows(query: str = "", source: str = "all", chapter: str = "all",
                 verdict: str = "all", table: dict | None = None) -> list[dict]:
    """The printed versions of the committed verdict table that pass the filters.

    Parameters
    ----------
    query : str
        Text to find (case and accents ignored) in the id, item, version, verdict, reason,
        counterexample or note; empty: every version.
    source : str
        ``"all"`` or a source key of :data:`photolib.errata.table.ORIGINS` (``"luhmann"``, …).
    chapter : str
        ``"all"`` or a chapter of Luhmann's book (``"4"``); other sources have none.
    verdict : str
        ``"all"``, a verdict kind, or ``"differs"``: where our verdict's kind is not the
        source's claim (:meth:`photolib.errata.Record.differs_from_source`).
    table : dict, optional
        A table as :func:`photolib.errata.table.load_table` returns it (the committed one).

    Returns
    -------
    list of dict
        One row per (record, version), in the catalogue's order: ``id``, ``origin``,
        ``chapter``, ``item``, ``version``, ``claim``, ``verdict`` (the full text), ``why``,
        ``counterexample``, ``note``.

    Raises
    ------
    ValueError
        For an unknown source, chapter or verdict filter, naming it and the choices.

    >>> [r["version"] for r in verdict_rows("", "luhmann", "4", "wrong") if r["id"] == "luhmann:4.18b"]
    ['old']
    """
    from photolib.errata.table import ORIGINS, load_table
    from photolib.glossary import _fold

    table = load_table() if table is None else table
    if source != "all" and source not in ORIGINS:
        raise ValueError(f"unknown source {source!r}; expected 'all' or one of {list(ORIGINS)}")
    chapters = sorted({e["chapter"] for e in table["records"] if e["chapter"]}, key=int)
    if chapter != "all" and chapter not in chapters:
        raise ValueError(f"unknown chapter {chapter!r}; expected 'all' or one of {chapters}")
    if verdict not in VERDICT_FILTERS:
        raise ValueError(f"unknown verdict filter {verdict!r}; expected one of "
                         f"{list(VERDICT_FILTERS)}")
    q = _fold(query.strip())
    rows = []
    for e in table["records"]:
        if (source != "all" and e["origin"] != source) or (chapter != "all"
                                                           and e["chapter"] != chapter):
            continue
        for name, v in e["versions"].items():
            kind = _kind(v["verdict"])
            if verdict == "differs" and kind == v["claim"]:
                continue
            if verdict not in ("all", "differs") and kind != verdict:
                continue
            row = {"id": e["id"], "origin": e["origin"], "chapter": e["chapter"],
                   "item": e["item"], "version": name, "claim": v["claim"],
                   "verdict": v["verdict"], "why": v["why"],
                   "counterexample": v["counterexample"], "note": e["note"]}
            if q and not any(q in _fold(row[k]) for k in ("id", "item", "version", "verdict",
                                                          "why", "counterexample", "note")):
                continue
            rows.append(row)
    return rows


def _verdict_cell(verdict: str) -> str:
    import html

    kind, sep, rest = verdict.partition(": ")
    colour = {"right": "#1a7f37", "wrong": "#cf222e", "right-under-condition": "#9a6700",
              "not-checkable": "#57606a"}.get(kind, "inherit")
    return (f"<b style='color:{colour}'>{html.escape(kind)}</b>"
            + (f": {html.escape(rest)}" if sep else ""))


def verdict_table_html(query: str = "", source: str = "all", chapter: str = "all",
                       verdict: str = "all", table: dict | None = None) -> str:
    """The explorer's text: how many versions match, and their table with the full verdicts.

    Nothing is cut: each verdict, reason and counterexample is shown whole (wrapped).

    >>> verdict_table_html("no such words anywhere").startswith("<p>0 of ")
    True
    """
    import html

    from photolib.errata.table import load_table

    table = load_table() if table is None else table
    rows = verdict_rows(query, source, chapter, verdict, table)
    total = sum(len(e["versions"]) for e in table["records"])
    n_rec = len({r["id"] for r in rows})
    head = (f"<p>{len(rows)} of {total} printed versions ({n_rec} of {len(table['records'])} "
            "records). Evidence of one record: <code>python -m photolib errata --id ID</code>"
            "</p>")
    if not rows:
        return head
    th = "".join(f"<th style='text-align:left'>{c}</th>" for c in _COLUMNS)
    body = []
    for r in rows:
        why = html.escape(r["why"]) + (
            f"<br><i>counterexample</i>: {html.escape(r['counterexample'])}"
            if r["counterexample"] and _kind(r["verdict"]) == "wrong" else "")
        cells = (f"<code>{html.escape(r['id'])}</code>", html.escape(r["item"]),
                 html.escape(r["version"]), html.escape(r["claim"]),
                 _verdict_cell(r["verdict"]), why)
        body.append("<tr>" + "".join(f"<td style='text-align:left;vertical-align:top'>{c}</td>"
                                     for c in cells) + "</tr>")
    return (f"{head}<table style='font-size:90%;white-space:normal'><tr>{th}</tr>"
            f"{''.join(body)}</table>")
