"""Chapter 05-interior-orientation: graded exercises on interior orientation and distortion.

* ``io.field-angle`` (number): the half angle of view of a close-range camera;
* ``io.radial-factor`` (expression): the radial distortion model written with SymPy;
* ``io.image-vector`` (array): a measured point corrected into the image vector x*;
* ``io.measured-position`` (function): where an ideal image point is measured (iteration);
* ``io.plumb-line`` (array): A1 and its σ from a plumb-line calibration (Plumblines);
* ``io.real-corner`` and ``io.real-distortion`` (arrays, two steps of one scenario on the real
  chessboard images of mvtb-data): a measured corner in the course's image frame, then this
  real lens's distortion there, from the chapter's self-calibration.

Course conventions (docs/conventions.md): c > 0, ``x* = (x' − x'0 − Δx', y' − y'0 − Δy', −c)``,
``Δ = distorted − ideal`` evaluated at the **measured** point reduced to the principal point.
The distortion-point hints recompute the answer with Δ evaluated at the ideal point instead.
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "05-interior-orientation"

_DISTORTION_POINT = ("Δ was evaluated at the ideal point; the course evaluates Δ at the "
                     "measured point reduced to the principal point")
_SIGN_DISTORTION = "Δ = distorted − ideal: the ideal point is the measured one minus Δ"


def _sig(value: float) -> float:
    """``value`` rounded to four significant digits, as printed with ``:.3e``."""
    return float(f"{value:.3e}")


def _distortion(p, sign=1.0, balanced=True):
    """The student's lens as a :class:`photolib.Distortion` (coefficients times ``sign``)."""
    import photolib as pl
    keys = ("A1", "A2", "B1", "B2")
    coefficients = {k: sign * p[k] for k in keys if k in p}
    return pl.Distortion(r0=p.get("r0", 0.0) if balanced else 0.0, **coefficients)


# -- 1. half angle of view (number) -----------------------------------------------------------
_FORMATS = ((6000, 4000), (8256, 5504), (4096, 3000), (5472, 3648), (7952, 5304), (2448, 2048))


def _half_diagonal(p):
    """Half the format diagonal in mm: the distance of a corner from the principal point."""
    return math.hypot(p["W"], p["H"]) * p["pixel_um"] / 1000.0 / 2.0


def _field_params(rng):
    # c relative to the format, as real lenses are: from a wide angle (c = half the half
    # diagonal, τ ≈ 63°) to a short telephoto (c = twice the half diagonal, τ ≈ 27°)
    W, H = _FORMATS[int(rng.integers(len(_FORMATS)))]
    p = {"W": W, "H": H, "pixel_um": round(float(rng.uniform(2.0, 6.0)), 2)}
    p["c_mm"] = round(float(rng.uniform(0.5, 2.0)) * _half_diagonal(p), 3)
    return p


def _field_angle(p):
    return math.degrees(math.atan2(_half_diagonal(p), p["c_mm"]))




field_angle = Exercise(
    params_name="p_field",
    id="io.field-angle", points=2, kind="number", answer="tau_deg",
    title="Half format angle (halber Formatwinkel / Bildwinkel)",
    statement="A close-range camera has a sensor of {W} × {H} pixels of {pixel_um:.2f} µm "
              "(Pixelgröße) and the camera constant $c = {c_mm:.3f}$ mm (Kamerakonstante); the "
              "principal point (Bildhauptpunkt) is at the centre of the format. Compute the "
              "angle τ between the optical axis and the ray to a corner of the image format, "
              "i.e. half the format angle over the diagonal (halber Formatwinkel or "
              "Bildwinkel, tan τ = r′/c), in degrees.",
    parameters=_field_params, reference=_field_angle, tolerance=PRINTED,
    mistakes=(
        hints.scaled_parameter(_field_angle, "pixel_um", 1000.0, "units-mm-m",
                               "off by 1000 in the pixel size: µm versus mm?"),
        hints.scaled_parameter(_field_angle, "pixel_um", 1e-3, "units-mm-m",
                               "off by 1000 in the pixel size: µm versus mm?"),
        Mistake("degrees", "this is in radians; the task asks for degrees",
                lambda p: math.radians(_field_angle(p))),
        Mistake("angle-of-view", "this is the full angle of view 2τ; τ is half of it",
                lambda p: 2.0 * _field_angle(p)),
        Mistake("diagonal", "the full diagonal was used; the corner is half a diagonal from "
                            "the principal point",
                lambda p: math.degrees(math.atan2(2 * math.tan(math.radians(_field_angle(p)))
                                                  * p["c_mm"], p["c_mm"]))),
        hints.sign_of(_field_angle, "c_mm"),
    ))


# -- 2. the radial distortion model with SymPy (expression) ------------------------------------
_QUANTITIES = {"factor": "the radial factor Δr′/r as a function of r",
               "dx": "the radial part Δx′ = x·Δr′/r as a function of x and y"}


def _radial_params(rng):
    terms = int(rng.integers(2, 4))
    balanced = bool(rng.integers(2))
    quantity = str(rng.choice(sorted(_QUANTITIES)))
    return {"terms": terms, "balanced": balanced, "quantity": quantity,
            "coefficients": ", ".join(f"A{i}" for i in range(1, terms + 1)),
            "model": "balanced with the radius r0 (symbol r0) where Δr′ = 0"
                     if balanced else "unbalanced (Seidel form, r0 = 0)",
            "what": _QUANTITIES[quantity],
            "names": ", ".join((["r"] if quantity == "factor" else ["x", "y"])
                               + [f"A{i}" for i in range(1, terms + 1)]
                               + (["r0"] if balanced else []))}


def _radial(p, balanced=None, divide=True):
    import sympy as sp

    from photolib.derive import distortion as dd
    balanced = p["balanced"] if balanced is None else balanced
    unused = {dd.A3: 0} if p["terms"] == 2 else {}
    if not balanced:
        unused[dd.r0] = 0
    profile = dd.radial_profile(dd.rr).subs(unused)
    value = sp.expand(profile / dd.rr) if divide else profile
    if p["quantity"] == "dx":
        value = dd.x * value.subs(dd.rr, sp.sqrt(dd.x**2 + dd.y**2))
    return sp.expand(value)


radial_factor = Exercise(
    params_name="p_radial",
    id="io.radial-factor",
    few_variants="a symbolic derivation: the radial models of the course give 8 formulas", points=2, kind="expression", answer="radial",
    symbols=("r", "x", "y", "A1", "A2", "A3", "r0"),
    title="Radial-symmetric distortion (radialsymmetrische Verzeichnung)",
    statement="Write with SymPy {what}, for the radial-symmetric distortion with the "
              "coefficients {coefficients}, {model}. Use the symbols {names} and no others "
              "(sympy.symbols(...)).",
    parameters=_radial_params, reference=_radial,
    mistakes=(
        Mistake("r0", "check the balancing radius: the balanced model is "
                      "Δr′ = A1·r(r² − r0²) + A2·r(r⁴ − r0⁴) + …, the Seidel form has r0 = 0",
                lambda p: _radial(p, balanced=not p["balanced"])),
        Mistake("radial-factor", "this is Δr′ itself; the factor is Δr′/r "
                                 "(and Δx′ = x·Δr′/r)", lambda p: _radial(p, divide=False)),
    ))


# -- 3. image vector of a measured point (array) ------------------------------------------------
#: the smallest distance (mm) of the two distortion-point mistakes from x* and from each
#: other: far outside the rounding of the inputs printed to 0.0001 mm
_VECTOR_GAP = 4e-4


def _vector_params(rng):
    # drawn again where a distortion-point mistake nearly equals x* (x'0, y'0 near 0) or
    # the other one: the rounding of the printed inputs would reach its hint
    while True:
        sx, sy = rng.choice([-1.0, 1.0], size=2)
        p = {"c_mm": round(float(rng.uniform(8.0, 50.0)), 3),
             "x0": round(float(rng.uniform(-0.15, 0.15)), 3),
             "y0": round(float(rng.uniform(-0.15, 0.15)), 3),
             "x": round(float(sx * rng.uniform(6.0, 11.5)), 3),
             "y": round(float(sy * rng.uniform(4.0, 7.8)), 3),
             "A1": _sig(-rng.uniform(0.5e-4, 1.5e-4)), "A2": _sig(rng.uniform(1e-8, 8e-8)),
             "B1": _sig(rng.uniform(-8e-6, 8e-6)), "B2": _sig(rng.uniform(-8e-6, 8e-6))}
        ref, ideal, measured = _vector(p), _ideal_point_mistake(p), _measured_point_mistake(p)
        if min(np.max(np.abs(a - b)) for a, b in ((ref, ideal), (ref, measured),
                                                   (ideal, measured))) >= _VECTOR_GAP:
            return p


def _reduced(p):
    return np.array([p["x"] - p["x0"], p["y"] - p["y0"]])


def _vector(p, ideal=None):
    ideal = _distortion(p).correct(_reduced(p)) if ideal is None else ideal
    return np.array([ideal[0], ideal[1], -p["c_mm"]])


def _ideal_point_mistake(p):
    return _vector(p, _distortion(p, sign=-1.0).distort(_reduced(p)))


def _measured_point_mistake(p):
    return _vector(p, _reduced(p) - _distortion(p).delta(np.array([p["x"], p["y"]])))


image_vector = Exercise(
    params_name="p_vector",
    id="io.image-vector", points=3, kind="array", answer="x_star",
    title="Image vector of a measured point (Bildvektor)",
    statement="A camera has the camera constant $c = {c_mm:.4f}$ mm (Kamerakonstante), the "
              "principal point (Bildhauptpunkt) $x'_0 = {x0:.4f}$ mm, $y'_0 = {y0:.4f}$ mm and the "
              "distortion "
              "(Verzeichnung) $A_1 = {A1:.3e}$ mm⁻², $A_2 = {A2:.3e}$ mm⁻⁴ (r0 = 0), $B_1 = {B1:.3e}$ mm⁻¹, "
              "$B_2 = {B2:.3e}$ mm⁻¹. A point is measured at $x' = {x:.4f}$ mm, $y' = {y:.4f}$ mm. Give its "
              "image vector x* = (x' − x'0 − Δx', y' − y'0 − Δy', −c) in mm as a NumPy array.",
    # relative 1e-6 accepts float32 (eps ≈ 6e-8) and a result printed to 1e-6 mm, plus the
    # rounding of the inputs, printed to 0.1 µm so that it stays far inside the
    # distortion-point mistakes (drawn ≥ 0.4 µm away)
    parameters=_vector_params, reference=_vector, tolerance=PRINTED, rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("distortion-point", _DISTORTION_POINT, _ideal_point_mistake),
        Mistake("distortion-point", "Δ must be evaluated at the measured point reduced to the "
                                    "principal point, (x' − x'0, y' − y'0)",
                _measured_point_mistake),
        Mistake("sign-distortion", _SIGN_DISTORTION,
                lambda p: _vector(p, _reduced(p) + _distortion(p).delta(_reduced(p)))),
        hints.sign_of(_vector, "c_mm"),
    ))


# -- 4. measured position of an ideal point (function) -----------------------------------------
def _lens_params(rng):
    return {"A1": _sig(-rng.uniform(0.5e-4, 1.5e-4)), "A2": _sig(rng.uniform(1e-8, 6e-8)),
            "r0": round(float(rng.uniform(8.0, 12.0)), 1)}


def _lens_function(solve):
    """``wrong(params)``: a function ``(x, y) -> (2,)`` applying ``solve(params, xy)``."""
    def make(p):
        def measured_position(x, y):
            return solve(p, np.array([x, y], float))
        return measured_position
    return make


def _measured(p, xy):
    return _distortion(p).distort(xy, method="newton", tol=1e-12)


#: the smallest distance (mm) of the distortion-point mistake from the measured position on a
#: hidden point: it is |Δ|·|Δ′| and vanishes near r = r0 and the centre, where the rounding of
#: the printed r0 would reach its hint
_LENS_GAP = 4e-5


def _lens_cases(rng, p):
    # the grader sends scalar arguments only (batch converts each to float)
    cases = []
    for _ in range(8):
        for _attempt in range(1000):
            xy = (round(float(rng.uniform(-12.0, 12.0)), 3), round(float(rng.uniform(-8.0, 8.0)), 3))
            right = _measured(p, np.array(xy, float))
            wrong = np.array(xy, float) + _distortion(p).delta(np.array(xy, float))
            if np.max(np.abs(right - wrong)) >= _LENS_GAP:
                break
        cases.append(xy)
    return cases


measured_position = Exercise(
    params_name="p_lens",
    id="io.measured-position", points=3, kind="function", answer="measured_position",
    title="Where is an ideal point measured? (Iteration der Verzeichnung)",
    statement="Your lens has the balanced radial distortion (Verzeichnung) $A_1 = {A1:.3e}$ mm⁻², "
              "$A_2 = {A2:.3e}$ mm⁻⁴, $r_0 = {r0:.4f}$ mm. Write measured_position(x, y) that takes ideal "
              "image coordinates reduced to the principal point (x, y in mm) and returns where "
              "this point is measured, as a NumPy array (x_m, y_m) in mm, to 1e-6 mm. "
              "Remember that Δ is evaluated at the measured point. It is tested on points you "
              "do not see.",
    # rtol 1e-6: float32 work (the rounding of r0, printed to 0.1 µm, is far smaller)
    parameters=_lens_params, reference=_lens_function(_measured), tolerance=PRINTED, cases=_lens_cases,
    rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("distortion-point", _DISTORTION_POINT + ": iterate x ← x_ideal + Δ(x)",
                _lens_function(lambda p, xy: xy + _distortion(p).delta(xy))),
        Mistake("direction", "this corrects a measured point; here the ideal point is given and "
                             "the measured one is wanted",
                _lens_function(lambda p, xy: _distortion(p).correct(xy))),
        Mistake("sign-distortion", _SIGN_DISTORTION,
                _lens_function(lambda p, xy: _distortion(p, sign=-1.0).distort(xy, tol=1e-12))),
        Mistake("r0", "the balancing radius r0 is missing: Δr′ = A1·r(r² − r0²) + A2·r(r⁴ − r0⁴)",
                _lens_function(lambda p, xy: _distortion(p, balanced=False).distort(
                    xy, tol=1e-12))),
    ))


# -- 5. plumb-line calibration (array) ------------------------------------------------------------
#: plumb-line positions as fractions of the half format (36 mm × 24 mm), none through the centre
_PLUMB_FRACTIONS = (-0.8, -0.4, 0.35, 0.75)
_PLUMB_HALF = (18.0, 12.0)


def _plumb_params(rng):
    import photolib as pl
    p = {"A1": _sig(-rng.uniform(2e-5, 6e-5)), "c_mm": round(float(rng.uniform(20.0, 50.0)), 1),
         "noise_um": 0.5}
    lens = pl.Distortion(A1=p["A1"])
    hw, hh = _PLUMB_HALF
    s = np.linspace(-1.0, 1.0, 13)
    lines = [np.column_stack([hw * s, np.full(13, f * hh)]) for f in _PLUMB_FRACTIONS]
    lines += [np.column_stack([np.full(13, f * hw), hh * s]) for f in _PLUMB_FRACTIONS]
    # measured = distorted + noise, printed to 0.1 µm
    p["lines"] = [np.round(lens.distort(q) + rng.normal(0.0, p["noise_um"] / 1000.0, q.shape),
                           4).tolist() for q in lines]
    p["first"] = _fmt_point(p["lines"][0][0])
    return p


def _fmt_point(xy):
    return "(" + ", ".join(f"{v:.4f}" for v in xy) + ")"


def _plumb_fit(p):
    from photolib.calibration import plumb_line
    return plumb_line([np.array(q) for q in p["lines"]], c=p["c_mm"], terms=("A1",))


def _plumb(p, sign=1.0, scaled=True):
    fit = _plumb_fit(p)
    sigma = fit.sigma["A1"] if scaled else fit.sigma["A1"] / fit.sigma0
    return np.array([sign * fit.distortion.params["A1"], sigma])


def _plumb_tolerance(p):
    """A tenth of σ(A1): every least-squares solution of the same model agrees far better;
    an estimate with another model (e.g. with A2, or Δ at the ideal point) does not."""
    return 0.0, 0.1 * _plumb_fit(p).sigma["A1"]


plumb_line_exercise = Exercise(
    params_name="p_plumb",
    id="io.plumb-line", points=3, kind="array", answer="plumb",
    title="Plumb-line calibration (Kalibrierung mit Lotlinien, Plumblines)",
    statement="Eight lines that are straight in object space were imaged by a camera with "
              "$c = {c_mm}$ mm (Kamerakonstante). Their measured points, in mm and reduced to the "
              "principal point (Bildhauptpunkt), are in p_plumb.lines: a list of 8 lines, each a "
              "list of 13 points (x′, y′); the first point is {first}. The coordinates have "
              "a noise of about {noise_um} µm. Estimate the radial distortion coefficient A1 "
              "of the course model (Seidel form, r0 = 0, no other distortion term) so that "
              "the corrected points of every line are collinear, and give the NumPy array "
              "[A1, σ(A1)] in mm⁻², σ(A1) being the a-posteriori standard deviation of the "
              "least-squares estimate (scaled by σ0).",
    parameters=_plumb_params, reference=_plumb, tolerance=_plumb_tolerance,
    mistakes=(
        Mistake("sign-distortion", _SIGN_DISTORTION, lambda p: _plumb(p, sign=-1.0)),
        Mistake("unscaled-sigma", "σ(A1) must be scaled by the a-posteriori σ0: "
                                  "σ(A1) = σ0·√Q(A1, A1)", lambda p: _plumb(p, scaled=False)),
    ))


# -- 6./7. a real corner of the chessboard camera, two steps (arrays) -----------------------------
#: the terms of the chapter's real calibration as printed in the task (4 significant digits)
_REAL_TERMS = ("A1", "A2", "A3", "B1", "B2")


def _real_data():
    """The chessboard views, their corners (photolib.nb.realdata.detect_corners, OpenCV's
    cornerSubPix as the measuring tool) and the chapter's self-calibration (cached)."""
    from photolib.nb import realdata as rd

    cal = rd.chessboard_calibration()
    return cal


def _real_params(rng):
    """A view of left01–14 and one of its 54 corners, as measured; the chapter's calibration."""
    cal = _real_data()
    view = int(rng.integers(0, len(cal.corners)))
    k = int(rng.integers(0, len(cal.corners[view])))
    col, row = (round(float(v), 2) for v in cal.corners[view][k])
    res = cal.result
    p = {"file": cal.files[view], "corner": k, "col": col, "row": row,
         "width": cal.width, "height": cal.height,
         "x0": round(float(res.x0), 2), "y0": round(float(res.y0), 2)}
    for term in _REAL_TERMS:
        p[term] = _sig(res.distortion.params[term])
    return p


def _real_image(p, centre=None, flip=True, swap=False):
    """``x' = col − (W − 1)/2``, ``y' = (H − 1)/2 − row`` (px; the course's pixel frame)."""
    col, row = (p["row"], p["col"]) if swap else (p["col"], p["row"])
    cx, cy = centre if centre is not None else ((p["width"] - 1) / 2, (p["height"] - 1) / 2)
    return np.array([col - cx, (cy - row) if flip else (row - cy)])


def _real_delta(p, reduce=True, tangential=True, swap_b=False):
    """Δ = (Δx', Δy') (px) at the measured point reduced to the principal point."""
    import photolib as pl

    xy = _real_image(p) - (np.array([p["x0"], p["y0"]]) if reduce else 0.0)
    b1, b2 = (p["B2"], p["B1"]) if swap_b else (p["B1"], p["B2"])
    dist = pl.Distortion(A1=p["A1"], A2=p["A2"], A3=p["A3"],
                         B1=b1 if tangential else 0.0, B2=b2 if tangential else 0.0)
    return dist.delta(xy)


_REAL_FRAME = ("the course's image frame has its origin at the image centre, x′ to the right "
               "and y′ **up**: x′ = col − (W − 1)/2, y′ = (H − 1)/2 − row")

real_corner = Exercise(
    params_name="p_corner", scenario="io.real-corner",
    id="io.real-corner", points=2, kind="array", answer="xy_corner",
    title="Step 1 of 2: a real corner in the image frame / eine echte Ecke im Bildsystem",
    statement="In the real chessboard image `{file}` ({width} × {height} px, mvtb-data) the "
              "chapter measured corner number {corner} at $(col, row) = ({col:.2f}, {row:.2f})$ px "
              "(pixel centres at integers, row downwards). Give its image coordinates "
              "$(x', y')$ in px in the course's frame (origin at the image centre, $x'$ right, "
              "$y'$ up) as a NumPy array, to 0.01 px.",
    parameters=_real_params, reference=_real_image, rtol=0.0, atol=0.0051,
    exact=("x0", "y0", "A1", "A2", "A3", "B1", "B2"),
    mistakes=(
        Mistake("y-down", "y′ points up: " + _REAL_FRAME, lambda p: _real_image(p, flip=False)),
        Mistake("centre", "the centre of a 640-px row lies between pixels 319 and 320, at "
                          "(W − 1)/2 = 319.5 when pixel centres are integers",
                lambda p: _real_image(p, centre=(p["width"] / 2, p["height"] / 2))),
        Mistake("swapped", "col is the horizontal coordinate (x′), row the vertical (y′)",
                lambda p: _real_image(p, swap=True)),
    ))

real_distortion = Exercise(
    params_name="p_corner_distortion", scenario="io.real-corner",
    id="io.real-distortion", points=3, kind="array", answer="delta_corner",
    title="Step 2 of 2: the real lens's distortion there / die Verzeichnung des echten Objektivs",
    statement="The same corner lies at $(x', y') = ({xy_corner_x:.2f}, {xy_corner_y:.2f})$ px "
              "(step 1). The chapter's self-calibration of this lens gives the principal point "
              "$(x'_0, y'_0) = ({x0:.2f}, {y0:.2f})$ px and the distortion terms (Seidel, "
              "$r_0 = 0$, and Brown's tangential terms) $A_1 = {A1:.3e}$ px⁻², "
              "$A_2 = {A2:.3e}$ px⁻⁴, $A_3 = {A3:.3e}$ px⁻⁶, $B_1 = {B1:.3e}$ px⁻¹, "
              "$B_2 = {B2:.3e}$ px⁻¹. Compute the distortion $(\\Delta x', \\Delta y')$ at this "
              "corner (course model, evaluated at the measured point reduced to the principal "
              "point) as a NumPy array in px, to 0.01 px.",
    parameters=lambda rng: _with_corner(_real_params(rng)), reference=_real_delta,
    rtol=0.0, atol=0.0051, exact=("x0", "y0", "A1", "A2", "A3", "B1", "B2"),
    mistakes=(
        Mistake("centre", "the distortion is a function of the coordinates reduced to the "
                          "principal point, x̄ = x′ − x′0, ȳ = y′ − y′0, not of the "
                          "coordinates from the image centre",
                lambda p: _real_delta(p, reduce=False)),
        Mistake("tangential", "the model has tangential terms too: Δx′ += B1(r² + 2x̄²) + "
                              "2B2·x̄ȳ, Δy′ += B2(r² + 2ȳ²) + 2B1·x̄ȳ",
                lambda p: _real_delta(p, tangential=False)),
        Mistake("swapped", "B1 goes with r² + 2x̄² in Δx′ and B2 with r² + 2ȳ² in Δy′",
                lambda p: _real_delta(p, swap_b=True)),
        Mistake("sign-distortion", _SIGN_DISTORTION + "; Δ itself is distorted − ideal",
                lambda p: -_real_delta(p)),
    ))


def _with_corner(p):
    """Step 2 carries step 1's correct result (so a wrong step 1 does not cost step 2)."""
    x, y = _real_image(p)
    return {**p, "xy_corner_x": round(float(x), 2), "xy_corner_y": round(float(y), 2)}


EXERCISES = (field_angle, radial_factor, image_vector, measured_position, plumb_line_exercise,
             real_corner, real_distortion)
