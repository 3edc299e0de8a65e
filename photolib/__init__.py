"""photolib: the numeric library of the photogrammetry course.

``import photolib`` loads NumPy only (no SymPy, no matplotlib). The formulas are derived
in :mod:`photolib.derive` with SymPy and generated as NumPy code into
:mod:`photolib._generated`; the modules below wrap that code with shape checks,
clear errors and the conventions of ``docs/conventions.md``.
"""

from __future__ import annotations

__version__ = "0.1.0"
