"""The shared behaviour of the course's interactive widgets: controls → ``update``.

:class:`_Controls` is the plumbing of every widget (the slider explorers of
:class:`photolib.nb.live.Explorer` too); :class:`HtmlTableExplorer` adds the interactive HTML
tables (glossary, errata verdicts).

No ipywidgets import here: the errata module uses it without the notebook extras loaded.
"""

from __future__ import annotations


class _Controls:
    """Controls (``self.controls``, name → widget) whose every change calls ``update()``.

    A subclass defines ``update()`` and calls :meth:`_connect` once its widgets exist.
    """

    def _connect(self) -> None:
        """Call :meth:`update` on every change of a control's value, and once now."""
        for control in self.controls.values():
            control.observe(self._on_change, names="value")
        self.update()

    def values(self) -> dict:
        """The current control values, by name."""
        return {name: c.value for name, c in self.controls.items()}

    def _on_change(self, change) -> None:
        self.update()


class HtmlTableExplorer(_Controls):
    """Controls whose every change re-renders one HTML table: the glossary's and the errata's.

    A subclass sets ``self.controls`` (name → widget), ``self.html`` and ``self.widget``, defines
    ``render(**values) -> str`` and calls :meth:`_connect` at the end of ``__init__``.
    """

    def update(self) -> str:
        """Recompute the table from the current controls; returns the HTML."""
        self.html.value = self.render(**self.values())
        return self.html.value

    def _ipython_display_(self):
        from IPython.display import display

        display(self.widget)
