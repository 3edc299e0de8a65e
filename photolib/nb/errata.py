"""The errata chapter's widgets: sliders over a record's symbols (:func:`build_widget`) and the
interactive verdict table (:class:`VerdictExplorer`). Their callbacks are the plain functions of
:mod:`photolib.errata.evaluate` (unit-tested there); this module only wires them to ipywidgets.

>>> build_widget("de-summary:reflection").children[1].value.startswith("cannot be evaluated")
True
"""

from __future__ import annotations

from photolib.errata import get
from photolib.errata.evaluate import (
    VERDICT_FILTERS,
    _explanation,
    _fmt,
    _free_symbols,
    evaluate_versions,
    not_evaluable_reason,
    verdict_table_html,
)
from photolib.nb._table import HtmlTableExplorer

__all__ = ["VerdictExplorer", "build_widget"]


def build_widget(record_id: str, lo: float = -2.0, hi: float = 2.0):
    """An ipywidgets box: one slider per symbol and an output showing every version's value.

    For a record that cannot be evaluated at numbers (see :func:`not_evaluable_reason`) the
    box holds the title and a message saying why, and no sliders.
    """
    import ipywidgets as w

    rec = get(record_id)
    title = w.HTML(f"<b>{rec.id}</b>: {rec.item}")
    reason = not_evaluable_reason(rec)
    if reason is not None:
        return w.VBox([title, w.HTML(
            f"cannot be evaluated at numbers: {reason}. The verdict and its evidence: "
            f"<code>python -m photolib errata --id {rec.id}</code>")])
    syms = _free_symbols(rec)
    sliders = {s.name: w.FloatSlider(value=round(0.3 + 0.1 * i, 2), min=lo, max=hi, step=0.01,
                                     description=s.name, continuous_update=False)
               for i, s in enumerate(syms)}
    out = w.HTML()

    def refresh(_=None):
        try:
            vals = evaluate_versions(record_id, {k: s.value for k, s in sliders.items()})
            out.value = "<br>".join(f"<b>{k}</b>: {_fmt(v)}" for k, v in sorted(vals.items()))
        except (ArithmeticError, TypeError, ValueError) as exc:
            out.value = f"cannot evaluate here: {exc}"

    for s in sliders.values():
        s.observe(refresh, names="value")
    refresh()
    note = _explanation(rec)
    return w.VBox([title, *([w.HTML(note)] if note else []), *sliders.values(), out])


class VerdictExplorer(HtmlTableExplorer):
    """Search box, source, chapter and verdict filters → the committed verdicts, in full.

    The errata chapter's interactive table, built like the glossary's
    (:class:`photolib.nb.glossary.GlossaryExplorer`): the controls call the plain function
    :func:`verdict_table_html` on every change. It reads the committed table
    (:mod:`photolib.errata.table`), so it opens at once; nothing is recomputed.
    """

    title = "errata verdicts"

    def __init__(self, query: str = "", source: str = "all", chapter: str = "all",
                 verdict: str = "all"):
        import ipywidgets as w

        from photolib.errata.table import ORIGINS, load_table
        from photolib.nb.live import Panel

        table = load_table()
        chapters = sorted({e["chapter"] for e in table["records"] if e["chapter"]}, key=int)
        wide = w.Layout(width="max-content")
        self.controls = {
            "query": w.Text(value=query, placeholder="id, item, verdict or reason",
                            description="search", continuous_update=True),
            "source": w.Dropdown(options=[("all sources", "all")]
                                 + [(v, k) for k, v in ORIGINS.items()],
                                 value=source, description="source", layout=wide),
            "chapter": w.Dropdown(options=[("all chapters", "all")]
                                  + [(f"Luhmann ch. {c}", c) for c in chapters],
                                  value=chapter, description="chapter", layout=wide),
            "verdict": w.Dropdown(options=[(v, k) for k, v in VERDICT_FILTERS.items()],
                                  value=verdict, description="verdict", layout=wide),
        }
        self.html = w.HTML()
        controls = w.HBox(list(self.controls.values()),
                          layout=w.Layout(flex_flow="row wrap"))
        self.widget = Panel([controls, self.html], title=self.title)
        self._connect()

    def render(self, **values) -> str:
        return verdict_table_html(**values)
