"""What every explorer test asks of a widget, written once for the ``tests/test_nb*.py`` files.

Import relatively (``from .explorer_checks import moves``): under ``--import-mode=importlib``
the test modules are ``tests.test_nb_*`` and this module is ``tests.explorer_checks``. The
figures are closed after each test by the ``close_figures`` fixture of ``tests/conftest.py``.
"""

from __future__ import annotations

import time


def moves(explorer, name, value):
    """Set slider ``name`` to ``value``: (did the PNG change, did the text change)."""
    before_png, before_html = explorer.live.png, explorer.html.value
    explorer.controls[name].value = value
    return explorer.live.png != before_png, explorer.html.value != before_html


def fastest_update(explorer, name, values):
    """The shortest time, in seconds, of setting slider ``name`` to each of ``values`` in turn."""
    best = float("inf")
    for value in values:
        t = time.perf_counter()
        explorer.controls[name].value = value
        best = min(best, time.perf_counter() - t)
    return best


def assert_update_is_fast(cls, name, values, *, repeats=5, bound=0.25):
    """A fresh ``cls()`` redraws for slider ``name`` (``values`` set ``repeats`` times over) in
    less than ``bound`` seconds at best. The target is 50 ms (benchmarks/bench_widgets.py:
    about 15-30 ms measured); the default bound only catches a redraw of the whole figure and
    tolerates a loaded test machine."""
    assert fastest_update(cls(), name, tuple(values) * repeats) < bound


def assert_explorer_widget(explorer, title):
    """The widget shows as ``[widget: title]`` and carries the ``photolib-explorer`` class."""
    assert repr(explorer.widget) == f"[widget: {title}]"
    assert "photolib-explorer" in explorer.widget._dom_classes
