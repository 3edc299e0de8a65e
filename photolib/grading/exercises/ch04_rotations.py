"""Chapter 04-rotations: graded exercises on the ω-φ-κ rotation matrix.

Four exercises, one per answer kind that fits the chapter:

* ``rot.opk-matrix`` (rotation): R from an aerial attitude given in gon;
* ``rot.angles-from-matrix`` (array): ω, φ, κ in degrees back out of a printed matrix;
* ``rot.matrix-derivative`` (expression): ∂R/∂t·x* (or ∂M/∂t·(X − X0) for Wolf's M = Rᵀ)
  with SymPy;
* ``rot.ray-direction`` (function): the object-frame direction of an image ray.

References are computed by :mod:`photolib` (``rotation_opk``, ``opk_from_rotation``) and by
:mod:`photolib.derive.rotation`; every hint recomputes the answer the way the mistake would.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake, Params

CHAPTER = "04-rotations"

_ORDER_MESSAGE = ("this is the φ-ω-κ product R_φ·R_ω·R_κ; the course's order is "
                  "R = R_ω·R_φ·R_κ (primary axis X)")


def scaled_parameters(reference, names, factor: float, tag: str, message: str | None = None):
    """Mistake: every parameter in ``names`` used ``factor`` times too large (e.g. all angles)."""
    def wrong(params):
        changed = Params(params)
        for name in names:
            changed[name] = params[name] * factor
        return reference(changed)
    return Mistake(tag, message or hints.MESSAGES[tag], wrong)


# -- 1. R from an aerial attitude in gon (rotation) ------------------------------------------
_GON = ("omega_gon", "phi_gon", "kappa_gon")


def _opk_params(rng):
    return {"omega_gon": round(float(rng.uniform(-5.0, 5.0)), 4),
            "phi_gon": round(float(rng.uniform(-5.0, 5.0)), 4),
            "kappa_gon": round(float(rng.uniform(0.0, 400.0)), 4)}


def _opk_reference(p):
    import photolib as pl
    return pl.rotation_opk(*pl.gon2rad(np.array([p[n] for n in _GON])))


def _opk_order(p):
    import photolib as pl
    return pl.rotation_pok(*pl.gon2rad(np.array([p[n] for n in _GON])))


def _opk_reversed_product(p):
    """R_κ·R_φ·R_ω: the three elementary rotations multiplied in the reverse order."""
    import photolib as pl
    omega, phi, kappa = pl.gon2rad(np.array([p[n] for n in _GON]))
    return (pl.rotation_opk(0.0, 0.0, kappa) @ pl.rotation_opk(0.0, phi, 0.0)
            @ pl.rotation_opk(omega, 0.0, 0.0))


_REVERSED_PRODUCT_MESSAGE = ("this is the κ-φ-ω product R_κ·R_φ·R_ω (the factors in reverse "
                             "order); the course's order is R = R_ω·R_φ·R_κ (primary axis X)")


opk_matrix = Exercise(
    params_name="p_opk",
    id="rot.opk-matrix", points=3, kind="rotation", answer="R",
    title="Rotation matrix from an aerial attitude (Drehmatrix aus der Fluglage)",
    statement=r"An aerial image was taken with roll $\omega = {omega_gon}$ gon (Querneigung), "
              r"pitch $\varphi = {phi_gon}$ gon (Längsneigung) and yaw $\kappa = {kappa_gon}$ "
              r"gon (Kantung); 400 gon = 360°. Build the rotation matrix (Drehmatrix) "
              r"$R = R_\omega R_\varphi R_\kappa$ of the course, which turns camera vectors "
              r"into the object frame, as a 3×3 NumPy array.",
    parameters=_opk_params, reference=_opk_reference, tolerance=PRINTED, atol=1e-6,
    mistakes=(
        scaled_parameters(_opk_reference, _GON, 200.0 / math.pi, "gon"),
        scaled_parameters(_opk_reference, _GON, 200.0 / 180.0, "degrees",
                          "the angles were converted as if they were degrees; they are in "
                          "gon (multiply by π/200)"),
        Mistake("order", _ORDER_MESSAGE, _opk_order),
        Mistake("order", _REVERSED_PRODUCT_MESSAGE, _opk_reversed_product),
        hints.reversed_sense(_opk_reference, "omega_gon"),
        hints.reversed_sense(_opk_reference, "phi_gon"),
        hints.reversed_sense(_opk_reference, "kappa_gon"),
        hints.reversed_sense(_opk_reference, "phi_gon", "kappa_gon"),
    ))


# -- 2. angles from a printed matrix (array) ---------------------------------------------------
def _angles_params(rng):
    import photolib as pl
    angles = (round(float(rng.uniform(-170.0, 170.0)), 3),
              round(float(rng.uniform(-80.0, 80.0)), 3),
              round(float(rng.uniform(-170.0, 170.0)), 3))
    R = np.round(pl.rotation_opk(*np.radians(angles)), 9)
    rows = ",\n ".join("[" + ", ".join(f"{v: .9f}" for v in row) + "]" for row in R)
    return {"R": R.tolist(), "matrix": f"[{rows}]"}


def _angles_reference(p):
    import photolib as pl
    return np.degrees(pl.opk_from_rotation(np.array(p["R"])))


def _angles_transposed(p):
    import photolib as pl
    return np.degrees(pl.opk_from_rotation(np.array(p["R"]).T))


def _angles_order(p):
    import photolib as pl
    return np.degrees(pl.pok_from_rotation(np.array(p["R"])))


def _angles_arctan(p):
    R = np.array(p["R"])
    wrong = np.degrees([math.atan(-R[1, 2] / R[2, 2]), math.asin(R[0, 2]),
                        math.atan(-R[0, 1] / R[0, 0])])
    return None if np.allclose(wrong, _angles_reference(p), atol=1e-6) else wrong


angles_from_matrix = Exercise(
    params_name="p_angles",
    id="rot.angles-from-matrix", points=3, kind="array", answer="angles_deg",
    title="Angles from a rotation matrix (Winkel aus der Drehmatrix)",
    statement=r"A close-range camera has the rotation matrix (Drehmatrix, "
              r"$R = R_\omega R_\varphi R_\kappa$)" "\n"
              "R = {matrix}\n(also as the list p_angles.R). Recover the angles and give them as "
              r"the NumPy array $[\omega, \varphi, \kappa]$ in degrees, with "
              r"$\varphi \in [-90°, 90°]$ and $\omega, \kappa \in (-180°, 180°]$.",
    parameters=_angles_params, reference=_angles_reference, rtol=0.0, atol=1e-4,
    mistakes=(
        Mistake("degrees", "these are radians; the task asks for degrees (numpy.degrees)",
                lambda p: np.radians(_angles_reference(p))),
        Mistake("transposed", "these are the angles of Rᵀ (Wolf's M), not of R",
                _angles_transposed),
        Mistake("quadrant", "arctan loses the quadrant when r₁₁ or r₃₃ is negative: use "
                            "atan2(−r₂₃, r₃₃) and atan2(−r₁₂, r₁₁)", _angles_arctan),
        Mistake("order", "these are the angles of the φ-ω-κ order; R here is R_ω·R_φ·R_κ",
                _angles_order),
    ))


# -- 3. derivative of the rotation matrix (expression) -----------------------------------------
_ANGLE_NAMES = {"omega": "ω", "phi": "φ", "kappa": "κ"}
_MATRICES = {"R": "the course's R = R_ω·R_φ·R_κ", "M": "Wolf's M = Rᵀ (object → camera)"}


_VECTORS = {"R": "the image vector x* = (x', y', −c)", "M": "the object vector X − X0"}


def _derivative_params(rng):
    """Which angle, which matrix, and the vector it acts on (whole mm, so exact in SymPy).

    R acts on an image vector (x', y' within ±110 mm, c from 80 to 160 mm), M on an object
    vector below the camera; no component is 0, so neither mistake can vanish.
    """
    angle = str(rng.choice(sorted(_ANGLE_NAMES)))
    matrix = str(rng.choice(sorted(_MATRICES)))
    def nonzero(lo, hi):
        return int(rng.choice([v for v in range(lo, hi + 1) if v != 0]))
    if matrix == "R":
        v = (nonzero(-110, 110), nonzero(-110, 110), -int(rng.integers(80, 161)))
    else:
        v = (nonzero(-500, 500), nonzero(-500, 500), -int(rng.integers(500, 1501)))
    return {"angle": angle, "angle_symbol": _ANGLE_NAMES[angle], "matrix": matrix,
            "matrix_text": _MATRICES[matrix], "vector_text": _VECTORS[matrix],
            "v": v, "v_text": f"({v[0]}, {v[1]}, {v[2]}) mm"}


@functools.cache
def _symbolic_rotation(order: str):
    """R_ω·R_φ·R_κ (``"opk"``) or R_φ·R_ω·R_κ (``"pok"``) from the derivation, derived once."""
    import sympy as sp

    from photolib.derive import rotation as dr
    return sp.ImmutableMatrix(dr.rotation_pok() if order == "pok" else dr.rotation_opk())


def _derivative(p, order="opk", sense=1, transposed=False):
    from photolib.derive import rotation as dr
    t = {"omega": dr.omega, "phi": dr.phi, "kappa": dr.kappa}[p["angle"]]
    R = _symbolic_rotation(order).as_mutable()
    if sense < 0:
        R = R.xreplace({t: -t})
    if (p["matrix"] == "M") != transposed:
        R = R.T
    import sympy as sp
    return R.diff(t) * sp.Matrix(p["v"])


def _derivative_order(p):
    return _derivative(p, order="pok")


matrix_derivative = Exercise(
    params_name="p_deriv",
    id="rot.matrix-derivative", points=3, kind="expression", answer="dR",
    symbols=("omega", "phi", "kappa"),
    title="Derivative of the rotation matrix (Ableitung der Drehmatrix)",
    statement="Linearising the collinearity equations needs derivatives of the rotation. "
              "Derive with SymPy ∂/∂{angle_symbol} of {matrix_text}, applied to "
              "{vector_text} = {v_text} (the vector is p_deriv.v): the 3×1 sympy.Matrix "
              "∂({matrix}·v)/∂{angle_symbol} in the symbols omega, phi, kappa "
              "(sympy.symbols('omega phi kappa')).",
    parameters=_derivative_params, reference=_derivative,
    mistakes=(
        Mistake("sense", f"{hints.MESSAGES['sense']} (in the elementary rotation)",
                lambda p: _derivative(p, sense=-1)),
        Mistake("order", _ORDER_MESSAGE, _derivative_order),
        Mistake("transposed", "this is the derivative of the transposed matrix (∂Rᵀ/∂t for "
                "∂R/∂t, or ∂R/∂t for Wolf's ∂M/∂t = ∂Rᵀ/∂t): check which matrix the task asks "
                "for", lambda p: _derivative(p, transposed=True)),
    ))


# -- 4. direction of an image ray in the object frame (function) -------------------------------
_UNITS = {"degrees": math.pi / 180.0, "gon": math.pi / 200.0}


def _ray_params(rng):
    aerial = bool(rng.integers(2))
    c = rng.uniform(100.0, 150.0) if aerial else rng.uniform(8.0, 50.0)
    return {"c_mm": round(float(c), 3), "unit": str(rng.choice(sorted(_UNITS))),
            "camera": "an aerial camera" if aerial else "a close-range camera"}


def _ray(x, y, angles_rad, c, transpose=False, order="opk"):
    import photolib as pl
    R = (pl.rotation_pok if order == "pok" else pl.rotation_opk)(*angles_rad)
    if transpose:
        R = R.T
    v = R @ np.array([float(x), float(y), -float(c)])
    return v / np.linalg.norm(v)


def _ray_function(to_radians=None, c_factor=1.0, transpose=False, senses=(1, 1, 1),
                  order="opk"):
    """``wrong(params)`` building a ray function with one thing done differently."""
    def make(p):
        scale = _UNITS[p["unit"]] if to_radians is None else to_radians(p)
        if scale is None:
            return None
        c = p["c_mm"] * c_factor

        def ray_direction(x, y, omega, phi, kappa):
            angles = [s * a * scale for s, a in zip(senses, (omega, phi, kappa))]
            return _ray(x, y, angles, c, transpose, order)
        return ray_direction
    return make


def _ray_cases(rng, p):
    # the order mistake (R_φ·R_ω·R_κ) moves the ray by about ω·φ·r′/c: ω and φ are drawn
    # at least a quarter of their range away from 0 and the image point at least a third of
    # the half format from the principal point, so that it stays far outside the rounding of
    # the printed c
    def angle(limit):
        return float(rng.choice([-1.0, 1.0])) * float(rng.uniform(0.25 * limit, limit))

    cases = []
    for _ in range(6):
        half = 0.6 * p["c_mm"]
        full = 400.0 if p["unit"] == "gon" else 360.0
        small = full / 72.0
        while True:
            x, y = (round(float(v), 3) for v in rng.uniform(-half, half, 2))
            if np.hypot(x, y) >= half / 3.0:
                break
        cases.append((x, y, round(angle(small), 4), round(angle(small), 4),
                      round(float(rng.uniform(0.0, full)), 4)))
    return cases


def _degrees_as_gon(p):
    return _UNITS["degrees"] if p["unit"] == "gon" else None


def _gon_as_degrees(p):
    return _UNITS["gon"] if p["unit"] == "degrees" else None


ray_direction = Exercise(
    params_name="p_ray",
    id="rot.ray-direction", points=3, kind="function", answer="ray_direction",
    title="Image ray in the object frame (Bildstrahl im Objektsystem)",
    statement="Your camera is {camera} with camera constant $c = {c_mm:.3f}$ mm (Kamerakonstante); "
              "the principal point is the origin. Write ray_direction(x, y, omega, phi, kappa) "
              "returning the unit vector, in the object frame, of the ray from the projection "
              "centre through the image point (x', y') = (x, y) in mm, for angles ω, φ, κ in "
              "{unit}. Use the image vector $x^* = (x', y', -c)$ and $R = R_\\omega R_\\varphi R_\\kappa$. "
              "It is tested "
              "on image points and attitudes you do not see.",
    # the cases are exact numbers and the result a unit vector: 1e-6 accepts float32 and
    # OpenCV (float32 eps ≈ 6e-8) while every mistake below moves some entry by far more
    parameters=_ray_params, reference=_ray_function(), tolerance=PRINTED, cases=_ray_cases, rtol=0.0, atol=1e-6,
    mistakes=(
        Mistake("transposed", "Rᵀ turns object vectors into the camera frame; here R·x* is "
                              "needed", _ray_function(transpose=True)),
        Mistake("degrees", "the angles were used as radians without conversion",
                _ray_function(to_radians=lambda p: 1.0)),
        Mistake("degrees", "the angles are in gon, not degrees (multiply by π/200)",
                _ray_function(to_radians=_degrees_as_gon)),
        Mistake("gon", "the angles are in degrees, not gon (multiply by π/180)",
                _ray_function(to_radians=_gon_as_degrees)),
        Mistake("sign-c", hints.MESSAGES["sign-c"], _ray_function(c_factor=-1.0)),
        Mistake("units-mm-m", "c and x', y' must have the same unit (mm)",
                _ray_function(c_factor=1e-3)),
        Mistake("sense", f"{hints.MESSAGES['sense']} (phi)", _ray_function(senses=(1, -1, 1))),
        Mistake("sense", f"{hints.MESSAGES['sense']} (kappa)", _ray_function(senses=(1, 1, -1))),
        Mistake("order", _ORDER_MESSAGE, _ray_function(order="pok")),
    ))


EXERCISES = (opk_matrix, angles_from_matrix, matrix_derivative, ray_direction)
