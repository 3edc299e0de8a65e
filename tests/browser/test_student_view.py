"""What a student sees, in headless Chromium at device scale factor 2 (issue 14, point 8).

* A student exercise copy, run all: the rendered task statements (the output areas) have no
  number broken across two lines.
* A chapter with widgets: every widget image has at least two device pixels per CSS pixel
  (natural width ≥ 2 × the width it is laid out at), and no control label is truncated —
  checked in ``test_lab.test_chapter_runs_and_widgets_react`` on the same Run All (the
  JavaScript probes ``_IMAGES`` and ``_TRUNCATED`` are defined here).

Screenshots go to ``test-artifacts/screenshots/`` (gitignored).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .test_lab import CHAPTERS, _KERNEL, _PROGRESS

pytestmark = [pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(600)]

#: one student copy per chapter (each runs in a minute or less)
_EXERCISE_DIR = Path(__file__).resolve().parents[2] / "exercises"
EXERCISES = [c for c in CHAPTERS if (_EXERCISE_DIR / f"{c}.ipynb").exists()]

#: a line break inside a number: the characters before and after the break, per output area.
#: Each character's box comes from a Range over it (getClientRects); a new line starts where
#: a box's top moves down. A break at white space is a break between words, not in a number.
_SPLIT_NUMBERS = r"""() => {
    const numeric = /[0-9]/, joins = /[0-9.,\u2212+\-]/;   // digits, decimal point, sign
    const found = [];
    for (const out of document.querySelectorAll('.jp-OutputArea-output')) {
        const walker = document.createTreeWalker(out, NodeFilter.SHOW_TEXT);
        let prev = null, node, seen = 0;
        while ((node = walker.nextNode()) && seen < 50000) {
            if (node.parentElement.closest('mjx-container, .MathJax, svg, script, style')) {
                prev = null;                      // typeset maths: MathJax breaks it, not us
                continue;
            }
            const text = node.textContent;
            for (let i = 0; i < text.length; i++, seen++) {
                const ch = text[i];
                if (/\s/.test(ch)) { prev = null; continue; }
                const range = document.createRange();
                range.setStart(node, i);
                range.setEnd(node, i + 1);
                const rects = range.getClientRects();
                if (!rects.length) continue;
                const box = rects[rects.length - 1];
                if (prev && box.top > prev.bottom - 1 && joins.test(prev.ch) && numeric.test(ch)
                        || prev && box.top > prev.bottom - 1 && numeric.test(prev.ch) && joins.test(ch)) {
                    const before = (prev.text.slice(Math.max(0, prev.i - 12), prev.i + 1));
                    const after = text.slice(i, i + 12);
                    found.push(before + ' ⏎ ' + after);
                }
                prev = {ch: ch, top: box.top, bottom: box.bottom, text: text, i: i};
            }
        }
    }
    return found;
}"""

#: widget images: natural (PNG) width against the CSS width they are laid out at
_IMAGES = """() => Array.from(document.querySelectorAll('.photolib-explorer img')).map(img => ({
    natural: img.naturalWidth, css: img.getBoundingClientRect().width,
    attribute: img.getAttribute('width')}))"""

#: control labels whose text is wider than their box (the ellipsis a student sees)
_TRUNCATED = """() => Array.from(document.querySelectorAll(
        '.photolib-explorer .widget-label, .photolib-explorer .widget-toggle-button'))
    .filter(el => el.offsetParent !== null && el.scrollWidth > el.clientWidth)
    .map(el => el.textContent + ' (' + el.scrollWidth + ' > ' + el.clientWidth + ')')"""


def _run_all(page, lab_log, timeout_ms=180_000):
    """Run every cell; unlike test_lab's, a raised error (an unanswered check) is allowed."""
    page.wait_for_function(
        "() => window.jupyterapp && window.jupyterapp.shell.currentWidget"
        " && window.jupyterapp.shell.currentWidget.sessionContext"
        " && window.jupyterapp.shell.currentWidget.sessionContext.session"
        f" && {_KERNEL} && {_KERNEL}.status === 'idle'",
        timeout=60_000)
    page.evaluate("() => { window.jupyterapp.commands.execute('notebook:run-all-cells');"
                  " return true; }")
    done = ("() => { const p = (" + _PROGRESS + ")();"
            " return p.status === 'idle' && p.pending.length === 0; }")
    try:
        page.wait_for_function(done, timeout=timeout_ms)
    except Exception as exc:  # playwright's TimeoutError: say where it stopped
        pytest.fail(f"cells did not finish: {page.evaluate(_PROGRESS)} ({exc});\n"
                    f"JupyterLab log:\n{lab_log.read_text()[-3000:]}")
    # let MathJax typeset and the output areas settle before measuring them
    page.wait_for_timeout(1500)


def _with_student_id(lab_root, exercise, sid="s1234567"):
    """Open the copy as a student who has set STUDENT_ID: task() then shows the statements
    (with the id empty it shows one line per task and no numbers)."""
    import json
    path = lab_root / "exercises" / f"{exercise}.ipynb"
    nb = json.loads(path.read_text())
    for cell in nb["cells"]:
        source = "".join(cell["source"])
        if cell["cell_type"] == "code" and source.lstrip().startswith("STUDENT_ID"):
            cell["source"] = [f'STUDENT_ID = "{sid}"\n']
            break
    else:
        pytest.fail(f"{exercise}: no STUDENT_ID cell")
    path.write_text(json.dumps(nb))


@pytest.mark.parametrize("exercise", EXERCISES)
def test_exercise_statements_keep_numbers_on_one_line(lab_url, lab_root, lab_log, hidpi_page,
                                                      screenshots, exercise):
    page = hidpi_page
    _with_student_id(lab_root, exercise)
    page.goto(f"{lab_url}/lab/tree/exercises/{exercise}.ipynb?reset")
    _run_all(page, lab_log)
    assert page.evaluate("() => window.devicePixelRatio") == 2
    statements = page.locator('.jp-OutputArea-output[data-mime-type="text/markdown"]')
    assert statements.count() >= 3, f"{exercise}: the tasks displayed no statements"
    statements.first.scroll_into_view_if_needed()
    page.wait_for_timeout(1000)         # MathJax typesets the statements' maths
    page.screenshot(path=str(screenshots / f"exercise-{exercise}.png"), full_page=False)
    split = page.evaluate(_SPLIT_NUMBERS)
    assert split == [], f"{exercise}: numbers split across lines: {split[:8]}"


def test_split_number_check_finds_a_split_number(lab_url, hidpi_page):
    """The check above can fail: a number forced onto two lines in a narrow box is found."""
    page = hidpi_page
    page.goto(f"{lab_url}/lab?reset")
    page.wait_for_function("() => window.jupyterapp && document.body", timeout=60_000)
    page.evaluate("""() => {
        const out = document.createElement('div');
        out.className = 'jp-OutputArea-output';
        out.style.cssText = 'width: 5ch; word-break: break-all; position: absolute; top: 0';
        out.textContent = 'x = 123456789012';
        document.body.appendChild(out);
    }""")
    assert page.evaluate(_SPLIT_NUMBERS) != []
