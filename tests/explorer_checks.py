"""What every explorer test asks of a widget, written once for the ``tests/test_nb*.py`` files.

Import relatively (``from .explorer_checks import moves``): under ``--import-mode=importlib``
the test modules are ``tests.test_nb_*`` and this module is ``tests.explorer_checks``. The
figures are closed after each test by the ``close_figures`` fixture of ``tests/conftest.py``.
"""

from __future__ import annotations


def moves(explorer, name, value):
    """Set slider ``name`` to ``value``: (did the PNG change, did the text change)."""
    before_png, before_html = explorer.live.png, explorer.html.value
    explorer.controls[name].value = value
    return explorer.live.png != before_png, explorer.html.value != before_html


def assert_every_value_redraws(cls, name, values):
    """A fresh ``cls()`` redraws (figure or text) each time slider ``name`` moves to the next of
    ``values``. How fast it redraws is measured in ``benchmarks/bench_widgets.py`` (target
    50 ms), not here: a timed test would only measure how busy the test machine is."""
    explorer = cls()
    for value in values:
        if explorer.controls[name].value == value:
            continue
        assert any(moves(explorer, name, value)), f"{cls.__name__}: {name} = {value!r} redrew nothing"


def assert_explorer_widget(explorer, title):
    """The widget shows as ``[widget: title]`` and carries the ``photolib-explorer`` class."""
    assert repr(explorer.widget) == f"[widget: {title}]"
    assert "photolib-explorer" in explorer.widget._dom_classes
