"""Chapter 08-resection-dlt: graded exercises on space resection and the DLT.

* ``rdl.redundancy`` (number): redundancy of a space resection or of a DLT with n points;
* ``rdl.dlt-vector`` (array): the eleven DLT parameters of a given close-range camera;
* ``rdl.dlt-interior`` (array): principal point and camera constant from printed L1…L11
  (Luhmann 4.26; the corrected example 4.3 of the errata list still prints x'0, y'0 with the
  wrong sign);
* ``rdl.dlt-coefficient`` (expression): one DLT coefficient derived with SymPy;
* ``rdl.image-point`` (function): image coordinates from the DLT parameters of an aerial image.

Course conventions (docs/conventions.md): ``(kx, ky, N) = Rᵀ(X − X0)``,
``x' = x'0 − c·kx/N``, ``R = R_ω·R_φ·R_κ``, c > 0. The DLT is
``x' = (L1X + L2Y + L3Z + L4)/(L9X + L10Y + L11Z + 1)``, y' likewise with L5…L8.
References come from :func:`photolib.dlt_from_camera`, :func:`photolib.dlt_decompose` and
:func:`photolib.derive.dlt.dlt_from_orientation`.

>>> [ex.id for ex in EXERCISES]
['rdl.redundancy', 'rdl.dlt-vector', 'rdl.dlt-interior', 'rdl.dlt-coefficient', 'rdl.image-point']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.exercises.ch04_rotations import scaled_parameters
from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import aerial_camera, close_range_camera

CHAPTER = "08-resection-dlt"

_ANGLES = ("omega_deg", "phi_deg", "kappa_deg")
_DEGREES = "the angles in degrees were used as radians (convert with numpy.radians)"


def _rotation(p, scale=math.pi / 180.0):
    import photolib as pl
    return pl.rotation_opk(*[p[n] * scale for n in _ANGLES])


def _centre(p):
    return np.array([p["X0"], p["Y0"], p["Z0"]])


def _printed(values, digits=10):
    """Values rounded to ``digits`` significant digits, as printed in the task."""
    return [float(f"{float(v):.{digits}g}") for v in values]


def _dlt_formula(p, R=None, c=None, x0=None, y0=None, normalise=True):
    """``K·Rᵀ·[I | −X0]`` scaled to L12 = 1, typed out (for the mistakes: any sign of c)."""
    R = _rotation(p) if R is None else R
    c = p["c_mm"] if c is None else c
    x0 = p["x0_mm"] if x0 is None else x0
    y0 = p["y0_mm"] if y0 is None else y0
    K = np.array([[-c, 0.0, x0], [0.0, -c, y0], [0.0, 0.0, 1.0]])
    P = K @ R.T @ np.column_stack([np.eye(3), -_centre(p)])
    return (P / P[2, 3] if normalise else P).reshape(-1)[:11]


# -- 1. redundancy (number) -----------------------------------------------------------------------
_UNKNOWNS = {"space resection": 6, "DLT": 11}


def _redundancy_params(rng):
    method = str(rng.choice(list(_UNKNOWNS)))
    return {"n": int(rng.integers(8, 41)), "method": method,
            "other": "DLT" if method == "space resection" else "space resection"}


def _redundancy(p, per_point=2, unknowns=None):
    u = _UNKNOWNS[p["method"]] if unknowns is None else unknowns
    return float(per_point * p["n"] - u)


redundancy = Exercise(
    params_name="p_redundancy",
    id="rdl.redundancy", points=2, kind="number", answer="r",
    title="Redundancy / Redundanz (Überbestimmung)",
    statement="{n} control points (Passpunkte) with known X, Y, Z are measured in one image. "
              "The {method} determines the orientation of the image from them. How many "
              "redundant observations (redundancy r = observations − unknowns) does the "
              "{method} have?",
    parameters=_redundancy_params, reference=_redundancy, rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("unknowns", "the number of unknowns is the other method's: the space resection "
                            "has 6 (X0, Y0, Z0, ω, φ, κ), the DLT 11 (L1 … L11)",
                lambda p: _redundancy(p, unknowns=_UNKNOWNS[p["other"]])),
        Mistake("observations", "each image point gives two observations (x′ and y′), not one",
                lambda p: _redundancy(p, per_point=1)),
        Mistake("observations", "each image point gives two observations (x′, y′); X, Y, Z "
                                "of a control point are given, not observed",
                lambda p: _redundancy(p, per_point=3)),
    ))


# -- 2. DLT parameters of a camera (array) --------------------------------------------------------
def _signed(rng, low, high):
    return float(rng.choice([-1.0, 1.0]) * rng.uniform(low, high))


def _close_range_orientation(rng):
    """A close-range camera 3–30 m in front of a façade (Y = 0 plane), looking along +Y."""
    cam = close_range_camera(rng)
    return {"c_mm": cam["c_mm"],
            "x0_mm": round(_signed(rng, 0.1, 0.6), 3), "y0_mm": round(_signed(rng, 0.1, 0.6), 3),
            "X0": round(float(rng.uniform(-10.0, 10.0)), 3),
            "Y0": round(float(-rng.uniform(3.0, 30.0)), 3),
            "Z0": round(float(rng.uniform(1.0, 8.0)), 3),
            "omega_deg": round(float(rng.uniform(80.0, 100.0)), 3),
            "phi_deg": round(float(rng.uniform(-15.0, 15.0)), 3),
            "kappa_deg": round(float(rng.uniform(-10.0, 10.0)), 3)}


def _dlt_vector(p):
    import photolib as pl
    return pl.dlt_from_camera(p["c_mm"], p["c_mm"], p["x0_mm"], p["y0_mm"], _centre(p), _rotation(p))


_CAMERA_TEXT = ("camera constant (Kamerakonstante) c = {c_mm} mm, principal point "
                "(Bildhauptpunkt) x'0 = {x0_mm} mm, y'0 = {y0_mm} mm, projection centre "
                "X0 = ({X0}, {Y0}, {Z0}) m, ω = {omega_deg}°, φ = {phi_deg}°, κ = {kappa_deg}°")

dlt_vector = Exercise(
    params_name="p_dlt",
    id="rdl.dlt-vector", points=3, kind="array", answer="L",
    title="DLT parameters of a known camera (DLT-Parameter)",
    statement="A close-range camera has the " + _CAMERA_TEXT + " (c_x = c_y = c, no shear, no "
              "distortion). Compute its eleven DLT parameters L1 … L11 (scaled so that the "
              "constant of the denominator is 1) as a NumPy array of shape (11,).",
    # the printed inputs' rounding (1e-3 mm, m and °) and float32 (rtol 1e-6); the old
    # rtol 1e-7 rejected a float32 computation and L printed to 7 significant digits
    parameters=_close_range_orientation, reference=_dlt_vector,
    tolerance=PRINTED,
    mistakes=(
        Mistake("transposed", "R and Rᵀ are swapped: the DLT matrix is K·Rᵀ·[I | −X0]",
                lambda p: _dlt_formula(p, R=_rotation(p).T)),
        scaled_parameters(_dlt_vector, _ANGLES, 180.0 / math.pi, "degrees", _DEGREES),
        Mistake("sign-c", hints.MESSAGES["sign-c"], lambda p: _dlt_formula(p, c=-p["c_mm"])),
        Mistake("principal-point", "the sign of the principal point is reversed: "
                                   "x' = x'0 − c·kx/N, so L1 = (x'0·r13 − c·r11)/D",
                lambda p: _dlt_formula(p, x0=-p["x0_mm"], y0=-p["y0_mm"])),
        Mistake("normalisation", "the parameters must be divided by the constant of the "
                                 "denominator (−r3·X0) so that it becomes 1",
                lambda p: _dlt_formula(p, normalise=False)),
        Mistake("units-mm-m", "c, x'0 and y'0 were used in m: the image unit is mm "
                              "(L1 … L8 come out 1000 times too small)",
                lambda p: _dlt_formula(p, c=p["c_mm"] * 1e-3, x0=p["x0_mm"] * 1e-3,
                                       y0=p["y0_mm"] * 1e-3)),
    ))




# -- 3. interior orientation from L (array) -------------------------------------------------------
def _interior_params(rng):
    import photolib as pl
    p = _close_range_orientation(rng)
    L = pl.dlt_from_camera(p["c_mm"], p["c_mm"], p["x0_mm"], p["y0_mm"], _centre(p), _rotation(p))
    return {"L": _printed(L)}


def _interior(p):
    import photolib as pl
    d = pl.dlt_decompose(np.array(p["L"]))
    return np.array([d.x0, d.y0, d.c_x])


def _interior_no_x0(p):
    """c_x² = D²(L1² + L2² + L3²) without the − x'0² term."""
    L = np.array(p["L"])
    D2 = 1.0 / (L[8:11] @ L[8:11])
    x0, y0, _ = _interior(p)
    return np.array([x0, y0, math.sqrt(D2 * (L[0:3] @ L[0:3]))])


def _interior_no_D2(p):
    """x'0 = L1L9 + L2L10 + L3L11 without the factor D² (and c_x from it)."""
    L = np.array(p["L"])
    D2 = 1.0 / (L[8:11] @ L[8:11])
    x0, y0 = L[0:3] @ L[8:11], L[4:7] @ L[8:11]
    c2 = D2 * (L[0:3] @ L[0:3]) - x0**2
    return None if c2 <= 0 else np.array([x0, y0, math.sqrt(c2)])


dlt_interior = Exercise(
    params_name="p_interior",
    id="rdl.dlt-interior", points=3, kind="array", answer="interior",
    title="Interior orientation from the DLT (Luhmann 4.26, example 4.3)",
    statement="A DLT of a close-range image gave (image unit mm, object unit m) "
              "L1 … L11 = {L}. Decompose it: give the principal point x'0, y'0 and the camera "
              "constant c_x in mm as a NumPy array (x'0, y'0, c_x) of shape (3,).",
    # 2e-5 mm: a float32 decomposition loses up to 1e-5 mm (c² = L²·ΣL1..3² − x'0²); the
    # nearest mistake (the − x'0² forgotten) is ≥ 1e-4 mm away
    parameters=_interior_params, reference=_interior, rtol=0.0, atol=2e-5,
    mistakes=(
        Mistake("sign-c", "c comes out negative, as on the diagonal of OpenCV's K (its camera "
                          "looks along +z): the camera constant is c > 0",
                lambda p: _interior(p) * np.array([1.0, 1.0, -1.0])),
        Mistake("erratum", "x'0 and y'0 have the wrong sign, as printed in Luhmann's example "
                           "4.3 (luhmann:example-4.3): x'0 = +L²(L1L9 + L2L10 + L3L11)",
                lambda p: _interior(p) * np.array([-1.0, -1.0, 1.0])),
        Mistake("dlt-scale", "x'0 = L²(L1L9 + L2L10 + L3L11) with L² = 1/(L9² + L10² + L11²): "
                             "the factor L² is missing",
                _interior_no_D2),
        Mistake("dlt-scale", "c_x² = L²(L1² + L2² + L3²) − x'0²: the − x'0² is missing",
                _interior_no_x0),
        Mistake("swapped", "x'0 comes from L1 … L3 and y'0 from L5 … L7; they are swapped",
                lambda p: _interior(p)[[1, 0, 2]]),
    ))


# -- 4. one DLT coefficient with SymPy (expression) -----------------------------------------------
def _coefficient_params(rng):
    return {"k": int(rng.integers(1, 12))}


def _coefficient(p, transpose=False, c_sign=1, normalise=True, d_sign=1, x0_sign=1):
    import sympy as sp

    from photolib.derive import collinearity as dc
    from photolib.derive import dlt as dd
    R = dc.rotation_symbols()
    L = dd.dlt_from_orientation(R.T if transpose else R)
    value = L[p["k"] - 1].xreplace({dd.cx: dc.c, dd.cy: dc.c})
    if not normalise:
        D = -(R[:, 2].T * sp.Matrix([dc.X0, dc.Y0, dc.Z0]))[0]
        value = sp.cancel(value * D)
    if c_sign < 0:
        if p["k"] > 8:
            return None  # L9 … L11 do not contain c
        value = value.xreplace({dc.c: -dc.c})
    if x0_sign < 0:
        if p["k"] > 8:
            return None  # L9 … L11 do not contain x0, y0
        value = value.xreplace({dc.x0: -dc.x0, dc.y0: -dc.y0})
    return -value if d_sign < 0 else value


dlt_coefficient = Exercise(
    params_name="p_coef",
    id="rdl.dlt-coefficient",
    few_variants="a symbolic derivation: one of the eleven DLT coefficients", points=3, kind="expression", answer="Lk",
    symbols=("r11", "r12", "r13", "r21", "r22", "r23", "r31", "r32", "r33",
             "X0", "Y0", "Z0", "c", "x0", "y0"),
    title="A DLT coefficient from the collinearity equations (Herleitung)",
    statement="Multiply out the collinearity equations x' = x0 − c·kx/N, y' = y0 − c·ky/N with "
              "(kx, ky, N) = Rᵀ·(X − X0, Y − Y0, Z − Z0), R = [[r11, r12, r13], [r21, r22, r23], "
              "[r31, r32, r33]], and bring them into the DLT form x' = (L1X + L2Y + L3Z + L4)/"
              "(L9X + L10Y + L11Z + 1), y' = (L5X + L6Y + L7Z + L8)/(L9X + L10Y + L11Z + 1). "
              "Give L{k} as a SymPy expression in r11 … r33, X0, Y0, Z0, c, x0, y0.",
    parameters=_coefficient_params, reference=_coefficient,
    mistakes=(
        Mistake("transposed", "R was used where Rᵀ belongs: (kx, ky, N) = Rᵀ(X − X0)",
                lambda p: _coefficient(p, transpose=True)),
        Mistake("sign-c", hints.MESSAGES["sign-c"], lambda p: _coefficient(p, c_sign=-1)),
        Mistake("principal-point", "the sign of the principal point is reversed: "
                                   "x' = x0 − c·kx/N, so x0 enters with the sign of N",
                lambda p: _coefficient(p, x0_sign=-1)),
        Mistake("normalisation", "divide numerator and denominator by the constant "
                                 "D = −(r13·X0 + r23·Y0 + r33·Z0) so that the denominator "
                                 "ends in + 1", lambda p: _coefficient(p, normalise=False)),
        Mistake("sign", "the sign is reversed: the constant of the denominator is "
                        "D = −(r13·X0 + r23·Y0 + r33·Z0), not +(…)",
                lambda p: _coefficient(p, d_sign=-1)),
    ))


# -- 5. image coordinates from L (function) -------------------------------------------------------
def _image_params(rng):
    import photolib as pl
    cam = aerial_camera(rng)
    terrain = round(float(rng.uniform(100.0, 600.0)), 1)
    p = {"c_mm": cam["c_mm"], "X0": round(float(rng.uniform(2000.0, 8000.0)), 2),
         "Y0": round(float(rng.uniform(2000.0, 8000.0)), 2), "Z0": round(terrain + cam["h_m"], 2),
         "omega_deg": round(float(rng.uniform(-3.0, 3.0)), 4),
         "phi_deg": round(float(rng.uniform(-3.0, 3.0)), 4),
         "kappa_deg": round(float(rng.uniform(0.0, 360.0)), 4)}
    L = pl.dlt_from_camera(p["c_mm"], p["c_mm"], 0.0, 0.0, _centre(p), _rotation(p))
    return {"L": _printed(L), "terrain": terrain, "h_m": cam["h_m"], "X0": p["X0"], "Y0": p["Y0"]}


def _image_function(swapped=False, plus_one=True):
    def make(p):
        L = np.array(p["L"])
        a, b = (L[4:8], L[0:4]) if swapped else (L[0:4], L[4:8])

        def image_point(X, Y, Z):
            h = np.array([X, Y, Z, 1.0])
            den = L[8:11] @ h[:3] + (1.0 if plus_one else 0.0)
            return np.array([a @ h, b @ h]) / den
        return image_point
    return make


def _image_cases(rng, p):
    reach = 0.3 * p["h_m"]
    return [(round(p["X0"] + float(rng.uniform(-reach, reach)), 3),
             round(p["Y0"] + float(rng.uniform(-reach, reach)), 3),
             round(p["terrain"] + float(rng.uniform(-50.0, 50.0)), 2)) for _ in range(6)]


image_point = Exercise(
    params_name="p_img",
    id="rdl.image-point", points=3, kind="function", answer="image_point",
    title="Image coordinates from the DLT parameters (Bildkoordinaten aus der DLT)",
    statement="The DLT of an aerial image (image unit mm, object unit m) is "
              "L1 … L11 = {L}. Write image_point(X, Y, Z) returning the image coordinates "
              "(x', y') in mm of the object point (X, Y, Z) in m as a NumPy array of shape (2,). "
              "It is tested on ground points you do not see.",
    parameters=_image_params, reference=_image_function(), cases=_image_cases,
    # 1 µm: float32 loses up to 0.3 µm to the cancellation in L1·X + … + L4 (X ≈ 5000 m);
    # the old 1e-9 rejected float32 and coordinates rounded to 0.1 µm
    rtol=0.0, atol=1e-3,
    mistakes=(
        Mistake("swapped", "x' uses L1 … L4 and y' uses L5 … L8; they are swapped",
                _image_function(swapped=True)),
        Mistake("denominator", "the denominator is L9·X + L10·Y + L11·Z + 1: the + 1 "
                               "(the normalised twelfth parameter) is missing",
                _image_function(plus_one=False)),
    ))


EXERCISES = (redundancy, dlt_vector, dlt_interior, dlt_coefficient, image_point)
