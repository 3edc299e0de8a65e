"""Image-matching formulas derived with SymPy: the subpixel parabola and the RANSAC count.

* Subpixel peak: the parabola ``c(δ) = α δ² + β δ + γ`` through (−1, c₋), (0, c₀), (1, c₊)
  is solved for α, β, γ; its vertex ``δ = −β/(2α)`` is
  ``(c₋ − c₊)/(2(c₋ − 2c₀ + c₊))`` — for a correlation maximum and a cost minimum alike.
* RANSAC: a sample of s points drawn from inliers of share ``w = 1 − ε`` is clean with
  probability ``w^s``; all N samples are contaminated with ``(1 − w^s)^N``. Setting this to
  ``1 − p`` and solving for N gives ``N = log(1 − p)/log(1 − (1 − ε)^s)``.

Examples
--------
>>> import sympy as sp
>>> sp.simplify(parabola_vertex() - (cm - cp) / (2 * (cm - 2 * c0 + cp)))
0
"""

from __future__ import annotations

import sympy as sp

cm, c0, cp, delta = sp.symbols("c_minus c_0 c_plus delta", real=True)
p, eps = sp.symbols("p epsilon", positive=True)
s, N = sp.symbols("s N", positive=True)


def parabola_vertex():
    """δ of the vertex of the parabola through (−1, c₋), (0, c₀), (1, c₊), solved by SymPy."""
    a, b, g = sp.symbols("alpha beta gamma", real=True)
    par = a * delta**2 + b * delta + g
    sol = sp.solve([par.subs(delta, -1) - cm, par.subs(delta, 0) - c0, par.subs(delta, 1) - cp],
                   [a, b, g], dict=True)[0]
    vertex = sp.solve(sp.diff(par, delta), delta)[0]
    return sp.simplify(vertex.subs(sol))


def ransac_trials():
    """N from ``(1 − (1 − ε)^s)^N = 1 − p``, solved by SymPy (before rounding up)."""
    sol = sp.solve(sp.Eq(N * sp.log(1 - (1 - eps) ** s), sp.log(1 - p)), N)
    return sol[0]
