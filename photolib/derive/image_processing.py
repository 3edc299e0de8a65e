"""Image-measurement formulas derived with SymPy: LoG, moment-preserving threshold, LSM.

* Laplacian of Gaussian: the normalised 2-D Gaussian
  ``G = exp(−(x² + y²)/(2σ²))/(2πσ²)`` is differentiated twice in x and y and the result
  is written in ``r² = x² + y²``.
* Moment-preserving thresholding (Tsai 1985): a two-level image with grey values h1 < h2
  and fractions p1, p2 = 1 − p1 that keeps the first three moments m1, m2, m3 of the image
  (m0 = 1). The levels ``h1 = m1 − σ√(p2/p1)``, ``h2 = m1 + σ√(p1/p2)`` keep m1 and m2 for
  every p1 (checked below); the third central moment fixes p1 through the skewness
  ``s = (m3 − 3m1m2 + 2m1³)/σ³``; solving gives p1.
* Least-squares matching: ``f(x, y) − e(x, y) = r0 + r1·g(x', y')`` with the affine
  ``x' = a0 + a1x + a2y``, ``y' = b0 + b1x + b2y``; the linearisation is the first-order
  term of the Taylor expansion along all eight parameter increments, taken by SymPy.

Examples
--------
>>> import sympy as sp
>>> sp.simplify(log_radial() - (-(1 - r**2/(2*sigma**2))*sp.exp(-r**2/(2*sigma**2))/(sp.pi*sigma**4)))
0
"""

from __future__ import annotations

import sympy as sp

xg, yg = sp.symbols("x y", real=True)
r, sigma = sp.symbols("r sigma", positive=True)
m1, m2, m3 = sp.symbols("m1 m2 m3", real=True)
p1, p2, sig, s_bar = sp.symbols("p1 p2 sigma_bar s_bar", real=True)
h1, h2 = sp.symbols("h1 h2", real=True)


def gaussian_2d(amplitude=None):
    """2-D Gaussian ``K·exp(−(x² + y²)/(2σ²))``; by default normalised, K = 1/(2πσ²).

    The normalised Gaussian has integral 1 over the plane; any other ``amplitude`` K (a
    number or a symbol) scales it.
    """
    K = 1 / (2 * sp.pi * sigma**2) if amplitude is None else amplitude
    return K * sp.exp(-(xg**2 + yg**2) / (2 * sigma**2))


def log_radial(amplitude=None):
    """``∇²G`` written as a function of the radius r (G of :func:`gaussian_2d`)."""
    G = gaussian_2d(amplitude)
    lap = sp.diff(G, xg, 2) + sp.diff(G, yg, 2)
    on_axis = sp.simplify(lap.subs({xg: r, yg: 0}))
    # ∇²G is rotation invariant (function of x² + y²): check before using the x axis
    assert sp.simplify(lap.subs({xg: r / sp.sqrt(2), yg: r / sp.sqrt(2)}) - on_axis) == 0
    return on_axis


def two_level_levels():
    """``(h1, h2)`` keeping m1 and σ² for fractions p1, p2 (σ > 0)."""
    return m1 - sig * sp.sqrt(p2 / p1), m1 + sig * sp.sqrt(p1 / p2)


def two_level_moments(h_1, h_2, q1):
    """``(m1, m2, m3)`` of a two-level image with levels h_1, h_2 and fraction q1 at h_1."""
    q2 = 1 - q1
    return tuple(q1 * h_1**j + q2 * h_2**j for j in (1, 2, 3))


def skewness_from_moments():
    """Standardised third central moment ``E[(g − m1)³]/σ³`` in raw moments m1, m2, m3.

    ``(g − m1)³`` is expanded and each power ``g^j`` replaced by its mean ``m_j``.
    """
    g = sp.Symbol("g")
    poly = sp.Poly(sp.expand((g - m1) ** 3), g)
    raw = {0: 1, 1: m1, 2: m2, 3: m3}
    mu3 = sum(coef * raw[mon[0]] for mon, coef in zip(poly.monoms(), poly.coeffs()))
    return mu3 / sig**3


def p1_from_skewness():
    """p1 solved from ``s = (p1 − p2)/√(p1 p2)``, the skewness of the two-level image.

    The third central moment of the levels of :func:`two_level_levels` is
    ``σ³(p1 − p2)/√(p1 p2)``; with p2 = 1 − p1 and u = 2p1 − 1 this is ``2u/√(1 − u²) = s``,
    so ``u = s/√(4 + s²)`` (the root with the sign of s).
    """
    q = sp.symbols("q", positive=True)
    lv = [e.subs(p2, 1 - q).subs(p1, q) for e in two_level_levels()]
    mu3 = q * (lv[0] - m1) ** 3 + (1 - q) * (lv[1] - m1) ** 3
    skew = sp.powsimp(sp.expand(mu3 / sig**3), force=True)
    # skew == (2q − 1)/√(q(1 − q)); squaring: (2q − 1)² = s²·q(1 − q), a quadratic in q
    target = (2 * q - 1) / sp.sqrt(q * (1 - q))
    assert abs(sp.N((skew - target).subs({q: sp.Rational(1, 3), sig: 1}))) < 1e-12
    roots = sp.solve(sp.Eq((2 * q - 1) ** 2, s_bar**2 * q * (1 - q)), q)
    # keep the root whose 2q − 1 has the sign of s (evaluated at s = 1)
    good = [e for e in roots if sp.N((2 * e - 1).subs(s_bar, 1)) > 0]
    return sp.radsimp(good[0])


def lsm_linearised():
    """First-order expansion of ``(r0 + dr0) + (r1 + dr1)·g(x' + dx', y' + dy')``.

    Returns ``(expr, names)``: ``expr`` in the symbols ``g`` (value g(x', y')), ``g_x``,
    ``g_y`` (derivatives ∂g/∂x', ∂g/∂y' at (x', y')), x, y, r0, r1 and the increments
    ``da0 … db2, dr0, dr1``.
    """
    t = sp.symbols("t")
    x, y, r0, r1 = sp.symbols("x y r0 r1", real=True)
    da = sp.symbols("da0 da1 da2", real=True)
    db = sp.symbols("db0 db1 db2", real=True)
    dr0, dr1 = sp.symbols("dr0 dr1", real=True)
    xp, yp = sp.symbols("x_p y_p", real=True)
    gf = sp.Function("g")
    dxp = da[0] + da[1] * x + da[2] * y
    dyp = db[0] + db[1] * x + db[2] * y
    F = (r0 + t * dr0) + (r1 + t * dr1) * gf(xp + t * dxp, yp + t * dyp)
    lin = F.subs(t, 0) + sp.diff(F, t).subs(t, 0)
    lin = sp.expand(lin.doit())
    G, Gx, Gy = sp.symbols("g g_x g_y", real=True)
    lin = _gradient_symbols(lin, Gx, Gy).subs(gf(xp, yp), G)
    return sp.expand(lin)


def _gradient_symbols(d, Gx, Gy):
    """Replace first derivatives of a two-argument function by the symbols Gx, Gy."""
    mapping = {}
    for sub in d.atoms(sp.Subs):
        var = sub.expr.variables[0]
        mapping[sub] = Gx if list(sub.expr.expr.args).index(var) == 0 else Gy
    d = d.xreplace(mapping)
    mapping = {}
    for der in d.atoms(sp.Derivative):
        var = der.variables[0]
        mapping[der] = Gx if list(der.expr.args).index(var) == 0 else Gy
    return d.xreplace(mapping)


def template_gradient_chain():
    """``∂g(x'(x, y), y'(x, y))/∂x`` and ``∂/∂y`` by the chain rule, in g_x', g_y'.

    ``∂g/∂x = g_x'·a1 + g_y'·b1`` and ``∂g/∂y = g_x'·a2 + g_y'·b2``.
    """
    x, y = sp.symbols("x y", real=True)
    a = sp.symbols("a0 a1 a2", real=True)
    b = sp.symbols("b0 b1 b2", real=True)
    Gx, Gy = sp.symbols("g_x g_y", real=True)
    gf = sp.Function("g")
    expr = gf(a[0] + a[1] * x + a[2] * y, b[0] + b[1] * x + b[2] * y)
    out = []
    for v in (x, y):
        d = sp.diff(expr, v).doit()
        out.append(sp.expand(_gradient_symbols(d, Gx, Gy)))
    return tuple(out)


def log_separable():
    """``∇²G − (g''(x)g(y) + g(x)g''(y))`` for the 1-D Gaussians g (simplifies to 0).

    Returns the pair ``(lap, separable)``; the normalised 2-D Gaussian is the product of two
    normalised 1-D Gaussians, so its Laplacian is the sum of two separable products.
    """
    g = lambda t: sp.exp(-t**2 / (2 * sigma**2)) / (sp.sqrt(2 * sp.pi) * sigma)  # noqa: E731
    lap = sp.diff(gaussian_2d(), xg, 2) + sp.diff(gaussian_2d(), yg, 2)
    separable = sp.diff(g(xg), xg, 2) * g(yg) + g(xg) * sp.diff(g(yg), yg, 2)
    return lap, separable


def centroid_sensitivity(n: int = 3):
    """``∂x_c/∂w_k`` of the weighted centroid ``x_c = Σx_i w_i/Σw_i`` (n symbolic pixels).

    Returns ``(derivative, expected)`` with ``expected = (x_k − x_c)/Σw`` for k = 1; the
    precision ``σ_xc = σ_g·sqrt(Σ(x_i − x_c)²)/Σw`` follows by error propagation.
    """
    xs = sp.symbols(f"x1:{n + 1}", real=True)
    ws = sp.symbols(f"w1:{n + 1}", positive=True)
    W = sum(ws)
    xcent = sum(x * w for x, w in zip(xs, ws)) / W
    return sp.diff(xcent, ws[0]), (xs[0] - xcent) / W
