"""Glossary notebook helpers: tables of terms and a search widget.

:func:`table_html` turns terms into an HTML table with a link to the chapter of each term;
:class:`GlossaryExplorer` is a text box plus language and chapter filters whose callback
:func:`search_html` is a plain function (tested in ``tests/test_glossary.py``).
"""

from __future__ import annotations

import html as _html

import ipywidgets as widgets

from photolib.glossary import CHAPTERS, LANGUAGES, SOURCES, load_glossary, search
from photolib.nb._table import HtmlTableExplorer
from photolib.nb.live import Panel

__all__ = ["GlossaryExplorer", "counts", "search_html", "table_html"]

_SHORT = {"de-summary": "DE", "luhmann-errata": "L", "pl-notes": "PL", "hu-wiki": "HU"}


def table_html(terms, limit: int | None = None) -> str:
    """An HTML table: English, German, Polish, Hungarian, chapter (linked), sources.

    >>> "<a href='12-products.ipynb'>" in table_html(load_glossary()[-20:])
    True
    """
    shown = list(terms) if limit is None else list(terms)[:limit]
    head = "".join(f"<th style='text-align:left'>{name}</th>"
                   for name in (*LANGUAGES.values(), "chapter", "sources"))
    rows = []
    for t in shown:
        cells = [_html.escape(getattr(t, lang)) for lang in LANGUAGES]
        cells.append(f"<a href='{t.link}'>{t.chapter}</a>")
        cells.append(" ".join(_SHORT[s] for s in t.sources))
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    more = ("" if limit is None or len(terms) <= limit
            else f"<p>… and {len(terms) - limit} more: narrow the search.</p>")
    return (f"<table style='font-size:90%'><tr>{head}</tr>{''.join(rows)}</table>{more}")


def search_html(query: str = "", language: str = "all", chapter: str = "all",
                limit: int = 40) -> str:
    """The widget's text: the number of matches and their table.

    >>> "orthophoto" in search_html("ortofot", "hu")
    True
    >>> search_html("no such term").startswith("<p>0 of")
    True
    """
    terms = load_glossary()
    langs = None if language == "all" else [language]
    found = search(terms, query, langs, None if chapter == "all" else chapter)
    return f"<p>{len(found)} of {len(terms)} terms</p>" + (table_html(found, limit) if found else "")


def counts() -> dict:
    """Number of terms per chapter and per source.

    >>> counts()["chapters"]["12-products"] > 10
    True
    """
    terms = load_glossary()
    chapters = {c: sum(t.chapter == c for t in terms) for c in CHAPTERS}
    sources = {s: sum(s in t.sources for t in terms) for s in SOURCES}
    return {"chapters": {c: n for c, n in chapters.items() if n}, "sources": sources}


class GlossaryExplorer(HtmlTableExplorer):
    """Search box, language and chapter filters → matching terms with links to the chapters."""

    title = "glossary search"

    def __init__(self, query: str = "", language: str = "all", chapter: str = "all"):
        present = [c for c in CHAPTERS if any(t.chapter == c for t in load_glossary())]
        self.controls = {
            "query": widgets.Text(value=query, placeholder="a term in any language",
                                  description="search", continuous_update=True),
            "language": widgets.Dropdown(options=[("all languages", "all")]
                                         + [(v, k) for k, v in LANGUAGES.items()],
                                         value=language, description="language"),
            "chapter": widgets.Dropdown(options=[("all chapters", "all")] + [(c, c) for c in present],
                                        value=chapter, description="chapter"),
        }
        self.html = widgets.HTML()
        self.widget = Panel([widgets.HBox(list(self.controls.values())), self.html],
                            title=self.title)
        self._connect()

    def render(self, **values) -> str:
        return search_html(**values)
