"""JupyterLab server and headless Chromium for the browser tests (marker ``browser``).

The server runs on a copy of ``notebooks/`` in a temporary directory, so executed
outputs never touch the repository. Where Chromium or Playwright is missing, the tests
skip with the reason (the Makefile runs them with ``pytest -rs -m browser``).
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
CHROMIUM = Path(os.environ.get("PHOTOLIB_CHROMIUM", "/usr/bin/chromium"))
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
ARTIFACTS = REPO / "test-artifacts" / "browser"
SCREENSHOTS = REPO / "test-artifacts" / "screenshots"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str, timeout: float = 5.0) -> int:
    with urllib.request.urlopen(url, timeout=timeout) as response:
        return response.status


@pytest.fixture(scope="session")
def lab_root(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("lab")


@pytest.fixture(scope="session")
def lab_log(lab_root) -> Path:
    """The JupyterLab server's log (quoted when a browser test fails)."""
    return lab_root / "jupyter.log"


@pytest.fixture(scope="session")
def lab_url(lab_root, lab_log):
    """Start JupyterLab on a copy of the notebooks; yield its base URL."""
    root = lab_root
    shutil.copytree(REPO / "notebooks", root / "notebooks")
    # the student copies, as a student opens them (they link to ../notebooks)
    shutil.copytree(REPO / "exercises", root / "exercises")
    # the solution masters: test_rerun runs them as an instructor does
    shutil.copytree(REPO / "solutions", root / "solutions")
    # cells outside the viewport are not in the DOM under JupyterLab 4's default
    # windowing; render them all so that every widget can be found and moved
    settings = root / "settings" / "@jupyterlab" / "notebook-extension"
    settings.mkdir(parents=True)
    (settings / "tracker.jupyterlab-settings").write_text('{"windowingMode": "none"}')
    # no "notified about official Jupyter news?" toast over the screenshots
    news = root / "settings" / "@jupyterlab" / "apputils-extension"
    news.mkdir(parents=True)
    (news / "notification.jupyterlab-settings").write_text('{"fetchNews": "false"}')
    port = _free_port()
    log = open(lab_log, "w")  # noqa: SIM115 - lives as long as the server
    proc = subprocess.Popen(
        [sys.executable, "-m", "jupyter", "lab", "--no-browser", "--ServerApp.ip=127.0.0.1",
         f"--ServerApp.port={port}", "--ServerApp.port_retries=0",
         "--IdentityProvider.token=", "--ServerApp.password=", "--ServerApp.disable_check_xsrf=True",
         f"--ServerApp.root_dir={root}", f"--LabApp.user_settings_dir={root / 'settings'}",
         f"--LabApp.workspaces_dir={root / 'workspaces'}", "--LabApp.expose_app_in_browser=True",
         "--LabApp.news_url=", "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate"]
        + (["--allow-root"] if hasattr(os, "geteuid") and os.geteuid() == 0 else []),
        stdout=log, stderr=subprocess.STDOUT, cwd=root)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                if _get(f"{url}/api/status") == 200:
                    break
            except OSError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                log.flush()
                pytest.fail("JupyterLab did not start:\n" + lab_log.read_text()[-3000:])
            time.sleep(0.5)
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
        log.close()


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium (Debian's /usr/bin/chromium) through Playwright, or a skip."""
    if not CHROMIUM.exists():
        pytest.skip(f"Chromium not installed at {CHROMIUM} (apt-get install -y chromium, "
                    "or set PHOTOLIB_CHROMIUM)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture(scope="session")
def artifacts() -> Path:
    """``test-artifacts/browser`` (gitignored), where the screenshots go."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    return ARTIFACTS


def _shutdown_kernels(url: str) -> None:
    """Delete every session (and its kernel), so chapters do not pile up kernels."""
    import json
    with urllib.request.urlopen(f"{url}/api/sessions", timeout=10) as response:
        sessions = json.load(response)
    for s in sessions:
        req = urllib.request.Request(f"{url}/api/sessions/{s['id']}", method="DELETE")
        urllib.request.urlopen(req, timeout=30).close()


@pytest.fixture(scope="session")
def screenshots() -> Path:
    """``test-artifacts/screenshots`` (gitignored): what a student sees, at device scale 2."""
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    return SCREENSHOTS


@pytest.fixture
def hidpi_page(browser, lab_url):
    """A page as on a HiDPI laptop: device scale factor 2 (two device pixels per CSS pixel)."""
    context = browser.new_context(viewport={"width": 1400, "height": 1000}, device_scale_factor=2)
    p = context.new_page()
    try:
        yield p
    finally:
        context.close()
        _shutdown_kernels(lab_url)


@pytest.fixture
def page(browser, lab_url):
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    p = context.new_page()
    try:
        yield p
    finally:
        context.close()
        _shutdown_kernels(lab_url)
