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


# -- chapter 10: bundle adjustment ----------------------------------------------------------------

def similarity_parameters() -> int:
    """Datum defect of a free network: the rank of ∂(m·R·X + t)/∂(t, rotation, m) at m = 1,
    R = I for a generic set of points (three translations, three rotations, one scale).

    >>> similarity_parameters()
    7
    """
    t = sp.symbols("t1:4")
    a = sp.symbols("a1:4")
    m = sp.Symbol("m")
    W = sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    params = (*t, *a, m)
    rows = []
    for X in ([0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [2, 3, 5]):
        Xv = sp.Matrix(X)
        image = (1 + m) * (sp.eye(3) + W) * Xv + sp.Matrix(t)   # first order at m = 0, W = 0
        J = image.jacobian(params).subs({p: 0 for p in params})
        rows.extend(J.tolist())
    return sp.Matrix(rows).rank()


def datum_defect(datum: str = "free") -> int:
    """7 for a free network (similarity), 0 for a datum by ≥ 3 control points."""
    if datum == "free":
        return similarity_parameters()
    if datum == "control":
        return 0
    raise ValueError(f"datum must be 'free' or 'control', got {datum!r}")


def block_redundancy(images: int, points: int, rays: int, control: int = 0,
                     interior: int = 0, datum: str = "control") -> dict:
    """Counts of a bundle block: ``n = 2·rays``, ``u = 6·images + 3·(points − control) +
    interior`` (control points fixed), ``d`` and ``r = n − u + d``.

    >>> block_redundancy(2, 10, 20, control=4)
    {'n': 40, 'u': 30, 'd': 0, 'r': 10}
    """
    if min(images, points, rays, control, interior) < 0 or control > points:
        raise ValueError("counts must be non-negative and control ≤ points")
    n = 2 * rays
    u = bundle_unknowns(images, points - control) + interior
    d = datum_defect(datum)
    return {"n": n, "u": u, "d": d, "r": n - u + d}


def redundancy_trace(n: int = 3, u: int = 2):
    """``trace(I − A (AᵀA)⁻¹ Aᵀ)`` for a symbolic n×u design matrix A (SymPy, cancelled).

    The redundancy numbers r_k = (Q_vv P)_kk (P = I) sum to n − u.

    >>> redundancy_trace(3, 2)
    1
    """
    A = sp.Matrix(n, u, sp.symbols(f"a0:{n * u}"))
    N = A.T * A
    H = A * N.adjugate() * A.T / N.det()
    return sp.cancel(sp.trace(sp.eye(n) - H))


def normal_contribution(u: int = 3):
    """``(aᵀa, aᵀl)`` of one observation row ``a`` (1×u) with reduced observation l:
    the observation's contribution to the normal equations ``N = Σ aᵀa``, ``n = Σ aᵀl``.

    >>> N, b = normal_contribution(2)
    >>> N.shape, b.shape
    ((2, 2), (2, 1))
    """
    a = sp.Matrix(1, u, sp.symbols(f"a1:{u + 1}"))
    lv = sp.Symbol("l")
    return a.T * a, a.T * lv


def tau_from_t():
    """Pope's τ as a function of Student's t with r − 1 degrees of freedom.

    With ``w`` the standardised residual, ``Ω'`` the sum of squares of the *other*
    observations and ``σ̂0² = (w² + Ω')/r`` (σ = 1): ``τ² = r·w²/(w² + Ω')`` and
    ``t² = (r − 1)·w²/Ω'``. Eliminating Ω' gives ``τ = t·√r/√(r − 1 + t²)``.

    >>> tau_from_t()
    sqrt(r)*t/sqrt(r + t**2 - 1)
    """
    w, om, r, t = sp.symbols("w Omega r t", positive=True)
    tau2 = r * w**2 / (w**2 + om)
    om_t = sp.solve(sp.Eq(t**2, (r - 1) * w**2 / om), om)[0]
    return sp.sqrt(r) * t / sp.sqrt(sp.factor(sp.cancel(r * t**2 / tau2.subs(om, om_t))))


def t_quantile(alpha, nu, digits: int = 30):
    """Two-sided critical value k with ``P(|T_ν| > k) = alpha`` (mpmath root of :func:`t_tail`)."""
    with mpmath.workdps(digits):
        f = lambda k: t_tail(k, nu) - mpmath.mpf(alpha)  # noqa: E731 - falls in k
        lo, hi = mpmath.mpf(0), mpmath.mpf(1)
        while f(hi) > 0:
            lo, hi = hi, 2 * hi
        return mpmath.findroot(f, (lo, hi), solver="illinois")
