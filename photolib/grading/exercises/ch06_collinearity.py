"""Chapter 06-collinearity: graded exercises on the collinearity equations.

* ``col.project`` (array): image coordinates of a ground point in an aerial image;
* ``col.partial-derivative`` (expression): ∂x'/∂X0 (or another entry) derived with SymPy;
* ``col.dy-dphi`` (number): ∂y'/∂φ of a close-range image (Luhmann 4.18b, corrected);
* ``col.ground-point`` (function): image point → object point on a given height Z (the ray
  intersected with the plane), with a principal point; degenerate: the plane behind the camera;
* scenario ``col.nav-rotation`` (direct georeferencing, 3 steps): the camera rotation from
  roll, pitch, heading and boresight; the projection centre from the antenna and lever arm;
  the image point of a ground point with that exterior orientation;
* scenario ``col.refraction-constant`` (aerial image corrections, 3 steps): the refraction
  constant K (ARDC atmosphere); the image coordinates corrected for refraction and earth
  curvature; the object point of the corrected ray on a given height.

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


# -- 4. image point to object point on a given height (function) ------------------------------
def _last_digit_nonzero(value, digits):
    """``value`` rounded to ``digits`` decimals, its last printed digit not 0 (a printed
    0.35 would read as rounded to 2 decimals, not 4)."""
    unit = 10.0 ** -digits
    k = round(value / unit)
    return round((k + 1 if k % 10 == 0 else k) * unit, digits)


def _ground_params(rng):
    p = _aerial_orientation(rng)
    del p["h_m"]
    for name in _ANGLES:
        p[name] = _last_digit_nonzero(p[name], 4)
    sx, sy = rng.choice([-1.0, 1.0], size=2)
    p.update(x0_mm=_last_digit_nonzero(sx * float(rng.uniform(0.01, 0.05)), 3),
             y0_mm=_last_digit_nonzero(sy * float(rng.uniform(0.01, 0.05)), 3))
    return p


def _ground_reference(p):
    import photolib as pl
    R = _rotation(p)

    def ground_point(x, y, Z):
        return pl.monoplot(np.array([x, y]), _centre(p), R, p["c_mm"], Z, p["x0_mm"], p["y0_mm"])
    return ground_point


def _ground_function(transpose=False, c_factor=1.0, scale=math.pi / 180.0, senses=(1, 1, 1),
                     principal=1.0):
    """``wrong(params)``: a ground_point with one thing done differently. It raises ValueError
    where the reference does (the plane behind the camera), as a student who checks that
    case but makes this mistake elsewhere would."""
    def make(p):
        R = _rotation(p, senses, scale)
        R = R.T if transpose else R
        c = p["c_mm"] * c_factor
        reference = _ground_reference(p)

        def ground_point(x, y, Z):
            reference(x, y, Z)                      # raises on the degenerate case
            ray = R @ np.array([x - principal * p["x0_mm"], y - principal * p["y0_mm"], -c])
            return _centre(p) + (Z - p["Z0"]) / ray[2] * ray
        return ground_point
    return make


def _ground_cases(rng, p):
    clean = [(round(float(rng.uniform(-100.0, 100.0)), 3),
              round(float(rng.uniform(-100.0, 100.0)), 3),
              round(p["terrain"] + float(rng.uniform(-50.0, 50.0)), 2)) for _ in range(4)]
    noisy = [(float(x + rng.normal(0.0, 0.004)), float(y + rng.normal(0.0, 0.004)), Z)
             for x, y, Z in clean[:2]]
    above = round(p["Z0"] + float(rng.uniform(10.0, 200.0)), 2)   # the plane above the camera
    return clean + noisy + [(round(float(rng.uniform(-50.0, 50.0)), 3),
                             round(float(rng.uniform(-50.0, 50.0)), 3), above)]


ground_point = Exercise(
    params_name="p_mono",
    id="col.ground-point", points=3, kind="function", answer="ground_point",
    title="Image point to object point on a given height (Monoplotting)",
    statement="Your aerial image has the exterior orientation (äußere Orientierung): projection "
              "centre $\\mathbf X_0$ = ({X0}, {Y0}, {Z0}) m, $\\omega$ = {omega_deg}°, "
              "$\\varphi$ = {phi_deg}°, $\\kappa$ = {kappa_deg}°, camera constant "
              "(Kamerakonstante) $c$ = {c_mm} mm, principal point (Bildhauptpunkt) "
              "$x'_0$ = {x0_mm} mm, $y'_0$ = {y0_mm} mm, no distortion. "
              "Write `ground_point(x, y, Z)` returning the object point (X, Y, Z) in m, as a "
              "NumPy array of shape (3,), where the ray through the measured image point "
              "$(x', y')$ = (x, y) in mm meets the horizontal plane at height Z (m): "
              "$\\mathbf X = \\mathbf X_0 + \\lambda R\\,\\mathbf x^*$ with "
              "$\\mathbf x^* = (x' - x'_0,\\ y' - y'_0,\\ -c)$. Where the plane is not in "
              "front of the camera along the ray (parallel to it, or met behind the projection "
              "centre, $\\lambda \\le 0$) raise `ValueError` saying so. Accurate to 1 mm; "
              "it is tested on image points (some with measurement noise) and heights you do "
              "not see.",
    parameters=_ground_params, reference=_ground_reference, tolerance=PRINTED,
    cases=_ground_cases, rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("transposed", "the ray in the object frame is R·x*, not Rᵀ·x*",
                _ground_function(transpose=True)),
        Mistake("degrees", _DEGREES, _ground_function(scale=1.0)),
        Mistake("sign-c", hints.MESSAGES["sign-c"], _ground_function(c_factor=-1.0)),
        Mistake("principal-point", "the principal point is missing: x* = (x' − x'0, y' − y'0, "
                                   "−c), reduce the measured point to the principal point first",
                _ground_function(principal=0.0)),
        Mistake("principal-point", "the principal point has the wrong sign: subtract it, "
                                   "x* = (x' − x'0, y' − y'0, −c)",
                _ground_function(principal=-1.0)),
        Mistake("units-mm-m", "c and x', y' must have the same unit (mm); only the object "
                              "coordinates are in m",
                _ground_function(c_factor=1e-3)),
        Mistake("sense", f"{hints.MESSAGES['sense']} (phi)", _ground_function(senses=(1, -1, 1))),
        Mistake("sense", f"{hints.MESSAGES['sense']} (kappa)",
                _ground_function(senses=(1, 1, -1))),
    ))


# -- 5. scenario: direct georeferencing (3 steps) -----------------------------------------------
def _nav_scenario(rng):
    """GNSS/IMU of a nadir camera, a ground point, and the correct results of steps 1 and 2."""
    import photolib as pl
    from photolib.aerial import NED_TO_ENU, rotation_body_to_ned
    terrain = _last_digit_nonzero(float(rng.uniform(100.0, 600.0)), 1)
    p = {"E": _last_digit_nonzero(float(rng.uniform(2000.0, 8000.0)), 3),
         "N": _last_digit_nonzero(float(rng.uniform(2000.0, 8000.0)), 3),
         "U": _last_digit_nonzero(terrain + float(rng.uniform(800.0, 3000.0)), 3),
         "roll_deg": _last_digit_nonzero(float(rng.uniform(-3.0, 3.0)), 5),
         "pitch_deg": _last_digit_nonzero(float(rng.uniform(-3.0, 3.0)), 5),
         "heading_deg": _last_digit_nonzero(float(rng.uniform(0.0, 360.0)), 5),
         "bx_deg": _last_digit_nonzero(float(rng.uniform(-0.3, 0.3)), 5),
         "by_deg": _last_digit_nonzero(float(rng.uniform(-0.3, 0.3)), 5),
         "bz_deg": _last_digit_nonzero(float(rng.uniform(-0.3, 0.3)), 5),
         "lx": _last_digit_nonzero(float(rng.uniform(-1.0, 1.0)), 3),
         "ly": _last_digit_nonzero(float(rng.uniform(-0.5, 0.5)), 3),
         "lz": _last_digit_nonzero(float(rng.uniform(-2.0, -0.5)), 3),
         "c_mm": _last_digit_nonzero(float(rng.uniform(50.0, 150.0)), 3)}
    angles = np.radians([p["roll_deg"], p["pitch_deg"], p["heading_deg"]])
    X0, R = pl.exterior_from_navigation([p["E"], p["N"], p["U"]], *angles,
                                        lever_arm=[p["lx"], p["ly"], p["lz"]],
                                        boresight=np.radians([p["bx_deg"], p["by_deg"],
                                                              p["bz_deg"]]))
    R_nav = NED_TO_ENU @ rotation_body_to_ned(*angles)
    reach = 0.3 * (p["U"] - terrain) * 100.0 / p["c_mm"]
    p.update(R_nav=[[_last_digit_nonzero(float(v), 9) for v in row] for row in R_nav],
             R=[[_last_digit_nonzero(float(v), 9) for v in row] for row in R],
             X0=[_last_digit_nonzero(float(v), 4) for v in X0],
             X=_last_digit_nonzero(float(X0[0] + rng.uniform(-reach, reach)), 3),
             Y=_last_digit_nonzero(float(X0[1] + rng.uniform(-reach, reach)), 3),
             Z=_last_digit_nonzero(terrain + float(rng.uniform(-30.0, 30.0)), 3))
    return p


def _nav_rotation(p, boresight=True, enu=True, heading_sense=1.0, scale=math.pi / 180.0):
    from photolib.aerial import NADIR_MOUNT, NED_TO_ENU, rotation_body_to_ned
    import photolib as pl
    R_nb = rotation_body_to_ned(p["roll_deg"] * scale, p["pitch_deg"] * scale,
                                heading_sense * p["heading_deg"] * scale)
    bore = (pl.rotation_opk(*[p[n] * scale for n in ("bx_deg", "by_deg", "bz_deg")])
            if boresight else np.eye(3))
    return (NED_TO_ENU if enu else np.eye(3)) @ R_nb @ NADIR_MOUNT @ bore


_NAV_TEXT = ("A nadir camera is georeferenced directly (direkte Georeferenzierung) by GNSS/IMU. "
             "The inertial unit gives roll = {roll_deg}°, pitch = {pitch_deg}°, heading = "
             "{heading_deg}°, the aerospace attitude body → north-east-down "
             "$R_{{nb}} = R_z(\\psi)\\,R_y(\\theta)\\,R_x(\\phi)$ (body x forward, y right, "
             "z down); the object frame is east-north-up, "
             "$R_{{nav}} = T\\,R_{{nb}}$ with $T$ = [[0, 1, 0], [1, 0, 0], [0, 0, −1]]. The "
             "camera is mounted with x′ forward, y′ left, z′ up, "
             "$M$ = diag(1, −1, −1) (camera → body), with the boresight misalignment "
             "(ω, φ, κ) = ({bx_deg}°, {by_deg}°, {bz_deg}°) "
             "(calibrated): $R = R_{{nav}}\\,M\\,R_\\omega R_\\varphi R_\\kappa$. ")

nav_rotation = Exercise(
    params_name="p_nav_rot", scenario="col.nav-rotation",
    id="col.nav-rotation", points=2, kind="rotation", answer="R_cam",
    title="Step 1 of 3: the camera rotation from GNSS/IMU (direkte Georeferenzierung)",
    statement=_NAV_TEXT + "Compute the rotation $R$ camera → object (east, north, up) of the "
              "collinearity equations as a 3 × 3 NumPy array, to 6 decimals.",
    parameters=_nav_scenario, reference=_nav_rotation, rtol=0.0, atol=2e-6,
    mistakes=(
        Mistake("boresight", "the boresight misalignment is missing: R = R_nav·M·R_ω·R_φ·R_κ "
                             "with the calibrated (ω, φ, κ) of the mount",
                lambda p: _nav_rotation(p, boresight=False)),
        Mistake("ned-enu", "this rotates into north-east-down; the object frame is "
                           "east-north-up: multiply by T = [[0, 1, 0], [1, 0, 0], [0, 0, −1]]",
                lambda p: _nav_rotation(p, enu=False)),
        Mistake("sense", "heading turns clockwise seen from above (about z down): "
                         "R_z(ψ) = [[cos ψ, −sin ψ, 0], [sin ψ, cos ψ, 0], [0, 0, 1]] in NED",
                lambda p: _nav_rotation(p, heading_sense=-1.0)),
        Mistake("degrees", _DEGREES, lambda p: _nav_rotation(p, scale=1.0)),
    ))


def _nav_centre(p, sign=-1.0, rotate=True, transpose=False):
    R_nav = np.array(p["R_nav"])
    R_nav = R_nav.T if transpose else R_nav
    lever = np.array([p["lx"], p["ly"], p["lz"]])
    return np.array([p["E"], p["N"], p["U"]]) + sign * (R_nav @ lever if rotate else lever)


nav_centre = Exercise(
    params_name="p_nav_x0", scenario="col.nav-rotation",
    id="col.nav-centre", points=2, kind="array", answer="X0_cam",
    title="Step 2 of 3: the projection centre from the antenna and the lever arm (Hebelarm)",
    statement=_NAV_TEXT + "The GNSS antenna is at (E, N, U) = ({E}, {N}, {U}) m; the lever "
              "arm (Hebelarm) from the projection centre to the antenna is "
              "({lx}, {ly}, {lz}) m in the body frame (x forward, y right, z down). With "
              "$R_{{nav}}$ = {R_nav} (body → object, from step 1's attitude), compute the "
              "projection centre $\\mathbf X_0$ in m as an array of shape (3,), to 0.001 m.",
    parameters=_nav_scenario, reference=_nav_centre, tolerance=PRINTED, rtol=1e-6, atol=5e-4,
    mistakes=(
        Mistake("sign", "the lever arm points from the camera to the antenna: "
                        "X0 = antenna − R_nav·lever arm",
                lambda p: _nav_centre(p, sign=1.0)),
        Mistake("lever-frame", "the lever arm is given in the body frame: rotate it into the "
                               "object frame with R_nav before subtracting it",
                lambda p: _nav_centre(p, rotate=False)),
        Mistake("transposed", "R_nav turns body vectors into the object frame: R_nav·l, not "
                              "R_navᵀ·l", lambda p: _nav_centre(p, transpose=True)),
        Mistake("lever-arm", "the antenna is not the projection centre: subtract the lever "
                             "arm", lambda p: np.array([p["E"], p["N"], p["U"]])),
    ))


def _nav_image(p, transpose=False, centre=None):
    R = np.array(p["R"])
    X0 = np.array(p["X0"]) if centre is None else centre
    kx, ky, N = (R if transpose else R.T) @ (np.array([p["X"], p["Y"], p["Z"]]) - X0)
    return -p["c_mm"] * np.array([kx, ky]) / N


nav_image = Exercise(
    params_name="p_nav_xy", scenario="col.nav-rotation",
    id="col.nav-image", points=2, kind="array", answer="xy_nav",
    title="Step 3 of 3: the image point of a ground point, directly georeferenced",
    statement="With the exterior orientation of steps 1 and 2, $\\mathbf X_0$ = {X0} m and "
              "$R$ = {R}, and the camera constant $c$ = {c_mm} mm (principal point at the "
              "origin, no distortion), compute the image coordinates $(x', y')$ in mm of the "
              "ground point X = ({X}, {Y}, {Z}) m, to 0.0001 mm, as an array of shape (2,).",
    parameters=_nav_scenario, reference=lambda p: _nav_image(p), tolerance=PRINTED,
    rtol=0.0, atol=5e-5,
    mistakes=(
        Mistake("transposed", "Rᵀ and R are swapped: (kx, ky, N) = Rᵀ(X − X0)",
                lambda p: _nav_image(p, transpose=True)),
        Mistake("sign-c", hints.MESSAGES["sign-c"], lambda p: -_nav_image(p)),
        Mistake("lever-arm", "the antenna is not the projection centre: use X0 of step 2",
                lambda p: _nav_image(p, centre=np.array([p["E"], p["N"], p["U"]]))),
    ))


# -- 6. scenario: refraction and earth curvature (3 steps) -------------------------------------
def _ardc(H_m, h_m):
    Hk, hk = H_m / 1000.0, h_m / 1000.0
    return (2410.0 * Hk / (Hk**2 - 6.0 * Hk + 250.0)
            - 2410.0 * hk**2 / ((hk**2 - 6.0 * hk + 250.0) * Hk)) * 1e-6


def _refraction_scenario(rng):
    import photolib as pl
    nz = _last_digit_nonzero
    h = nz(float(rng.uniform(100.0, 1200.0)), 2)
    p = {"h_m": h, "H_m": nz(h + float(rng.uniform(2000.0, 7000.0)), 2),
         "c_mm": nz(float(rng.uniform(100.0, 160.0)), 4),
         "X0": nz(float(rng.uniform(2000.0, 8000.0)), 3),
         "Y0": nz(float(rng.uniform(2000.0, 8000.0)), 3),
         "omega_deg": nz(float(rng.uniform(-1.0, 1.0)), 5),
         "phi_deg": nz(float(rng.uniform(-1.0, 1.0)), 5),
         "kappa_deg": nz(float(rng.uniform(0.0, 360.0)), 5)}
    p["Z0"] = p["H_m"]
    r = float(rng.uniform(70.0, 110.0))
    a = float(rng.uniform(0.0, 2.0 * math.pi))
    p.update(x=nz(r * math.cos(a), 4), y=nz(r * math.sin(a), 4))
    K = _ardc(p["H_m"], p["h_m"])
    p["K_urad"] = nz(K * 1e6, 4)
    xy = pl.earth_curvature_correction(pl.refraction_correction([p["x"], p["y"]], p["c_mm"],
                                                                p["K_urad"] * 1e-6),
                                       p["c_mm"], p["H_m"] - p["h_m"])
    p.update(xc=nz(float(xy[0]), 5), yc=nz(float(xy[1]), 5),
             Zg=nz(h + float(rng.uniform(-20.0, 20.0)), 3))
    return p


refraction_constant = Exercise(
    params_name="p_refr_k", scenario="col.refraction-constant",
    id="col.refraction-constant", points=2, kind="number", answer="K_urad",
    title="Step 1 of 3: the refraction constant of the ARDC atmosphere (Refraktionskonstante)",
    statement="A vertical aerial image is taken from the flying height $H$ = {H_m} m above sea "
              "level over ground at $h$ = {h_m} m. The ARDC model atmosphere gives the "
              "refraction constant of $d\\alpha = K\\tan\\alpha$ as "
              "$K = \\left(\\frac{{2410\\,H}}{{H^2 - 6H + 250}} - \\frac{{2410\\,h^2}}"
              "{{(h^2 - 6h + 250)\\,H}}\\right)\\cdot 10^{{-6}}$ with $H$, $h$ in km. "
              "Compute K in µrad (microradians) to 0.01 µrad.",
    parameters=_refraction_scenario, reference=lambda p: _ardc(p["H_m"], p["h_m"]) * 1e6,
    tolerance=PRINTED, rtol=0.0, atol=5e-3,
    mistakes=(
        Mistake("ground", "the second term, the air below the ground height h, is missing",
                lambda p: _ardc(p["H_m"], 0.0) * 1e6),
        Mistake("units-km", "H and h enter the ARDC formula in km, not m",
                lambda p: _ardc(p["H_m"] * 1000.0, p["h_m"] * 1000.0) * 1e6),
        Mistake("height-above-ground", "H is the flying height above sea level, not above "
                                       "the ground",
                lambda p: _ardc(p["H_m"] - p["h_m"], p["h_m"]) * 1e6
                if p["H_m"] - p["h_m"] > p["h_m"] else None),
    ))


def _far_enough(wrong, right, distance):
    """``wrong``, or None where it is within ``distance`` of the right answer (indistinct)."""
    return wrong if np.max(np.abs(np.asarray(wrong) - right)) > distance else None


def _corrected(p, refraction_sign=1.0, curvature_sign=1.0, H=None, curvature=True):
    c, K = p["c_mm"], p["K_urad"] * 1e-6
    xy = np.array([p["x"], p["y"]])
    r2 = xy @ xy
    height = p["H_m"] - p["h_m"] if H is None else H
    out = xy * (1.0 - refraction_sign * K * (1.0 + r2 / c**2))
    if curvature:
        out = out * (1.0 + curvature_sign * (out @ out) * height / (2.0 * 6371000.0 * c**2))
    return out


refraction_corrected = Exercise(
    params_name="p_refr_xy", scenario="col.refraction-constant",
    id="col.refraction-corrected", points=2, kind="array", answer="xy_corrected",
    title="Step 2 of 3: image coordinates corrected for refraction and earth curvature",
    statement="The camera constant is $c$ = {c_mm} mm; the measured image point, reduced to "
              "the principal point and corrected for distortion, is $(x', y')$ = ({x}, {y}) mm. "
              "With step 1's refraction constant $K$ = {K_urad} µrad, flying height "
              "$H$ = {H_m} m and ground height $h$ = {h_m} m: refraction moved the point "
              "outwards by $\\Delta r' = K(r' + r'^3/c^2)$, earth curvature (earth radius "
              "6371 km) moved it towards the nadir by $\\Delta r' = r'^3 (H - h)/(2 R c^2)$. "
              "Remove both (refraction first) and give the corrected $(x', y')$ in mm as an "
              "array of shape (2,), to 0.0001 mm (0.1 µm).",
    parameters=_refraction_scenario, reference=lambda p: _corrected(p), tolerance=PRINTED,
    rtol=0.0, atol=5e-5,
    mistakes=(
        Mistake("sign-refraction", "refraction moved the image outwards: the correction "
                                   "moves it back in, x·(1 − K(1 + r'²/c²))",
                lambda p: _corrected(p, refraction_sign=-1.0)),
        Mistake("sign-curvature", "earth curvature moved the image towards the nadir: the "
                                  "correction moves it back out, x·(1 + r'²(H − h)/(2Rc²))",
                lambda p: _corrected(p, curvature_sign=-1.0)),
        Mistake("curvature", "the earth curvature correction is missing",
                lambda p: _corrected(p, curvature=False)),
        Mistake("height-above-ground", "the curvature correction uses the flying height above "
                                       "the ground, H − h",
                lambda p: _far_enough(_corrected(p, H=p["H_m"]), _corrected(p), 5e-4)),
        Mistake("units-urad", "K is in µrad: multiply by 10⁻⁶ before using it",
                lambda p: _corrected(p | {"K_urad": p["K_urad"] * 1e-6})),
    ))


def _refraction_ground(p, corrected=True, transpose=False, c_sign=1.0):
    R = _rotation(p)
    R = R.T if transpose else R
    xy = (p["xc"], p["yc"]) if corrected else (p["x"], p["y"])
    ray = R @ np.array([xy[0], xy[1], -c_sign * p["c_mm"]])
    return np.array([p["X0"], p["Y0"], p["Z0"]]) + (p["Zg"] - p["Z0"]) / ray[2] * ray


refraction_ground = Exercise(
    params_name="p_refr_gp", scenario="col.refraction-constant",
    id="col.refraction-ground", points=2, kind="array", answer="X_ground",
    title="Step 3 of 3: the object point of the corrected ray on a given height",
    statement="The image has the exterior orientation $\\mathbf X_0$ = ({X0}, {Y0}, {Z0}) m, "
              "$\\omega$ = {omega_deg}°, $\\varphi$ = {phi_deg}°, $\\kappa$ = {kappa_deg}° and "
              "$c$ = {c_mm} mm. Step 2's corrected image point is $(x', y')$ = ({xc}, {yc}) mm "
              "(reduced to the principal point). Intersect its ray with the plane Z = {Zg} m "
              "and give the object point (X, Y, Z) in m to 0.01 m, as an array of shape (3,).",
    parameters=_refraction_scenario, reference=lambda p: _refraction_ground(p),
    tolerance=PRINTED, rtol=1e-6, atol=5e-3,
    mistakes=(
        Mistake("uncorrected", "these are the measured, uncorrected coordinates: use step 2's "
                               "corrected ones",
                lambda p: _refraction_ground(p, corrected=False)),
        Mistake("transposed", "the ray in the object frame is R·x*, not Rᵀ·x*",
                lambda p: _refraction_ground(p, transpose=True)),
        Mistake("sign-c", hints.MESSAGES["sign-c"],
                lambda p: _refraction_ground(p, c_sign=-1.0)),
    ))


EXERCISES = (project, partial_derivative, dy_dphi, ground_point, nav_rotation, nav_centre,
             nav_image, refraction_constant, refraction_corrected, refraction_ground)
