"""Deprecated: the errata chapter's callbacks moved to :mod:`photolib.errata.evaluate`, its
widgets to :mod:`photolib.nb.errata` (UI belongs in ``photolib.nb``). The old names still
import from here for one release, with a ``DeprecationWarning``.
"""

from __future__ import annotations

import importlib
import warnings

_WIDGETS = {"build_widget", "VerdictExplorer"}


def __getattr__(name: str):
    if name.startswith("__"):
        raise AttributeError(name)
    new = "photolib.nb.errata" if name in _WIDGETS else "photolib.errata.evaluate"
    module = importlib.import_module(new)
    if not hasattr(module, name):
        raise AttributeError(f"module 'photolib.errata.widgets' has no attribute {name!r}")
    warnings.warn(f"photolib.errata.widgets.{name} moved to {new}.{name}; the old place goes "
                  "in the next release", DeprecationWarning, stacklevel=2)
    return getattr(module, name)
