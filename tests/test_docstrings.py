"""Every public function of photolib documents itself in numpydoc form, with a doctest.

Issue 2: "Every public function has a numpydoc docstring with units, shapes, the formula and
a doctest." This checks the form that can be checked mechanically: the sections a reader
looks for, every parameter named in Parameters, and an example that pytest's doctest run
executes (``--doctest-modules photolib`` in ``make test``).
"""

from __future__ import annotations

import inspect
import re

import pytest

import photolib as pl

FUNCTIONS = sorted(n for n in pl.__all__ if inspect.isfunction(getattr(pl, n)))


def _sections(doc: str) -> dict[str, str]:
    """numpydoc sections: title -> body (a title is a line underlined with dashes)."""
    parts = re.split(r"^(\w[\w ]*)\n-{3,}\s*$", doc, flags=re.M)
    return {parts[i].strip(): parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def test_the_public_api_is_not_empty():
    assert len(FUNCTIONS) > 80


@pytest.mark.parametrize("name", FUNCTIONS)
def test_public_function_has_numpydoc_sections_and_a_doctest(name):
    func = getattr(pl, name)
    doc = inspect.getdoc(func) or ""
    assert doc.strip(), f"{name} has no docstring"
    sections = _sections(doc)
    params = [p for p in inspect.signature(func).parameters.values()
              if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    if params:
        assert "Parameters" in sections, f"{name}: no Parameters section"
        body = sections["Parameters"]
        for p in params:
            # numpydoc allows several names on one line: "x0, y0 : float"
            assert re.search(rf"^\s*(\w+, )*\*?{p.name}\b[\w, ]*( :|$)", body, flags=re.M), \
                f"{name}: parameter {p.name!r} is not described in Parameters"
    assert "Returns" in sections or "Yields" in sections, f"{name}: no Returns section"
    assert ">>>" in doc, f"{name}: no doctest example"
