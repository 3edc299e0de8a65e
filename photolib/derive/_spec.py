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
    """

    name: str
    args: tuple
    outputs: tuple
    doc: str

    @property
    def exprs(self) -> list[sp.Expr]:
        return [sp.sympify(e) for _, e in self.outputs]

    @property
    def output_names(self) -> list[str]:
        return [n for n, _ in self.outputs]
