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

>>> [ex.id for ex in EXERCISES]  # doctest: +NORMALIZE_WHITESPACE
['im.log-value', 'im.moment-p1', 'im.circle-conic', 'im.centroid', 'im.lsm-row',
 'im.conic-centre', 'im.weighted-centroid', 'im.lsm-step', 'im.real-target', 'im.ransac-eps',
 'im.ransac-homography', 'im.ransac-fundamental', 'im.subpixel-disparity', 'im.disparity-depth']
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



# -- 7. weighted centroid of a window (function, with a degenerate case) --------------------------
def _blob(rng, size, noise):
    col, row = (float(v) for v in rng.uniform(size * 0.35, size * 0.65, 2))
    rr, cc = np.mgrid[:size, :size]
    bg, amp = float(rng.integers(15, 40)), float(rng.integers(120, 220))
    g = bg + amp * np.exp(-((cc - col) ** 2 + (rr - row) ** 2) / (2 * (size / 6) ** 2))
    return np.round(g + rng.normal(0, noise, g.shape), 1), bg


def _wc_params(rng):
    patch, bg = _blob(rng, 5, 2.0)
    return {"t": int(rng.integers(10, 70)), "patch": patch.tolist()}


def _wc_reference(p):
    from photolib.measurement import weighted_centroid

    def centroid_of_window(window):
        return weighted_centroid(np.asarray(window, float), p["t"]).colrow
    return centroid_of_window


def _wc_wrong(kind):
    def make(p):
        t = p["t"]

        def centroid_of_window(window):
            g = np.asarray(window, float)
            w = np.maximum(g - t, 0.0)
            if not w.sum() > 0:
                raise ValueError("empty target")
            if kind == "binary":
                w = (g > t).astype(float)
            elif kind == "background":
                w = g
            rows, cols = np.indices(g.shape)
            total = w.size if kind == "normalise" else w.sum()
            c = np.array([np.sum(cols * w), np.sum(rows * w)]) / total
            return c[::-1] if kind == "swapped" else c
        return centroid_of_window
    return make


def _wc_cases(rng, p):
    t = p["t"]
    clean, bg1 = _blob(rng, 7, 0.0)
    noisy, bg2 = _blob(rng, 9, 4.0)
    wide, bg3 = _blob(rng, 8, 1.0)
    flat = np.full((6, 6), t - float(rng.integers(0, 10)))   # nothing above t: degenerate
    return [(clean - bg1 + t - 3.0,), (noisy - bg2 + t - 5.0,), (wide[:, :6] - bg3 + t - 4.0,),
            (flat,)]


weighted_centroid_fn = Exercise(
    params_name="p_wc",
    id="im.weighted-centroid", points=3, kind="function", answer="centroid_of_window",
    title="Implement the weighted centroid / gewichteter Schwerpunkt",
    statement=r"Write `centroid_of_window(window)` for a bright target in a 2-D NumPy array "
              r"`window` of grey values: weights $w_i = \max(g_i - t, 0)$, centroid "
              r"$x_c = \sum x_i w_i / \sum w_i$, $y_c = \sum y_i w_i/\sum w_i$ with "
              r"$x$ = column, $y$ = row, $(0, 0)$ the centre of the top-left pixel; return the "
              r"NumPy array $(x_c, y_c)$ of shape (2,). Your background threshold is $t$ = {t}. "
              r"If no pixel lies above $t$ (e.g. a constant window), raise a `ValueError` that "
              r"says so. Try it on the 5 × 5 patch {patch} (hidden tests use other windows; "
              r"checked to $10^{{-6}}$ relative).",
    parameters=_wc_params, reference=_wc_reference, cases=_wc_cases, rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("swapped", "that is (row, col): return (x_c, y_c) = (column, row)",
                _wc_wrong("swapped")),
        Mistake("normalise", "the weights are not normalised: divide by Σw, not by the number "
                             "of pixels", _wc_wrong("normalise")),
        Mistake("binary", "every pixel above t got weight 1: weight by w = g − t",
                _wc_wrong("binary")),
        Mistake("background", "the background t was not subtracted: w = max(g − t, 0)",
                _wc_wrong("background")),
    ))


# -- 8. one least-squares matching step (function, degenerate: flat search patch) -----------------
def _lsm_step_params(rng):
    return {"a0": round(float(rng.uniform(11.0, 13.0)), 2),
            "b0": round(float(rng.uniform(11.0, 13.0)), 2)}


def _lsm_texture(rng, shape, shift=(0.0, 0.0)):
    k = rng.uniform(0.2, 0.6, 4)
    ph = rng.uniform(0, 6.3, 4)
    r, c = np.mgrid[:shape[0], :shape[1]].astype(float)
    c, r = c - shift[0], r - shift[1]
    return (100 + 40 * np.sin(k[0] * c + ph[0]) * np.cos(k[1] * r + ph[1])
            + 25 * np.cos(k[2] * c + k[3] * r + ph[2]))


def _lsm_step_cases(rng, p):
    cases = []
    for noise in (0.0, 2.0):
        seed = int(rng.integers(1 << 30))
        g = _lsm_texture(np.random.default_rng(seed), (26, 26))
        true = rng.uniform(11.5, 13.5, 2)
        f = _lsm_texture(np.random.default_rng(seed), (9, 9), shift=(4.0 - true[0], 4.0 - true[1]))
        f = 5.0 + 0.9 * f + rng.normal(0, noise, f.shape)
        q = np.array([true[0] + rng.uniform(-0.6, 0.6), 1.0, 0.0,
                      true[1] + rng.uniform(-0.6, 0.6), 0.0, 1.0, rng.uniform(2.0, 6.0),
                      rng.uniform(0.8, 0.95)])
        cases.append((np.round(f, 3), np.round(g, 3), np.round(q, 3)))
    flat = np.full((26, 26), 90.0)
    cases.append((cases[0][0], flat, cases[0][2]))
    return cases


def _lsm_step_reference(p):
    from photolib.matching import least_squares_matching

    def lsm_step(template, search, q):
        res = least_squares_matching(template, search, np.asarray(q, float), max_iter=1,
                                     check=False, tol=1e-12)
        return res.history[1]
    return lsm_step


def _lsm_step_wrong(kind):
    def make(p):
        def lsm_step(template, search, q):
            f, g = np.asarray(template, float), np.asarray(search, float)
            q = np.asarray(q, float)
            gy, gx = np.gradient(g)
            if kind == "swapped":
                gx, gy = gy, gx
            if kind == "sign":
                gx, gy = -gx, -gy
            h, w = f.shape
            y, x = np.mgrid[:h, :w].astype(float)
            x, y = (x - (w - 1) / 2).ravel(), (y - (h - 1) / 2).ravel()
            a0, a1, a2, b0, b1, b2, r0, r1 = q
            cols, rows = a0 + a1 * x + a2 * y, b0 + b1 * x + b2 * y
            c0, rr0 = np.floor(cols).astype(int), np.floor(rows).astype(int)
            u, v = cols - c0, rows - rr0

            def bil(im):
                return ((1 - u) * (1 - v) * im[rr0, c0] + u * (1 - v) * im[rr0, c0 + 1]
                        + (1 - u) * v * im[rr0 + 1, c0] + u * v * im[rr0 + 1, c0 + 1])
            gs, gxs, gys = bil(g), bil(gx), bil(gy)
            k = 1.0 if kind == "erratum" else r1
            A = np.column_stack([k * gxs, k * gxs * x, k * gxs * y, k * gys, k * gys * x,
                                 k * gys * y, np.ones_like(x), gs])
            dq = np.linalg.solve(A.T @ A, A.T @ (f.ravel() - (r0 + r1 * gs)))
            return dq if kind == "update" else q + dq
        return lsm_step
    return make


lsm_step = Exercise(
    params_name="p_lsm_step",
    id="im.lsm-step", points=4, kind="function", answer="lsm_step",
    title="Implement one least-squares matching step / ein Iterationsschritt der LSM",
    statement=r"Write `lsm_step(template, search, q)`: one Gauss–Newton step of least-squares "
              r"matching for $f(x, y) = r_0 + r_1 g(x', y')$, $x' = a_0 + a_1x + a_2y$, "
              r"$y' = b_0 + b_1x + b_2y$, with `q` = $(a_0, a_1, a_2, b_0, b_1, b_2, r_0, r_1)$. "
              r"Template coordinates $(x, y)$ = (column, row) from the template's centre pixel; "
              r"gradients of the search image by `gy, gx = np.gradient(search)`; $g$, $g_x$, "
              r"$g_y$ bilinearly interpolated at $(x', y')$; solve the normal equations "
              r"$A^TA\,\Delta = A^T(f - r_0 - r_1 g)$ and return the **updated** parameters "
              r"$q + \Delta$, shape (8,). A search patch without texture makes $A^TA$ singular: "
              r"raise a `ValueError` (`np.linalg.LinAlgError` is one). The patch starts near "
              r"$(a_0, b_0)$ = ({a0}, {b0}) in the hidden 26 × 26 search images (to $10^{{-6}}$).",
    parameters=_lsm_step_params, reference=_lsm_step_reference, cases=_lsm_step_cases,
    rtol=1e-5, atol=1e-5,
    few_variants="one Gauss-Newton step is the same algorithm for every student: the function "
                 "cannot depend on the variant; each student's hidden windows and start "
                 "values are drawn from their own seed",
    mistakes=(
        Mistake("swapped", "x and y are swapped: gx = ∂g/∂x' (along the columns) belongs to "
                           "a0, a1, a2; np.gradient returns the row derivative first",
                _lsm_step_wrong("swapped")),
        Mistake("sign", "the gradient has the wrong sign: the columns of A are +r1·∂g/∂x' …, "
                        "the derivative of r0 + r1·g(x', y') by the parameters",
                _lsm_step_wrong("sign")),
        Mistake("update", "that is the increment Δ: return the updated parameters q + Δ",
                _lsm_step_wrong("update")),
        Mistake("erratum", "the geometric columns lack the factor r1 (the old print of 5.72)",
                _lsm_step_wrong("erratum")),
    ))


# -- 9. a target of a real photograph (array, variants drawn from the data) -----------------------
def _real_params(rng):
    from photolib.nb.measurement import real_targets

    k = int(rng.integers(0, 4))
    c0, r0, c1, r1 = real_targets()[k].bbox
    return {"k": k, "c0": c0, "r0": r0, "c1": c1, "r1": r1, "t": int(rng.integers(20, 51)) * 2}


def _real_window(p, channel="yellow"):
    from photolib.data import yellowtargets
    from photolib.measurement._real import yellowness

    rgb = yellowtargets()[0]
    img = yellowness(rgb) if channel == "yellow" else np.asarray(rgb, float).mean(axis=2)
    return img[p["r0"]:p["r1"], p["c0"]:p["c1"]]


def _real_target(p, offset=True, kind=""):
    win = _real_window(p, "grey" if kind == "grey" else "yellow")
    w = np.maximum(win - p["t"], 0.0)
    if kind == "background":
        w = np.where(win > p["t"], win, 0.0)
    if kind == "binary":
        w = (win > p["t"]).astype(float)
    rows, cols = np.indices(win.shape)
    c = np.array([np.sum(cols * w), np.sum(rows * w)]) / w.sum()
    return c + ([p["c0"], p["r0"]] if offset else 0.0)


def _real_reference(p):
    from photolib.measurement import weighted_centroid
    return weighted_centroid(_real_window(p), p["t"]).colrow + [p["c0"], p["r0"]]


real_target = Exercise(
    params_name="p_target",
    id="im.real-target", points=3, kind="array", answer="target_centre",
    title="A target in a real photograph / Zielmarke in einer realen Aufnahme",
    statement=r"Load `rgb = pl.data.yellowtargets()[0]` (640 × 480 px) and form the yellowness "
              r"image $Y = \min(R, G) - B$ (float). Target {k} lies in the window "
              r"`Y[{r0}:{r1}, {c0}:{c1}]`. With the weights $w = \max(Y - t, 0)$, $t$ = {t}, "
              r"compute its weighted centroid in **whole-image** pixel coordinates "
              r"(col, row) as a NumPy array of shape (2,), to 0.01 px.",
    # 0.01 px as asked; the centroid's own noise σ (σ_g ≈ 5 grey values over the target's
    # ~6000 pixels, ≈ 0.02-0.03 px) is the image's limit, but the computation on the same
    # pixels is exact, and every mistake below moves it by more than 0.3 px
    parameters=_real_params, reference=_real_reference, rtol=0.0, atol=0.01,
    mistakes=(
        Mistake("window", "that is the position inside the window: add the window's origin "
                          "(col {c0}, row {r0})", lambda p: _real_target(p, offset=False)),
        Mistake("swapped", "that is (row, col): give (col, row)",
                lambda p: _real_reference(p)[::-1]),
        Mistake("background", "the threshold was not subtracted from the weights: "
                              "w = max(Y − t, 0)", lambda p: _real_target(p, kind="background")),
        Mistake("binary", "every pixel above t got weight 1: weight by Y − t",
                lambda p: _real_target(p, kind="binary")),
        Mistake("grey", "that is the centroid in the mean grey image: use Y = min(R, G) − B",
                lambda p: _real_target(p, kind="grey")),
    ))


# -- 10-12. scenario: RANSAC trial counts from the matches of a real pair (3 steps) ---------------
def _ransac_params(rng):
    n = int(rng.integers(120, 600))
    n_in = int(round(n * rng.uniform(0.45, 0.7)))
    p = float(rng.choice([0.95, 0.99, 0.999]))
    eps = 1.0 - n_in / n
    return {"n": n, "n_in": n_in, "p": p, "eps": round(eps, 4)}


def _trials(p, s, eps=None, rounding=math.ceil):
    e = p["eps"] if eps is None else eps
    return float(rounding(math.log(1 - p["p"]) / math.log(1 - (1 - e) ** s)))


ransac_eps = Exercise(
    params_name="p_ransac",
    id="im.ransac-eps", points=1, kind="number", answer="eps", scenario="im.ransac-eps",
    title="Step 1 of 3: the outlier rate of feature matches / Ausreißeranteil",
    statement=r"Feature matching of two photographs gave $n$ = {n} matches; a robust fit "
              r"accepted {n_in} of them as inliers. Give the outlier rate $\varepsilon$ "
              r"(a fraction, to 4 decimals).",
    parameters=_ransac_params, reference=lambda p: 1.0 - p["n_in"] / p["n"],
    rtol=0.0, atol=6e-5,
    mistakes=(Mistake("inliers", "that is the inlier ratio 1 − ε: ε is the share of outliers",
                      lambda p: p["n_in"] / p["n"]),
              Mistake("percent", "give ε as a fraction, not in percent",
                      lambda p: 100.0 * (1.0 - p["n_in"] / p["n"]))))

ransac_homography = Exercise(
    params_name="p_ransac_h",
    id="im.ransac-homography", points=2, kind="number", answer="n_homography",
    scenario="im.ransac-eps",
    title="Step 2 of 3: RANSAC trials for a homography / Projektivtransformation",
    statement=r"With the outlier rate $\varepsilon$ = {eps} (step 1), how many random minimal "
              r"samples $N$ must RANSAC draw for a **homography** (projective transformation, "
              r"minimal sample $s$ = 4 points) so that with probability $p$ = {p} at least one "
              r"sample is free of outliers? Give the smallest such whole number.",
    parameters=_ransac_params, reference=lambda p: _trials(p, 4), rtol=0.0, atol=0.0,
    mistakes=(Mistake("floor", "N must be rounded up: the smallest whole N with "
                               "(1 − (1 − ε)^s)^N ≤ 1 − p", lambda p: _trials(p, 4, rounding=math.floor)),
              Mistake("epsilon", "the probability of a clean sample is (1 − ε)^s, the inlier "
                                 "ratio to the power s, not ε^s",
                      lambda p: _trials(p, 4, eps=1 - p["eps"])),
              Mistake("sample", "a homography has 8 parameters, 2 per point: s = 4, not 8",
                      lambda p: _trials(p, 8))))

ransac_fundamental = Exercise(
    params_name="p_ransac_f",
    id="im.ransac-fundamental", points=2, kind="number", answer="n_fundamental",
    scenario="im.ransac-eps",
    title="Step 3 of 3: RANSAC trials for the fundamental matrix / Fundamentalmatrix",
    statement=r"For the same matches ($\varepsilon$ = {eps}, $p$ = {p}) RANSAC estimates the "
              r"**fundamental matrix** with the normalised 8-point algorithm. How many samples "
              r"$N$ are needed now? Give the smallest whole number.",
    parameters=_ransac_params, reference=lambda p: _trials(p, 8), rtol=0.0, atol=0.0,
    mistakes=(Mistake("seven", "the 8-point algorithm draws s = 8 correspondences (7 is the "
                               "7-point algorithm)", lambda p: _trials(p, 7)),
              Mistake("homography", "that is N for s = 4 (step 2): the 8-point algorithm "
                                    "needs s = 8", lambda p: _trials(p, 4))))


# -- 13-14. scenario: subpixel disparity from the correlation peak, then depth (2 steps) ----------
def _subpix_params(rng):
    d0 = int(rng.integers(20, 60))
    delta = float(rng.uniform(-0.45, 0.45))
    peak, curv = float(rng.uniform(0.85, 0.97)), float(rng.uniform(0.05, 0.2))
    rho = [peak - curv * (k - delta) ** 2 for k in (-1, 0, 1)]
    rho = [round(v, 4) for v in rho]
    from photolib.dense import parabola_vertex
    d = d0 + float(parabola_vertex(*rho))
    return {"d0": d0, "rm": rho[0], "r0": rho[1], "rp": rho[2], "d": round(d, 3)}


def _subpix(p, sign=1.0, factor=1.0):
    from photolib.dense import parabola_vertex
    return p["d0"] + sign * factor * float(parabola_vertex(p["rm"], p["r0"], p["rp"]))


def _subpix_mistake(p, sign=1.0, factor=1.0):
    """A mistake's disparity, or None where it lies within four significant digits of the
    right one: the offset δ is a fraction of a pixel on a disparity of tens of pixels, and a
    right answer rounded to four digits must not be told it made this mistake."""
    wrong, right = _subpix(p, sign, factor), _subpix(p)
    return None if abs(wrong - right) <= 1e-3 * abs(right) else wrong


def _depth(p, doffs=True, scale=1.0):
    from photolib.data import MOTORCYCLE_CALIBRATION as cal
    return scale * cal.f_px * cal.baseline_mm / (p["d"] + (cal.doffs_px if doffs else 0.0))


subpixel_disparity = Exercise(
    params_name="p_subpix",
    id="im.subpixel-disparity", points=2, kind="number", answer="d_subpixel",
    scenario="im.subpixel-disparity",
    title="Step 1 of 2: subpixel disparity from the correlation peak / Subpixel-Interpolation",
    statement=r"Along a row of a rectified pair the correlation coefficient of a left window "
              r"with the right windows peaks at the integer disparity $d_0$ = {d0} px: "
              r"$\rho(d_0 - 1)$ = {rm:.4f}, $\rho(d_0)$ = {r0:.4f}, $\rho(d_0 + 1)$ = {rp:.4f}. Fit the "
              r"parabola through the three values and give the disparity of its vertex in px, "
              r"to 0.0001 px.",
    parameters=_subpix_params, reference=_subpix, tolerance=PRINTED,
    mistakes=(Mistake("sign", "the offset has the wrong sign: δ = (ρ₋ − ρ₊)/(2(ρ₋ − 2ρ₀ + ρ₊)) "
                              "moves towards the larger neighbour", lambda p: _subpix_mistake(p, -1.0)),
              Mistake("factor-2", "the vertex is at (ρ₋ − ρ₊)/(2(ρ₋ − 2ρ₀ + ρ₊)): the factor "
                                  "2 in the denominator is missing",
                      lambda p: _subpix_mistake(p, 1.0, 2.0)),
              Mistake("half", "the denominator is 2(ρ₋ − 2ρ₀ + ρ₊), not 4(…)",
                      lambda p: _subpix_mistake(p, 1.0, 0.5))))

disparity_depth = Exercise(
    params_name="p_depth",
    id="im.disparity-depth", points=2, kind="number", answer="depth_mm",
    scenario="im.subpixel-disparity",
    title="Step 2 of 2: depth from the disparity / Tiefe aus der Disparität",
    statement=r"The pair is the Middlebury motorcycle pair of `pl.data.motorcycle()`: "
              r"$f$ = 994.978 px, $B$ = 193.001 mm, principal-point offset "
              r"$d_\mathrm{{offs}}$ = 31.086 px, $Z = fB/(d + d_\mathrm{{offs}})$. With the "
              r"subpixel disparity $d$ = {d:.3f} px (step 1), give the depth $Z$ in mm to 0.01 mm.",
    parameters=_subpix_params, reference=_depth, tolerance=PRINTED,
    mistakes=(Mistake("doffs", "the principal points' offset d_offs belongs to the disparity: "
                               "Z = fB/(d + d_offs)", lambda p: _depth(p, doffs=False)),
              Mistake("metres", "give Z in mm (B is in mm), not in m",
                      lambda p: _depth(p, scale=1e-3))))


EXERCISES = (log_value, moment_p1, circle_conic, centroid, lsm_row, conic_centre,
             weighted_centroid_fn, lsm_step, real_target, ransac_eps, ransac_homography,
             ransac_fundamental, subpixel_disparity, disparity_depth)
