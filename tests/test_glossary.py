"""The glossary: complete rows, known chapters, search, the notebook widget.

The chapter list is checked against the notebooks that exist and against the course
outline held in :data:`photolib.glossary.CHAPTERS` (COURSE.md's table).
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from photolib import glossary as g
from photolib.nb import glossary as ng

ROOT = Path(__file__).resolve().parents[1]


def test_every_term_has_four_languages_and_a_known_chapter():
    terms = g.load_glossary()
    assert len(terms) >= 100
    for t in terms:
        for lang in g.LANGUAGES:
            value = getattr(t, lang)
            assert value and value == value.strip() and "  " not in value, (t.en, lang)
        assert t.chapter in g.CHAPTERS, t
        assert set(t.sources) <= set(g.SOURCES), t


def test_the_csv_has_exactly_the_documented_columns_and_no_duplicates():
    with open(ROOT / "photolib" / "data" / "glossary.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["en", "de", "pl", "hu", "chapter", "sources"]
    english = [r["en"].casefold() for r in rows]
    assert len(english) == len(set(english))
    assert len(rows) == len(g.load_glossary())


def test_chapters_are_the_course_outline_and_existing_notebooks_are_in_it():
    assert g.CHAPTERS[0] == "00-start" and g.CHAPTERS[-1] == "glossary"
    numbered = [c for c in g.CHAPTERS if c[:2].isdigit()]
    assert [int(c[:2]) for c in numbered] == list(range(14))
    for path in (ROOT / "notebooks").glob("*.ipynb"):
        assert path.stem in g.CHAPTERS, path.name
    # every chapter of the course teaches at least one term, except the start page
    taught = {t.chapter for t in g.load_glossary()}
    assert set(g.CHAPTERS) - taught == {"00-start", "glossary"}


def test_every_source_contributes_terms():
    terms = g.load_glossary()
    for source in g.SOURCES:
        assert sum(source in t.sources for t in terms) >= 5, source


@pytest.mark.parametrize("query, langs, expected", [
    ("kameraallando", None, "camera constant"),            # accents ignored
    ("ÄUSSERE", ["de"], "exterior orientation"),           # case and ß/ss
    ("wiazek", ["pl"], "bundle adjustment"),               # ą folded
    ("transformacja rzutowa", ["pl"], "projective transformation"),
    ("true ortho", ["hu"], "true orthophoto"),
])
def test_search_finds_terms_in_each_language(query, langs, expected):
    assert expected in [t.en for t in g.search(g.load_glossary(), query, langs)]


def test_search_filters_by_language_and_chapter():
    terms = g.load_glossary()
    assert g.search(terms, "orthophoto", ["pl"]) == []      # Polish says ortofotografia
    in12 = g.search(terms, "", chapter="12-products")
    assert in12 and all(t.chapter == "12-products" for t in in12)
    assert len(g.search(terms, "")) == len(terms)
    with pytest.raises(ValueError, match="unknown language 'fr'"):
        g.search(terms, "x", ["fr"])
    with pytest.raises(ValueError, match="unknown chapter '99-x'"):
        g.search(terms, "x", chapter="99-x")


def test_loader_names_the_bad_line(monkeypatch):
    bad = "en,de,pl,hu,chapter,sources\nx,y,,w,12-products,\n"

    class _File:
        def joinpath(self, _):
            return self

        def read_text(self, encoding):
            return bad
    monkeypatch.setattr(g.resources, "files", lambda _: _File())
    g._read.cache_clear()
    try:
        with pytest.raises(ValueError, match="glossary.csv line 2: empty pl"):
            g.load_glossary()
        bad = "en,de,pl,hu,chapter,sources\nx,y,z,w,99-nothing,\n"
        g._read.cache_clear()
        with pytest.raises(ValueError, match="unknown chapter '99-nothing'"):
            g.load_glossary()
    finally:
        g._read.cache_clear()


def test_links_point_to_the_chapter_notebooks():
    t = next(t for t in g.load_glossary() if t.en == "orthophoto")
    assert t.link == "12-products.ipynb"
    html = ng.table_html([t])
    assert "<a href='12-products.ipynb'>12-products</a>" in html and "ortofotó" in html


def test_explorer_callbacks_filter():
    e = ng.GlossaryExplorer()
    assert "photolib-explorer" in e.widget._dom_classes
    assert repr(e.widget) == "[widget: glossary search]"
    e.controls["query"].value = "kalibr"
    assert "self-calibration" in e.html.value and "of 1" in e.html.value
    e.controls["language"].value = "hu"
    assert "önkalibráció" in e.html.value
    e.controls["chapter"].value = "12-products"
    assert e.html.value.startswith("<p>0 of")
    e.controls["chapter"].value = "all"     # back to all chapters: the query matches again
    assert not e.html.value.startswith("<p>0 of") and "önkalibráció" in e.html.value


def test_counts_cover_all_terms():
    c = ng.counts()
    assert sum(c["chapters"].values()) == len(g.load_glossary())
    assert set(c["sources"]) == set(g.SOURCES)
