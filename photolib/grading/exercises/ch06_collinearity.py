"""Chapter 06-collinearity: graded exercises on the collinearity equations.

* ``col.project`` (array): image coordinates of a ground point in an aerial image;
* ``col.partial-derivative`` (expression): ∂x'/∂X0 (or another entry) derived with SymPy;
* ``col.dy-dphi`` (number): ∂y'/∂φ of a close-range image (Luhmann 4.18b, corrected);
* ``col.ground-point`` (function): monoplotting an image point onto a plane Z = const.

Course conventions (docs/conventions.md): ``(kx, ky, N) = Rᵀ(X − X0)``,
``x' = x'0 − c·kx/N``, ``y' = y'0 − c·ky/N``, ``R = R_ω·R_φ·R_κ``, c > 0, N < 0 in front.
References come from :func:`photolib.project`, :func:`photolib.collinearity_jacobian`,
:func:`photolib.monoplot` and :mod:`photolib.derive.collinearity`.
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.exercises.ch04_rotations import scaled_parameters
from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "06-collinearity"

_ANGLES = ("omega_deg", "phi_deg", "kappa_deg")
_DEGREES = "the angles in degrees were used as radians (convert with numpy.radians)"


def _rotation(p, senses=(1, 1, 1), scale=math.pi / 180.0):
    import photolib as pl
    return pl.rotation_opk(*[s * p[n] * scale for s, n in zip(senses, _ANGLES)])


def _aerial_orientation(rng):
    """An aerial exterior orientation: c 100–150 mm, flying height 500–3000 m, small ω, φ."""
    terrain = round(float(rng.uniform(100.0, 600.0)), 1)
    h = float(round(rng.uniform(500.0, 3000.0)))
    return {"c_mm": round(float(rng.uniform(100.0, 150.0)), 3), "h_m": h, "terrain": terrain,
            "X0": round(float(rng.uniform(2000.0, 8000.0)), 2),
            "Y0": round(float(rng.uniform(2000.0, 8000.0)), 2),
            "Z0": round(terrain + h, 2),
            "omega_deg": round(float(rng.uniform(-3.0, 3.0)), 4),
            "phi_deg": round(float(rng.uniform(-3.0, 3.0)), 4),
            "kappa_deg": round(float(rng.uniform(0.0, 360.0)), 4)}


def _centre(p):
    return np.array([p["X0"], p["Y0"], p["Z0"]])


_ORIENTATION_TEXT = ("projection centre (Projektionszentrum) X0 = ({X0}, {Y0}, {Z0}) m, "
                     "ω = {omega_deg}°, φ = {phi_deg}°, κ = {kappa_deg}°, camera constant "
                     "(Kamerakonstante) c = {c_mm} mm, principal point at the origin, no "
                     "distortion")


# -- 1. projection of a ground point (array) ---------------------------------------------------
def _project_params(rng):
    p = _aerial_orientation(rng)
    reach = 0.35 * p["h_m"]
    p.update(X=round(p["X0"] + float(rng.uniform(-reach, reach)), 3),
             Y=round(p["Y0"] + float(rng.uniform(-reach, reach)), 3),
             Z=round(p["terrain"] + float(rng.uniform(-30.0, 30.0)), 3))
    return p


def _project(p):
    import photolib as pl
    return pl.project(np.array([p["X"], p["Y"], p["Z"]]), _centre(p), _rotation(p), p["c_mm"])


def _project_formula(p, transpose=False):
    """The collinearity equations typed out, for mistakes (no check that N < 0)."""
    R = _rotation(p)
    kx, ky, N = (R if transpose else R.T) @ (np.array([p["X"], p["Y"], p["Z"]]) - _centre(p))
    return -p["c_mm"] * np.array([kx, ky]) / N


project = Exercise(
    params_name="p_project",
    id="col.project", points=3, kind="array", answer="xy",
    title="Image coordinates of a ground point (Bildkoordinaten, Kollinearitätsgleichungen)",
    statement="An aerial image has the exterior orientation (äußere Orientierung): "
              + _ORIENTATION_TEXT + ". Compute the image coordinates (x', y') in mm of the "
              "ground point X = ({X}, {Y}, {Z}) m, as a NumPy array of shape (2,).",
    parameters=_project_params, reference=_project, tolerance=PRINTED, rtol=0.0, atol=1e-6,
    mistakes=(
        Mistake("transposed", "Rᵀ and R are swapped: (kx, ky, N) = Rᵀ(X − X0)",
                lambda p: _project_formula(p, transpose=True)),
        scaled_parameters(_project_formula, _ANGLES, 180.0 / math.pi, "degrees", _DEGREES),
        Mistake("sign-c", hints.MESSAGES["sign-c"], lambda p: -_project(p)),
        hints.reversed_sense(_project_formula, "phi_deg"),
        hints.reversed_sense(_project_formula, "kappa_deg"),
        hints.reversed_sense(_project_formula, "phi_deg", "kappa_deg"),
    ))


# -- 2. a partial derivative with SymPy (expression) -------------------------------------------
_WRT = ("X0", "Y0", "Z0", "X", "Y", "Z")


def _partial_params(rng):
    # the principal distance of the camera as a whole number of mm (close range to aerial):
    # 2 coordinates × 6 unknowns × 146 cameras
    return {"coordinate": str(rng.choice(["x", "y"])), "wrt": str(rng.choice(_WRT)),
            "c_mm": int(rng.integers(8, 154))}


def _partial(p, transpose=False, c_sign=1, numerator_only=False):
    from photolib.derive import collinearity as dc
    R = dc.rotation_symbols()
    t = getattr(dc, p["wrt"])
    if numerator_only:  # the quotient rule forgotten: only the numerator differentiated
        kx, ky, N = dc.k_vector(R)
        value = -dc.c * (kx if p["coordinate"] == "x" else ky).diff(t) / N
    else:
        xs, ys = dc.image_coordinates(R.T if transpose else R)
        value = (xs if p["coordinate"] == "x" else ys).diff(t)
    if c_sign < 0:
        value = value.xreplace({dc.c: -dc.c})
    import sympy as sp
    return value.xreplace({dc.c: sp.Integer(p["c_mm"])})


partial_derivative = Exercise(
    params_name="p_partial",
    id="col.partial-derivative", points=3, kind="expression", answer="derivative",
    symbols=("r11", "r12", "r13", "r21", "r22", "r23", "r31", "r32", "r33",
             "X", "Y", "Z", "X0", "Y0", "Z0", "c", "x0", "y0"),
    title="A partial derivative of the collinearity equations (partielle Ableitung)",
    statement="Derive with SymPy ∂{coordinate}'/∂{wrt} of the collinearity equations "
              "x' = x0 − c·kx/N, y' = y0 − c·ky/N with (kx, ky, N) = Rᵀ·(X − X0, Y − Y0, Z − Z0), "
              "for a general rotation matrix R = [[r11, r12, r13], [r21, r22, r23], "
              "[r31, r32, r33]]. The camera has the principal distance c = {c_mm} mm: substitute "
              "it. Use the symbols r11 … r33, X, Y, Z, X0, Y0, Z0, x0, y0.",
    parameters=_partial_params, reference=_partial,
    mistakes=(
        Mistake("sign-c", hints.MESSAGES["sign-c"] + "; and note ∂/∂X0 = −∂/∂X",
                lambda p: _partial(p, c_sign=-1)),
        Mistake("transposed", "R was used where Rᵀ belongs: (kx, ky, N) = Rᵀ(X − X0)",
                lambda p: _partial(p, transpose=True)),
        Mistake("quotient-rule", "N depends on the coordinates too: "
                                 "∂(kx/N) = (∂kx·N − kx·∂N)/N²",
                lambda p: _partial(p, numerator_only=True)),
    ))


# -- 3. ∂y'/∂φ, Luhmann 4.18b (number) ----------------------------------------------------------
def _dphi_params(rng):
    import photolib as pl
    p = {"c_mm": round(float(rng.uniform(8.0, 50.0)), 3),
         "X0": round(float(rng.uniform(-5.0, 5.0)), 3),
         "Y0": round(float(rng.uniform(-25.0, -10.0)), 3),
         "Z0": round(float(rng.uniform(1.0, 5.0)), 3),
         "omega_deg": round(float(rng.uniform(70.0, 110.0)), 3),
         "phi_deg": round(float(rng.uniform(-20.0, 20.0)), 3),
         "kappa_deg": round(float(rng.uniform(-60.0, 60.0)), 3)}
    u, v = rng.choice([-1.0, 1.0], size=2) * rng.uniform(0.1, 0.4, size=2)
    ray = pl.rotation_opk(*np.radians([p[n] for n in _ANGLES])) @ np.array([u, v, -1.0])
    X = _centre(p) + ray / np.linalg.norm(ray) * rng.uniform(1.0, 30.0)
    p.update(X=round(float(X[0]), 3), Y=round(float(X[1]), 3), Z=round(float(X[2]), 3))
    return p


def _dphi_jacobian(p):
    import photolib as pl
    X = np.array([p["X"], p["Y"], p["Z"]])
    return np.reshape(pl.collinearity_jacobian(X, _centre(p), _rotation(p), p["c_mm"]), (2, 9))


def _dy_dphi(p):
    return float(_dphi_jacobian(p)[1, 4])


def _evaluate_418(expr, p):
    """Luhmann's printed form, numerically: k from Rᵀ(X − X0), z' = −c, κ in radians."""
    kx, ky, N = _rotation(p).T @ (np.array([p["X"], p["Y"], p["Z"]]) - _centre(p))
    values = {"k_x": kx, "k_y": ky, "N": N, "z_p": -p["c_mm"], "z'": -p["c_mm"],
              "kappa": math.radians(p["kappa_deg"])}
    return float(expr.subs({s: values[s.name] for s in expr.free_symbols}))


def _dy_dphi_done_wrongly(p, transpose=False, phi_sense=1):
    """∂y'/∂φ of the collinearity equations written with one mistake, by central differences.

    ``transpose``: (kx, ky, N) = R·(X − X0) instead of Rᵀ·(X − X0); ``phi_sense = −1``: the
    elementary rotation R_φ turned the other way. The student differentiates their own
    formula with respect to the φ of the task, so the difference quotient is taken in φ.
    """
    import photolib as pl
    X = np.array([p["X"], p["Y"], p["Z"]])
    omega, kappa = math.radians(p["omega_deg"]), math.radians(p["kappa_deg"])

    def y_image(phi):
        R = pl.rotation_opk(omega, phi_sense * phi, kappa)
        kx, ky, N = (R if transpose else R.T) @ (X - _centre(p))
        return -p["c_mm"] * ky / N

    phi, h = math.radians(p["phi_deg"]), 1e-5
    return (y_image(phi + h) - y_image(phi - h)) / (2.0 * h)


dy_dphi = Exercise(
    params_name="p_dy",
    id="col.dy-dphi", points=3, kind="number", answer="dy_dphi",
    title="∂y'/∂φ for a close-range image (Luhmann 4.18)",
    statement="A close-range camera has the " + _ORIENTATION_TEXT
              + " (object coordinates in m). It images the point X = ({X}, {Y}, {Z}) m. "
              "Compute the partial derivative ∂y'/∂φ (partielle Ableitung nach φ) of the "
              "collinearity equations for this point, in mm per radian (Luhmann 4.18 in kx, ky, "
              "N, or your own derivation).",
    parameters=_dphi_params, reference=_dy_dphi, tolerance=PRINTED, rtol=1e-6, atol=1e-9,
    mistakes=(
        hints.erratum_version("luhmann:4.18b", _evaluate_418),
        Mistake("degrees", "this is per degree; the derivative is wanted per radian",
                lambda p: _dy_dphi(p) * math.pi / 180.0),
        Mistake("sign-c", hints.MESSAGES["sign-c"], lambda p: -_dy_dphi(p)),
        Mistake("coordinate", "this is ∂x'/∂φ; the task asks for ∂y'/∂φ",
                lambda p: float(_dphi_jacobian(p)[0, 4])),
        Mistake("transposed", "R and Rᵀ are swapped: (kx, ky, N) = Rᵀ(X − X0), and R·x* "
                              "turns an image vector into the object frame",
                lambda p: _dy_dphi_done_wrongly(p, transpose=True)),
        Mistake("sense", f"{hints.MESSAGES['sense']} (phi: R_φ = [[cos φ, 0, sin φ], "
                         "[0, 1, 0], [−sin φ, 0, cos φ]])",
                lambda p: _dy_dphi_done_wrongly(p, phi_sense=-1)),
    ))


# -- 4. monoplotting (function) -----------------------------------------------------------------
def _ground_params(rng):
    p = _aerial_orientation(rng)
    del p["h_m"]
    return p


def _ground_function(transpose=False, c_factor=1.0, scale=math.pi / 180.0, senses=(1, 1, 1),
                     library=False):
    """``wrong(params)`` building a monoplotting function with one thing done differently."""
    def make(p):
        R = _rotation(p, senses, scale)
        R = R.T if transpose else R
        c = p["c_mm"] * c_factor

        def ground_point(x, y, Z):
            if library:
                import photolib as pl
                return pl.monoplot(np.array([x, y]), _centre(p), R, c, Z)
            ray = R @ np.array([x, y, -c])
            return _centre(p) + (Z - p["Z0"]) / ray[2] * ray
        return ground_point
    return make


def _ground_cases(rng, p):
    return [(round(float(rng.uniform(-50.0, 50.0)), 3), round(float(rng.uniform(-50.0, 50.0)), 3),
             round(p["terrain"] + float(rng.uniform(-50.0, 50.0)), 2)) for _ in range(6)]


ground_point = Exercise(
    params_name="p_mono",
    id="col.ground-point", points=3, kind="function", answer="ground_point",
    title="Monoplotting onto a plane (Monoplotting)",
    statement="Your aerial image has the exterior orientation (äußere Orientierung): "
              + _ORIENTATION_TEXT + ". "
              "Write ground_point(x, y, Z) returning the object point (X, Y, Z) in m, as a "
              "NumPy array of shape (3,), where the ray through the image point (x', y') = "
              "(x, y) in mm meets the horizontal plane at height Z (m). It is tested on image "
              "points and heights you do not see.",
    parameters=_ground_params, reference=_ground_function(library=True), tolerance=PRINTED, cases=_ground_cases,
    rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("transposed", "the ray in the object frame is R·x*, not Rᵀ·x*",
                _ground_function(transpose=True)),
        Mistake("degrees", _DEGREES, _ground_function(scale=1.0)),
        Mistake("sign-c", hints.MESSAGES["sign-c"], _ground_function(c_factor=-1.0)),
        Mistake("units-mm-m", "c and x', y' must have the same unit (mm)",
                _ground_function(c_factor=1e-3)),
        Mistake("sense", f"{hints.MESSAGES['sense']} (phi)", _ground_function(senses=(1, -1, 1))),
        Mistake("sense", f"{hints.MESSAGES['sense']} (kappa)",
                _ground_function(senses=(1, 1, -1))),
    ))


EXERCISES = (project, partial_derivative, dy_dphi, ground_point)
