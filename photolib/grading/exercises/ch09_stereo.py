"""Chapter 09-stereo: graded exercises on stereo photogrammetry.

* ``st.height`` (number): Z of the normal case from the x-parallax, ``Z = −c·B/px'``;
* ``st.sigma-z`` (number): σ_Z of a stereo pair (Luhmann example 3.7 style) from the σ of
  one image coordinate, ``σ_px' = √2·σ_x'`` for independently measured x'1, x'2;
* ``st.intersection`` (function): forward intersection in the normal case with a principal
  point, ``point(x1, y1, x2, y2) → (X, Y, Z)``;
* ``st.essential`` (array): the essential matrix ``E = R1ᵀ·[b]×·R2`` of an oriented pair
  (``x*1ᵀ·E·x*2 = 0``);
* ``st.unknowns`` (choice): unknowns of relative / absolute orientation and their relatives.

Course conventions (docs/conventions.md): c > 0, ``R = R_ω·R_φ·R_κ``, image vector
``x* = (x' − x'0, y' − y'0, −c)``; normal case: camera 1 at the origin, camera 2 at (B, 0, 0),
R = I. References come from :mod:`photolib.stereo`.

>>> [ex.id for ex in EXERCISES]
['st.height', 'st.sigma-z', 'st.intersection', 'st.essential', 'st.unknowns']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.exercises.ch04_rotations import scaled_parameters
from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import aerial_camera, close_range_camera

CHAPTER = "09-stereo"


# -- 1. Z from the x-parallax (number) ------------------------------------------------------------
def _height_params(rng):
    cam = aerial_camera(rng)
    B = round(float(cam["h_m"] * rng.uniform(0.25, 0.6)), 1)
    h = cam["h_m"] * float(rng.uniform(0.9, 1.1))
    return {"c_mm": cam["c_mm"], "B_m": B, "px_mm": round(cam["c_mm"] * B / h, 3)}


def _height(p, c=None, B=None):
    import photolib as pl
    return pl.height_from_parallax(p["px_mm"], p["c_mm"] if c is None else c,
                                   p["B_m"] if B is None else B)


height = Exercise(
    params_name="p_height",
    id="st.height", points=2, kind="number", answer="Z",
    title="Height from parallax / Höhe aus der x-Parallaxe",
    statement="A stereo pair in the normal case (Normalfall): camera constant c = {c_mm} mm, "
              "base B = {B_m} m. A point has the x-parallax px' = x'1 − x'2 = {px_mm} mm. "
              "Give its Z coordinate in m in the course's normal-case frame (camera 1 at the "
              "origin, camera 2 at (B, 0, 0), both looking down −Z).",
    # the rounding of the printed c (0.01 mm), B (0.1 m) and px' (0.001 mm): some 0.1 m, so Z
    # given to the cm (six digits) passes; rtol 1e-6 alone rejected it. The mistakes below
    # change the sign or the unit of Z, far outside
    parameters=_height_params, reference=_height, tolerance=PRINTED,
    mistakes=(
        Mistake("sign-c", hints.MESSAGES["sign-c"] + ": Z = −c·B/px' is negative, the point "
                "lies below the cameras (the distance h = −Z is positive)",
                lambda p: -_height(p)),
        Mistake("units-mm-m", "B was converted to mm, so Z came out in mm: c and px' share "
                              "one unit (mm) and cancel, Z has the unit of B (m)",
                lambda p: _height(p, B=p["B_m"] * 1000.0)),
        Mistake("units-mm-m", "c was converted to m but px' was left in mm: c and px' must "
                              "have the same unit",
                lambda p: _height(p, c=p["c_mm"] / 1000.0)),
    ))



# -- 2. σ_Z of a stereo pair (number) -------------------------------------------------------------
def _sigma_params(rng):
    cam = close_range_camera(rng)
    h = round(float(rng.uniform(3.0, 30.0)), 2)
    return {"c_mm": cam["c_mm"], "h_m": h, "B_m": round(h * float(rng.uniform(0.28, 0.42)), 3),
            "s_x_um": round(float(rng.uniform(1.0, 6.0)), 1)}


_SQRT2 = math.sqrt(2.0)


def _sigma_z(p, factor=_SQRT2, base_ratio=True):
    import photolib as pl
    s_x = p["s_x_um"] * 1e-3                                    # mm
    acc = pl.normal_case_accuracy(p["h_m"] * 1e3, p["B_m"] * 1e3, p["c_mm"], factor * s_x, s_x)
    return acc.sigma_Z if base_ratio else acc.sigma_Z * p["B_m"] / p["h_m"]


sigma_z = Exercise(
    params_name="p_sigma",
    id="st.sigma-z", points=3, kind="number", answer="sigma_Z",
    title="Accuracy of a stereo pair / Genauigkeit im Normalfall (example 3.7)",
    statement="A close-range stereo pair in the normal case: c = {c_mm} mm, object distance "
              "h = {h_m} m, base B = {B_m} m. The image coordinates x'1 and x'2 are measured "
              "independently, each with σ_x' = {s_x_um:.2f} µm. Give the standard deviation σ_Z of "
              "the depth in mm.",
    parameters=_sigma_params, reference=_sigma_z, tolerance=PRINTED, rtol=1e-6, atol=1e-9,
    mistakes=(
        Mistake("parallax", "the parallax px' = x'1 − x'2 is the difference of two independently "
                            "measured coordinates: σ_px' = √2·σ_x' (error propagation), not "
                            "σ_x' (that holds if the parallax is measured once, "
                            "stereoscopically)",
                lambda p: _sigma_z(p, factor=1.0)),
        Mistake("parallax", "σ_px' = σ_x'/√2 is the corrected print of Luhmann's example 3.7 "
                            "(luhmann:example-3.7), an assumption about stereoscopic "
                            "measurement; for independently measured x'1, x'2 error "
                            "propagation gives σ_px' = √2·σ_x'",
                lambda p: _sigma_z(p, factor=1.0 / math.sqrt(2.0))),
        Mistake("base-ratio", "σ_Z = (h/B)·m·σ_px': the height-to-base ratio h/B is missing",
                lambda p: _sigma_z(p, base_ratio=False)),
    ))


# -- 3. forward intersection in the normal case (function) ----------------------------------------
def _intersection_params(rng):
    cam = close_range_camera(rng)
    return {"c_mm": cam["c_mm"], "B_m": round(float(rng.uniform(0.5, 5.0)), 3),
            "x0_mm": round(float(rng.uniform(-0.3, 0.3)), 3),
            "y0_mm": round(float(rng.uniform(-0.3, 0.3)), 3),
            "h_m": round(float(rng.uniform(5.0, 40.0)), 1)}


def _intersection_function(centre=True, from_image=1):
    def make(p):
        c, B, x0, y0 = p["c_mm"], p["B_m"], p["x0_mm"], p["y0_mm"]

        def point(x1, y1, x2, y2):
            import photolib as pl
            if centre and from_image == 1:
                return pl.normal_case_points([x1, y1], [x2, y2], c, B, x0, y0)
            px = x1 - x2
            a, b = (x0, y0) if centre else (0.0, 0.0)
            xi = x1 if from_image == 1 else x2
            return np.array([B * (xi - a) / px, B * (y1 - b) / px, -c * B / px])
        return point
    return make


def _intersection_cases(rng, p):
    import photolib as pl
    out = []
    for _ in range(6):
        X = np.array([p["B_m"] * float(rng.uniform(-0.2, 1.2)), p["h_m"] * float(rng.uniform(-0.3, 0.3)),
                      -p["h_m"] * float(rng.uniform(0.8, 1.2))])
        a = pl.project(X, np.zeros(3), np.eye(3), p["c_mm"], p["x0_mm"], p["y0_mm"])
        b = pl.project(X, [p["B_m"], 0.0, 0.0], np.eye(3), p["c_mm"], p["x0_mm"], p["y0_mm"])
        out.append(tuple(round(float(v), 4) for v in (a[0], a[1], b[0], b[1])))
    return out


intersection = Exercise(
    params_name="p_int",
    id="st.intersection", points=3, kind="function", answer="point",
    title="Forward intersection in the normal case / Vorwärtsschnitt im Normalfall",
    statement="A stereo camera in the normal case: c = {c_mm:.3f} mm, principal point "
              "x'0 = {x0_mm:.3f} mm, y'0 = {y0_mm:.3f} mm (both images), base B = {B_m:.3f} m; camera 1 at "
              "the origin, camera 2 at (B, 0, 0), R = I. Write point(x1, y1, x2, y2) that "
              "returns the object point (X, Y, Z) in m (NumPy array of shape (3,)) from the "
              "image coordinates (mm) of both images. It is tested on points you do not see.",
    parameters=_intersection_params, reference=_intersection_function(), tolerance=PRINTED,
    cases=_intersection_cases, rtol=1e-6, atol=1e-9,
    mistakes=(
        Mistake("principal-point", "the image coordinates must be reduced to the principal "
                                   "point (x' − x'0, y' − y'0) before X = B·x'/px', "
                                   "Y = B·y'/px'", _intersection_function(centre=False)),
        Mistake("base", "X from image 2 is X = B + B·(x'2 − x'0)/px': camera 2 stands at "
                        "(B, 0, 0)", _intersection_function(from_image=2)),
    ))


# -- 4. essential matrix (array) ------------------------------------------------------------------
_ANGLES = ("omega1_deg", "phi1_deg", "kappa1_deg", "omega2_deg", "phi2_deg", "kappa2_deg")


def _essential_params(rng):
    p = {"X01": [round(float(v), 3) for v in rng.uniform([-5, -5, 95], [5, 5, 105])]}
    p["X02"] = [round(float(v), 3) for v in np.array(p["X01"]) + rng.uniform([30, -3, -3],
                                                                              [50, 3, 3])]
    for name in _ANGLES:
        p[name] = round(float(rng.uniform(-6.0, 6.0)), 2)
    return p


def _essential(p, swap_R=False, base_sign=1.0):
    import photolib as pl
    R1 = pl.rotation_opk(*np.radians([p[n] for n in _ANGLES[:3]]))
    R2 = pl.rotation_opk(*np.radians([p[n] for n in _ANGLES[3:]]))
    if swap_R:
        R1, R2 = R1.T, R2.T
    b = base_sign * (np.array(p["X02"]) - np.array(p["X01"]))
    return pl.essential_matrix(np.zeros(3), R1, b, R2)


essential = Exercise(
    params_name="p_essential",
    id="st.essential", points=3, kind="array", answer="E",
    title="Essential matrix / Essentielle Matrix (coplanarity)",
    statement="Two images are oriented: X01 = {X01} m, ω1 = {omega1_deg}°, φ1 = {phi1_deg}°, "
              "κ1 = {kappa1_deg}°; X02 = {X02} m, ω2 = {omega2_deg}°, φ2 = {phi2_deg}°, "
              "κ2 = {kappa2_deg}° (R = R_ω·R_φ·R_κ, camera → object). The coplanarity condition "
              "b·(R1·x*1 × R2·x*2) = 0 with b = X02 − X01 can be written x*1ᵀ·E·x*2 = 0. "
              "Give E = R1ᵀ·[b]×·R2 (in m) as a NumPy array of shape (3, 3), where "
              "[b]×·v = b × v.",
    parameters=_essential_params, reference=_essential, tolerance=PRINTED, rtol=1e-7, atol=1e-6,
    mistakes=(
        Mistake("transposed", "R and Rᵀ are swapped: R turns camera vectors into the object "
                              "frame, so the rays are R·x* and E = R1ᵀ·[b]×·R2",
                lambda p: _essential(p, swap_R=True)),
        Mistake("transposed", "this is Eᵀ, the matrix of x*2ᵀ·E·x*1 = 0; the task has image 1 "
                              "on the left: x*1ᵀ·E·x*2 = 0",
                lambda p: _essential(p).T),
        Mistake("sign", "the base points from camera 1 to camera 2: b = X02 − X01",
                lambda p: _essential(p, base_sign=-1.0)),
        scaled_parameters(_essential, _ANGLES, 180.0 / math.pi, "degrees",
                          "the angles in degrees were used as radians (numpy.radians)"),
    ))


# -- 5. unknowns of the orientations (choice) -----------------------------------------------------
_COUNTS = {"a": 5, "b": 6, "c": 7, "d": 12, "e": 3}
_ORIENTATION = "count the orientation parameters, not the object coordinates of the tie points"
_POINT = "the orientations of both images are known: count the unknown coordinates of that point"
#: task → (number of unknowns, what is counted); the order fixes the variants (rng.choice)
_TASKS = {
    "the dependent relative orientation (Folgebildanschluss) of the pair": (5, _ORIENTATION),
    "the independent relative orientation (gegenseitige Orientierung mit Drehungen beider "
    "Bilder) of the pair": (5, _ORIENTATION),
    "the absolute orientation (7-parameter spatial similarity) of the model": (7, _ORIENTATION),
    "the exterior orientations of both images together": (12, _ORIENTATION),
    "the space resection of one of the two images": (6, _ORIENTATION),
    "the forward intersection of one object point": (3, _POINT),
}


#: the lead-in of the question: the pair for the orientation tasks, the oriented images for
#: the forward intersection of one point (a count of the whole pair is not asked there)
_LEAD_PAIR = "A stereo pair with {n} tie points and enough control points."
_LEAD_POINT = "Both images of a stereo pair are oriented."


def _unknowns_params(rng):
    task = str(rng.choice(list(_TASKS)))
    n = int(rng.integers(6, 40))
    counted = _TASKS[task][1]
    lead = _LEAD_POINT if counted == _POINT else _LEAD_PAIR.format(n=n)
    return {"task": task, "n": n, "counted": counted, "lead": lead}


def _letter_of(count):
    """The letter printed before ``count`` in the statement (read from the text: no answer in p)."""
    return next(k for k, v in _COUNTS.items() if v == count)


def _unknowns_key(p):
    return _letter_of(_TASKS[p["task"]][0])


def _wrong_count(count):
    def wrong(p):
        key = _letter_of(count)
        return None if key == _unknowns_key(p) else key
    return wrong


def _swapped(p):
    return {"a": "c", "c": "a"}.get(_unknowns_key(p))


unknowns = Exercise(
    params_name="p_unknowns",
    id="st.unknowns",
    few_variants="a multiple choice: the correct answer is one of its few option letters", points=1, kind="choice", answer="choice_unknowns",
    title="Unknowns of the orientations / Unbekannte der Orientierungen",
    statement="{lead} How many unknowns does {task} have ({counted})? "
              "(a) 5, (b) 6, (c) 7, (d) 12, (e) 3. Set the answer to the letter.",
    parameters=_unknowns_params, reference=_unknowns_key,
    choices={k: str(v) for k, v in _COUNTS.items()},
    mistakes=(
        Mistake("count", "6 is the exterior orientation of one image; of the 12 parameters of "
                         "a pair, 7 (3 shifts, 3 rotations, scale) are the datum that only the "
                         "absolute orientation fixes: relative 5, absolute 7",
                _wrong_count(6)),
        Mistake("count", "12 − 7 = 5 for the relative orientation, 7 for the absolute one: "
                         "they are swapped", _swapped),
    ))


EXERCISES = (height, sigma_z, intersection, essential, unknowns)
