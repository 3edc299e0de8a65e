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
    return {"W": W, "H": H, "pixel_um": _PIXEL_UM[k], "cal": cal.tolist(), "pix": pix.tolist(),
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
    params_name="p_affine",
    id="plane.fiducial-affine", points=3, kind="array", answer="xy_image",
    title="Image coordinates from fiducial marks (Bildkoordinaten aus Rahmenmarken)",
    statement="An analogue aerial photograph was scanned to {W} × {H} pixels of {pixel_um} µm. "
              "Its four corner fiducial marks (Rahmenmarken) have the calibrated image "
              "coordinates (x', y') [mm] {cal_text} and were measured in the scan at "
              "(col, row) [pixel] {pix_text}, in the same order (p_affine.cal, p_affine.pix). The scanner "
              "may scale, shear and turn the image. Estimate the affine transformation "
              "(col, row) → (x', y') by least squares from the four marks (interior "
              "orientation) and give the image coordinates of the point measured at "
              "(col, row) = {P_text} as the NumPy array [x', y'] in mm.",
    parameters=_fiducial_params, reference=_fiducial_reference, tolerance=PRINTED, rtol=0.0, atol=1e-4,
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


EXERCISES = (helmert_two_points, helmert_angle, projective_point, cross_ratio,
             cross_ratio_solved, fiducial_affine, bilinear_function)
