"""Chapter 07-plane-transformations: graded exercises on plane transformations.

* ``plane.helmert-two-points`` (array): the four Helmert parameters from two identical points;
* ``plane.helmert-angle`` (number): the rotation angle of a Helmert transformation in gon;
* ``plane.projective-point`` (array): a façade point from four control points (Luhmann 2.18);
* ``plane.cross-ratio`` (number): a distance along a line from the cross ratio (2.21);
* ``plane.cross-ratio-solved`` (expression): 2.21 solved for one point with SymPy;
* ``plane.fiducial-affine`` (array): image coordinates from fiducial marks (Rahmenmarken);
* ``plane.bilinear-function`` (function): a bilinear transformation as a Python function.

Course conventions (docs/conventions.md): Helmert ``X = a0 + a1x − b1y``,
``Y = b0 + b1x + a1y`` (α counter-clockwise, ``a1 = m·cos α``, ``b1 = m·sin α``); projective
as Luhmann 2.18; bilinear ``X = a0 + a1x + a2y + a3xy``, ``Y = b0 + b1x + b2y + b3xy``;
the cross ratio is the corrected 2.21, ``λ = AB·CD / (BC·AD)`` with signed segments.
References are computed with :mod:`photolib.transforms`; every hint recomputes the answer the
way the mistake would.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "07-plane-transformations"

_SWAPPED = ("these are the parameters of the inverse transformation: source and destination "
            "were swapped (the task maps {src} → {dst})")


def _fmt_points(points, digits):
    return ", ".join("(" + ", ".join(f"{v:.{digits}f}" for v in p) + ")" for p in points)


# -- 1. Helmert from two identical points (array) -------------------------------------------
def _helmert_params(rng):
    alpha = float(rng.uniform(0.0, 2.0 * math.pi))
    m = 1.0 + float(rng.uniform(-80e-6, 80e-6))
    a0, b0 = float(rng.uniform(1000.0, 9000.0)), float(rng.uniform(1000.0, 9000.0))
    src = np.round(rng.uniform(0.0, 400.0, (2, 2)), 3)
    while np.hypot(*(src[1] - src[0])) < 150.0:
        src = np.round(rng.uniform(0.0, 400.0, (2, 2)), 3)
    R = m * np.array([[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]])
    dst = np.round(src @ R.T + [a0, b0], 3)
    return {"src": src.tolist(), "dst": dst.tolist(),
            "P1": _fmt_points(src[:1], 3), "P2": _fmt_points(src[1:], 3),
            "Q1": _fmt_points(dst[:1], 3), "Q2": _fmt_points(dst[1:], 3)}


def _helmert_fit(p, swapped=False):
    from photolib.transforms import HelmertTransform
    src, dst = np.array(p["src"]), np.array(p["dst"])
    return HelmertTransform.from_estimate(dst, src) if swapped else \
        HelmertTransform.from_estimate(src, dst)


def _helmert_reference(p):
    return np.array(list(_helmert_fit(p).params.values()))


def _helmert_swapped(p):
    return np.array(list(_helmert_fit(p, swapped=True).params.values()))




def _helmert_notes_sign(p):
    a0, b0, a1, b1 = _helmert_reference(p)
    return np.array([a0, b0, a1, -b1])


helmert_two_points = Exercise(
    params_name="p_helmert",
    id="plane.helmert-two-points", points=3, kind="array", answer="helmert",
    title="Helmert transformation from two points (Helmert-Transformation aus zwei Punkten)",
    statement="Two points were measured in a local site system (x, y) [m] and are known in "
              "the map system (X, Y) [m]: P1 {P1} → {Q1}, P2 {P2} → {Q2} (also as the lists "
              "p_helmert.src and p_helmert.dst). Determine the 4-parameter similarity (Helmert) transformation "
              "local → map of the course, X = a0 + a1·x − b1·y, Y = b0 + b1·x + a1·y, and give "
              "the NumPy array [a0, b0, a1, b1].",
    parameters=_helmert_params, reference=_helmert_reference, tolerance=PRINTED,
    mistakes=(
        Mistake("swapped", _SWAPPED.format(src="(x, y)", dst="(X, Y)"), _helmert_swapped),
        Mistake("sign-b1", "the sign of b1 is reversed: that is the Polish notes' form "
                           "X = a0 + a1·x + b1·y, Y = b0 − b1·x + a1·y; the course writes "
                           "X = a0 + a1·x − b1·y, Y = b0 + b1·x + a1·y", _helmert_notes_sign),
    ))


# -- 2. rotation angle of a Helmert transformation in gon (number) ---------------------------
def _angle_params(rng):
    alpha = float(rng.uniform(0.0, 400.0))
    m = float(rng.uniform(0.2, 5.0))
    a1 = round(m * math.cos(alpha * math.pi / 200.0), 9)
    b1 = round(m * math.sin(alpha * math.pi / 200.0), 9)
    return {"a1": a1, "b1": b1}


def _angle_gon(p):
    return math.atan2(p["b1"], p["a1"]) * 200.0 / math.pi % 400.0


def _angle_arctan(p):
    wrong = math.atan(p["b1"] / p["a1"]) * 200.0 / math.pi
    return None if abs(wrong - _angle_gon(p)) < 1e-6 else wrong


helmert_angle = Exercise(
    params_name="p_angle",
    id="plane.helmert-angle", points=2, kind="number", answer="alpha_gon",
    title="Rotation angle of a Helmert transformation (Drehwinkel)",
    statement="A Helmert transformation X = a0 + a1·x − b1·y, Y = b0 + b1·x + a1·y has "
              "a1 = {a1} and b1 = {b1} (a1 = m·cos α, b1 = m·sin α). Give its rotation angle α "
              "(counter-clockwise) in gon, in [0, 400) gon (400 gon = 360°).",
    parameters=_angle_params, reference=_angle_gon, rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("degrees", "this is the angle in degrees; the task asks for gon "
                           "(400 gon = 360°)", lambda p: _angle_gon(p) * 0.9),
        Mistake("radians", "this is the angle in radians; the task asks for gon "
                           "(multiply by 200/π)", lambda p: _angle_gon(p) * math.pi / 200.0),
        Mistake("quadrant", "arctan(b1/a1) loses the quadrant: use atan2(b1, a1) and add "
                            "400 gon to a negative angle", _angle_arctan),
        Mistake("sign-b1", "this is −α: with the course's sign of b1 the angle is "
                           "atan2(b1, a1), counter-clockwise",
                lambda p: (400.0 - _angle_gon(p)) % 400.0),
        Mistake("atan2-args", "the arguments of atan2 are swapped: α = atan2(b1, a1) "
                              "(sine first)",
                lambda p: math.atan2(p["a1"], p["b1"]) * 200.0 / math.pi % 400.0),
    ))


# -- 3. projective transformation from four control points (array) --------------------------
def _projective_params(rng):
    W, H = round(float(rng.uniform(6.0, 12.0)), 2), round(float(rng.uniform(4.0, 8.0)), 2)
    obj = np.array([[0.0, 0.0], [W, 0.0], [W, H], [0.0, H]])
    left, right = float(rng.uniform(9.0, 12.0)), float(rng.uniform(5.0, 8.0))
    if rng.integers(2):
        left, right = right, left
    img = np.array([[-16.0, -left], [16.0, -right], [16.0, right], [-16.0, left]])
    img = np.round(img + rng.uniform(-1.0, 1.0, img.shape), 3)
    P = np.round(rng.uniform(-10.0, 10.0, 2) * [1.0, 0.5], 3)
    return {"img": img.tolist(), "obj": obj.tolist(), "P": P.tolist(),
            "img_text": _fmt_points(img, 3), "obj_text": _fmt_points(obj, 3),
            "P_text": _fmt_points([P], 3)}


def _projective_with(cls, swapped=False):
    def value(p):
        img, obj, P = np.array(p["img"]), np.array(p["obj"]), np.array(p["P"])
        t = cls.from_estimate(obj, img) if swapped else cls.from_estimate(img, obj)
        return t(P)
    return value


def _transforms():
    from photolib import transforms
    return transforms


def _projective_reference(p):
    return _projective_with(_transforms().ProjectiveTransform)(p)


projective_point = Exercise(
    params_name="p_proj",
    id="plane.projective-point", points=3, kind="array", answer="XY",
    title="Projective transformation from four points (Projektivtransformation)",
    statement="A façade was photographed obliquely. Its four corners have the façade "
              "coordinates (X, Y) [m] {obj_text} and were measured in the image at "
              "(x', y') [mm] {img_text}, in the same order (also as p_proj.obj and p_proj.img). "
              "Determine the projective transformation image → façade (Luhmann 2.18, "
              "X = (a0 + a1·x' + a2·y')/(1 + c1·x' + c2·y'), …) and give the façade "
              "coordinates of the window corner measured at (x', y') = {P_text} mm as the "
              "NumPy array [X, Y] in m.",
    parameters=_projective_params, reference=_projective_reference, tolerance=PRINTED, rtol=0.0, atol=1e-6,
    mistakes=(
        Mistake("swapped", "the transformation was estimated façade → image and applied to "
                           "image coordinates: estimate image → façade (or apply the inverse)",
                lambda p: _projective_with(_transforms().ProjectiveTransform, True)(p)),
        Mistake("affine", "an affine transformation (6 parameters, least squares) cannot "
                          "rectify a central projection: parallel lines converge in the "
                          "image; use the projective transformation (8 parameters)",
                lambda p: _projective_with(_transforms().AffineTransform)(p)),
        Mistake("bilinear", "the bilinear transformation also fits four points exactly, "
                            "but it bends straight lines; a plane in central projection "
                            "needs the projective transformation",
                lambda p: _projective_with(_transforms().BilinearTransform)(p)),
    ))


# -- 4. a distance from the cross ratio (number) ---------------------------------------------
def _cross_params(rng):
    s = np.cumsum(rng.uniform(4.0, 15.0, 4))
    s = np.round(s - s[0], 3)                      # A at 0
    p_, q_, r_ = float(rng.uniform(3.0, 6.0)), float(rng.uniform(-20.0, -10.0)), \
        float(rng.uniform(0.02, 0.08))
    t = np.round((p_ * s + q_) / (r_ * s + 1.0), 3)  # a central projection of the line
    return {"sB": float(s[1]), "sC": float(s[2]), "a": float(t[0]), "b": float(t[1]),
            "c": float(t[2]), "d": float(t[3])}


def _lam(a, b, c, d):
    return (b - a) * (d - c) / ((c - b) * (d - a))


def _cross_reference(p):
    lam = _lam(p["a"], p["b"], p["c"], p["d"])
    sB, sC = p["sB"], p["sC"]
    return sB * sC / (sB - lam * (sC - sB))




cross_ratio = Exercise(
    params_name="p_cross",
    id="plane.cross-ratio", points=2, kind="number", answer="s_D",
    title="Distance from the cross ratio (Doppelverhältnis)",
    statement="Four points A, B, C, D on a straight kerb are imaged on a line of the photo at "
              "the positions a = {a}, b = {b}, c = {c}, d = {d} mm (measured along the image "
              "line). In the object, B is {sB} m and C is {sC} m from A, in the same direction "
              "as D. The cross ratio (Doppelverhältnis, Luhmann 2.21) is invariant under "
              "central projection: compute the distance s_D of D from A in m.",
    parameters=_cross_params, reference=_cross_reference, tolerance=PRINTED,
    mistakes=(
        Mistake("affine-ratio", "the simple ratio (Teilverhältnis) is kept by affine maps only; "
                                "a central projection keeps the cross ratio of four points",
                lambda p: (p["d"] - p["a"]) / (p["b"] - p["a"]) * p["sB"]),
        Mistake("affine-ratio", "the simple ratio (Teilverhältnis) is kept by affine maps only; "
                                "a central projection keeps the cross ratio of four points",
                lambda p: p["sB"] + (p["d"] - p["b"]) / (p["c"] - p["b"]) * (p["sC"] - p["sB"])),
    ))


# -- 5. the cross ratio solved for one point (expression) ------------------------------------
_POINTS = ("A", "B", "C", "D")


def _solved_params(rng):
    point = _POINTS[int(rng.integers(4))]
    return {"point": point, "symbol": f"t_{point}"}


@functools.cache
def _solve_for(expr_text: str, point: str):
    import sympy as sp
    lam = sp.Symbol("lam")
    expr = sp.sympify(expr_text)
    t = {s.name: s for s in expr.free_symbols}[f"t_{point}"]
    num, den = sp.fraction(sp.together(expr))
    (sol,) = sp.solve(sp.expand(lam * den - num), t)
    return sp.cancel(sol)


def _corrected_expr():
    import sympy as sp
    tA, tB, tC, tD = sp.symbols("t_A t_B t_C t_D")
    return (tB - tA) * (tD - tC) / ((tC - tB) * (tD - tA))


def _solved_reference(p):
    return _solve_for(str(_corrected_expr()), p["point"])


_old_print = hints.erratum_version("luhmann:2.21", lambda expr, p: _solve_for(str(expr), p["point"]))

cross_ratio_solved = Exercise(
    params_name="p_cross_sym",
    id="plane.cross-ratio-solved",
    few_variants="a symbolic derivation: the cross ratio solved for one of four points", points=2, kind="expression", answer="t_solved",
    symbols=("t_A", "t_B", "t_C", "t_D", "lam"),
    title="The cross ratio solved for one point (Doppelverhältnis nach einem Punkt aufgelöst)",
    statement="The cross ratio of four collinear points with signed positions t_A, t_B, t_C, "
              "t_D along their line is (Luhmann 2.21 as corrected) "
              "λ = (t_B − t_A)(t_D − t_C) / ((t_C − t_B)(t_D − t_A)). Solve λ = lam for "
              "{symbol} with SymPy and give {symbol} as an expression in the other three "
              "positions and lam (symbols t_A, t_B, t_C, t_D, lam).",
    parameters=_solved_params, reference=_solved_reference,
    mistakes=(Mistake("erratum", "this solves the cross ratio as printed before the erratum "
                                 "(1/(A,B;C,D), luhmann:2.21); the task uses the corrected "
                                 "λ = AB·CD/(BC·AD)", _old_print.wrong),))


# -- 6. image coordinates from fiducial marks (array) ----------------------------------------
_SCANS = ((10500, 10500), (11000, 11000), (15400, 15400), (9240, 9240))
_PIXEL_UM = (21.0, 20.0, 14.0, 25.0)


def _fiducial_params(rng):
    """The scan, its four marks and a point; mark 1's position is the correct result of step 1
    (the centroid of its rendered patch), rounded to 0.01 px."""
    k = int(rng.integers(len(_SCANS)))
    (W, H), ps = _SCANS[k], _PIXEL_UM[k] / 1000.0
    cal = np.array([[-106.0, -106.0], [106.0, -106.0], [106.0, 106.0], [-106.0, 106.0]])
    cal = np.round(cal + rng.uniform(-0.03, 0.03, cal.shape), 3)
    theta = float(rng.uniform(-0.4, 0.4)) * math.pi / 180.0
    sx, sy, shear = 1 + float(rng.uniform(-2e-3, 2e-3)), 1 + float(rng.uniform(-2e-3, 2e-3)), \
        float(rng.uniform(-1e-3, 1e-3))
    A = np.array([[sx * math.cos(theta), -math.sin(theta) + shear],
                  [math.sin(theta), sy * math.cos(theta)]]) / ps
    centre = np.array([(W - 1) / 2, (H - 1) / 2]) + rng.uniform(-60.0, 60.0, 2)

    def to_pixel(xy):
        v = np.asarray(xy) @ A.T
        return np.column_stack([centre[0] + v[:, 0], centre[1] - v[:, 1]])

    pix = np.round(to_pixel(cal) + rng.normal(0.0, 0.3, cal.shape), 2)
    P = np.round(to_pixel(rng.uniform(-90.0, 90.0, (1, 2)))[0], 2)
    # step 1: mark 1 scanned as a patch around its position; its centroid replaces pix[0]
    origin = np.floor(pix[0]).astype(int) - 10
    patch = _render_mark(pix[0] - origin, rng)
    pix[0] = np.round(origin + _centroid(patch, _MARK_BACKGROUND), 2)
    return {"patch": patch.tolist(), "origin": origin.tolist(),
            "origin_text": f"({origin[0]}, {origin[1]})", "background": _MARK_BACKGROUND,
            "W": W, "H": H, "pixel_um": _PIXEL_UM[k], "cal": cal.tolist(), "pix": pix.tolist(),
            "P": P.tolist(), "cal_text": _fmt_points(cal, 3), "pix_text": _fmt_points(pix, 2),
            "P_text": _fmt_points([P], 2)}


def _fiducial_with(cls, flip=False):
    def value(p):
        pix, cal, P = np.array(p["pix"]), np.array(p["cal"]), np.array(p["P"])
        f = np.array([1.0, -1.0]) if flip else np.array([1.0, 1.0])
        return cls.from_estimate(pix * f, cal)(P * f)
    return value


def _fiducial_reference(p):
    return _fiducial_with(_transforms().AffineTransform)(p)


def _fiducial_swapped(p):
    t = _transforms().AffineTransform.from_estimate(np.array(p["cal"]), np.array(p["pix"]))
    return t(np.array(p["P"]))


def _fiducial_pixel_grid(p):
    import photolib as pl
    return pl.image_from_pixel(np.array(p["P"]), p["W"], p["H"], p["pixel_um"] / 1000.0)


fiducial_affine = Exercise(
    params_name="p_affine", scenario="plane.fiducial-centroid",
    id="plane.fiducial-affine", points=3, kind="array", answer="xy_image",
    title="Step 2 of 3: Image coordinates from fiducial marks (Bildkoordinaten aus Rahmenmarken)",
    statement="An analogue aerial photograph was scanned to {W} × {H} pixels of {pixel_um} µm. "
              "Its four corner fiducial marks (Rahmenmarken) have the calibrated image "
              "coordinates (x', y') [mm] {cal_text} and were measured in the scan at "
              "(col, row) [pixel] {pix_text}, in the same order (p_affine.cal, p_affine.pix). The scanner "
              "may scale, shear and turn the image. Estimate the affine transformation "
              "(col, row) → (x', y') by least squares from the four marks (interior "
              "orientation) and give the image coordinates of the point measured at "
              "(col, row) = {P_text} as the NumPy array [x', y'] in mm (to 0.0001 mm). "
              "(Mark 1's position is the correct result of step 1.)",
    parameters=_fiducial_params, reference=_fiducial_reference, tolerance=PRINTED, rtol=0.0, atol=1e-4,
    # the certificate's values define the image coordinate system: exact as printed
    exact=("cal",),
    mistakes=(
        Mistake("helmert", "a Helmert (similarity) transformation cannot absorb the scanner's "
                           "different scales and shear; the task asks for the affine "
                           "transformation (6 parameters)",
                lambda p: _fiducial_with(_transforms().HelmertTransform, flip=True)(p)),
        Mistake("swapped", "this is the transformation (x', y') → (col, row) applied to the "
                           "pixel position: estimate (col, row) → (x', y'), or invert",
                _fiducial_swapped),
        Mistake("projective", "the projective transformation (8 parameters) has no redundancy "
                              "with four marks and models no scanner error; use the affine "
                              "transformation",
                lambda p: _fiducial_with(_transforms().ProjectiveTransform)(p)),
        Mistake("pixel-grid", "this uses the nominal pixel size and the scan centre; the "
                              "fiducial marks, not the pixel grid, define the image coordinate "
                              "system", _fiducial_pixel_grid),
    ))


# -- 7. a bilinear transformation as a function (function) -----------------------------------
#: how each coefficient is printed: to the digits it is drawn to (repr would print a0 drawn
#: to 0.001 as "6948.6", good to 0.05 m only)
_BILINEAR_FORMATS = {"a0": ".3f", "a1": ".6f", "a2": ".6f", "a3": ".3e",
                     "b0": ".3f", "b1": ".6f", "b2": ".6f", "b3": ".3e"}


def _bilinear_params(rng):
    m = float(rng.choice([0.5, 1.0, 2.0]))           # map scale 1:500, 1:1000, 1:2000: m per mm
    # drawn again where both x·y coefficients are tiny: the no-xy mistake would then be
    # within the rounding of the printed a0, b0
    while True:
        a = [round(float(rng.uniform(2000.0, 8000.0)), 3),
             round(m * (1 + rng.uniform(-3e-3, 3e-3)), 6),
             round(m * float(rng.uniform(-2e-3, 2e-3)), 6), round(float(rng.uniform(-2e-6, 2e-6)), 9)]
        b = [round(float(rng.uniform(2000.0, 8000.0)), 3), round(m * float(rng.uniform(-2e-3, 2e-3)), 6),
             round(m * (1 + rng.uniform(-3e-3, 3e-3)), 6), round(float(rng.uniform(-2e-6, 2e-6)), 9)]
        if max(abs(a[3]), abs(b[3])) >= 5e-7:
            break
    coeff = {f"a{i}": a[i] for i in range(4)} | {f"b{i}": b[i] for i in range(4)}
    coeff["text"] = ", ".join(f"{k} = {v:{_BILINEAR_FORMATS[k]}}" for k, v in coeff.items())
    return coeff


def _bilinear_function(p, drop_xy=False):
    a = [p[f"a{i}"] for i in range(4)]
    b = [p[f"b{i}"] for i in range(4)]
    k = 0.0 if drop_xy else 1.0

    def bilinear(x, y):
        x, y = float(x), float(y)
        return np.array([a[0] + a[1] * x + a[2] * y + k * a[3] * x * y,
                         b[0] + b[1] * x + b[2] * y + k * b[3] * x * y])
    return bilinear


def _bilinear_printed(expr, p):
    """The notes' printed formula with the exercise's coefficients.

    The notes number Y's coefficients b0 + b1·y + b2·x + b3·x·y; their b1 is the course's b2
    and their b2 the course's b1.
    """
    import sympy as sp
    names = {s.name: s for s in expr.free_symbols}
    values = {names[n]: p[n] for n in ("a0", "a1", "a2", "a3", "b0") if n in names}
    values[names["b1"]] = p["b2"]
    values[names["b2"]] = p["b1"]
    fX, fY = (sp.lambdify((names["x_s"], names["y_s"]), e, "math") for e in expr.subs(values))

    def bilinear(x, y):
        return np.array([fX(float(x), float(y)), fY(float(x), float(y))], dtype=float)
    return bilinear


_printed = hints.erratum_version("pl-notes:bilinear", _bilinear_printed, version="printed")


def _bilinear_cases(rng, p):
    # away from the sheet's axes, where x·y and so the no-xy mistake vanish
    return [(round(float(rng.uniform(100.0, 500.0)), 2), round(float(rng.uniform(100.0, 500.0)), 2))
            for _ in range(6)]


bilinear_function = Exercise(
    params_name="p_bil",
    id="plane.bilinear-function", points=3, kind="function", answer="bilinear",
    title="A bilinear transformation as a function (bilineare Transformation)",
    statement="A distorted map sheet is corrected with the bilinear transformation from sheet "
              "coordinates (x, y) [mm] to grid coordinates (X, Y) [m]: "
              "X = a0 + a1·x + a2·y + a3·x·y, Y = b0 + b1·x + b2·y + b3·x·y with {text} "
              "(also p_bil.a0, …, p_bil.b3). Write bilinear(x, y) returning the NumPy array [X, Y]. It "
              "is tested on sheet points you do not see.",
    parameters=_bilinear_params, reference=_bilinear_function, tolerance=PRINTED, cases=_bilinear_cases,
    rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("erratum", "this is the bilinear formula as printed in the Polish notes "
                           "(pl-notes:bilinear, see the errata chapter): in Y one coefficient "
                           "appears twice (b2 in the notes' numbering, the coefficient of x) and "
                           "b3 is missing; Y = b0 + b1·x + b2·y + b3·x·y", _printed.wrong),
        Mistake("no-xy", "the x·y terms (a3·x·y, b3·x·y) are missing: that is the affine "
                         "transformation, not the bilinear one",
                lambda p: _bilinear_function(p, drop_xy=True)),
    ))


# -- 6b. fiducial mark: centroid (step 1) and σ0 of the comparator transformation (step 3) ---
#: threshold t of the centroid weights w = max(g − t, 0), grey values
_MARK_BACKGROUND = 60.0


def _render_mark(centre, rng, shape=(21, 21), radius=2.5, k=8):
    """A scanned fiducial mark: a bright dot (radius px) integrated over each pixel
    (k² sub-samples), film 20, dot 220, grey-value noise σ = 4, rounded to integers."""
    rows, cols = shape
    fr = (np.arange(rows * k) + 0.5) / k - 0.5
    fc = (np.arange(cols * k) + 0.5) / k - 0.5
    inside = (fc[None, :] - centre[0]) ** 2 + (fr[:, None] - centre[1]) ** 2 <= radius ** 2
    cover = inside.reshape(rows, k, cols, k).mean(axis=(1, 3))
    return np.round(20.0 + 200.0 * cover + rng.normal(0.0, 4.0, shape)).astype(int)


def _centroid(patch, t, swap=False):
    g = np.asarray(patch, dtype=float)
    w = np.maximum(g - t, 0.0)
    rows, cols = np.indices(g.shape)
    c = np.array([np.sum(cols * w), np.sum(rows * w)]) / w.sum()
    return c[::-1] if swap else c


def _mark_reference(p):
    return np.asarray(p["origin"], dtype=float) + _centroid(p["patch"], p["background"])


fiducial_centroid = Exercise(
    params_name="p_mark", scenario="plane.fiducial-centroid",
    id="plane.fiducial-centroid", points=2, kind="array", answer="mark1",
    title="Step 1 of 3: Measuring a fiducial mark by its centroid (Rahmenmarke, Schwerpunkt)",
    statement="Fiducial mark 1 of a scanned aerial photograph is a bright dot on dark film. "
              "The scan around it is the 21 × 21 patch of grey values p_mark.patch (a list "
              "of rows); its top-left pixel is the scan pixel (col, row) = {origin_text}. "
              "Measure the mark semi-automatically by the grey-value weighted centroid, "
              "weights $w = \\max(g - t, 0)$ with the threshold $t = {background}$, "
              "$c = \\sum c_i w_i / \\sum w_i$ (rows alike), and give its position in the "
              "scan as the NumPy array [col, row] in pixels (to 0.001 px).",
    parameters=_fiducial_params, reference=_mark_reference, rtol=1e-6, atol=0.004,
    exact=("background",),
    mistakes=(
        Mistake("row-col", "these are (row, col): the course's pixel coordinates are "
                           "(col, row), column first",
                lambda p: np.asarray(p["origin"], float)
                + _centroid(p["patch"], p["background"], swap=True)),
        Mistake("patch-origin", "this is the position in the patch: add the scan position "
                                "{origin_text} of the patch's top-left pixel",
                lambda p: _centroid(p["patch"], p["background"])),
        Mistake("no-threshold", "without the threshold every pixel of the film weighs in "
                                "and pulls the centroid towards the patch centre: use "
                                "w = max(g − t, 0)",
                lambda p: np.asarray(p["origin"], float) + _centroid(p["patch"], 0.0)),
    ))


def _fiducial_fit(p, cls=None):
    cls = cls or _transforms().AffineTransform
    pix, cal = np.array(p["pix"]), np.array(p["cal"])
    return cls.from_estimate(pix * [1.0, -1.0], cal)


def _sigma0_um(p, divisor=None, cls=None):
    t = _fiducial_fit(p, cls)
    v = t.residuals
    r = t.redundancy if divisor is None else divisor
    return 1000.0 * math.sqrt(float(np.sum(v ** 2)) / r)


fiducial_sigma0 = Exercise(
    params_name="p_sigma0", scenario="plane.fiducial-centroid",
    id="plane.fiducial-sigma0", points=2, kind="number", answer="sigma0_um",
    title="Step 3 of 3: The precision of the interior orientation (σ0 der Rahmenmarken)",
    statement="The same scan: the four fiducial marks with calibrated image coordinates "
              "(x', y') [mm] {cal_text} measured at (col, row) [pixel] {pix_text} "
              "(p_sigma0.cal, p_sigma0.pix; mark 1 as step 1 measured it). After the affine "
              "transformation (col, −row) → (x', y') by least squares (step 2), give the "
              "standard deviation of unit weight $\\sigma_0 = \\sqrt{{v^Tv / r}}$ of the "
              "residuals in µm (to 0.01 µm), with r the redundancy.",
    parameters=_fiducial_params, reference=_sigma0_um, tolerance=PRINTED, atol=0.005,
    exact=("cal",),
    mistakes=(
        Mistake("divide-n", "this divides vᵀv by the number of observations n = 8; σ0 "
                            "divides by the redundancy r = n − u = 8 − 6 = 2",
                lambda p: _sigma0_um(p, divisor=8)),
        Mistake("mm", "this is σ0 in mm; the task asks for µm (× 1000)",
                lambda p: _sigma0_um(p) / 1000.0),
        Mistake("helmert", "this is σ0 of the Helmert (similarity) transformation (r = 4); "
                           "the task asks for the affine one",
                lambda p: _sigma0_um(p, cls=_transforms().HelmertTransform)),
    ))


# -- 8. homography from points as a function (function) ---------------------------------------
def _hartley(p):
    c = p.mean(axis=0)
    s = math.sqrt(2.0) / float(np.mean(np.linalg.norm(p - c, axis=1)))
    return np.array([[s, 0.0, -s * c[0]], [0.0, s, -s * c[1]], [0.0, 0.0, 1.0]])


def _dlt(src, dst, normalise=True, swap=False):
    """The (normalised) linear solution of the homography src → dst, h33 = 1."""
    src, dst = np.asarray(src, dtype=float), np.asarray(dst, dtype=float)
    if swap:
        src, dst = src[:, ::-1], dst[:, ::-1]
    transforms = _transforms()
    transforms.ProjectiveTransform.from_estimate(src, dst)   # ValueError for degenerate points
    Ts, Td = (_hartley(src), _hartley(dst)) if normalise else (np.eye(3), np.eye(3))
    u = src @ Ts[:2, :2].T + Ts[:2, 2]
    U = dst @ Td[:2, :2].T + Td[:2, 2]
    A = np.zeros((2 * len(u), 9))
    for i, ((x, y), (X, Y)) in enumerate(zip(u, U)):
        A[2 * i] = [x, y, 1, 0, 0, 0, -X * x, -X * y, -X]
        A[2 * i + 1] = [0, 0, 0, x, y, 1, -Y * x, -Y * y, -Y]
    H = np.linalg.inv(Td) @ np.linalg.svd(A)[2][-1].reshape(3, 3) @ Ts
    H = H / H[2, 2]
    if swap:
        P = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
        H = P @ H @ P           # the same map written for (y, x): what swapping x, y gives
        H = H.T                 # read back in the wrong order (the swap does not cancel)
    return H


def _homography_params(rng):
    H = np.array([[round(float(rng.uniform(40.0, 60.0)), 2), round(float(rng.uniform(-8, 8)), 2),
                   round(float(rng.uniform(-20, 20)), 2)],
                  [round(float(rng.uniform(-8, 8)), 2), round(float(rng.uniform(40.0, 60.0)), 2),
                   round(float(rng.uniform(-20, 20)), 2)],
                  [round(float(rng.uniform(-0.05, 0.05)), 4),
                   round(float(rng.uniform(-0.05, 0.05)), 4), 1.0]])
    return {"H": H.tolist()}


def _map(H, pts):
    P = np.column_stack([pts, np.ones(len(pts))]) @ np.asarray(H, dtype=float).T
    return P[:, :2] / P[:, 2:]


def _homography_cases(rng, p):
    H = np.array(p["H"])
    square = rng.uniform(0.5, 1.5, (4, 2)) + [[0, 0], [8, 0], [8, 6], [0, 6]]
    clean = (np.round(square, 3).tolist(), np.round(_map(H, square), 3).tolist())
    # eight points spread over the plane (a jittered 3 × 3 grid without its centre)
    many = np.array([[x, y] for x in (0.0, 5.0, 10.0) for y in (0.0, 5.0, 10.0)
                     if (x, y) != (5.0, 5.0)]) + rng.uniform(-1.0, 1.0, (8, 2))
    noisy = (np.round(many, 3).tolist(),
             np.round(_map(H, many) + rng.normal(0.0, 0.5, many.shape), 3).tolist())
    # three points exactly collinear (whole numbers: exact in float32 as well)
    a = rng.integers(0, 5, 2).astype(float)
    b = a + 2 * rng.integers(1, 3, 2)
    line = [a, b, (a + b) / 2, np.array([float(rng.integers(0, 4)), float(rng.integers(7, 10))])]
    degenerate = (np.array(line).tolist(), np.round(_map(H, np.array(line))
                                                        + [[0.0, 0.0], [0.0, 0.0], [3.0, -2.0],
                                                           [0.0, 0.0]], 3).tolist())
    return [clean, noisy, degenerate]


def _homography_reference(p):
    def homography(src, dst):
        return _dlt(src, dst)
    return homography


homography_function = Exercise(
    params_name="p_hfun",
    id="plane.homography-function", points=4, kind="function", answer="homography",
    few_variants="a function of its arguments alone: one correct function for every student "
                 "(the hidden test points differ)",
    title="The projective transformation from points, as a function (Projektivtransformation)",
    statement="Write homography(src, dst): src and dst are lists of n ≥ 4 corresponding "
              "points [[x, y], …] and [[X, Y], …]. Return the 3 × 3 NumPy array H of the "
              "projective transformation src → dst, $(X, Y, 1)^T \\propto H\\,(x, y, 1)^T$, "
              "scaled to $h_{{33}} = 1$, from the **normalised linear solution**: normalise "
              "both point sets (centroid to 0, mean distance √2), take the right singular "
              "vector of the smallest singular value of the 2n × 9 DLT matrix, undo the "
              "normalisation. If three of four points are collinear, raise ValueError. "
              "Your numbers: the test points are mapped by p_hfun.H = {H} with noise added; the "
              "function is tested on points you do not see.",
    parameters=_homography_params, reference=_homography_reference,
    cases=_homography_cases, rtol=1e-4, atol=1e-6,  # float32 work on noisy points: 1e-5
    mistakes=(
        Mistake("transposed", "H is transposed: the row i of H gives the i-th homogeneous "
                              "coordinate, (X, Y, 1)ᵀ ∝ H·(x, y, 1)ᵀ",
                lambda p: lambda s, d: _dlt(s, d).T),
        Mistake("no-normalisation", "the linear solution without normalising the points "
                                    "first: with noise it is a worse, different estimate; "
                                    "centre each set and scale it to mean distance √2",
                lambda p: lambda s, d: _dlt(s, d, normalise=False)),
        Mistake("h33", "H is not scaled to h33 = 1 (a singular vector has norm 1): "
                       "divide by H[2, 2]",
                lambda p: lambda s, d: _dlt(s, d) / np.linalg.norm(_dlt(s, d))),
        Mistake("swapped", "this is the transformation dst → src: estimate src → dst",
                lambda p: lambda s, d: _dlt(d, s)),
    ))


# -- 9. mapping a grid by a homography as a function (function) -----------------------------
def _map_checked(H, points, transpose=False, divide=True, swap=False):
    H = np.asarray(H, dtype=float)
    if H.shape != (3, 3):
        raise ValueError(f"H must be 3 × 3, got shape {H.shape}")
    if abs(np.linalg.det(H)) <= 1e-6 * np.linalg.norm(H) ** 3:
        raise ValueError(f"H is singular (det H = {np.linalg.det(H):.3g}): it maps the plane "
                         "onto a line or a point, no transformation of the plane")
    pts = np.asarray(points, dtype=float)
    if swap:
        pts = pts[:, ::-1]
    P = np.column_stack([pts, np.ones(len(pts))]) @ (H if transpose else H.T)
    out = P[:, :2] / P[:, 2:] if divide else P[:, :2]
    return out[:, ::-1] if swap else out


def _grid_cases(rng, p):
    H = np.array(p["H"])
    grid = [[float(x), float(y)] for x in (0.0, 2.5, 5.0) for y in (0.0, 2.0, 4.0)]
    pts = np.round(rng.uniform(0.0, 10.0, (5, 2)), 3).tolist()
    other = np.array(_homography_params(rng)["H"])     # another homography of the same kind
    singular = other.copy()
    singular[2] = 0.5 * other[0] + 0.02 * other[1]     # third row dependent: rank 2
    return [(H.tolist(), grid), (other.tolist(), pts), (singular.tolist(), grid)]


map_points = Exercise(
    params_name="p_grid",
    id="plane.map-points-function", points=3, kind="function", answer="map_points",
    few_variants="a function of its arguments alone: one correct function for every student "
                 "(the hidden test matrices and points differ)",
    title="Rectifying a grid of points, as a function (Punkte entzerren)",
    statement="Write map_points(H, points): H is a 3 × 3 homography (list of rows), points a "
              "list of n points [[x, y], …]. Return the NumPy array (n, 2) of the mapped "
              "points $(X, Y)$ with $(u, v, w)^T = H\\,(x, y, 1)^T$, $X = u/w$, $Y = v/w$. "
              "Raise ValueError if H is singular (det H = 0 relative to its size, "
              "$|\\det H| \\le 10^{{-6}}\\,\\|H\\|^3$, ‖H‖ the Frobenius norm). Your H for trying it: p_grid.H "
              "= {H}; the function is tested on other points and matrices.",
    parameters=_homography_params, reference=lambda p: _map_checked,
    cases=_grid_cases, rtol=1e-5, atol=1e-7,
    mistakes=(
        Mistake("transposed", "H is transposed: (u, v, w)ᵀ = H·(x, y, 1)ᵀ, so u is row 1 "
                              "of H times (x, y, 1)",
                lambda p: lambda H, pts: _map_checked(H, pts, transpose=True)),
        Mistake("no-division", "the division by the third homogeneous coordinate w is "
                               "missing: X = u/w, Y = v/w",
                lambda p: lambda H, pts: _map_checked(H, pts, divide=False)),
        Mistake("xy-swapped", "x and y are swapped: each point is [x, y], and the result "
                              "[X, Y]",
                lambda p: lambda H, pts: _map_checked(H, pts, swap=True)),
    ))


# -- 10. the church: homography, a check point and the cross ratio (a scenario) -------------
#: glass height of the church's windows in window spacings (chapter 07, from the camera)
CHURCH_HEIGHT = 0.67
#: measuring precision of a corner, px per coordinate (σ0 of the ten corners, chapter 07)
CHURCH_SIGMA_PX = 0.5


@functools.cache
def _church_pixels():
    import json
    from importlib import resources
    data = json.loads(resources.files("photolib.data").joinpath("church_windows.json")
                      .read_text(encoding="utf-8"))
    return np.array(data["refined_px"], dtype=float).reshape(-1, 2)


def _church_facade():
    return np.array([[k, y] for k in range(5) for y in (CHURCH_HEIGHT, 0.0)], dtype=float)


_CORNER_NAMES = tuple(f"window {k} {c}" for k in range(5) for c in ("top-left", "bottom-left"))


def _church_params(rng):
    pix, obj = _church_pixels(), _church_facade()
    top = sorted(rng.choice(5, 2, replace=False).tolist())
    bottom = sorted(rng.choice(5, 2, replace=False).tolist())
    control = [2 * top[0], 2 * top[1], 2 * bottom[1] + 1, 2 * bottom[0] + 1]
    rest = [i for i in range(10) if i not in control]
    check = int(rng.choice(rest))
    T = _transforms().ProjectiveTransform.from_estimate(pix[control], obj[control])
    H = T.matrix / T.matrix[2, 2]
    # step 3: four of the five corners of one row, in a random order
    row = int(rng.integers(2))
    left_out = int(rng.integers(5))
    windows = [k for k in range(5) if k != left_out]
    order = rng.permutation(4).tolist()
    line = [2 * windows[i] + row for i in order]
    fmt = lambda pts: _fmt_points(pts, 2)  # noqa: E731
    return {"control": control, "img": pix[control].tolist(), "obj": obj[control].tolist(),
            "img_text": fmt(pix[control]), "obj_text": _fmt_points(obj[control], 2),
            "names": ", ".join(_CORNER_NAMES[i] for i in control),
            "check": check, "check_name": _CORNER_NAMES[check], "P": pix[check].tolist(),
            "P_text": fmt(pix[[check]]), "H": H.tolist(),
            "H_text": "[" + ", ".join("[" + ", ".join(f"{v:.10g}" for v in r) + "]"
                                      for r in H) + "]",
            "line": line, "line_pts": pix[line].tolist(), "line_text": fmt(pix[line]),
            "line_names": ", ".join(_CORNER_NAMES[i] for i in line)}


def _church_H(p, swapped=False, transposed=False):
    img, obj = np.array(p["img"]), np.array(p["obj"])
    T = _transforms().ProjectiveTransform.from_estimate(*((obj, img) if swapped else (img, obj)))
    H = T.matrix / T.matrix[2, 2]
    return H.T if transposed else H


def _church_point(p, H=None, divide=True):
    H = np.array(p["H"]) if H is None else H
    u = H @ [*p["P"], 1.0]
    return u[:2] / u[2] if divide else u[:2]


def _church_point_atol(p):
    """A tenth of the σ of X and Y that the corners' measuring precision gives (σ = 0.5 px,
    through the Jacobian of the transformation at the point): an answer rounded to 0.001
    spacings passes, a method error of the size of the measuring noise does not."""
    H = np.array(p["H"])
    J = np.zeros((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = 1e-3
        J[:, j] = (_church_point({**p, "P": np.add(p["P"], e).tolist()})
                   - _church_point({**p, "P": np.subtract(p["P"], e).tolist()})) / 2e-3
    del H
    return 0.0, 0.1 * CHURCH_SIGMA_PX * np.sqrt((J ** 2).sum(axis=1))


def _church_H_atol(p):
    """The rounding of the printed pixel coordinates (half of 0.01 px), propagated to each
    entry of H, plus float32."""
    from photolib.grading.judge import propagated_atol
    return 1e-6, propagated_atol(_church_H, p, {"img": 0.005}, floor=1e-12)


church_homography = Exercise(
    params_name="p_church", scenario="plane.church-homography",
    id="plane.church-homography", points=3, kind="array", answer="H_church",
    title="Step 1 of 3: Rectifying a real façade — the projective transformation",
    statement="The photograph church.png (photolib.data.church(), treated as an archival "
              "photograph) shows the church's aisle wall with five windows. Four glass "
              "corners ({names}) were measured at (col, row) [px] {img_text} "
              "(p_church.img, precision 0.5 px); on the façade (window spacings, glass height "
              "0.67) they are at (X, Y) {obj_text} (p_church.obj). Determine the projective "
              "transformation image (col, row) → façade (X, Y) and give it as the 3 × 3 "
              "NumPy array H, $(X, Y, 1)^T \\propto H\\,(col, row, 1)^T$, scaled to "
              "$h_{{33}} = 1$.",
    parameters=_church_params, reference=_church_H, tolerance=_church_H_atol,
    exact=("obj",),  # the façade system is defined by them
    mistakes=(
        Mistake("swapped", "this is the transformation façade → image: estimate image → "
                           "façade (or invert H)", lambda p: _church_H(p, swapped=True)),
        Mistake("transposed", "H is transposed: (X, Y, 1)ᵀ ∝ H·(col, row, 1)ᵀ",
                lambda p: _church_H(p, transposed=True)),
    ))

church_point = Exercise(
    params_name="p_church_point", scenario="plane.church-homography",
    id="plane.church-point", points=2, kind="array", answer="XY_check",
    title="Step 2 of 3: Rectifying a real façade — a check point",
    statement="With the transformation of step 1, H = {H_text} (p_church_point.H, image "
              "(col, row) → façade), rectify the check point {check_name}, measured at "
              "(col, row) = {P_text} px: give its façade coordinates as the NumPy array "
              "[X, Y] in window spacings (to 0.001).",
    parameters=_church_params, reference=_church_point, tolerance=_church_point_atol,
    mistakes=(
        Mistake("no-division", "the division by the third homogeneous coordinate is "
                               "missing: X = u/w, Y = v/w",
                lambda p: _church_point(p, divide=False)),
        Mistake("transposed", "H is transposed: (u, v, w)ᵀ = H·(col, row, 1)ᵀ",
                lambda p: _church_point(p, H=np.array(p["H"]).T)),
        Mistake("swapped", "this applies the inverse of H (façade → image): H maps the "
                           "image to the façade",
                lambda p: _church_point(p, H=np.linalg.inv(np.array(p["H"])))),
    ))


def _church_lambda(p, pts=None):
    P = np.array(p["line_pts"] if pts is None else pts)
    return _transforms().cross_ratio(*P, atol=0.01)


def _church_lambda_atol(p):
    """A tenth of σ_λ propagated from the corners' precision (0.5 px per coordinate)."""
    P = np.array(p["line_pts"]).ravel()
    grad = [(_church_lambda(p, (P + e).reshape(4, 2)) - _church_lambda(p, (P - e).reshape(4, 2)))
            / 2e-3 for e in 1e-3 * np.eye(8)]
    return 0.0, 0.1 * CHURCH_SIGMA_PX * float(np.linalg.norm(grad))


def _church_lambda_facade(p):
    obj = _church_facade()[p["line"]]
    value = _transforms().cross_ratio(*obj)
    return None if abs(value - _church_lambda(p)) < 3 * _church_lambda_atol(p)[1] else value


church_cross_ratio = Exercise(
    params_name="p_church_cr", scenario="plane.church-homography",
    id="plane.church-cross-ratio", points=2, kind="number", answer="lam_church",
    title="Step 3 of 3: Rectifying a real façade — the cross ratio of a row of windows",
    statement="Four collinear corners of the same photograph, A, B, C, D = {line_names}, "
              "were measured at (col, row) [px] {line_text} (p_church_cr.line_pts). Compute "
              "their cross ratio (Doppelverhältnis) as the course defines it, "
              "$\\lambda = \\overline{{AB}}\\cdot\\overline{{CD}} / (\\overline{{BC}}\\cdot"
              "\\overline{{AD}})$ with signed segments along the fitted line, from the "
              "measured image points (to 4 decimals; the points are collinear only to the "
              "measuring precision, so pass atol=0.01 to pl.cross_ratio).",
    parameters=_church_params, reference=_church_lambda, tolerance=_church_lambda_atol,
    mistakes=(
        Mistake("facade", "this is the cross ratio of the façade positions; the task asks "
                          "for the one measured in the image (they agree only to σ_λ)",
                _church_lambda_facade),
        Mistake("classical", "this is the classical cross ratio (A, B; C, D) = AC·BD/(BC·AD) "
                             "= λ + 1; the course's λ is AB·CD/(BC·AD)",
                lambda p: _church_lambda(p) + 1.0),
        Mistake("erratum", "this is 1/(A, B; C, D), the cross ratio as first printed "
                           "(luhmann:2.21); the course uses the corrected λ = AB·CD/(BC·AD)",
                lambda p: 1.0 / (_church_lambda(p) + 1.0)),
    ))


EXERCISES = (helmert_two_points, helmert_angle, projective_point, cross_ratio,
             cross_ratio_solved, fiducial_centroid, fiducial_affine, fiducial_sigma0,
             bilinear_function, homography_function, map_points, church_homography,
             church_point, church_cross_ratio)
