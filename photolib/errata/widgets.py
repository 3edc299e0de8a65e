"""Widgets of the errata notebook: evaluate printed versions and the derivation at chosen values.

The callback :func:`evaluate_versions` is a plain function (unit-tested); :func:`build_widget`
wires it to ipywidgets sliders (``continuous_update=False``, since a SymPy substitution takes
milliseconds, not microseconds).

Examples
--------
>>> vals = evaluate_versions("luhmann:2.86", {"A": 2, "D": 3, "E": 4, "F": 1})
>>> sorted(vals)
['corrected', 'derived', 'old']
>>> round(vals["corrected"], 6) == round(vals["derived"], 6)
True
"""

from __future__ import annotations

import sympy as sp

from photolib.errata import get


def _free_symbols(rec) -> list:
    syms = set()
    for e in list(rec.versions.values()) + [rec.derived()]:
        if isinstance(e, (sp.Basic, sp.MatrixBase)):
            e = e.subs(rec.given_substitution()) if rec.given_substitution() else e
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
        printed (no condition applied), and the derivation.

    Raises
    ------
    ValueError
        If a symbol has no value, naming the missing ones.
    """
    rec = get(record_id)
    syms = _free_symbols(rec)
    missing = [s.name for s in syms if s.name not in values]
    if missing:
        raise ValueError(f"{record_id}: no value for {missing}")
    sub = {s: sp.Float(values[s.name], 30) for s in syms}

    def num(e):
        e = e.subs(rec.given_substitution()) if rec.given_substitution() else e
        v = e.subs(sub) if not isinstance(e, sp.MatrixBase) else e.subs(sub)
        if isinstance(v, sp.MatrixBase):
            return [complex(x.evalf(20)).real for x in v]
        return complex(sp.N(v, 20)).real

    out = {}
    for name, expr in rec.versions.items():
        out[name] = num(expr)
    out["derived"] = num(rec.derived())
    return out


def build_widget(record_id: str, lo: float = -2.0, hi: float = 2.0):
    """An ipywidgets box: one slider per symbol and an output showing every version's value."""
    import ipywidgets as w

    rec = get(record_id)
    syms = _free_symbols(rec)
    sliders = {s.name: w.FloatSlider(value=round(0.3 + 0.1 * i, 2), min=lo, max=hi, step=0.01,
                                     description=s.name, continuous_update=False)
               for i, s in enumerate(syms)}
    out = w.HTML()

    def refresh(_=None):
        try:
            vals = evaluate_versions(record_id, {k: s.value for k, s in sliders.items()})
            out.value = "<br>".join(f"<b>{k}</b>: {v}" for k, v in sorted(vals.items()))
        except (ZeroDivisionError, TypeError, ValueError) as exc:
            out.value = f"cannot evaluate here: {exc}"

    for s in sliders.values():
        s.observe(refresh, names="value")
    refresh()
    return w.VBox([w.HTML(f"<b>{rec.id}</b>: {rec.item}"), *sliders.values(), out])
