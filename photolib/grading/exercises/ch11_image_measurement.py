"""Chapter 11-image-measurement: graded exercises on image measurement (Bildmessung).

* ``im.log-value`` (number): ∇²G of the normalised Gaussian at a radius (Luhmann 5.42; the
  old print is recognised, record ``luhmann:5.42``);
* ``im.moment-p1`` (number): Tsai's p1 from a histogram (5.50; the errata's printed
  "corrected" p1 is wrong and recognised, record ``luhmann:5.50-p1``);
* ``im.circle-conic`` (array): centre and radius from A, D, E, F (2.86; the old print
  without 1/A² is recognised, record ``luhmann:2.86``);
* ``im.centroid`` (array): weighted centroid of a 5 × 5 patch above a background threshold
  (row/col versus x/y, no background, unweighted, 1-based indices recognised);
* ``im.lsm-row`` (function): one row of the LSM design matrix (5.72 corrected; the old print
  without the factor r1 is recognised, record ``luhmann:5.72``);
* ``im.conic-centre`` (expression): a coordinate of the centre of a general conic, derived
  with SymPy (the other coordinate, the factor-2 convention and the sign are recognised).

References come from :mod:`photolib.measurement`, :mod:`photolib.fitting`,
:func:`photolib.matching.lsm_design_matrix` and :func:`photolib.derive.conic.conic_centre`.

>>> [ex.id for ex in EXERCISES]
['im.log-value', 'im.moment-p1', 'im.circle-conic', 'im.centroid', 'im.lsm-row', 'im.conic-centre']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "11-image-measurement"


# -- 1. LoG value (number) ------------------------------------------------------------------------
def _log_params(rng):
    sigma = round(float(rng.uniform(1.0, 3.0)), 2)
    return {"sigma": sigma, "r": round(float(rng.uniform(0.3, 2.5) * sigma), 2)}


def _log_value(p):
    from photolib.measurement import laplacian_of_gaussian
    return laplacian_of_gaussian(p["r"], p["sigma"])


def _log_unnormalised(p):
    q = p["r"] ** 2 / (2 * p["sigma"] ** 2)
    return -(1 - q) * math.exp(-q)


def _log_half(p):
    """∂²G/∂x² only (one term of the Laplacian), at (r, 0)."""
    x2, s2 = p["r"] ** 2, p["sigma"] ** 2
    return (x2 / s2**2 - 1 / s2) * math.exp(-x2 / (2 * s2)) / (2 * math.pi * s2)


def _subs_r_sigma(expr, p):
    from photolib.derive import image_processing as ip
    return float(expr.subs({ip.r: p["r"], ip.sigma: p["sigma"]}))


log_value = Exercise(
    params_name="p_log",
    id="im.log-value", points=2, kind="number", answer="log_value",
    title="Laplacian of Gaussian / LoG (Luhmann 5.42)",
    statement="The LoG operator uses the normalised Gaussian G(x, y) = exp(−r²/(2σ²))/(2πσ²), "
              "r² = x² + y², with σ = {sigma} px. Compute ∇²G = ∂²G/∂x² + ∂²G/∂y² at the "
              "radius r = {r} px (unit px⁻⁴).",
    # the rounding of the printed r and σ (0.01 px), kept off the mistakes; the old rtol 1e-6
    # rejected ∇²G given to 4 significant digits
    parameters=_log_params, reference=_log_value, tolerance=PRINTED,
    mistakes=(
        hints.erratum_version("luhmann:5.42", _subs_r_sigma, "old"),
        Mistake("normalisation", "the factor 1/(πσ⁴) of the normalised Gaussian is missing: "
                                 "∇²G = −(1/(πσ⁴))(1 − r²/(2σ²))·exp(−r²/(2σ²))",
                _log_unnormalised),
        Mistake("laplacian", "that is ∂²G/∂x² alone; the Laplacian adds ∂²G/∂y² "
                             "(at (r, 0) it is −G/σ²)", _log_half),
    ))




# -- 2. moment-preserving threshold p1 (number) --------------------------------------------------
def _moment_params(rng):
    values = sorted(int(v) for v in rng.choice(np.arange(10, 250, 10), size=3, replace=False))
    counts = [int(rng.integers(40, 90)), int(rng.integers(5, 25)), int(rng.integers(10, 40))]
    hist = ", ".join(f"{v}: {c}" for v, c in zip(values, counts))
    return {"grey": values, "counts": counts, "hist": hist, "n": sum(counts)}


def _moments(p, ddof=0):
    g = np.repeat(np.array(p["grey"], float), p["counts"])
    m1 = g.mean()
    var = float(np.sum((g - m1) ** 2) / (len(g) - ddof))
    s = float(np.mean((g - m1) ** 3)) / var**1.5
    return m1, var, s


def _p1(p):
    from photolib.measurement import moment_threshold
    return moment_threshold(np.repeat(np.array(p["grey"], float), p["counts"])).p1


def _p1_from_s(s, sign=1.0):
    return 0.5 * (1 + sign * s / math.sqrt(4 + s * s))


def _p1_printed(p):
    """The errata list's printed (and wrong) "corrected" 5.50, via the catalogue record."""
    try:
        import importlib

        from photolib.derive import image_processing as ip
        expr = importlib.import_module("photolib.errata").get("luhmann:5.50-p1").versions["corrected"]
    except Exception:  # noqa: BLE001 - no catalogue, no hint
        return None
    return float(expr.subs(ip.s_bar, _moments(p)[2]))


def _p1_sample_variance(p):
    g = np.repeat(np.array(p["grey"], float), p["counts"])
    m1, _, _ = _moments(p)
    return _p1_from_s(float(np.mean((g - m1) ** 3)) / _moments(p, ddof=1)[1] ** 1.5)


moment_p1 = Exercise(
    params_name="p_moment",
    id="im.moment-p1", points=3, kind="number", answer="p1",
    title="Moment-preserving threshold / momentenerhaltender Schwellwert (5.49, 5.50)",
    statement="An image of n = {n} pixels has the histogram (grey value: count) {hist}. "
              "Tsai's moment-preserving threshold replaces it by two levels h1 < h2 with "
              "fractions p1, p2 = 1 − p1 that keep the moments m1, m2, m3 (mi = mean of gⁱ). "
              "Compute p1, the fraction of the dark class.",
    # p1 to 5 decimals (the old 1e-7 rejected 6); the n − 1 mistake is ≥ 5e-5 away
    parameters=_moment_params, reference=_p1, rtol=0.0, atol=1e-5,
    mistakes=(
        Mistake("erratum", "this is p1 as printed in the errata list's corrected 5.50 "
                           "(luhmann:5.50-p1), which is wrong: the root belongs in the "
                           "denominator, p1 = ½[1 + s̄/√(4 + s̄²)]", _p1_printed),
        Mistake("sign", "that is p2, the bright fraction: p1 = ½[1 + s̄/√(4 + s̄²)] with the "
                        "skewness s̄ = (m3 − 3m1m2 + 2m1³)/σ̄³ (positive for a small bright "
                        "target)", lambda p: _p1_from_s(_moments(p)[2], -1.0)),
        Mistake("variance", "σ̄² = m2 − m1² divides by n, not n − 1 (moments of the image, "
                            "not a sample estimate)", _p1_sample_variance),
    ))


# -- 3. circle from the general conic (array) -----------------------------------------------------
def _circle_params(rng):
    A = round(float(rng.uniform(1.5, 4.0)), 2)
    xc, yc = (round(float(v), 2) for v in rng.uniform(-20, 20, 2))
    r = round(float(rng.uniform(2.0, 15.0)), 2)
    return {"A": A, "D": round(-A * xc, 4), "E": round(-A * yc, 4),
            "F": round(A * (xc * xc + yc * yc - r * r), 4)}


def _circle(p):
    from photolib.fitting import circle_from_conic
    centre, radius = circle_from_conic(p["A"], p["D"], p["E"], p["F"])
    return np.r_[centre, radius]


def _circle_old(expr, p):
    from photolib.derive import conic
    radius = float(expr.subs({conic.A: p["A"], conic.D: p["D"], conic.E: p["E"], conic.F: p["F"]}))
    return np.r_[_circle(p)[:2], radius]


def _circle_no_twos(p):
    A, D, E, F = p["A"], p["D"], p["E"], p["F"]
    r2 = (D * D + E * E) / (4 * A * A) - F / A
    return None if r2 <= 0 else np.array([-D / (2 * A), -E / (2 * A), math.sqrt(r2)])


circle_conic = Exercise(
    params_name="p_circle",
    id="im.circle-conic", points=3, kind="array", answer="circle",
    title="Circle from the general conic / Kreis (Luhmann 2.86)",
    statement="A circle fit gave the conic A(x² + y²) + 2Dx + 2Ey + F = 0 with A = {A}, "
              "D = {D}, E = {E}, F = {F} (image coordinates in px). Give its centre and radius "
              "as a NumPy array (x_c, y_c, r) of shape (3,).",
    # 1e-4 px: D, E, F are printed to 4 decimals; float32 (1e-6 px) and answers to 4
    # decimals were rejected by the old 1e-7
    parameters=_circle_params, reference=_circle, tolerance=PRINTED, rtol=1e-6, atol=1e-4,
    mistakes=(
        hints.erratum_version("luhmann:2.86", _circle_old, "old"),
        Mistake("factor-2", "the conic is written with 2D and 2E (Luhmann 2.85): the centre is "
                            "(−D/A, −E/A), not (−D/(2A), −E/(2A))", _circle_no_twos),
        Mistake("sign", "the centre is (−D/A, −E/A): completing the square, "
                        "A(x + D/A)² + A(y + E/A)² = (D² + E²)/A − F",
                lambda p: _circle(p) * np.array([-1.0, -1.0, 1.0])),
    ))


# -- 4. centroid of a patch (array) ---------------------------------------------------------------
def _centroid_params(rng):
    col, row = 2.0 + float(rng.uniform(-0.8, 0.8)), 2.0 + float(rng.uniform(-0.8, 0.8))
    if abs(col - row) < 0.3:  # keep (row, col) distinguishable from (col, row)
        row = col - 0.5 if col > 2.0 else col + 0.5
    rr, cc = np.mgrid[:5, :5]
    bg = int(rng.integers(15, 40))
    amp = int(rng.integers(120, 220))
    patch = bg + amp * np.exp(-((cc - col) ** 2 + (rr - row) ** 2) / 2.0) + rng.normal(0, 2, (5, 5))
    patch = np.clip(np.round(patch), 0, 255).astype(int)
    return {"patch": patch.tolist(), "t": bg + 10}


def _centroid(p):
    from photolib.measurement import weighted_centroid
    return weighted_centroid(np.array(p["patch"], float), p["t"]).colrow


def _centroid_plain(p, binary=False, threshold=True):
    g = np.array(p["patch"], float)
    w = np.maximum(g - p["t"], 0.0) if threshold else g
    if binary:
        w = (g > p["t"]).astype(float)
    rows, cols = np.indices(g.shape)
    return np.array([np.sum(cols * w), np.sum(rows * w)]) / w.sum()


centroid = Exercise(
    params_name="p_centroid",
    id="im.centroid", points=3, kind="array", answer="centroid",
    title="Centroid of a target / Schwerpunkt einer Zielmarke",
    statement="A bright target is imaged in the 5 × 5 patch (rows from top, grey values) "
              "{patch}. With the background threshold t = {t} and the weights "
              "w = max(g − t, 0), compute the weighted centroid in pixel coordinates "
              "(col, row), (0, 0) = centre of the top-left pixel, as a NumPy array of shape (2,).",
    # 1e-4 px accepts float32 and 4 decimals (the old 1e-7 did not); mistakes ≥ 5e-3 px away
    parameters=_centroid_params, reference=_centroid, rtol=0.0, atol=1e-4,
    mistakes=(
        Mistake("swapped", "that is (row, col): the course's pixel coordinates are (col, row) = "
                           "(x, y) — SciPy's center_of_mass returns (row, col)",
                lambda p: _centroid(p)[::-1]),
        Mistake("background", "the background threshold was not subtracted: the weights are "
                              "w = max(g − t, 0), not g",
                lambda p: _centroid_plain(p, threshold=False)),
        Mistake("binary", "every pixel above t got the weight 1: the centroid is weighted by "
                          "w = g − t", lambda p: _centroid_plain(p, binary=True)),
        Mistake("one-based", "the first pixel has the coordinate 0, not 1",
                lambda p: _centroid(p) + 1.0),
    ))


# -- 5. LSM design-matrix row (function) ---------------------------------------------------------
def _lsm_params(rng):
    return {"r0": round(float(rng.uniform(-15, 15)), 2), "r1": round(float(rng.uniform(0.7, 1.4)), 3)}


def _lsm_function(old=False, swapped=False):
    def make(p):
        r1 = 1.0 if old else p["r1"]

        def lsm_row(x, y, g, gx, gy):
            if swapped:
                gx, gy = gy, gx
            return np.array([r1 * gx, r1 * gx * x, r1 * gx * y, r1 * gy, r1 * gy * x,
                             r1 * gy * y, 1.0, g])
        return lsm_row
    return make


def _lsm_reference(p):
    from photolib.matching import lsm_design_matrix

    def lsm_row(x, y, g, gx, gy):
        return lsm_design_matrix([0, 1, 0, 0, 0, 1, p["r0"], p["r1"]], [x], [y], [g], [gx], [gy])[0]
    return lsm_row


def _lsm_cases(rng, p):
    return [tuple(round(float(v), 3) for v in (rng.uniform(-7, 7), rng.uniform(-7, 7),
                                                rng.uniform(20, 230), rng.uniform(-30, 30),
                                                rng.uniform(-30, 30))) for _ in range(6)]


lsm_row = Exercise(
    params_name="p_lsm",
    id="im.lsm-row", points=3, kind="function", answer="lsm_row",
    title="A row of the LSM design matrix / Kleinste-Quadrate-Zuordnung (5.72)",
    statement="Least-squares matching models f(x, y) − e = r0 + r1·g(x', y') with "
              "x' = a0 + a1x + a2y, y' = b0 + b1x + b2y. In the current iteration r0 = {r0}, "
              "r1 = {r1}. Write lsm_row(x, y, g, gx, gy) returning the row of the design matrix "
              "for the increments (da0, da1, da2, db0, db1, db2, dr0, dr1) as a NumPy array of "
              "shape (8,), for the template pixel (x, y), the search-image grey value g = "
              "g(x', y') and its gradient gx = ∂g/∂x', gy = ∂g/∂y'.",
    # rtol 1e-6 accepts float32 (the old 1e-9 did not)
    parameters=_lsm_params, reference=_lsm_reference, tolerance=PRINTED, cases=_lsm_cases, rtol=1e-6, atol=1e-9,
    mistakes=(
        Mistake("erratum", "the geometric columns lack the factor r1: that is the old print of "
                           "5.72 (luhmann:5.72), right only while r1 = 1 (first iteration)",
                _lsm_function(old=True)),
        Mistake("swapped", "gx belongs to the a-parameters (x') and gy to the b-parameters (y')",
                _lsm_function(swapped=True)),
    ))


# -- 6. centre of a general conic (expression) ----------------------------------------------------
def _conic_centre_params(rng):
    # a nonzero whole xy coefficient |b| ≤ 30, either sign: 120 variants with the coordinate
    return {"b": int(rng.integers(1, 31)) * int(rng.choice([-1, 1])),
            "coordinate": str(rng.choice(["x_c", "y_c"]))}


def _conic_centre(p, halves=False, other=False):
    import sympy as sp

    from photolib.derive import conic
    if halves:  # a x² + 2b xy + c y² + 2d x + 2e y + f: the centre solves [[a, b], [b, c]]·x = −(d, e)
        a, b, c, d, e = conic.ca, conic.cb, conic.cc, conic.cd, conic.ce
        det = a * c - b**2
        xc, yc = (b * e - c * d) / det, (b * d - a * e) / det
    else:
        xc, yc = conic.conic_centre()
    want_x = (p["coordinate"] == "x_c") != other
    return sp.cancel((xc if want_x else yc).subs(conic.cb, p["b"]))


conic_centre = Exercise(
    params_name="p_conic",
    id="im.conic-centre", points=3, kind="expression", answer="centre_coordinate",
    symbols=("a", "c", "d", "e", "f"),
    title="Centre of an ellipse from its conic / Mittelpunkt aus der Kegelschnittgleichung",
    statement="An ellipse fit returns the conic a·x² + ({b})·x·y + c·y² + d·x + e·y + f = 0 "
              "(the coefficient of x·y is the number {b}). Derive the centre, where the "
              "gradient of the conic vanishes, and give its coordinate {coordinate} as a SymPy "
              "expression (or formula string) in a, c, d, e, f.",
    parameters=_conic_centre_params, reference=_conic_centre,
    mistakes=(
        Mistake("swapped", "that is the other coordinate of the centre",
                lambda p: _conic_centre(p, other=True)),
        Mistake("factor-2", "that is the centre of a·x² + 2b·xy + c·y² + 2d·x + 2e·y + f: here "
                            "the coefficients carry no factor 2 (∂/∂x: 2a·x + b·y + d = 0)",
                lambda p: _conic_centre(p, halves=True)),
        Mistake("sign", "the sign is reversed: the centre solves 2a·x + b·y = −d, "
                        "b·x + 2c·y = −e", lambda p: -_conic_centre(p)),
    ))


EXERCISES = (log_value, moment_p1, circle_conic, centroid, lsm_row, conic_centre)
