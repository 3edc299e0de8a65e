"""The course website (issue 19, point 6): build it, open it in headless Chromium.

The site is built once per session from the committed notebooks into a temporary folder
(``site/build_site.py``, the same as ``make site``) and served on 127.0.0.1. The tests follow the
table of contents in the course's order, find every chapter's figures loaded and its widgets'
first states, MathJax typeset from the site itself, the glossary found by the search in all four
languages, and no broken link on any page.

Marker ``site``: ``make test-site`` installs the site environment and runs them (``.ci/run``).
"""

from __future__ import annotations

import functools
import http.server
import json
import subprocess
import sys
import threading
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urljoin, urlparse

import pytest

pytestmark = [pytest.mark.site, pytest.mark.timeout(900)]

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "site"))
import build_site  # noqa: E402  (site/ is not a package: the build script is a tool)

WIDGET = "application/vnd.jupyter.widget-view+json"


@pytest.fixture(scope="session")
def site(tmp_path_factory) -> Path:
    pytest.importorskip("sphinx", reason="the site environment is not installed (make test-site)")
    pytest.importorskip("myst_nb", reason="the site environment is not installed (make test-site)")
    out = tmp_path_factory.mktemp("site")
    subprocess.run([sys.executable, str(REPO / "site" / "build_site.py"), "--out", str(out)],
                   check=True, cwd=REPO)
    return out / "html"


@pytest.fixture(scope="session")
def site_url(site):
    handler = functools.partial(_QuietHandler, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    protocol_version = "HTTP/1.0"   # one request per connection: none is left open at the end

    def log_message(self, *args):
        pass


@pytest.fixture(scope="session")
def site_page(site_url):
    from tests.browser.conftest import CHROMIUM, CHROMIUM_ARGS
    if not CHROMIUM.exists():
        pytest.skip(f"Chromium not installed at {CHROMIUM}")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS,
                                     headless=True)
        page = browser.new_page(viewport={"width": 1300, "height": 900})
        failed = []
        page.on("requestfailed", lambda r: failed.append(r.url))
        page.failed_requests = failed
        try:
            yield page
        finally:
            browser.close()


def _widget_outputs(chapter: str) -> int:
    nb = json.loads((REPO / "notebooks" / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    return sum(WIDGET in o.get("data", {}) for c in nb["cells"] for o in c.get("outputs", []))


def _widgets_with_figures(chapter: str) -> int:
    """Widget outputs whose saved state holds a figure (an Output widget with a PNG)."""
    nb = json.loads((REPO / "notebooks" / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    state = nb["metadata"].get("widgets", {}).get(
        "application/vnd.jupyter.widget-state+json", {}).get("state", {})

    def has_png(mid):
        entry = state.get(mid.replace("IPY_MODEL_", ""), {})
        s = entry.get("state", {})
        if any("image/png" in o.get("data", {}) for o in s.get("outputs", [])):
            return True
        return any(has_png(c) for c in s.get("children", []))

    return sum(has_png(o["data"][WIDGET]["model_id"]) for c in nb["cells"]
               for o in c.get("outputs", []) if WIDGET in o.get("data", {}))


def _title(chapter: str) -> str:
    """The notebook's first heading, as its page's title."""
    nb = json.loads((REPO / "notebooks" / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    first = "".join(nb["cells"][0]["source"]).splitlines()[0]
    return first.lstrip("# ").strip()


def _figures(chapter: str) -> int:
    nb = json.loads((REPO / "notebooks" / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    return sum("image/png" in o.get("data", {}) for c in nb["cells"] for o in c.get("outputs", []))


def test_the_table_of_contents_follows_the_course_and_every_chapter_shows_its_figures(
        site_page, site_url):
    page = site_page
    page.goto(f"{site_url}/index.html")
    links = page.locator("article a.reference.internal").evaluate_all(
        "els => els.map(a => a.getAttribute('href'))")
    chapters = [h for h in links if h.startswith("notebooks/")]
    assert [Path(urlparse(h).path).stem for h in chapters] == build_site.CHAPTERS
    assert "glossary.html" in links
    for href in chapters:
        chapter = Path(urlparse(href).path).stem
        page.goto(urljoin(f"{site_url}/index.html", href))
        page.wait_for_load_state("load")
        images = page.evaluate("""() => Array.from(document.querySelectorAll('article img'))
            .map(img => ({src: img.src.slice(0, 60), ok: img.complete && img.naturalWidth > 0}))""")
        broken = [im["src"] for im in images if not im["ok"]]
        assert not broken, f"{chapter}: images that did not load: {broken}"
        # every figure the notebook stored, and every widget's first state with its figure
        static = page.locator(".photolib-static-widget")
        assert static.count() == _widget_outputs(chapter), chapter
        with_figure = static.filter(has=page.locator("img")).count()
        assert with_figure == _widgets_with_figures(chapter), chapter
        assert len(images) >= _figures(chapter) + with_figure, (chapter, len(images))
        if static.count():
            assert static.first.locator("table.controls td").count() >= 2, chapter
        heading = _title(chapter)
        assert page.locator("h1").first.inner_text().strip(" #¶\n").startswith(heading), chapter
    assert not page.failed_requests, page.failed_requests


def test_latex_is_typeset_by_the_sites_own_mathjax(site_page, site_url):
    page = site_page
    page.goto(f"{site_url}/notebooks/04-rotations.html")
    page.wait_for_function("() => document.querySelectorAll('mjx-container').length > 10",
                           timeout=60_000)
    scripts = page.evaluate("() => Array.from(document.scripts).map(s => s.src).filter(s => s)")
    assert all(s.startswith("http://127.0.0.1") for s in scripts), scripts
    assert not page.failed_requests, page.failed_requests


@pytest.mark.parametrize("query", ["Kamerakonstante", "kameraállandó", "camera constant"])
def test_the_glossary_is_found_by_the_search(site_page, site_url, query):
    page = site_page
    page.goto(f"{site_url}/search.html?q={query}")
    # Sphinx's search writes its summary when it has listed every page found
    page.locator("#search-results p.search-summary").wait_for(timeout=30_000)
    page.wait_for_function("() => /found/i.test(document.querySelector("
                           "'#search-results p.search-summary').textContent)", timeout=30_000)
    results = page.locator("#search-results ul.search li a")
    hrefs = results.evaluate_all("els => els.map(a => a.getAttribute('href'))")
    assert any("glossary" in h for h in hrefs), (query, hrefs)


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.hrefs, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and a.get("href"):
            self.hrefs.append(a["href"])
        if tag in ("img", "script") and a.get("src") and not a["src"].startswith("data:"):
            self.hrefs.append(a["src"])
        if tag == "link" and a.get("href"):
            self.hrefs.append(a["href"])


def test_no_page_has_a_broken_link(site):
    # the pages, not the theme's Jinja macro files that Sphinx copies into _static
    pages = {p: None for p in site.rglob("*.html") if "_static" not in p.relative_to(site).parts}
    parsed = {}
    for p in pages:
        parser = _Links()
        parser.feed(p.read_text(encoding="utf-8"))
        parsed[p] = parser
    broken = []
    for p, parser in parsed.items():
        for href in parser.hrefs:
            url = urlparse(href)
            if url.scheme in ("http", "https", "mailto") or href.startswith("javascript:"):
                continue
            target = (p.parent / unquote(url.path)).resolve() if url.path else p
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{p.relative_to(site)} → {href}")
            elif url.fragment and target.suffix == ".html" and target in parsed \
                    and url.fragment not in parsed[target].ids:
                broken.append(f"{p.relative_to(site)} → {href} (no such anchor)")
    assert not broken, f"{len(broken)} broken links, e.g. {broken[:10]}"
    # the check can fail: a page that links nowhere is found
    assert len(parsed) >= len(build_site.CHAPTERS) * 2


def test_external_links_are_the_sources_not_the_sites_assets(site):
    """The site loads nothing from outside: no script, style sheet or font from a CDN."""
    outside = set()
    for p in site.rglob("*.html"):
        if "_static" in p.relative_to(site).parts:
            continue
        text = p.read_text(encoding="utf-8")
        for tag in ("<script", "<link"):
            for chunk in text.split(tag)[1:]:
                head = chunk.split(">", 1)[0]
                if "http://" in head or "https://" in head:
                    outside.add(head.strip()[:120])
    assert not outside, sorted(outside)[:5]


def test_a_widget_becomes_its_first_state():
    state = {
        "box": {"model_name": "VBoxModel", "state": {"children": ["IPY_MODEL_s", "IPY_MODEL_row"]}},
        "s": {"model_name": "FloatSliderModel",
              "state": {"description": "ω [°]", "value": 12.5, "readout_format": ".1f"}},
        "row": {"model_name": "HBoxModel", "state": {"children": ["IPY_MODEL_out", "IPY_MODEL_t"]}},
        "out": {"model_name": "OutputModel", "state": {"outputs": [
            {"output_type": "display_data", "data": {"image/png": "iVBORw0KGgo="},
             "metadata": {"image/png": {"width": 320, "height": 240}}}]}},
        "t": {"model_name": "HTMLModel", "state": {"value": "<b>σ0 = 1.2 µm</b>"}},
    }
    html = build_site.widget_html("box", state, "demo")
    assert "<td>ω [°]</td><td>12.5</td>" in html
    assert 'src="data:image/png;base64,iVBORw0KGgo=" width="320"' in html
    assert "<b>σ0 = 1.2 µm</b>" in html and 'class="title">demo<' in html
    with pytest.raises(build_site.SiteError, match="nope"):
        build_site.widget_html("nope", state)


def test_links_to_notebooks_in_raw_html_point_to_pages():
    assert build_site._ipynb_links('<a href="05-x.ipynb#a">') == '<a href="05-x.html#a">'
    assert build_site._ipynb_links('<a href="https://e.org/x.ipynb">') == \
        '<a href="https://e.org/x.ipynb">'
