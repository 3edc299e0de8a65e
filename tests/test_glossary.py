"""The glossary: complete rows, known chapters, search, the notebook widget.

The chapter list is checked against the notebooks that exist and against the course
outline held in :data:`photolib.glossary.CHAPTERS` (COURSE.md's table).

The ``sources`` column claims that a source uses a term. Tests never read the sources
(they are not part of the package), so :data:`SOURCE_WORDING` records, for every row and
every source it lists, the term as that source spells it — copied verbatim from the source
text, inflected forms included (Polish and Hungarian decline, German compounds). It was
checked against the four source texts when the rows were written; the tests below check
that it covers exactly the listed sources and that each quote is a form of the glossary
entry in the source's language.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import pytest

from photolib import glossary as g
from photolib.nb import glossary as ng

ROOT = Path(__file__).resolve().parents[1]

#: the language of each source's text
SOURCE_LANGUAGE = {"de-summary": "de", "luhmann-errata": "de", "pl-notes": "pl", "hu-wiki": "hu"}

#: glossary English term → {source: the term as spelled in that source}
SOURCE_WORDING = {
    "photogrammetry": {
        "de-summary": "Photogrammetrie", "hu-wiki": "Fotogrammetria",
        "luhmann-errata": "Photogrammetrie", "pl-notes": "fotogrametrii",
    },
    "analogue photogrammetry": {
        "de-summary": "Analoge Photogrammetrie", "hu-wiki": "analóg fotogrammetria",
    },
    "analytical photogrammetry": {
        "hu-wiki": "analitikus fotogrammetria", "pl-notes": "fotogrametrii analitycznej",
    },
    "digital photogrammetry": {
        "de-summary": "Digitale Photogrammetrie", "hu-wiki": "digitális fotogrammetria",
    },
    "single-image photogrammetry": {"de-summary": "Einzelbildphotogrammetrie"},
    "stereophotogrammetry": {"de-summary": "Stereophotogrammetrie"},
    "multi-image photogrammetry": {"de-summary": "Mehrbildphotogrammetrie"},
    "aerial photogrammetry": {"hu-wiki": "légi fotogrammetriában"},
    "close-range photogrammetry": {"luhmann-errata": "Nahbereichsphotogrammetrie"},
    "remote sensing": {"hu-wiki": "távérzékelés"},
    "ISPRS (International Society for Photogrammetry and Remote Sensing)": {
        "hu-wiki": "Nemzetközi Fotogrammetriai Társaság",
    },
    "image processing": {"de-summary": "Bildverarbeitung", "hu-wiki": "képfeldolgozási"},
    "raster": {"hu-wiki": "raszter", "pl-notes": "rastra"},
    "photogrammetric process": {"de-summary": "Photogrammetrische Prozess"},
    "photogrammetric evaluation": {"hu-wiki": "fotogrammetriai kiértékelés"},
    "analytical plotter": {
        "hu-wiki": "analitikus plotterek", "pl-notes": "autografach analitycznych",
    },
    "digital photogrammetric workstation": {
        "hu-wiki": "digitális fotogrammetriai munkaállomásnak", "pl-notes": "autograf cyfrowy",
    },
    "refraction": {"de-summary": "Lichtbrechung", "pl-notes": "refrakcją"},
    "reflection": {"de-summary": "Reflektion"},
    "dispersion": {"de-summary": "Dispersion"},
    "diffraction": {"de-summary": "Beugung"},
    "pinhole camera": {"de-summary": "Lochkamera"},
    "imaging equation": {"de-summary": "Abbildungsgleichung"},
    "image scale": {"de-summary": "Bildmaßstab", "luhmann-errata": "Bildmaßstab"},
    "image scale number": {"de-summary": "Bildmaßstabszahl"},
    "aperture angle": {"de-summary": "Öffnungswinkel"},
    "field angle (angle of view)": {"de-summary": "Formatwinkel", "luhmann-errata": "Bildwinkel"},
    "f-number": {"de-summary": "Blendenkennzahl"},
    "depth of field": {"de-summary": "Schärfentiefe"},
    "circle of confusion": {"de-summary": "Zerstreuungskreis"},
    "vignetting": {"de-summary": "Vignettierung"},
    "light fall-off (cos⁴ law)": {"de-summary": "Lichtabfall"},
    "chromatic aberration": {"de-summary": "Chromatische Abberation"},
    "point spread function": {"de-summary": "Punktspreizfunktion"},
    "stereoscopic vision": {
        "de-summary": "Stereoskopisches (räumliches) Sehen", "hu-wiki": "sztereoszkópia",
    },
    "sampling (discretisation)": {"de-summary": "Abtastung"},
    "quantisation": {"de-summary": "Quantisierung"},
    "bit depth": {"de-summary": "Bildtiefe"},
    "CCD sensor": {"de-summary": "CCD-Sensoren", "pl-notes": "kamer CCD"},
    "full well capacity": {"de-summary": "Fassungsvermögen"},
    "gain (electrons per grey level)": {"de-summary": "Gain"},
    "micro-lenses": {"de-summary": "Mikrolinsen"},
    "fill factor": {"de-summary": "Pixel fill factor"},
    "Bayer sensor": {"de-summary": "Bayer-Sensor"},
    "pixel": {"de-summary": "Pixel", "pl-notes": "piksele"},
    "pixel resolution (ground area of one pixel)": {"de-summary": "Pixelauflösung"},
    "line sensor": {"de-summary": "Zeilensensor"},
    "area sensor": {"de-summary": "Flächensensoren"},
    "image pyramid": {"pl-notes": "piramidami obrazów"},
    "coordinate system": {"de-summary": "Koordinatensysteme", "pl-notes": "układ współrzędnych"},
    "image coordinates": {
        "de-summary": "Bildkoordinaten", "hu-wiki": "képkoordináták",
        "luhmann-errata": "Bildkoordinaten", "pl-notes": "Współrzędne tłowe",
    },
    "pixel coordinate system": {
        "de-summary": "Digitales Bildkoordinatensystem", "pl-notes": "układzie pikselowym",
    },
    "object coordinates": {
        "de-summary": "Objektkoordinatensystem", "hu-wiki": "terepi pont koordinátái",
        "luhmann-errata": "Objektkoordinaten", "pl-notes": "współrzędne terenowe",
    },
    "rotation matrix": {
        "de-summary": "Rotationsmatrizen", "hu-wiki": "forgatási mátrix",
        "luhmann-errata": "Rotationsmatrix",
    },
    "rotation order": {"hu-wiki": "forgatási sorrendben"},
    "roll (ω)": {"de-summary": "Querneigung"},
    "pitch (φ)": {"de-summary": "Längsneigung"},
    "yaw (κ)": {"de-summary": "Kantung"},
    "interior orientation": {
        "de-summary": "Innere Orientierung", "luhmann-errata": "Innere Orientierung",
        "pl-notes": "orientacja wewnętrzna",
    },
    "principal point": {
        "de-summary": "Bildhauptpunkt", "luhmann-errata": "Bildhauptpunkt",
        "pl-notes": "Punkt główny zdjęcia",
    },
    "camera constant": {
        "de-summary": "Kamerakonstante", "hu-wiki": "kameraállandó",
        "luhmann-errata": "Kamerakonstanten", "pl-notes": "odległość obrazowa kamery",
    },
    "radial distortion": {
        "de-summary": "Radialsymmetrische Verzeichnung", "pl-notes": "dystorsję radialną",
    },
    "tangential distortion": {"de-summary": "Tangentiale Verzeichnung"},
    "affine distortion and shear": {"de-summary": "Affine Verzeichnung und Scherung"},
    "calibration": {
        "de-summary": "Kalibrierungsverfahren", "luhmann-errata": "Kamerakalibrierung",
        "pl-notes": "kalibracja",
    },
    "laboratory calibration": {"de-summary": "Laborkalibrierung"},
    "test-field calibration": {"de-summary": "Testfeldkalibrierung"},
    "self-calibration": {"de-summary": "Selbstkalibrierung"},
    "simultaneous calibration": {"de-summary": "Simultankalibrierung"},
    "plumb-line calibration": {"de-summary": "Plumblines"},
    "metric camera": {"de-summary": "Messkamera", "pl-notes": "kamery fotogrametrycznej"},
    "collinearity equations": {
        "de-summary": "Kollinearitätsgleichungen", "hu-wiki": "kollinearitási egyenletre",
        "pl-notes": "równania kolinearności",
    },
    "collinearity condition": {"pl-notes": "warunek kolinearności"},
    "projection centre": {
        "de-summary": "Projektionszentrums", "hu-wiki": "vetítési centrum",
        "luhmann-errata": "Projektionszentrums", "pl-notes": "środka rzutów",
    },
    "central projection": {
        "de-summary": "Zentralprojektion", "hu-wiki": "centrális projekcióval",
        "pl-notes": "Rzut środkowy",
    },
    "exterior orientation": {
        "de-summary": "Äußere Orientierung", "luhmann-errata": "äußere Orientierungen",
        "pl-notes": "orientacji zewnętrznej",
    },
    "flight attitude": {"de-summary": "Fluglageparameter"},
    "fiducial marks": {"pl-notes": "znaczki tłowe"},
    "similarity transformation": {"de-summary": "Ähnlichkeitstransformation"},
    "affine transformation": {
        "de-summary": "Affine Transformation", "pl-notes": "transformacja afiniczna",
    },
    "bilinear transformation": {
        "de-summary": "Bilineare Transformation", "pl-notes": "Transformację bilinearną",
    },
    "projective transformation": {
        "de-summary": "Projektive Transformation", "pl-notes": "TRANSFORMACJA RZUTOWA",
    },
    "polynomial transformation": {"de-summary": "Polynomtransformation"},
    "resampling": {"pl-notes": "resamplingu"},
    "rectification": {"de-summary": "Entzerrung"},
    "plane rectification": {"de-summary": "Ebene Entzerrung"},
    "space resection": {"luhmann-errata": "räumlichen Rückwärtsschnittes"},
    "direct linear transformation": {"luhmann-errata": "DLT"},
    "control point": {"de-summary": "Passpunkten", "pl-notes": "fotopunktów"},
    "stereo normal case": {"de-summary": "Photogrammetrischer Normalfall"},
    "parallax": {
        "de-summary": "Parallaxe", "hu-wiki": "parallaxisok",
        "luhmann-errata": "Parallaxengenauigkeit",
    },
    "base": {"de-summary": "Basis", "luhmann-errata": "Basislänge"},
    "epipolar geometry": {"de-summary": "Epipolargeometrie"},
    "relative orientation": {"de-summary": "relativ orientiert"},
    "forward intersection": {"pl-notes": "przestrzennego wcięcia w przód"},
    "homologous points": {"de-summary": "homologe Punkte", "pl-notes": "punktów homologicznych"},
    "stereo model": {"hu-wiki": "térmodell", "pl-notes": "modelu przestrzennego"},
    "stereo digitising": {"pl-notes": "STEREODIGITALIZACJA"},
    "stereocomparator": {"pl-notes": "stereokomparatora"},
    "floating mark": {"pl-notes": "znaczek pomiarowy"},
    "bundle adjustment": {"de-summary": "Bündelblockausgleich", "pl-notes": "METODA WIĄZEK"},
    "aerial triangulation": {"pl-notes": "aerotriangulacji"},
    "Gruber points": {"pl-notes": "punkty Grubera"},
    "unknowns": {"de-summary": "Unbekannte", "pl-notes": "Niewiadomymi"},
    "free network adjustment": {"pl-notes": "swobodnego wyrównania sieci"},
    "standard deviation": {
        "luhmann-errata": "Standardabweichung", "pl-notes": "odchylenie standardowe",
    },
    "t-distribution": {"luhmann-errata": "t-Verteilung"},
    "photogrammetric products": {"de-summary": "Photogrammetrische Produkte"},
    "orthophoto": {"de-summary": "Orthophoto"},
    "true orthophoto": {"de-summary": "TrueOrthophoto"},
    "differential rectification": {"de-summary": "Differenzielle Entzerrung"},
    "spatial rectification": {"de-summary": "räumliche Entzerrung"},
    "parallel projection": {"de-summary": "Parallelprojektion"},
    "digital terrain model": {"de-summary": "Digitales Geländemodell"},
    "digital surface model": {"de-summary": "digitales Oberflächenmodell"},
    "surface modelling": {"hu-wiki": "felületmodellezéssel"},
    "image mosaic": {"de-summary": "Bildmosaike"},
    "map": {"de-summary": "Karten", "hu-wiki": "térképezési", "pl-notes": "mapa"},
    "vector map": {"pl-notes": "mapa wektorowa"},
    "contour lines": {"pl-notes": "warstwic"},
    "reference surface": {"de-summary": "Geometrische Bezugsflächen"},
    "3D city model": {"de-summary": "3D City Models"},
    "errata": {"luhmann-errata": "Korrekturen"},
    "gross error": {"pl-notes": "błędów grubych"},
}


def _alternatives(cell: str) -> list:
    """The forms of a cell: split at " / ", with and without a trailing parenthesis."""
    forms = []
    for alt in cell.split(" / "):
        forms.append(alt)
        if alt.endswith(")") and " (" in alt:
            outer, inner = alt[:-1].split(" (", 1)
            forms += [outer, *inner.split(" / ")]
    return [f for f in forms if len(f.strip("()")) >= 2]


def _words(text: str) -> list:
    return [w for w in re.split(r"[\s\-–()]+", text.casefold()) if w]


def _same_word(entry: str, quoted: str) -> bool:
    """Inflection or compounding: the stem of the entry's word occurs in the quoted word."""
    stem = entry if len(entry) <= 3 else entry[:max(3, len(entry) - 3)]
    return stem in quoted


def spelled_as(entry_cell: str, quote: str) -> bool:
    """Whether ``quote`` is a form of one of the alternatives of ``entry_cell``.

    Every word of the alternative must match, in order, a word of the quote, which may
    hold at most one extra word ("Stereoskopisches (räumliches) Sehen").
    """
    quoted = _words(quote)
    for alt in _alternatives(entry_cell):
        wanted = _words(alt)
        if not wanted or len(quoted) > len(wanted) + 1:
            continue
        i = 0
        for w in quoted:
            if i < len(wanted) and _same_word(wanted[i], w):
                i += 1
        if i == len(wanted):
            return True
    return False


@pytest.mark.parametrize("cell, quote, expected", [
    ("Relative Orientierung", "relativ orientiert", True),
    ("błąd gruby / błędy grube", "błędów grubych", True),
    ("Kalibrierung", "Kamerakalibrierung", True),
    ("Stereoskopisches Sehen", "Stereoskopisches (räumliches) Sehen", True),
    ("Karte", "Kartographie der Stadt", False),          # two extra words
    ("fotopunkt", "punkty", False),
    ("kąt skręcenia zdjęcia (κ)", "κ", False),          # a bare symbol is no evidence
])
def test_spelled_as(cell, quote, expected):
    assert spelled_as(cell, quote) is expected


def test_every_listed_source_has_its_wording_and_no_wording_is_unlisted():
    terms = {t.en: t for t in g.load_glossary()}
    assert set(SOURCE_WORDING) <= set(terms)
    for en, t in terms.items():
        assert set(SOURCE_WORDING.get(en, {})) == set(t.sources), en


@pytest.mark.parametrize("en", sorted(SOURCE_WORDING))
def test_the_quoted_wording_is_the_glossary_term(en):
    t = next(t for t in g.load_glossary() if t.en == en)
    for source, quote in SOURCE_WORDING[en].items():
        cells = (getattr(t, SOURCE_LANGUAGE[source]), t.en)
        assert any(spelled_as(cell, quote) for cell in cells), (en, source, quote)


def test_the_sources_own_terms_are_in_the_glossary():
    """Terms of the sources that a student meets in the chapters (audit of the glossary)."""
    terms = g.load_glossary()
    de = {alt for t in terms for alt in _alternatives(t.de)}
    for word in ("Formatwinkel", "Zerstreuungskreis", "Lichtabfall", "Querneigung",
                 "Längsneigung", "Kantung", "Einzelbildphotogrammetrie", "Mehrbildphotogrammetrie",
                 "Laborkalibrierung", "Testfeldkalibrierung", "Gain", "Full-Well", "Mikrolinsen",
                 "Bayer-Sensor", "Pixelauflösung", "Blendenkennzahl", "Plumblines", "Reflektion"):
        assert word in de, word
    pl = {alt for t in terms for alt in _alternatives(t.pl)}
    assert {"punkty Grubera", "znaczek pomiarowy", "piramida obrazów"} <= pl
    by_en = {t.en: t for t in terms}
    assert by_en["field angle (angle of view)"].hu == "látószög"
    assert "látószög" not in by_en["aperture angle"].hu
    assert by_en["photogrammetric evaluation"].hu == "fotogrammetriai kiértékelés"
    assert by_en["digital terrain model"].pl == "numeryczny model terenu (NMT)"
    assert by_en["image pyramid"].chapter == "11-image-measurement"


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
    assert [int(c[:2]) for c in numbered] == list(range(15))
    for path in (ROOT / "notebooks").glob("*.ipynb"):
        assert path.stem in g.CHAPTERS, path.name
    # every chapter of the course teaches at least one term, except the start page and the
    # capstone (which uses the terms of the chapters before it)
    taught = {t.chapter for t in g.load_glossary()}
    assert set(g.CHAPTERS) - taught == {"00-start", "14-project", "glossary"}


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
