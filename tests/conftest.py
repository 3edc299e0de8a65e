"""Shared pytest configuration: the ``--update-generated`` option of the codegen sync test, the
``close_figures`` fixture of the notebook-helper tests, and a summary line counting the tests a
``-m`` expression deselected by marker (``make test-fast`` deselects ``slow`` and ``browser``)."""

from __future__ import annotations

import pytest

#: marker -> number of tests deselected that carry it (``browser`` first, then ``slow``)
_DESELECTED = pytest.StashKey[dict]()
_COUNTED_MARKERS = ("browser", "slow")


def pytest_addoption(parser):
    parser.addoption("--update-generated", action="store_true", default=False,
                     help="rewrite photolib/_generated from photolib/derive instead of diffing")


@pytest.fixture
def close_figures():
    """Close every Matplotlib figure after the test (``pytest.mark.usefixtures``)."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def pytest_deselected(items):
    """Count the deselected tests by marker; an xdist worker passes its counts to the controller."""
    if not items:
        return
    config = items[0].config
    counts = config.stash.setdefault(_DESELECTED, {})
    for item in items:
        name = next((m for m in _COUNTED_MARKERS if item.get_closest_marker(m)), "other")
        counts[name] = counts.get(name, 0) + 1
    if hasattr(config, "workeroutput"):
        config.workeroutput["deselected_by_marker"] = dict(counts)


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    """xdist controller: every worker collects (and deselects) the same tests; keep one count."""
    counts = getattr(node, "workeroutput", {}).get("deselected_by_marker")
    if counts:
        node.config.stash[_DESELECTED] = counts


def pytest_terminal_summary(terminalreporter, config):
    counts = config.stash.get(_DESELECTED, {})
    if counts:
        parts = [f"{counts[m]} marked {m}" for m in (*_COUNTED_MARKERS, "other") if counts.get(m)]
        by = " ".join(f"{flag} {value!r}" for flag, value in
                      (("-m", config.getoption("markexpr")), ("-k", config.getoption("keyword")))
                      if value)
        terminalreporter.write_line(f"deselected{f' by {by}' if by else ''}: "
                                    f"{sum(counts.values())} tests, " + ", ".join(parts))
