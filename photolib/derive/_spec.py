"""The small record a derive module uses to ask for a generated NumPy function."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class GeneratedFunction:
    """One NumPy function to generate.

    Parameters
    ----------
    name : str
        Function name in the generated module.
    args : tuple of sympy.Symbol
        Positional arguments, in this order.
    outputs : tuple of (str, sympy.Expr)
        Named outputs; the generated function returns them as a tuple in this order.
    doc : str
        One-paragraph docstring (units and meaning).
    intermediates : tuple of (sympy.Symbol, sympy.Expr)
        Named quantities of the derivation (e.g. r², a polynomial in Horner form), computed in
        this order before the outputs; the outputs may use their symbols. :meth:`full_exprs`
        substitutes them back, which is what the lambdify test compares against.
    """

    name: str
    args: tuple
    outputs: tuple
    doc: str
    intermediates: tuple = ()

    @property
    def exprs(self) -> list[sp.Expr]:
        return [sp.sympify(e) for _, e in self.outputs]

    @property
    def full_exprs(self) -> list[sp.Expr]:
        """Outputs with every intermediate symbol replaced by its expression."""
        out = self.exprs
        for sym, expr in reversed(self.intermediates):
            out = [e.xreplace({sym: expr}) for e in out]
        return out

    @property
    def output_names(self) -> list[str]:
        return [n for n, _ in self.outputs]
