"""Chapter 00-start: one exercise of each answer kind, to practise `check` (and to test the grader).

Independent of the rest of photolib on purpose: the matrices are written out here.
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import CHOICE_KEYS, aerial_camera, close_range_camera, permuted_options

CHAPTER = "00-start"


# -- 1. image scale number (number) ----------------------------------------------------------
def _scale_params(rng):
    aerial = bool(rng.integers(2))
    cam = aerial_camera(rng) if aerial else close_range_camera(rng)
    cam["camera"] = "An aerial camera" if aerial else "A close-range camera"
    cam["distance"] = "flies at a height" if aerial else "is at a distance"
    return cam


def _scale(p):
    return p["h_m"] / (p["c_mm"] / 1000.0)




image_scale = Exercise(
    params_name="p_scale",
    id="demo.image-scale", points=2, title="Image scale number (Bildmaßstabszahl)",
    kind="number", answer="scale_number",
    statement="{camera} with camera constant $c = {c_mm}$ mm {distance} $h = {h_m}$ m above a "
              "flat object. Compute the image scale number m_b = h / c (dimensionless).",
    # m_b may be rounded to a whole number: at least 0.5
    parameters=_scale_params, reference=_scale, tolerance=PRINTED, atol=0.5,
    mistakes=(hints.sign_of(_scale, "c_mm"),))


# -- 2. 2-D rotation from an angle in gon (rotation) -------------------------------------------
def _rot2(p):
    k = p["kappa_gon"] * math.pi / 200.0
    return np.array([[math.cos(k), -math.sin(k)], [math.sin(k), math.cos(k)]])


rotation_2d = Exercise(
    params_name="p_rot2d",
    id="demo.rotation-2d", points=2, title="2-D rotation (ebene Drehung)", kind="rotation",
    answer="R2",
    statement="Build the 2×2 matrix that rotates plane coordinates counter-clockwise by "
              "κ = {kappa_gon} gon (400 gon = 360°), as a NumPy array.",
    parameters=lambda rng: {"kappa_gon": round(float(rng.uniform(5.0, 395.0)), 3)},
    reference=_rot2, tolerance=PRINTED, atol=1e-6,
    mistakes=(hints.scaled_parameter(_rot2, "kappa_gon", 200.0 / math.pi, "gon"),
              hints.scaled_parameter(_rot2, "kappa_gon", 200.0 / 180.0, "degrees",
                                     "the angle was converted as if it were in degrees; "
                                     "it is in gon (multiply by π/200)")))


# -- 3. rotation about X (rotation) -------------------------------------------------------------
def _rot_x(p):
    w = math.radians(p["omega_deg"])
    c, s = math.cos(w), math.sin(w)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


rotation_x = Exercise(
    params_name="p_rotx",
    id="demo.rotation-x", points=2, title="Rotation about X (Drehung um die X-Achse)",
    kind="rotation", answer="R_omega",
    statement="Build R_ω, the active right-handed rotation about the X axis by "
              "ω = {omega_deg}° (course convention), as a 3×3 NumPy array.",
    parameters=lambda rng: {"omega_deg": round(float(rng.uniform(-30.0, 30.0)), 2)},
    reference=_rot_x, tolerance=PRINTED, atol=1e-6,
    mistakes=(hints.scaled_parameter(_rot_x, "omega_deg", 180.0 / math.pi, "degrees"),))


# -- 4. symbolic rotation about X (expression) --------------------------------------------------
def _rot_x_symbolic(p):
    import sympy as sp
    w = sp.Symbol("omega")
    return sp.Matrix([[1, 0, 0], [0, sp.cos(w), -sp.sin(w)], [0, sp.sin(w), sp.cos(w)]])


rotation_x_symbolic = Exercise(
    params_name="p_rotx_sym",
    id="demo.rotation-x-symbolic",
    few_variants="the worked example of 00-start: R_x(omega) in symbols, the same for everyone", points=2, title="R_ω with SymPy", kind="expression",
    answer="R_omega_sym", symbols=("omega",),
    statement="Write R_ω as a SymPy Matrix in the symbol omega = sympy.Symbol('omega').",
    parameters=lambda rng: {}, reference=_rot_x_symbolic)


# -- 5. a function computing the image scale number (function) -------------------------------
def _scale_cases(rng, p):
    cams = [aerial_camera(rng) for _ in range(3)] + [close_range_camera(rng) for _ in range(3)]
    return [(cam["c_mm"], cam["h_m"]) for cam in cams]


scale_function = Exercise(
    params_name="p_scale_fn",
    id="demo.scale-function",
    few_variants="the worked example of 00-start: m_b(c, h) = h/c has no variant of its own", points=2, title="Image scale number as a function",
    kind="function", answer="image_scale_number", rtol=1e-6, atol=1e-9,
    statement="Write image_scale_number(c_mm, h_m) returning m_b for a camera constant in mm "
              "and a distance in m. It is tested on cameras you do not see.",
    parameters=lambda rng: {}, cases=_scale_cases,
    reference=lambda p: lambda c_mm, h_m: h_m / (c_mm / 1000.0),
    mistakes=(Mistake("sign-c", hints.MESSAGES["sign-c"],
                      lambda p: lambda c_mm, h_m: h_m / (-c_mm / 1000.0)),))


# -- 6. multiple choice ------------------------------------------------------------------------
_OPTIONS = ("its transpose Rᵀ", "its negative −R", "R itself", "det(R)·R²")


def _choice_params(rng):
    text, order = permuted_options(rng, _OPTIONS)
    return {"options": text, "correct": CHOICE_KEYS[order.index(0)]}


inverse_choice = Exercise(
    params_name="p_inverse",
    id="demo.inverse-choice",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, title="Inverse of a rotation matrix", kind="choice",
    answer="choice_inverse",
    statement="The inverse of a rotation matrix R is {options}. Set the answer to the letter.",
    parameters=_choice_params, reference=lambda p: p["correct"],
    choices=dict(zip(CHOICE_KEYS, _OPTIONS)))


EXERCISES = (image_scale, rotation_2d, rotation_x, rotation_x_symbolic, scale_function,
             inverse_choice)
