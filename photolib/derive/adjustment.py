"""Counting and probability for adjustments: unknowns, redundancy, the t-distribution.

* Exterior orientation of one image: a rigid motion of space, whose number of parameters
  is the dimension of its Lie algebra: 3 (skew-symmetric 3×3 generators, counted here)
  plus 3 translations. An object point has 3 coordinates. So a bundle block with fixed
  interior orientation has ``u = 6·images + 3·points`` unknowns; redundancy ``r = n − u``.
* Student's t: ``P(|T_ν| > k) = I_{ν/(ν + k²)}(ν/2, 1/2)`` (regularised incomplete beta),
  evaluated with mpmath; the normal limit is ``erfc(k/√2)``.

Examples
--------
>>> rigid_motion_parameters()
6
>>> bundle_unknowns(2, 10)
42
"""

from __future__ import annotations

import mpmath
import sympy as sp


def skew_generators() -> int:
    """Dimension of the space of skew-symmetric 3×3 matrices (rotation parameters)."""
    entries = sp.Matrix(3, 3, sp.symbols("w0:9"))
    eqs = list(entries + entries.T)
    sol = sp.solve(eqs, list(entries), dict=True)[0]
    return len(entries.free_symbols - set(sol.keys()))


def rigid_motion_parameters() -> int:
    """Rotation parameters plus three translations."""
    return skew_generators() + 3


def bundle_unknowns(images: int, points: int, interior_per_image: int = 0) -> int:
    """``u = images·(6 + interior) + 3·points``."""
    if images < 0 or points < 0:
        raise ValueError(f"counts must be non-negative, got images={images}, points={points}")
    return images * (rigid_motion_parameters() + interior_per_image) + 3 * points


def t_tail(k, nu):
    """``P(|T_ν| > k)`` for Student's t with ν degrees of freedom (ν = inf: normal)."""
    k = mpmath.mpf(k)
    if nu == mpmath.inf or nu == float("inf"):
        return mpmath.erfc(k / mpmath.sqrt(2))
    nu = mpmath.mpf(nu)
    return mpmath.betainc(nu / 2, mpmath.mpf(1) / 2, 0, nu / (nu + k**2), regularized=True)


def t_tail_monotone_in_dof(ks=None, nus=None):
    """Check that ``P(|T_ν| > k)`` falls as ν grows, on a grid; return the worst step.

    Returns ``(ok, (k, ν1, ν2, P1, P2))`` where the tuple is the grid step with the smallest
    decrease ``P(ν1) − P(ν2)`` (ν1 < ν2).
    """
    ks = ks or [0.25 * i for i in range(1, 17)]
    nus = nus or [1, 2, 3, 4, 5, 7, 10, 15, 20, 30, 50, 100, 1000, mpmath.inf]
    worst = None
    with mpmath.workdps(30):
        for k in ks:
            vals = [t_tail(k, nu) for nu in nus]
            for i in range(len(nus) - 1):
                step = vals[i] - vals[i + 1]
                if worst is None or step < worst[0]:
                    worst = (step, (k, nus[i], nus[i + 1], vals[i], vals[i + 1]))
    return worst[0] > 0, worst[1]


def grey_levels(bits: int) -> int:
    """Number of distinct values of ``bits`` binary digits (counted by enumeration up to 16)."""
    if not 0 < bits <= 16:
        raise ValueError(f"bits must be in 1..16, got {bits}")
    return len({tuple((v >> i) & 1 for i in range(bits)) for v in range(1 << bits)})
