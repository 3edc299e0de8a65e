"""Real-browser test: each chapter runs in JupyterLab and its widgets react to a slider."""

from __future__ import annotations

import urllib.request

import pytest

pytestmark = [pytest.mark.browser, pytest.mark.timeout(150)]

CHAPTERS = ["04-rotations", "05-interior-orientation", "06-collinearity"]


def test_lab_answers_200(lab_url):
    with urllib.request.urlopen(f"{lab_url}/lab", timeout=10) as response:
        assert response.status == 200
        assert b"JupyterLab" in response.read()


def _run_all(page):
    page.wait_for_function(
        "() => window.jupyterapp && window.jupyterapp.shell.currentWidget"
        " && window.jupyterapp.shell.currentWidget.sessionContext"
        " && window.jupyterapp.shell.currentWidget.sessionContext.session"
        " && window.jupyterapp.shell.currentWidget.sessionContext.session.kernel"
        " && window.jupyterapp.shell.currentWidget.sessionContext.session.kernel.status === 'idle'",
        timeout=60_000)
    page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
    # every code cell has an execution count and the kernel is idle again
    page.wait_for_function(
        """() => {
            const nb = window.jupyterapp.shell.currentWidget;
            const cells = nb.content.widgets.filter(c => c.model.type === 'code');
            return nb.sessionContext.session.kernel.status === 'idle'
                && cells.every(c => c.model.executionCount !== null);
        }""", timeout=120_000)


def _state(widget):
    img = widget.locator("img").first
    return img.get_attribute("src"), widget.locator(".widget-html-content").first.inner_text()


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_chapter_runs_and_widgets_react(lab_url, page, artifacts, chapter):
    errors = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(f"{lab_url}/lab/tree/notebooks/{chapter}.ipynb")
    _run_all(page)
    widgets = page.locator(".photolib-explorer")
    widgets.first.wait_for(timeout=30_000)
    n = widgets.count()
    assert n >= 2, f"{chapter}: expected at least two widgets, found {n}"
    for i in range(n):
        w = widgets.nth(i)
        w.scroll_into_view_if_needed()
        w.locator("img").first.wait_for(timeout=20_000)
        before = _state(w)
        handle = w.locator(".noUi-handle").first
        handle.scroll_into_view_if_needed()
        handle.hover()
        box = handle.bounding_box()
        assert box is not None, f"{chapter}: widget {i} has no visible slider"
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + 40, y, steps=4)
        page.mouse.up()
        page.wait_for_function(
            "([el, src]) => { const img = el.querySelector('img'); return img && img.src !== src; }",
            arg=[w.element_handle(), before[0]], timeout=30_000)
        after = _state(w)
        assert after[0] != before[0], f"{chapter}: widget {i} image did not change"
        assert after[1] != before[1], f"{chapter}: widget {i} text did not change"
    widgets.nth(0).scroll_into_view_if_needed()
    page.screenshot(path=str(artifacts / f"{chapter}.png"))
    assert not errors, f"{chapter}: page errors {errors}"
