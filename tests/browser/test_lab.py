"""Real-browser test: each chapter runs in JupyterLab and its widgets react to a slider."""

from __future__ import annotations

import urllib.request

import pytest

pytestmark = [pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(300)]

CHAPTERS = ["01-introduction", "02-optics", "03-digital-images", "04-rotations",
            "05-interior-orientation", "06-collinearity", "07-plane-transformations",
            "08-resection-dlt", "09-stereo", "10-bundle-adjustment", "11-image-measurement",
            "12-products", "14-project"]


def test_lab_answers_200(lab_url):
    with urllib.request.urlopen(f"{lab_url}/lab", timeout=10) as response:
        assert response.status == 200
        assert b"JupyterLab" in response.read()


_KERNEL = "window.jupyterapp.shell.currentWidget.sessionContext.session.kernel"

_PROGRESS = """() => {
    const nb = window.jupyterapp.shell.currentWidget;
    const cells = nb.content.widgets.filter(c => c.model.type === 'code');
    return {status: nb.sessionContext.session.kernel.status,
            pending: cells.map((c, i) => c.model.executionCount === null ? i : -1)
                          .filter(i => i >= 0),
            errors: cells.flatMap(c => c.model.outputs.toJSON())
                         .filter(o => o.output_type === 'error')
                         .map(o => o.ename + ': ' + o.evalue)};
}"""


def _run_all(page, lab_log):
    page.wait_for_function(
        "() => window.jupyterapp && window.jupyterapp.shell.currentWidget"
        " && window.jupyterapp.shell.currentWidget.sessionContext"
        " && window.jupyterapp.shell.currentWidget.sessionContext.session"
        f" && {_KERNEL} && {_KERNEL}.status === 'idle'",
        timeout=60_000)
    # start the run without awaiting the command's promise: the wait below has its own
    # deadline and says which cells never ran
    run_all = ("() => { window.jupyterapp.commands.execute('notebook:run-all-cells');"
               " return true; }")
    done = ("() => { const p = (" + _PROGRESS + ")();"
            " return p.status === 'idle' && p.pending.length === 0; }")
    page.evaluate(run_all)
    for attempt in (1, 2):
        try:
            page.wait_for_function(done, timeout=90_000)
            break
        except Exception as exc:  # playwright's TimeoutError: report where it stopped
            progress = page.evaluate(_PROGRESS)
            report = (f"kernel {progress['status']}, code cells never run {progress['pending']}, "
                      f"errors {progress['errors']} ({exc})")
            if attempt == 1 and progress["status"] == "idle" and not progress["errors"]:
                # an idle kernel with cells never run: the front end dropped the request;
                # ask once more, and say so in the test's output
                print(f"run-all-cells re-issued: {report}")
                page.evaluate(run_all)
                continue
            pytest.fail(f"cells did not finish: {report};\n"
                        f"JupyterLab log:\n{lab_log.read_text()[-3000:]}")
    errors = page.evaluate(_PROGRESS)["errors"]
    assert not errors, f"cells raised {errors}"


def _state(widget):
    img = widget.locator("img").first
    return img.get_attribute("src"), widget.locator(".widget-html-content").first.inner_text()


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_chapter_runs_and_widgets_react(lab_url, lab_log, hidpi_page, artifacts, screenshots,
                                        chapter):
    """Run All, then what a student sees before touching anything (issue 14, point 8: every
    widget image at two device pixels per CSS pixel, no control label truncated; checked on
    this run, at device scale 2, instead of running every chapter a second time), then every
    widget's first slider dragged: its figure and its text change."""
    from .test_student_view import _IMAGES, _TRUNCATED

    page = hidpi_page
    errors = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    # ?reset: a fresh workspace, or JupyterLab reopens every earlier chapter in a tab of its
    # own, each starting a kernel again, and the later chapters wait behind them
    page.goto(f"{lab_url}/lab/tree/notebooks/{chapter}.ipynb?reset")
    _run_all(page, lab_log)
    widgets = page.locator(".photolib-explorer")
    widgets.first.wait_for(timeout=30_000)
    first = widgets.first
    first.scroll_into_view_if_needed()
    first.locator("img").first.wait_for(timeout=20_000)
    page.wait_for_function(
        "() => Array.from(document.querySelectorAll('.photolib-explorer img'))"
        ".every(img => img.complete && img.naturalWidth > 0)", timeout=30_000)
    first.screenshot(path=str(screenshots / f"widget-{chapter}.png"))
    images = page.evaluate(_IMAGES)
    assert images, f"{chapter}: no widget image"
    blurry = [im for im in images if im["natural"] < 2 * im["css"] - 0.5]
    assert not blurry, f"{chapter}: widget images with less than 2 device px per CSS px: {blurry}"
    truncated = page.evaluate(_TRUNCATED)
    assert truncated == [], f"{chapter}: truncated control labels {truncated}"
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
        # drag towards the side with room: a slider may start at its maximum
        track = w.locator(".noUi-base").first.bounding_box()
        # by 0.45 of the track (at least 40 px): sliders are sized to one pixel per step or
        # more, so a fixed 40 px on a wide track of a 3-value slider (chapter 10's 'strips')
        # moved less than half a step and the value, hence the figure, did not change
        dist = max(40.0, 0.45 * track["width"]) if track else 40.0
        step = -dist if track and x > track["x"] + track["width"] / 2 else dist
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + step, y, steps=4)
        page.mouse.up()
        try:
            page.wait_for_function(
                "([el, src]) => { const img = el.querySelector('img'); return img && img.src !== src; }",
                arg=[w.element_handle(), before[0]], timeout=30_000)
        except Exception as exc:  # playwright's TimeoutError: say which widget and slider
            label = w.locator(".widget-label").first.inner_text()
            pytest.fail(f"{chapter}: widget {i} (first slider {label!r}) did not redraw within "
                        f"30 s of dragging the slider ({exc})")
        after = _state(w)
        assert after[0] != before[0], f"{chapter}: widget {i} image did not change"
        assert after[1] != before[1], f"{chapter}: widget {i} text did not change"
    widgets.nth(0).scroll_into_view_if_needed()
    page.screenshot(path=str(artifacts / f"{chapter}.png"))
    assert not errors, f"{chapter}: page errors {errors}"
