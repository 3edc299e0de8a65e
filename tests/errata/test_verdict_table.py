"""The committed verdict table is the catalogue's verdicts, and the chapter's explorer shows it.

The errata chapter reads ``photolib/data/errata-verdicts.json`` instead of recomputing some 20 s
of verdicts. As for the generated code (``tests/test_codegen.py``), a slow test recomputes the
whole table and diffs it against the committed file; fast tests check that the file covers the
catalogue exactly, agrees with every verdict the catalogue states, and was written from the
sources as they are now (hash).
"""

from __future__ import annotations

import html
import json

import pytest

from photolib import errata
from photolib.errata import cli, table
from photolib.errata import evaluate as widgets
from photolib.nb import errata as nb_errata

COMMITTED = table.TABLE_PATH


def _committed() -> dict:
    return json.loads(COMMITTED.read_text(encoding="utf-8"))


@pytest.mark.slow
def test_committed_table_equals_the_recomputed_one():
    """Every verdict, reason, counterexample and ``--id`` text recomputed from the records."""
    recomputed = table.render(table.build_table())
    committed = COMMITTED.read_text(encoding="utf-8")
    d = table.diff(committed, recomputed)
    if d:
        pytest.fail(f"{COMMITTED} is out of date (run `make regen` or `python -m photolib "
                    f"errata --write-table`):\n{d[:6000]}")


def test_table_was_written_from_the_current_sources():
    """A cheap tripwire before the slow diff: the hash of photolib/errata, photolib/derive and
    photolib/symcheck.py the table was written from is the hash of those files now."""
    assert _committed()["source_sha256"] == table.source_hash(), (
        "photolib/errata, photolib/derive or photolib/symcheck.py changed since the verdict "
        "table was written: run `make regen` (or `python -m photolib errata --write-table`) "
        "and commit photolib/data/errata-verdicts.json")


def test_table_covers_the_catalogue_and_agrees_with_every_stated_verdict():
    data = _committed()
    cat = errata.catalogue()
    assert [e["id"] for e in data["records"]] == [r.id for r in cat]
    for rec, e in zip(cat, data["records"]):
        assert list(e["versions"]) == list(rec.specs), rec.id
        assert (e["origin"], e["chapter"]) == (table.origin_of(rec.id), table.chapter_of(rec.id))
        assert (e["item"], e["kind"], e["note"]) == (rec.item, rec.kind, rec.note), rec.id
        for name, v in e["versions"].items():
            spec = rec.specs[name]
            assert v["verdict"] == spec.verdict, (rec.id, name)   # the catalogue's statement
            assert v["claim"] == spec.claim, (rec.id, name)
        assert e["describe"][0] == f"{rec.id}: {rec.item}"


def test_table_text_is_the_canonical_rendering_and_prints_no_float_repr():
    """The file is what ``render`` writes (so the slow diff is byte-exact), and its evidence is
    formatted as the CLI prints it: no float with more than 12 significant digits (which would
    differ between CPUs) except in a derivation's own SymPy text (``derivation: 1.2196698912665``
    is mpmath's j₁,₁/π, software arithmetic, the same everywhere), and no dyadic rationals."""
    from tests.test_committed_outputs import long_floats

    text = COMMITTED.read_text(encoding="utf-8")
    assert table.render(json.loads(text)) == text
    for line in text.splitlines():
        if long_floats(line):
            assert line.lstrip().startswith('"  derivation: '), line
    for e in json.loads(text)["records"]:
        for v in e["versions"].values():
            assert long_floats(v["counterexample"] + " " + v["why"]) == [], e["id"]
            assert "/524288" not in v["counterexample"], e["id"]       # decimals, not p/q


def test_diff_names_a_changed_verdict():
    """The sync test can fail: a table whose verdict was changed by hand differs, and the diff
    shows the record and the two verdicts."""
    text = COMMITTED.read_text(encoding="utf-8")
    data = json.loads(text)
    e = next(e for e in data["records"] if e["id"] == "luhmann:4.18b")
    e["versions"]["old"]["verdict"] = "right"
    d = table.diff(table.render(data), text)
    removed = [ln for ln in d.splitlines() if ln.startswith("-") and '"verdict"' in ln]
    added = [ln for ln in d.splitlines() if ln.startswith("+") and '"verdict"' in ln]
    assert [ln.split(":", 1)[1] for ln in removed + added] == [' "right",', ' "wrong",'], d
    assert table.diff(text, text) == ""


def test_load_table_errors_name_the_file_and_the_fix(tmp_path):
    with pytest.raises(FileNotFoundError, match="--write-table"):
        table.load_table(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": 99, "records": []}')
    with pytest.raises(ValueError, match=r"bad.json is not an errata verdict table of format 1 "
                                         r"\(format 99\)"):
        table.load_table(bad)


def test_write_table_option_writes_the_file(tmp_path, monkeypatch, capsys):
    """``errata --write-table PATH`` writes ``render(build_table())`` (build stubbed: the real
    one is the slow test above)."""
    fake = {"format": table.FORMAT, "source_sha256": "x", "records": []}
    monkeypatch.setattr(table, "build_table", lambda progress=None: fake)
    out = tmp_path / "t.json"
    assert cli.errata_main(["--write-table", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == table.render(fake)
    assert capsys.readouterr().out.startswith(f"wrote {out} (")


def test_chapter_and_origin_of_ids():
    assert table.chapter_of("luhmann:fig-8.67b") == "8"
    assert table.chapter_of("luhmann:p425-figure-ref") == "5"
    assert table.chapter_of("de-summary:gain") == ""
    with pytest.raises(ValueError, match="'nope:1' has no known source prefix"):
        table.origin_of("nope:1")


# ----------------------------------------------------------------- the chapter's explorer


def test_rows_filter_by_source_chapter_and_verdict():
    rows = widgets.verdict_rows(source="luhmann", chapter="4", verdict="wrong")
    pairs = {(r["id"], r["version"]) for r in rows}
    assert {("luhmann:4.13", "old"), ("luhmann:4.18b", "old")} <= pairs
    assert all(r["origin"] == "luhmann" and r["chapter"] == "4" and r["verdict"] == "wrong"
               for r in rows)
    every = widgets.verdict_rows()
    assert len(every) == sum(len(r.specs) for r in errata.catalogue())
    kinds = {r["verdict"].split(":")[0] for r in widgets.verdict_rows(verdict="not-checkable")}
    assert kinds == {"not-checkable"}


def test_differs_filter_is_differs_from_source():
    got = {(r["id"], r["version"]) for r in widgets.verdict_rows(verdict="differs")}
    want = {(rec.id, name) for rec in errata.catalogue() for name in rec.differs_from_source()}
    assert got == want and len(got) > 20


def test_search_ignores_case_and_accents_and_looks_in_the_verdicts():
    ids = {r["id"] for r in widgets.verdict_rows("LÄNGSFEHLER")}       # in a verdict text
    assert "de-summary:chromatic-aperture" in ids
    ids = {r["id"] for r in widgets.verdict_rows("tangential", source="de-summary")}
    assert ids == {"de-summary:tangential-distortion"}
    assert widgets.verdict_rows("no such words anywhere") == []


def test_html_shows_every_verdict_in_full():
    text = widgets.verdict_table_html()
    longest = max((r["verdict"] for r in widgets.verdict_rows()), key=len)
    assert len(longest) > 300
    assert html.escape(longest.partition(": ")[2]) in text            # not cut
    assert text.startswith(f"<p>{len(widgets.verdict_rows())} of ")
    assert "<code>luhmann:4.18b</code>" in text


@pytest.mark.parametrize("kw, match", [
    ({"source": "wiki"}, r"unknown source 'wiki'; expected 'all' or one of \['luhmann'"),
    ({"chapter": "9"}, r"unknown chapter '9'; expected 'all' or one of \['2'"),
    ({"verdict": "bad"}, r"unknown verdict filter 'bad'"),
])
def test_bad_filters_are_named(kw, match):
    with pytest.raises(ValueError, match=match):
        widgets.verdict_rows(**kw)


def test_explorer_updates_on_every_control():
    ex = nb_errata.VerdictExplorer()
    assert repr(ex.widget) == "[widget: errata verdicts]"
    everything = ex.html.value
    ex.controls["source"].value = "pl-notes"
    assert ex.html.value != everything and "luhmann:" not in ex.html.value
    ex.controls["verdict"].value = "wrong"
    assert "pl-notes:bilinear" in ex.html.value and "pl-notes:helmert" not in ex.html.value
    ex.controls["query"].value = "b2"
    assert ex.html.value.startswith("<p>1 of ") and "pl-notes:bilinear" in ex.html.value
    ex.controls["source"].value = "all"
    ex.controls["query"].value = ""
    ex.controls["chapter"].value = "5"
    assert "luhmann:5.50-p1" in ex.html.value and "pl-notes:" not in ex.html.value
