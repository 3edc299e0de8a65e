"""Chapter 14-project: the capstone, graded per step (one scenario, five steps).

The photogrammetric chain on two real chessboard views (mvtb-data left01 … left14) of a
student's own (a pair whose rays meet at ≥ 15°) with six corners of the student's own withheld
as check points (Kontrollpunkte):

1. ``prj.image-point`` (array): pixel → distortion-corrected image coordinates of one corner
   (interior orientation of chapter 05);
2. ``prj.resection`` (array): exterior orientation of both views from the 48 control points;
3. ``prj.sigma0`` (array): redundancy and σ0 of the first view's resection;
4. ``prj.intersection`` (array): forward intersection of the check points, from the correct
   orientations of step 2 (printed);
5. ``prj.check-rms`` (number): RMS of the check points' 3-D differences from the board
   geometry (square side 25 mm), from the correct points of step 4 (printed).

References: :mod:`photolib.nb.project` (photolib's space resection and forward intersection
on the corners OpenCV measured, the calibration of
:func:`photolib.testfield.plane_field_calibration`). Image unit px, object unit mm.

>>> [ex.id for ex in EXERCISES]
['prj.image-point', 'prj.resection', 'prj.sigma0', 'prj.intersection', 'prj.check-rms']
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "14-project"
SCENARIO = "prj.image-point"
_STEPS = 5
_NAMES = ("A1", "A2", "A3", "B1", "B2")


def _fmt(values, digits):
    """Numbers (a vector or a list of rows) printed with a fixed number of decimals."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        return "(" + ", ".join(f"{v:.{digits}f}" for v in values) + ")"
    return "[" + ", ".join(_fmt(row, digits) for row in values) + "]"


def _project():
    from photolib.nb import project
    return project


@functools.lru_cache(maxsize=64)
def _chain(a, b, check):
    return _project().chain(a, b, check)


def _draw(rng):
    """What every step draws from the scenario's seed: the pair, the check points, a corner."""
    pj = _project()
    a, b = pj.draw_pair(rng)
    check = pj.draw_check_points(rng)
    k = int(rng.integers(54))
    return {"view_a": a, "view_b": b, "name_a": pj.view_name(a), "name_b": pj.view_name(b),
            "check": check, "k": k}


def _interior():
    r = _project().calibration().result
    d = r.distortion.params
    return {"c": round(r.c, 3), "x0": round(r.x0, 3), "y0": round(r.y0, 3),
            **{n: float(f"{d[n]:.7g}") for n in _NAMES}}


# -- step 1: pixel -> corrected image coordinates -------------------------------------------------
def _pixel_params(rng):
    p = _draw(rng)
    col, row = _project().pixel_corners(p["view_a"])[p["k"]]
    return p | _interior() | {"col": round(float(col), 3), "row": round(float(row), 3),
                              "W": 640, "H": 480}


def _delta(p, x, y):
    """Δx', Δy' (px) at (x, y) reduced to the principal point: the statement's formula."""
    r2 = x * x + y * y
    radial = p["A1"] * r2 + p["A2"] * r2**2 + p["A3"] * r2**3
    return (x * radial + p["B1"] * (r2 + 2 * x * x) + 2 * p["B2"] * x * y,
            y * radial + p["B2"] * (r2 + 2 * y * y) + 2 * p["B1"] * x * y)


def _image_point(p, flip=True, sign=1.0, reduce=True, shift=True, distortion=True):
    x = p["col"] - ((p["W"] - 1) / 2 if shift else 0.0)
    y = ((p["H"] - 1) / 2 - p["row"]) if flip else (p["row"] - (p["H"] - 1) / 2)
    if not shift:
        y = -p["row"] if flip else p["row"]
    if not distortion:
        return np.array([x, y])
    x0, y0 = (p["x0"], p["y0"]) if reduce else (0.0, 0.0)
    dx, dy = _delta(p, x - x0, y - y0)
    return np.array([x - sign * dx, y - sign * dy])


def _image_point_reference(p):
    import photolib as pl
    x, y = pl.image_from_pixel([[p["col"], p["row"]]], p["W"], p["H"], 1.0)[0]
    d = pl.Distortion(**{n: p[n] for n in _NAMES})
    pp = np.array([p["x0"], p["y0"]])
    return pp + d.correct(np.array([x, y]) - pp)


_DISTORTION_TEXT = (
    "$\\Delta x' = \\bar x(A_1 r^2 + A_2 r^4 + A_3 r^6) + B_1(r^2 + 2\\bar x^2) + "
    "2B_2\\bar x\\bar y$, $\\Delta y' = \\bar y(A_1 r^2 + A_2 r^4 + A_3 r^6) + "
    "B_2(r^2 + 2\\bar y^2) + 2B_1\\bar x\\bar y$ with $\\bar x = x' - x'_0$, "
    "$\\bar y = y' - y'_0$, $r^2 = \\bar x^2 + \\bar y^2$")

image_point = Exercise(
    id="prj.image-point", scenario=SCENARIO, points=2, kind="array", answer="xy_ideal",
    params_name="p_pixel",
    title=f"Step 1 of {_STEPS}: interior orientation of a measured corner / Bildkoordinaten",
    statement="Your two views are **{name_a}** (view {view_a}) and **{name_b}** (view {view_b}) "
              "of `photolib.data.chessboard()`; your check points are the corners {check}. "
              "OpenCV measured corner {k} of {name_a} at column {col:.3f} px, row {row:.3f} px "
              "(image {W} × {H} px, origin at the centre of the top-left pixel). The chapter-05 "
              "calibration gives $c$ = {c:.3f} px, $x'_0$ = {x0:.3f} px, $y'_0$ = {y0:.3f} px "
              "and $A_1$ = {A1} px⁻², $A_2$ = {A2} px⁻⁴, $A_3$ = {A3} px⁻⁶, $B_1$ = {B1} px⁻¹, "
              "$B_2$ = {B2} px⁻¹. Convert the corner to image coordinates "
              "$x' = \\text{{col}} - (W-1)/2$, $y' = (H-1)/2 - \\text{{row}}$ (px, $y'$ up) and "
              "correct the distortion, evaluated at the measured point: $x_{{ideal}} = x' - "
              "\\Delta x'$, $y_{{ideal}} = y' - \\Delta y'$, " + _DISTORTION_TEXT + ". "
              "Give `xy_ideal` = $(x_{{ideal}}, y_{{ideal}})$ in px (to 0.001 px), shape (2,).",
    parameters=_pixel_params, reference=_image_point_reference, tolerance=PRINTED,
    exact=("W", "H"),
    mistakes=(
        Mistake("y-axis", "y′ points up: y′ = (H − 1)/2 − row, not row − (H − 1)/2",
                lambda p: _image_point(p, flip=False)),
        Mistake("sign", "the distortion is subtracted: x_ideal = x′ − Δx′ (Δ evaluated at the "
                        "measured point), not added", lambda p: _image_point(p, sign=-1.0)),
        Mistake("distortion", "the distortion correction is missing: Δx′ reaches tens of px "
                              "at the image corners of this wide-angle camera",
                lambda p: _image_point(p, distortion=False)),
        Mistake("principal-point", "Δ is evaluated at the coordinates reduced to the principal "
                                   "point, x̄ = x′ − x′0, ȳ = y′ − y′0",
                lambda p: _image_point(p, reduce=False)),
        Mistake("origin", "the image coordinates have their origin at the image centre: "
                          "subtract (W − 1)/2 from the column and take (H − 1)/2 − row",
                lambda p: _image_point(p, shift=False)),
    ))


# -- step 2: resection of both views --------------------------------------------------------------
def _resection_params(rng):
    return _draw(rng) | _interior()


def _orientations(p, degrees=False, raw=False):
    if raw:
        return _orientations_raw(p)
    ch = _chain(p["view_a"], p["view_b"], tuple(p["check"]))
    q = np.array([r.params for r in ch.resections])
    if degrees:
        q[:, 3:] = np.degrees(q[:, 3:])
    return q


def _orientations_raw(p):
    """The resections on the image coordinates without the distortion correction."""
    import photolib as pl
    from photolib.testfield import plane_start
    pj = _project()
    cal = pj.calibration()
    r = cal.result
    control = [k for k in range(54) if k not in p["check"]]
    X = pj.board_points()[control]
    out = []
    for v in (p["view_a"], p["view_b"]):
        xy = cal.xy[v][control]
        _, start = plane_start([xy - np.array([r.x0, r.y0])], X[:, :2], c=r.c)
        out.append(pl.space_resection(X, xy, r.c, r.x0, r.y0, initial=start[0], tol=1e-6,
                                      max_iter=200, check=False).params)
    return np.array(out)


def _resection_tolerance(p):
    """One standard deviation of each unknown: what the corner measurement noise
    (σ0 ≈ 0.15 px) leaves undetermined; a method that agrees within it is right."""
    ch = _chain(p["view_a"], p["view_b"], tuple(p["check"]))
    return 0.0, np.array([r.std for r in ch.resections])


resection = Exercise(
    id="prj.resection", scenario=SCENARIO, points=4, kind="array", answer="orientations",
    params_name="p_resection",
    title=f"Step 2 of {_STEPS}: space resection of both views / Rückwärtsschnitt",
    statement="Resect **{name_a}** (view {view_a}) and **{name_b}** (view {view_b}) from the "
              "control points: all 54 board corners except your check points {check}. Board "
              "points: `project.board_points()` (mm, Z = 0); distortion-corrected image "
              "coordinates of all corners of a view (step 1 for every corner): "
              "`project.image_coordinates(view)` (px), with `from photolib.nb import project`; "
              "$c$ = {c:.3f} px, $x'_0$ = {x0:.3f} px, $y'_0$ = {y0:.3f} px. Give "
              "`orientations`, shape (2, 6): one row $(X_0, Y_0, Z_0, \\omega, \\varphi, "
              "\\kappa)$ per view (mm, radians), {name_a} first. Accepted within one standard "
              "deviation of each unknown (the effect of the corner measurement noise).",
    parameters=_resection_params, reference=_orientations, tolerance=_resection_tolerance,
    mistakes=(
        Mistake("degrees", "the angles are asked in radians, not degrees",
                lambda p: _orientations(p, degrees=True)),
        Mistake("distortion", "the image coordinates must be corrected for distortion first "
                              "(project.image_coordinates does it); without it the projection "
                              "centre moves by far more than its standard deviation",
                lambda p: _orientations(p, raw=True)),
    ))


# -- step 3: redundancy and sigma0 ----------------------------------------------------------------
def _sigma0(p, divide="r"):
    ch = _chain(p["view_a"], p["view_b"], tuple(p["check"]))
    res = ch.resections[0]
    n = len(ch.control)
    vv = float(np.sum(res.residuals**2))
    den = {"r": 2 * n - 6, "2n": 2 * n, "n": n, "n-6": n - 6}[divide]
    r = 2 * n - 6 if divide in ("r", "2n") else n - 6
    return np.array([float(r), math.sqrt(vv / den)])


sigma0 = Exercise(
    id="prj.sigma0", scenario=SCENARIO, points=2, kind="array", answer="r_sigma0",
    params_name="p_sigma0",
    title=f"Step 3 of {_STEPS}: redundancy and σ0 of the resection / Redundanz und σ0",
    statement="For the resection of **{name_a}** in step 2 (control points: all corners but "
              "{check}), give `r_sigma0` = $(r, \\hat\\sigma_0)$: the redundancy $r$ "
              "(observations − unknowns) and the a-posteriori standard deviation of unit weight "
              "$\\hat\\sigma_0 = \\sqrt{{v^T v / r}}$ of one image coordinate in px (to "
              "0.001 px), shape (2,).",
    parameters=_resection_params, reference=_sigma0, rtol=0.0, atol=np.array([0.5, 0.001]),
    mistakes=(
        Mistake("redundancy", "σ0² = vᵀv/r divides by the redundancy r = 2n − 6, not by the "
                              "number of observations 2n", lambda p: _sigma0(p, "2n")),
        Mistake("redundancy", "each control point gives two observations (x′, y′): r = 2n − 6 "
                              "and σ0² = vᵀv/r", lambda p: _sigma0(p, "n-6")),
        Mistake("observations", "σ0² = vᵀv/(2n − 6): divided by the number of points n",
                lambda p: _sigma0(p, "n")),
    ))


# -- step 4: forward intersection -----------------------------------------------------------------
def _intersection_params(rng):
    p = _draw(rng) | _interior()
    ch = _chain(p["view_a"], p["view_b"], tuple(p["check"]))
    out = {"c": p["c"], "x0": p["x0"], "y0": p["y0"]}
    for key, res, xy in zip("ab", ch.resections, ch.xy):
        out[f"X0_{key}"] = [round(float(v), 3) for v in res.X0]
        out[f"angles_{key}"] = [round(float(v), 7) for v in res.params[3:]]
        out[f"xy_{key}"] = [[round(float(v), 3) for v in row] for row in xy]
        out[f"X0_{key}_text"] = _fmt(out[f"X0_{key}"], 3)
        out[f"angles_{key}_text"] = _fmt(out[f"angles_{key}"], 7)
        out[f"xy_{key}_text"] = _fmt(out[f"xy_{key}"], 3)
    return {k: p[k] for k in ("view_a", "view_b", "name_a", "name_b", "check", "k")} | out


def _rays(p, key, transpose=False, c_sign=1.0, pp=True):
    import photolib as pl
    R = pl.rotation_opk(*p[f"angles_{key}"])
    R = R.T if transpose else R
    xy = np.array(p[f"xy_{key}"]) - (np.array([p["x0"], p["y0"]]) if pp else 0.0)
    v = np.column_stack([xy, np.full(len(xy), -c_sign * p["c"])]) @ R.T
    return np.array(p[f"X0_{key}"]), v / np.linalg.norm(v, axis=1, keepdims=True)


def _intersect_by_hand(p, **kw):
    """Midpoint of the common perpendicular of the two rays (least squares), any rays."""
    (Ca, da), (Cb, db) = _rays(p, "a", **kw), _rays(p, "b", **kw)
    out = []
    for a, b in zip(da, db):
        A = np.column_stack([a, -b])
        lam = np.linalg.lstsq(A, Cb - Ca, rcond=None)[0]
        out.append(0.5 * (Ca + lam[0] * a + Cb + lam[1] * b))
    return np.array(out)


def _intersection(p):
    import photolib as pl
    R = [pl.rotation_opk(*p[f"angles_{k}"]) for k in "ab"]
    return pl.forward_intersection(np.array([p["xy_a"], p["xy_b"]]),
                                   np.array([p["X0_a"], p["X0_b"]]), np.array(R),
                                   p["c"], p["x0"], p["y0"]).points


intersection = Exercise(
    id="prj.intersection", scenario=SCENARIO, points=4, kind="array", answer="X_check",
    params_name="p_intersection",
    title=f"Step 4 of {_STEPS}: forward intersection of the check points / Vorwärtsschnitt",
    statement="The correct orientations of step 2 are, for **{name_a}**: $X_0$ = {X0_a_text} mm, "
              "$(\\omega, \\varphi, \\kappa)$ = {angles_a_text} rad; for **{name_b}**: $X_0$ = "
              "{X0_b_text} mm, $(\\omega, \\varphi, \\kappa)$ = {angles_b_text} rad "
              "($R = R_\\omega R_\\varphi R_\\kappa$); $c$ = {c:.3f} px, $x'_0$ = {x0:.3f} px, "
              "$y'_0$ = {y0:.3f} px. The corrected image coordinates (px) of your check points "
              "{check} are {xy_a_text} in {name_a} and {xy_b_text} in {name_b}. Intersect the two rays "
              "of each check point (least squares: the point closest to both rays) and give "
              "`X_check`, shape (6, 3), in mm, in the order of the corners.",
    parameters=_intersection_params, reference=_intersection, tolerance=PRINTED,
    mistakes=(
        Mistake("transposed", "the ray direction in the object frame is R·(x′ − x′0, y′ − y′0, "
                              "−c), not Rᵀ·(…)", lambda p: _intersect_by_hand(p, transpose=True)),
        Mistake("sign-c", "the image vector is (x′ − x′0, y′ − y′0, −c): the camera looks "
                          "along its −z axis", lambda p: _intersect_by_hand(p, c_sign=-1.0)),
        Mistake("principal-point", "reduce the image coordinates to the principal point "
                                   "(x′ − x′0, y′ − y′0) before forming the ray",
                lambda p: _intersect_by_hand(p, pp=False)),
    ))


# -- step 5: check-point accuracy -----------------------------------------------------------------
def _check_params(rng):
    p = _draw(rng)
    ch = _chain(p["view_a"], p["view_b"], tuple(p["check"]))
    X = [[round(float(v), 3) for v in row] for row in ch.points]
    return p | {"X_check": X, "X_check_text": _fmt(X, 3), "square_mm": 25.0}


def _true(p, y_sign=-1.0):
    k = np.array(p["check"])
    return np.column_stack([p["square_mm"] * (k % 9), y_sign * p["square_mm"] * (k // 9),
                            np.zeros(len(k))])


def _check_rms(p, y_sign=-1.0, how="rms"):
    d = np.linalg.norm(np.array(p["X_check"]) - _true(p, y_sign), axis=1)
    m = len(d)
    return float({"rms": math.sqrt(np.sum(d**2) / m), "mean": np.mean(d),
                  "coordinate": math.sqrt(np.sum(d**2) / (3 * m)),
                  "m-1": math.sqrt(np.sum(d**2) / (m - 1))}[how])


check_rms = Exercise(
    id="prj.check-rms", scenario=SCENARIO, points=3, kind="number", answer="rms_check",
    params_name="p_check",
    title=f"Step 5 of {_STEPS}: accuracy at the check points / Genauigkeit an Kontrollpunkten",
    statement="The correct intersected check points of step 4 are `X_check` = {X_check_text} mm "
              "(corners {check}, in this order). Corner $k$ lies in row $k$ // 9 and column "
              "$k$ % 9 of the board, at $X = s\\cdot$column, $Y = -s\\cdot$row, $Z = 0$, with "
              "the square side $s$ = {square_mm} mm (the data set's metadata). Give "
              "`rms_check`, the root mean square of the 3-D distances between the intersected "
              "and the true check points, $\\sqrt{{\\sum_i |X_i - X_i^{{true}}|^2 / m}}$, in mm "
              "(to 0.001 mm).",
    parameters=_check_params, reference=_check_rms, rtol=0.0, atol=1e-3, exact=("square_mm",),
    mistakes=(
        Mistake("sign", "the board's Y axis points against the rows: Y = −s·row",
                lambda p: _check_rms(p, y_sign=1.0)),
        Mistake("rms", "the root mean square of the distances is asked, not their mean",
                lambda p: _check_rms(p, how="mean")),
        Mistake("rms", "divide the sum of the squared 3-D distances by the number of points m, "
                       "not by the number of coordinates 3m", lambda p: _check_rms(p, how="coordinate")),
        Mistake("redundancy", "the true positions are known, nothing is estimated: divide by "
                              "m, not m − 1", lambda p: _check_rms(p, how="m-1")),
    ))


EXERCISES = (image_point, resection, sigma0, intersection, check_rms)
