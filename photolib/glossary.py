"""Glossary / Glossar / Słownik / Szójegyzék: the course's terms in four languages.

The terms of the four sources of the course — the German lecture summary, Luhmann's errata
list (German), the Polish exercise notes and the Hungarian Wikipedia article — in English,
German, Polish and Hungarian, each with the chapter that teaches it. Where a source uses a
term, the glossary gives the source's own wording (column ``sources`` names the sources
whose text contains it); the other languages give the usual technical term. Alternatives
are separated by `` / ``.

The data is ``photolib/data/glossary.csv`` (package data), columns
``en, de, pl, hu, chapter, sources``.

Examples
--------
>>> terms = load_glossary()
>>> t = next(t for t in terms if t.en == "orthophoto")
>>> t.de, t.pl, t.hu, t.chapter
('Orthophoto / Orthobild', 'ortofotografia', 'ortofotó', '12-products')
>>> [t.en for t in search(terms, "kameraállandó")]
['camera constant']
"""

from __future__ import annotations

import csv
import functools
import io
import unicodedata
from importlib import resources
from typing import NamedTuple

__all__ = ["CHAPTERS", "LANGUAGES", "SOURCES", "Term", "load_glossary", "search"]

#: language code → name
LANGUAGES = {"en": "English", "de": "Deutsch", "pl": "Polski", "hu": "Magyar"}
#: source key → the source document of the course
SOURCES = {"de-summary": "German lecture summary 'Grundlagen der Photogrammetrie'",
           "luhmann-errata": "errata list of Luhmann, Nahbereichsphotogrammetrie, 3rd ed.",
           "pl-notes": "Polish notes 'Teoria z ćwiczeń z fotogrametrii'",
           "hu-wiki": "Hungarian Wikipedia article 'Fotogrammetria'"}
#: the chapters of the course outline (notebook stems)
CHAPTERS = ("00-start", "01-introduction", "02-optics", "03-digital-images", "04-rotations",
            "05-interior-orientation", "06-collinearity", "07-plane-transformations",
            "08-resection-dlt", "09-stereo", "10-bundle-adjustment", "11-image-measurement",
            "12-products", "13-errata", "14-project", "glossary")


class Term(NamedTuple):
    """One glossary entry; ``sources`` is a tuple of keys of :data:`SOURCES`."""

    en: str
    de: str
    pl: str
    hu: str
    chapter: str
    sources: tuple

    @property
    def link(self) -> str:
        """The chapter notebook, relative to ``notebooks/``."""
        return f"{self.chapter}.ipynb"


@functools.lru_cache(maxsize=1)
def _read() -> tuple:
    text = resources.files("photolib").joinpath("data/glossary.csv").read_text(encoding="utf-8")
    rows = []
    for i, row in enumerate(csv.DictReader(io.StringIO(text)), start=2):
        missing = [k for k in ("en", "de", "pl", "hu", "chapter") if not (row.get(k) or "").strip()]
        if missing:
            raise ValueError(f"glossary.csv line {i}: empty {', '.join(missing)}")
        if row["chapter"] not in CHAPTERS:
            raise ValueError(f"glossary.csv line {i}: unknown chapter {row['chapter']!r}")
        sources = tuple((row.get("sources") or "").split())
        unknown = [s for s in sources if s not in SOURCES]
        if unknown:
            raise ValueError(f"glossary.csv line {i}: unknown source {unknown[0]!r}")
        rows.append(Term(row["en"].strip(), row["de"].strip(), row["pl"].strip(),
                         row["hu"].strip(), row["chapter"], sources))
    return tuple(rows)


def load_glossary() -> list[Term]:
    """All terms, in the order of the course (by chapter, then as listed).

    The terms are read once from the package data ``photolib/data/glossary.csv`` (columns
    ``en, de, pl, hu, chapter, sources``) and cached.

    Returns
    -------
    list of Term
        One :class:`Term` per row: ``en``, ``de``, ``pl``, ``hu`` (the term in English,
        German, Polish, Hungarian), ``chapter`` (one of :data:`CHAPTERS`) and ``sources``
        (keys of :data:`SOURCES`), sorted by the chapter's place in :data:`CHAPTERS`.

    Raises
    ------
    ValueError
        For a row of ``glossary.csv`` with an empty language, an unknown chapter or an
        unknown source; the message names the line.

    Examples
    --------
    >>> terms = load_glossary()
    >>> terms[0].en, terms[0].chapter
    ('photogrammetry', '01-introduction')
    >>> t = next(t for t in terms if t.en == "camera constant")
    >>> t.de, t.pl, t.hu
    ('Kamerakonstante', 'odległość obrazowa kamery', 'kameraállandó')
    """
    return sorted(_read(), key=lambda t: CHAPTERS.index(t.chapter))


def _fold(text: str) -> str:
    """Lower case without accents: 'Äußere' → 'aussere', 'wiązek' → 'wiazek', 'ł' → 'l'."""
    text = text.casefold().replace("ß", "ss").replace("ł", "l")
    return "".join(ch for ch in unicodedata.normalize("NFKD", text)
                   if not unicodedata.combining(ch))


def search(terms, query: str = "", languages=None, chapter: str | None = None) -> list[Term]:
    """Terms whose text in one of ``languages`` contains ``query`` (case and accents ignored).

    Parameters
    ----------
    terms : sequence of Term
    query : str
        Empty: every term (of the chapter).
    languages : iterable of {"en", "de", "pl", "hu"}, optional
        Where to look; all four by default.
    chapter : str, optional
        Only terms taught in this chapter.

    Examples
    --------
    >>> terms = load_glossary()
    >>> [t.en for t in search(terms, "aussere", ["de"])]
    ['exterior orientation']
    >>> len(search(terms, "", chapter="12-products")) > 10
    True
    """
    langs = tuple(LANGUAGES) if languages is None else tuple(languages)
    bad = [lang for lang in langs if lang not in LANGUAGES]
    if bad:
        raise ValueError(f"unknown language {bad[0]!r}; expected one of {list(LANGUAGES)}")
    if chapter is not None and chapter not in CHAPTERS:
        raise ValueError(f"unknown chapter {chapter!r}")
    q = _fold(query.strip())
    out = []
    for t in terms:
        if chapter is not None and t.chapter != chapter:
            continue
        if not q or any(q in _fold(getattr(t, lang)) for lang in langs):
            out.append(t)
    return out
