"""Numbers for people and for nbval: rounded, without ``-0``, as text or HTML tables."""

from __future__ import annotations

import numpy as np

__all__ = ["matrix_html", "rounded", "show"]


def rounded(value, digits: int = 6):
    """Round to ``digits`` decimals and turn ``-0.0`` into ``0.0``.

    Committed notebook outputs are compared as text, so printed numbers must not carry
    float noise from one machine to the next.

    >>> rounded(np.array([-1e-17, 0.12345678]))
    array([0.      , 0.123457])
    """
    return np.round(np.asarray(value, dtype=float), digits) + 0.0


def show(name: str, value, digits: int = 6) -> None:
    """Print ``name = value`` with the value rounded (see :func:`rounded`).

    >>> show("R", np.eye(2))
    R =
    [[1. 0.]
     [0. 1.]]
    >>> show("c", 35.0000000001)
    c = 35.0
    """
    v = rounded(value, digits)
    if v.ndim >= 2:
        print(f"{name} =\n{v}")
    elif v.ndim == 0:
        print(f"{name} = {float(v)!r}")
    else:
        print(f"{name} = {v}")


def matrix_html(M, caption: str = "", digits: int = 4) -> str:
    """A small HTML table of a matrix, for the widgets' text panel.

    >>> "<table" in matrix_html(np.eye(3), "R")
    True
    """
    M = rounded(M, digits)
    rows = "".join("<tr>" + "".join(f"<td style='text-align:right;padding:0 6px'>{v:+.{digits}f}</td>"
                                    for v in row) + "</tr>" for row in M)
    cap = f"<div>{caption}</div>" if caption else ""
    return f"{cap}<table style='font-family:monospace'>{rows}</table>"
