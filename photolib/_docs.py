"""Shared pieces of numpydoc docstrings: one text for what several functions document alike.

A docstring marks the place of a shared piece by a line holding only ``{name}``; the
decorator :func:`shared_doc` puts the piece there, every line indented as the marker. Help,
Sphinx and doctest read ``__doc__`` and see the whole text.
"""

from __future__ import annotations

import re

__all__ = ["shared_doc"]


def shared_doc(**pieces: str):
    """Decorator: replace each marker line ``{name}`` of the docstring by ``pieces[name]``.

    ``pieces`` are written without the docstring's indentation (relative indentation kept);
    each line gets the marker's indentation. A piece with no marker, or a marker with no
    piece, raises ``ValueError`` naming it (at import, so a typo cannot pass unnoticed).

    >>> @shared_doc(size="width : int\\n    Image width, px.")
    ... def f(width):
    ...     '''Example.
    ...
    ...     Parameters
    ...     ----------
    ...     {size}
    ...     '''
    >>> print(f.__doc__.splitlines()[4:6])
    ['    width : int', '        Image width, px.']
    """
    def decorate(func):
        doc = func.__doc__ or ""
        marker = re.compile(r"^([ \t]*)\{(\w+)\}[ \t]*$", re.M)
        names = {m.group(2) for m in marker.finditer(doc)}
        if names - pieces.keys():
            raise ValueError(f"{func.__qualname__}: no shared piece for {sorted(names - pieces.keys())}")
        if pieces.keys() - names:
            raise ValueError(f"{func.__qualname__}: no marker for {sorted(pieces.keys() - names)}")
        func.__doc__ = marker.sub(
            lambda m: "\n".join(m.group(1) + line if line else ""
                                for line in pieces[m.group(2)].split("\n")), doc)
        return func
    return decorate
