"""The command-line dispatcher: help, unknown commands, a closed pipe."""

from __future__ import annotations

import subprocess
import sys

from photolib.__main__ import COMMANDS, main


def test_help_lists_every_command(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in COMMANDS:
        assert name in out


def test_unknown_command_is_a_clear_error(capsys):
    assert main(["frobnicate"]) == 2
    assert "unknown command 'frobnicate'" in capsys.readouterr().err


def test_closed_pipe_is_not_a_traceback():
    p = subprocess.Popen([sys.executable, "-m", "photolib", "--help"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()  # the reader goes away at once, like `| head -0`
    err = p.stderr.read().decode()
    rc = p.wait(timeout=60)
    p.stderr.close()
    assert rc == 0 and err == "", (rc, err)


def test_every_command_has_help_and_writes_nothing(tmp_path, monkeypatch, capsys):
    # `codegen --help` once took "--help" for its output folder and wrote the code there
    monkeypatch.chdir(tmp_path)
    for name in COMMANDS:
        try:
            rc = main([name, "--help"])
        except SystemExit as exc:  # argparse's --help
            rc = exc.code
        assert rc == 0, name
        assert f"python -m photolib {name}" in capsys.readouterr().out, name
    assert list(tmp_path.iterdir()) == []


def test_assign_outside_the_course_is_a_one_line_error(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    # 2, not 1: `assign --check` returns 1 for "student copies out of date"
    assert main(["assign", "--check"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("assign: no folder solutions") and "Traceback" not in err


def _markup(text: str) -> list[str]:
    """reStructuredText markup a reader of a terminal would see raw: ``x``, `x`, :role:`x`."""
    import re
    return re.findall(r"(?::\w+:)?(?:``[^`\n]+``|`[^`\n]+`)", text)


def test_markup_detector():
    assert _markup("see ``--id`` and :func:`f` and `x`") == ["``--id``", ":func:`f`", "`x`"]
    assert _markup("plain text, no quotes") == []


def test_help_texts_show_no_rst_markup(capsys):
    texts = []
    for argv in [["--help"], *[[name, "--help"] for name in COMMANDS]]:
        try:
            main(argv)
        except SystemExit:  # argparse's --help
            pass
        texts.append((argv, capsys.readouterr().out))
    bad = [(argv, _markup(out)) for argv, out in texts if _markup(out)]
    assert not bad, bad


def test_errata_texts_show_no_rst_markup():
    """Every text of the catalogue the errata CLI prints (item, steps, declared verdicts, note)."""
    from photolib import errata
    bad = []
    for rec in errata.catalogue():
        steps = rec.steps() if callable(rec.steps) else rec.steps
        texts = [rec.item, rec.note or "", *map(str, steps)]
        texts += [spec.verdict for spec in rec.specs.values()]
        texts += [spec.condition_text for spec in rec.specs.values()]
        bad += [(rec.id, m) for t in texts for m in _markup(t)]
    assert not bad, bad
