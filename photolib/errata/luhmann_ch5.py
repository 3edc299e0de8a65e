"""Luhmann errata of chapter 5: LoG (5.42), moment-preserving threshold (5.49/5.50), LSM.

Symbols: ``sigma_bar`` is σ̄, ``s_bar`` s̄; in 5.72 ``g`` is the grey value g(x', y') of the
search image at the current parameters, ``g_x, g_y`` its derivatives by x', y'; ``g0`` in the
old print is read as the same g(x', y').
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import image_processing as ip
from photolib.errata._record import VersionSpec, figure, formula

SRC = "002_b1d9e6507973e20d.txt (Luhmann errata list, 11.7.2017)"
r, sigma = ip.r, ip.sigma
m1, m2, m3, p1, p2, sig, s_bar = ip.m1, ip.m2, ip.m3, ip.p1, ip.p2, ip.sig, ip.s_bar
x, y, r0, r1 = sp.symbols("x y r0 r1", real=True)
da = sp.symbols("da0 da1 da2", real=True)
db = sp.symbols("db0 db1 db2", real=True)
dr0, dr1 = sp.symbols("dr0 dr1", real=True)
G, Gx, Gy = sp.symbols("g g_x g_y", real=True)
a = sp.symbols("a0 a1 a2", real=True)
b = sp.symbols("b0 b1 b2", real=True)


def _lsm(old: bool):
    geo = (Gx * da[0] + Gx * x * da[1] + Gx * y * da[2] + Gy * db[0] + Gy * x * db[1]
           + Gy * y * db[2])
    if old:
        return G + geo + dr0 + dr1 * G
    return r0 + r1 * G + r1 * geo + dr0 + dr1 * G


def _taylor_gradient():
    """(∂g/∂x', ∂g/∂y') as they appear in 5.72: coefficients of da0 and db0 over r1."""
    lin = ip.lsm_linearised()
    return sp.Matrix([sp.cancel(lin.coeff(da[0]) / r1), sp.cancel(lin.coeff(db[0]) / r1)])


#: 5.73: the corrected print's g_x', g_y' (∂g/∂x', ∂g/∂y', by the search coordinates); the
#: old print's g_x, g_y (∂g⁰/∂x, ∂g⁰/∂y, by the template coordinates) are ``Gx, Gy``
Gxp, Gyp = sp.symbols("g_xp g_yp", real=True)


def _to_primed(e):
    """Rename photolib.derive's g_x, g_y (there: ∂g/∂x', ∂g/∂y') to g_xp, g_yp."""
    return e.xreplace({Gx: Gxp, Gy: Gyp})


def _taylor_gradient_primed():
    """The gradient 5.72 needs, (∂g/∂x', ∂g/∂y'), in the corrected 5.73's symbols."""
    return _to_primed(_taylor_gradient())


def _old_573_meaning():
    """Old 5.73: g_x = ∂g⁰(x, y)/∂x with g⁰(x, y) = g(x'(x, y), y'(x, y)), by the chain rule."""
    dgx, dgy = (_to_primed(d) for d in ip.template_gradient_chain())
    return {Gx: dgx, Gy: dgy}


OLD_572 = ("right-under-condition: r0 = 0, r1 = 1 (the radiometric start values) and, "
           "because the old 5.73 defines g_x, g_y by the template coordinates (x, y), "
           "a1 = b2 = 1, a2 = b1 = 0 (see luhmann:5.73): the first iteration")


def records():
    rr = []
    e = sp.exp(-r**2 / (2 * sigma**2))
    K = sp.Symbol("K", positive=True)   # amplitude of the Gaussian; 5.41 is not in the list
    norm = {K: 1 / (2 * sp.pi * sigma**2)}
    rr.append(formula(
        "luhmann:5.42", SRC + ", p. 413, formula 5.42", "Laplacian of Gaussian",
        {"old": VersionSpec("wrong", expr=lambda: -(1 - r / sigma**2) * e, claim="wrong"),
         "corrected": VersionSpec(
             "right-under-condition: G normalised, G = exp(−r²/(2σ²))/(2πσ²) (the Gaussian "
             "5.41 is not in the errata list; for G = exp(−r²/(2σ²)) the print is 2πσ² times "
             "too small)", expr=lambda: -(1 - r**2 / (2 * sigma**2)) * e / (sp.pi * sigma**4),
             condition=norm, claim="right",
             condition_text="G normalised, G = exp(−r²/(2σ²))/(2πσ²) (the Gaussian 5.41 is not "
                            "in the errata list; for G = exp(−r²/(2σ²)) the print is 2πσ² times "
                            "too small)")},
        derivation=lambda: ip.log_radial(K),
        steps=("G = K·exp(−(x² + y²)/(2σ²)), K the amplitude (normalised: K = 1/(2πσ²))",
               "∇²G = ∂²G/∂x² + ∂²G/∂y², written in r (rotation invariant)",
               "= K·(r² − 2σ²)·exp(−r²/(2σ²))/σ⁴; with K = 1/(2πσ²): "
               "−(1 − r²/(2σ²))·exp(−r²/(2σ²))/(πσ⁴)"),
        note="The old print has r instead of r²/2 and no normalisation; even up to a factor "
             "its zero crossing (r = σ²) is wrong (r = √2·σ). The corrected print holds for the "
             "normalised Gaussian only."))
    h1_old = m1 - sig * sp.sqrt(p2 / p1)
    rr.append(formula(
        "luhmann:5.49-h1", SRC + ", p. 420, formula 5.49 (old print)", "moment-preserving "
        "threshold: lower level h1",
        {"old": VersionSpec("right-under-condition: p2 = 1 − p1 (p2 undefined in the old "
                            "print)", expr=lambda: h1_old, condition={p2: 1 - p1},
                            condition_text="p2 = 1 − p1 (p2 undefined in the old print)",
                            claim="wrong")},
        derivation=lambda: ip.two_level_levels()[0].subs(p2, 1 - p1),
        domain=lambda: {p1: (0.05, 0.95), sig: (0.1, 3.0)},
        steps=("two levels h1 < h2 with fractions p1, p2 = 1 − p1 keep m1 and σ² iff "
               "h1 = m1 − σ√(p2/p1), h2 = m1 + σ√(p1/p2) (checked by the moments)",),
        note="The old h1 is right once p2 = 1 − p1 is stated, as the correction does. The "
             "layout of the list is ambiguous: h1 is printed once, under 'alte Fassung' after "
             "the remark that p2 was not defined; the 'richtig' block prints h2, p1 and "
             "p2 = 1 − p1 but not h1 again. The correction most likely keeps h1 unchanged "
             "(with p2 now defined it is right), but as no corrected h1 is printed, the "
             "record has no 'corrected' version."))
    rr.append(formula(
        "luhmann:5.49-h2", SRC + ", p. 420, formula 5.49", "moment-preserving threshold: "
        "upper level h2",
        {"corrected": VersionSpec("right", expr=lambda: m1 + sig * sp.sqrt(p1 / p2),
                                  claim="right")},
        derivation=lambda: ip.two_level_levels()[1],
        domain=lambda: {p1: (0.05, 0.95), p2: (0.05, 0.95), sig: (0.1, 3.0)}))
    rr.append(formula(
        "luhmann:5.50-p1", SRC + ", p. 420, formula 5.50", "moment-preserving threshold: "
        "fraction p1 from the skewness",
        {"corrected": VersionSpec("wrong", expr=lambda: (1 + s_bar * sp.sqrt(4 + s_bar**2)) / 2,
                                  claim="right")},
        derivation=ip.p1_from_skewness,
        steps=("third central moment of the two levels: σ³(p1 − p2)/√(p1p2)",
               "with u = 2p1 − 1: s̄ = 2u/√(1 − u²), so u = s̄/√(4 + s̄²)",
               "p1 = ½[1 + s̄/√(4 + s̄²)]: a division, the print multiplies"),
        note="As printed, p1 = ½[1 + s̄√(4 + s̄²)] exceeds 1 for s̄ = 1 (1.618): not a "
             "fraction. Right is p1 = ½[1 + s̄/√(4 + s̄²)] (Tsai 1985)."))
    rr.append(formula(
        "luhmann:5.50-skewness", SRC + ", p. 420, formula 5.50", "moment-preserving "
        "threshold: skewness s̄",
        {"corrected": VersionSpec("right", expr=lambda: (m3 + 2 * m1**3 - 3 * m1 * m2) / sig**3,
                                  claim="right")},
        derivation=ip.skewness_from_moments))
    rr.append(formula(
        "luhmann:5.50-variance", SRC + ", p. 420, formula 5.50", "moment-preserving "
        "threshold: σ̄² = m2 − m1²",
        {"corrected": VersionSpec("right", expr=lambda: m2 - m1**2, claim="right")},
        derivation=lambda: sp.expand(ip.two_level_moments(*ip.two_level_levels(), p1)[1]
                                     - ip.two_level_moments(*ip.two_level_levels(), p1)[0]**2)
        .subs(p2, 1 - p1).subs(sig, sp.sqrt(m2 - m1**2)),
        domain=lambda: {p1: (0.05, 0.95), m2: (10.0, 12.0), m1: (0.5, 2.0)},
        note="Derivation: the two-level image of 5.49 has variance σ̄², which equals "
             "m2 − m1² of the image."))
    rr.append(formula(
        "luhmann:5.72", SRC + ", p. 442, formula 5.72", "least-squares matching: "
        "linearised observation equation",
        {"old": VersionSpec(OLD_572, expr=lambda: _lsm(True), condition={r0: 0, r1: 1},
                            claim="wrong", condition_text=OLD_572[len("right-under-condition: "):]),
         "corrected": VersionSpec("right", expr=lambda: _lsm(False), claim="right")},
        derivation=ip.lsm_linearised,
        steps=("f − e = (r0 + dr0) + (r1 + dr1)·g(x' + dx', y' + dy')",
               "dx' = da0 + x·da1 + y·da2, dy' = db0 + x·db1 + y·db2",
               "first-order Taylor term (SymPy diff at t = 0 along all increments)"),
        note="The old print drops r0 and the factor r1: right only while r0 = 0, r1 = 1. "
             "The symbolic check reads g_x, g_y as ∂g/∂x', ∂g/∂y'; the old print's own "
             "definition (old 5.73, by x and y) agrees with that only for a pure shift, "
             "so the old print holds in the first iteration only."))
    rr.append(formula(
        "luhmann:5.73", SRC + ", p. 442, formula 5.73", "least-squares matching: gradients",
        {"old": VersionSpec("right-under-condition: a1 = b2 = 1, a2 = b1 = 0 (pure shift, the "
                            "start values)", expr=lambda: sp.Matrix([Gx, Gy]),
                            condition={a[1]: 1, b[2]: 1, a[2]: 0, b[1]: 0}, claim="wrong",
                            condition_text="a1 = b2 = 1, a2 = b1 = 0 (pure shift, the start "
                                           "values)"),
         "corrected": VersionSpec("right", expr=lambda: sp.Matrix([Gxp, Gyp]), claim="right")},
        derivation=_taylor_gradient_primed, given=_old_573_meaning,
        symbols=lambda: {s.name: s for s in (*a, *b, Gx, Gy, Gxp, Gyp)},
        steps=("5.72 linearised (image_processing.lsm_linearised): the gradient multiplying "
               "r1·da0 and r1·db0 is (∂g/∂x', ∂g/∂y') of the search image = (g_xp, g_yp): "
               "the derivation",
               "old 5.73 as printed: g_x = ∂g⁰(x, y)/∂x, g_y = ∂g⁰(x, y)/∂y, by the template "
               "coordinates, with g⁰(x, y) = g(x'(x, y), y'(x, y)) the resampled search patch",
               "chain rule (image_processing.template_gradient_chain): g_x = a1·g_xp + b1·g_yp, "
               "g_y = a2·g_xp + b2·g_yp; equal to (g_xp, g_yp) iff a1 = b2 = 1, a2 = b1 = 0",
               "corrected 5.73 as printed: g_x' = ∂g(x', y')/∂x', g_y' = ∂g(x', y')/∂y', by the "
               "search coordinates: (g_xp, g_yp), the derivation itself"),
        note="Symbols: g_x, g_y are the old print's (by the template coordinates x, y), "
             "g_xp, g_yp the corrected print's g_x', g_y' (by the search coordinates x', y'). "
             "The corrected print defines the gradient that the linearisation of "
             "5.72 produces (coefficients of da0, db0 over r1). The old g_x = ∂g⁰/∂x equals it "
             "only for an unsheared, unscaled patch. The corrected 5.72 still writes g_x, g_y "
             "for what the corrected 5.73 calls g_x', g_y'."))
    rr.append(figure("luhmann:p425-figure-ref", SRC + ", p. 425", "reference Abb. 5.4 → "
                     "Abb. 5.51", "a figure reference", claim="right"))
    rr.append(figure("luhmann:fig-8.67b", SRC + ", p. 611, Abb. 8.67b", "copyright note",
                     "not mathematics", claim="right"))
    return rr
