"""Command line: ``python -m photolib errata`` and ``python -m photolib check-formula``.

``errata``            verdict table of the whole catalogue
``errata --id ID``    one record with its derivation steps and the comparison
``errata --json``     JSON list of {id, source, item, verdicts, note}
``errata --write-table [PATH]``  recompute everything into the committed verdict table
                      (``photolib/data/errata-verdicts.json``, see :mod:`photolib.errata.table`)
``check-formula "EXPR" --against ID``  parse EXPR safely and compare it with the derivation
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from photolib.errata import catalogue, get


# A float is never printed as its full repr: its last digits differ between CPUs and BLAS kernels
# (1.0 here is 1.0000000000000002 there), and the notebooks' committed outputs must not.
SIGNIFICANT = 10


def _fmt(v) -> str:
    """Text of one value: floats to ``SIGNIFICANT`` significant digits, sequences element-wise."""
    try:
        import mpmath
        if isinstance(v, (mpmath.mpf, mpmath.mpc)):
            return mpmath.nstr(v, SIGNIFICANT)
    except ImportError:  # pragma: no cover
        pass
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(e) for e in v) + "]"
    if isinstance(v, (bool, int)):
        return str(v)
    try:
        import numbers
        if isinstance(v, numbers.Real):
            return f"{float(v):.{SIGNIFICANT}g}"
    except (TypeError, ValueError):  # pragma: no cover - a SymPy number that is not real
        pass
    return str(v)


def _fmt_row(row) -> str:
    """One comparison row ``(name, printed, recomputed, tolerance, agrees)``.

    The recomputed value is given to one decimal below the tolerance's leading digit (the digits
    the comparison can justify; at most ``SIGNIFICANT - 1`` decimals, so that an exact check with
    a tolerance of 1e-12 does not print rounding noise), the tolerance to two significant digits;
    other rows by ``_fmt``.
    """
    if len(row) == 5 and all(isinstance(c, float) for c in row[1:4]) and row[3] > 0:
        name, printed, recomputed, tol, agrees = row
        decimals = min(max(0, 1 - math.floor(math.log10(tol))), SIGNIFICANT - 1)
        text = f"{recomputed:.{decimals}f}"
        if len(text.lstrip("-").replace(".", "").lstrip("0")) > SIGNIFICANT:
            text = _fmt(recomputed)
        if float(text) == 0:        # -1e-17 on one CPU, +1e-17 on the next: both are 0
            text = text.lstrip("-")
        return " | ".join([str(name), _fmt(printed), text, f"{tol:.2g}", str(agrees)])
    return " | ".join(_fmt(c) for c in row)


def record_json(rec) -> dict:
    """The JSON object of one record."""
    return {"id": rec.id, "source": rec.source, "item": rec.item, "verdicts": rec.verdicts,
            "note": rec.note}


def describe(rec) -> str:
    """Multi-line text of one record: versions, derivation, steps and evidence."""
    lines = [f"{rec.id}: {rec.item}", f"  source: {rec.source}", f"  kind: {rec.kind}"]
    for name, expr in rec.versions.items():
        if rec.specs[name].reading:     # a sentence in the source: say it is our reading
            lines.append(f"  reading ({name}, the catalogue's reading of a sentence; no "
                         f"formula printed): {expr}")
        else:
            lines.append(f"  printed ({name}): {expr}")
    if rec.derivation is not None:
        lines.append(f"  derivation: {rec.derived()}")
    for i, step in enumerate(rec.steps, 1):
        lines.append(f"    step {i}: {step}")
    for name in rec.specs:
        ev = rec.evaluate(name)
        lines.append(f"  verdict ({name}): {ev.verdict}")
        if ev.detail:
            lines.append(f"    why: {ev.detail}")
        if ev.counterexample:
            pt = ", ".join(f"{k} = {_fmt(v)}" for k, v in sorted(ev.counterexample.items(),
                                                                 key=lambda kv: str(kv[0])))
            lines.append(f"    counterexample: {pt}")
        if ev.values:
            lines.append(f"    values (printed, derived): {_fmt(ev.values[0])} | "
                         f"{_fmt(ev.values[1])}")
        for row in ev.table:
            lines.append("    " + _fmt_row(row))
    if rec.note:
        lines.append(f"  note: {rec.note}")
    return "\n".join(lines)


def _progress(items, desc: str):
    """``items`` with a progress bar on stderr when that is a terminal and tqdm is installed."""
    try:
        from tqdm import tqdm
    except ImportError:  # tqdm comes with the course extras, not with the bare library
        return items
    return tqdm(items, desc=desc, unit="record", file=sys.stderr, disable=None, leave=False)


def errata_main(argv) -> int:
    """``python -m photolib errata [--id ID] [--json] [--write-table [PATH]]``."""
    p = argparse.ArgumentParser(prog="python -m photolib errata",
                                description="Verdicts of the errata catalogue.")
    p.add_argument("--id", help="print one record with derivation and comparison")
    p.add_argument("--json", action="store_true", help="JSON list of all records")
    p.add_argument("--write-table", nargs="?", const="", metavar="PATH",
                   help="recompute every verdict and write the committed verdict table read by "
                        "the errata chapter (default: photolib/data/errata-verdicts.json)")
    args = p.parse_args(argv)
    if args.write_table is not None:
        from photolib.errata import table

        path = table.write_table(args.write_table or table.TABLE_PATH,
                                 progress=lambda recs: _progress(recs, "deriving and judging"))
        print(f"wrote {path} ({len(catalogue())} records)")
        return 0
    if args.id:
        try:
            rec = get(args.id)
        except KeyError as exc:
            print(exc.args[0], file=sys.stderr)
            return 2
        print(json.dumps(record_json(rec), ensure_ascii=False, indent=1) if args.json
              else describe(rec))
        return 0
    recs = catalogue()
    if args.json:  # the verdicts take some 20 s and print at the end: a bar on a terminal
        rows = [record_json(r) for r in _progress(recs, "deriving and judging")]
        print(json.dumps(rows, ensure_ascii=False, indent=1))
        return 0
    width = max(len(r.id) for r in recs)
    for r in recs:
        for i, (name, verdict) in enumerate(r.verdicts.items()):
            head = r.id if i == 0 else ""
            print(f"{head:<{width}}  {name:<9}  {verdict}")
    return 0


#: significant digits of a counterexample's coordinates in ``check-formula``: enough to find the
#: point again, few enough to read (the exact dyadic rationals have some 20 digits)
POINT_DIGITS = 4


def _decimal(v, digits: int) -> str:
    """``v`` (SymPy rational, mpmath or float) as a decimal with ``digits`` significant digits."""
    try:
        import mpmath
        if isinstance(v, (mpmath.mpf, mpmath.mpc)):
            return mpmath.nstr(v, digits, min_fixed=-4, max_fixed=6)
    except ImportError:  # pragma: no cover
        pass
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_decimal(e, digits) for e in v) + "]"
    try:
        return f"{float(v):.{digits}g}"
    except (TypeError, ValueError):
        return str(v)


def format_point(point: dict, digits: int = POINT_DIGITS) -> str:
    """``name = value, …`` of a sample point, sorted by name, values to ``digits`` digits.

    >>> import sympy as sp
    >>> format_point({sp.Symbol("b"): sp.Rational(1083459, 524288), sp.Symbol("a"): 0})
    'a = 0, b = 2.067'
    """
    return ", ".join(f"{k} = {_decimal(v, digits)}"
                     for k, v in sorted(point.items(), key=lambda kv: str(kv[0])))


def format_values(a, b) -> tuple:
    """``(a, b)`` as decimals with the fewest digits (4 to ``SIGNIFICANT``) that tell them apart.

    >>> format_values(1.0, 1.00002)
    ('1', '1.00002')
    """
    for digits in range(POINT_DIGITS, SIGNIFICANT + 1):
        ta, tb = _decimal(a, digits), _decimal(b, digits)
        if ta != tb:
            return ta, tb
    return ta, tb


def _condition_text(cond) -> str:
    """A substitution ``{z_p: -c}`` as ``z_p = -c``; other conditions as text."""
    if isinstance(cond, dict):
        return ", ".join(f"{k} = {v}" for k, v in cond.items())
    return str(cond)


def _expected(rec) -> str:
    """The record's symbol names, each with its other accepted spellings in parentheses."""
    return ", ".join(name + (f" ({', '.join(alts)})" if alts else "")
                     for name, alts in rec.expected_names().items())


def check_formula_main(argv) -> int:
    """``python -m photolib check-formula "EXPR" --against ID``; exit 0 iff equal.

    EXPR may use the catalogue's names (``k_x``, ``z_p``, ``kappa``) or the textbook's
    (``kx``, ``zp`` or ``z'``, ``κ``): see :meth:`photolib.errata.Record.accepted_names`. A
    name the record does not know is an error (exit 2) that lists the names it accepts, not
    a comparison: an extra symbol would make any formula "not-equal". An
    ``equal-under-condition`` result names the condition first (the record's wording and the
    substitution); counterexamples are decimals to a few significant digits.
    """
    from photolib.symcheck import UnsafeExpressionError, parse_expression

    p = argparse.ArgumentParser(prog="python -m photolib check-formula",
                                description="Compare a typed formula with a derivation. "
                                            "Names as in the catalogue or as in the book "
                                            "(kx for k_x, z' or zp for z_p, κ or kappa).")
    p.add_argument("expr", help="formula, e.g. \"zp/N*(ky/N*(ky*sin(κ) - "
                                "kx*cos(κ)) + N*sin(κ))\"")
    p.add_argument("--against", required=True, help="record id, e.g. luhmann:4.18b")
    args = p.parse_args(argv)
    try:
        rec = get(args.against)
    except KeyError as exc:
        print(exc.args[0], file=sys.stderr)
        return 2
    if rec.derivation is None:
        print(f"{rec.id} has no derivation to compare with", file=sys.stderr)
        return 2
    accepted = rec.accepted_names()
    try:
        expr = parse_expression(args.expr, accepted)
    except UnsafeExpressionError as exc:
        print(f"rejected: {exc}", file=sys.stderr)
        return 2
    known = set(accepted.values())
    unknown = sorted((s for s in getattr(expr, "free_symbols", ()) if s not in known),
                     key=lambda s: s.name)
    if unknown:
        print(f"{rec.id}: unknown symbol{'s' if len(unknown) > 1 else ''} "
              f"{', '.join(s.name for s in unknown)}; the record knows: {_expected(rec)}",
              file=sys.stderr)
        return 2
    # the condition of the first version that has one; its wording from a version with the same
    specs = [s for s in rec.specs.values() if s.condition is not None]
    cond = _resolve(specs[0].condition) if specs else None
    specs = sorted((s for s in specs if _resolve(s.condition) == cond),
                   key=lambda s: not s.condition_text)
    v = rec.compare(expr, cond)
    if v.kind == "equal-under-condition":
        print(f"{rec.id}: equal-under-condition: {_condition_text(v.condition)}")
        if isinstance(v.condition, dict) and specs and specs[0].condition_text:
            print(f"  the record's condition: {specs[0].condition_text}")
        print(f"  how: {v.method}")
        if v.counterexample:
            yours, derived = format_values(*v.values)
            print(f"  (the condition is needed: without it, at {format_point(v.counterexample)}, "
                  f"yours is {yours} and the derivation {derived})")
        return 0
    print(f"{rec.id}: {v.kind} ({v.method})")
    if v.kind == "undecided" and v.detail:
        print(f"  why: {v.detail}")
    if v.counterexample:
        yours, derived = format_values(*v.values)
        print(f"  counterexample: {format_point(v.counterexample)}")
        print(f"  values (yours, derived): {yours} | {derived}")
    return 0 if v.kind == "equal" else 1


def _resolve(v):
    return v() if callable(v) else v
