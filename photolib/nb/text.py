"""Numbers for people and for nbval: rounded, without ``-0``, as text or HTML tables; SymPy
results as LaTeX (:func:`formulas`)."""

from __future__ import annotations

import numpy as np

__all__ = ["Formulas", "formulas", "matrix_html", "rounded", "show"]


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


class Formulas:
    """Several SymPy results shown as one line of LaTeX; see :func:`formulas`.

    The plain-text form (what nbval compares, and what a terminal shows) is IPython's
    pretty form of the tuple, as a bare tuple of the results would print.
    """

    def __init__(self, *exprs):
        self.exprs = exprs

    def _repr_latex_(self) -> str:
        import sympy as sp

        return "$\\displaystyle " + r",\quad ".join(sp.latex(e) for e in self.exprs) + "$"

    def __repr__(self) -> str:
        from IPython.lib.pretty import pretty

        return pretty(self.exprs[0] if len(self.exprs) == 1 else self.exprs)


def formulas(*exprs) -> Formulas:
    r"""Show SymPy results (matrices, equations, expressions) side by side as LaTeX.

    A cell ending in a tuple ``R_w, R_p, R_k`` or a list of ``Eq`` shows plain text: IPython
    renders a SymPy object as LaTeX only when it stands alone. ``nb.formulas(R_w, R_p, R_k)``
    renders all of them, separated by commas.

    >>> import sympy as sp
    >>> f = formulas(sp.Eq(sp.Symbol("a"), 1), sp.Matrix([[1, 0]]))
    >>> print(f._repr_latex_())
    $\displaystyle a = 1,\quad \left[\begin{matrix}1 & 0\end{matrix}\right]$
    >>> f
    (Eq(a, 1), Matrix([[1, 0]]))
    """
    return Formulas(*exprs)
