"""Command line: ``python -m photolib errata`` and ``python -m photolib check-formula``.

``errata``            verdict table of the whole catalogue
``errata --id ID``    one record with its derivation steps and the comparison
``errata --json``     JSON list of {id, source, item, verdicts, note}
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
    """``python -m photolib errata [--id ID] [--json]``."""
    p = argparse.ArgumentParser(prog="python -m photolib errata",
                                description="Verdicts of the errata catalogue.")
    p.add_argument("--id", help="print one record with derivation and comparison")
    p.add_argument("--json", action="store_true", help="JSON list of all records")
    args = p.parse_args(argv)
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


def check_formula_main(argv) -> int:
    """``python -m photolib check-formula "EXPR" --against ID``; exit 0 iff equal."""
    from photolib.symcheck import UnsafeExpressionError, parse_expression

    p = argparse.ArgumentParser(prog="python -m photolib check-formula",
                                description="Compare a typed formula with a derivation.")
    p.add_argument("expr", help="formula, e.g. \"z_p/N*(k_y/N*(k_y*sin(kappa) - "
                                "k_x*cos(kappa)) + N*sin(kappa))\"")
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
    try:
        expr = parse_expression(args.expr, rec.symbol_table())
    except UnsafeExpressionError as exc:
        print(f"rejected: {exc}", file=sys.stderr)
        return 2
    conds = [s.condition for s in rec.specs.values() if s.condition is not None]
    cond = conds[0]() if conds and callable(conds[0]) else (conds[0] if conds else None)
    v = rec.compare(expr, cond)
    print(f"{rec.id}: {v.kind} ({v.method})")
    if v.condition is not None:
        print(f"  condition: {v.condition}")
    if v.counterexample:
        pt = ", ".join(f"{k} = {_fmt(x)}" for k, x in sorted(v.counterexample.items(),
                                                             key=lambda kv: str(kv[0])))
        print(f"  counterexample: {pt}")
        print(f"  values (yours, derived): {_fmt(v.values[0])} | {_fmt(v.values[1])}")
    return 0 if v.kind in ("equal", "equal-under-condition") else 1
