"""Chapter 08-resection-dlt: graded exercises on space resection and the DLT.

* ``rdl.redundancy`` (number): redundancy of a space resection or of a DLT with n points;
* ``rdl.dlt-vector`` (array): the eleven DLT parameters of a given close-range camera;
* ``rdl.dlt-interior`` (array): principal point and camera constant from printed L1…L11
  (Luhmann 4.26; the corrected example 4.3 of the errata list still prints x'0, y'0 with the
  wrong sign);
* ``rdl.dlt-coefficient`` (expression): one DLT coefficient derived with SymPy;
* ``rdl.image-point`` (function): image coordinates from the DLT parameters of an aerial image;
* ``rdl.resection-step`` (function): one Gauss–Newton step of the space resection (degenerate:
  fewer than 3 or collinear control points → ValueError);
* ``rdl.dlt-estimate`` (function): the normalised DLT from ≥ 6 points (degenerate: coplanar);
* scenario ``rdl.dlt-chain`` (3 steps): redundancy → DLT from printed points → decomposition
  of the correct L;
* scenario ``rdl.real-resection`` (2 steps): resection of a real chessboard photograph
  (view and unused corners per student, tolerance one σ of the corner noise) → the
  precision of its projection centre from σ0 and (AᵀA)⁻¹.

Course conventions (docs/conventions.md): ``(kx, ky, N) = Rᵀ(X − X0)``,
``x' = x'0 − c·kx/N``, ``R = R_ω·R_φ·R_κ``, c > 0. The DLT is
``x' = (L1X + L2Y + L3Z + L4)/(L9X + L10Y + L11Z + 1)``, y' likewise with L5…L8.
References come from :func:`photolib.dlt_from_camera`, :func:`photolib.dlt_decompose` and
:func:`photolib.derive.dlt.dlt_from_orientation`.

>>> [ex.id for ex in EXERCISES]
['rdl.redundancy', 'rdl.dlt-vector', 'rdl.dlt-interior', 'rdl.dlt-coefficient', 'rdl.image-point', 'rdl.resection-step', 'rdl.dlt-estimate', 'rdl.dlt-chain', 'rdl.dlt-chain-estimate', 'rdl.dlt-chain-interior', 'rdl.real-resection', 'rdl.real-precision']
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


# -- 6. one Gauss-Newton step of the space resection (function) -----------------------------------
def _gn_params(rng):
    return {"c_mm": round(float(rng.uniform(20.0, 160.0)), 3)}


def _check_resection_points(X):
    X = np.asarray(X, dtype=float)
    if X.ndim != 2 or X.shape[1] != 3 or len(X) < 3:
        raise ValueError(f"a space resection needs ≥ 3 control points (N, 3), got shape "
                         f"{X.shape}")
    sv = np.linalg.svd(X - X.mean(axis=0), compute_uv=False)
    if sv[1] <= 1e-9 * sv[0]:
        raise ValueError("the control points are collinear (singular values of the centred "
                         f"points {sv.round(6).tolist()}): the rotation about their line is "
                         "not determined")
    return X


def _gn_reference(p):
    import photolib as pl
    c = p["c_mm"]

    def resection_step(X, xy, q):
        X = _check_resection_points(X)
        res = pl.space_resection(X, xy, c, initial=q, max_iter=1, check=False)
        return res.params
    return resection_step


def _gn_wrong(transpose=False, sign=1.0, degrees=False, update=True):
    """A Gauss–Newton step with one mistake (numerical Jacobian of the model as written)."""
    def make(p):
        import photolib as pl
        c = p["c_mm"]

        def model(X, q):
            angles = np.radians(q[3:]) if degrees else q[3:]
            R = pl.rotation_opk(*angles)
            R = R.T if transpose else R
            k = (X - q[:3]) @ R                      # rows (kx, ky, N) = Rᵀ(X − X0)
            return (-c * k[:, :2] / k[:, 2:]).ravel()

        def resection_step(X, xy, q):
            X, q = _check_resection_points(X), np.asarray(q, dtype=float)
            obs = np.asarray(xy, dtype=float).ravel() - model(X, q)
            A = np.column_stack([(model(X, q + h * e) - model(X, q - h * e)) / (2 * h)
                                 for h, e in zip([1e-6] * 3 + [1e-8] * 3, np.eye(6))])
            dq = np.linalg.solve(A.T @ A, A.T @ (sign * obs))
            return q + dq if update else dq
        return resection_step
    return make


def _gn_scene(rng, c, n, collinear=False, noise=0.0):
    import photolib as pl
    X0 = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(40, 80)])
    angles = np.radians(rng.uniform(-6, 6, 3))
    if collinear:
        t = rng.integers(-40, 41, n) / 2.0           # exactly on one line after rounding
        X = np.column_stack([t, 0.5 * t + 3.0, 0.25 * t])
    else:
        X = np.column_stack([rng.uniform(-20, 20, n), rng.uniform(-20, 20, n),
                             rng.uniform(-3, 3, n)])
    xy = pl.project(X, X0, pl.rotation_opk(*angles), c) + rng.normal(0, noise, (n, 2))
    q = np.r_[X0 + rng.uniform(-1.5, 1.5, 3), angles + np.radians(rng.uniform(-2, 2, 3))]
    return np.round(X, 3), np.round(xy, 4), np.round(q, 6)


def _gn_cases(rng, p):
    c = p["c_mm"]
    cases = [_gn_scene(rng, c, 8), _gn_scene(rng, c, 12, noise=0.005),
             _gn_scene(rng, c, 20, noise=0.005), _gn_scene(rng, c, 6, collinear=True)]
    X, xy, q = _gn_scene(rng, c, 6)
    return cases + [(X[:2], xy[:2], q)]


resection_step = Exercise(
    params_name="p_gn",
    id="rdl.resection-step", points=4, kind="function", answer="resection_step",
    title="One Gauss–Newton step of the space resection (Iterationsschritt des Rückwärtsschnitts)",
    statement="Your camera has the camera constant $c$ = {c_mm} mm (principal point at 0, no "
              "distortion). Write `resection_step(X, xy, q)`: control points `X` (N, 3) in m, "
              "their measured image coordinates `xy` (N, 2) in mm, the current approximate "
              "values `q` = $(X_0, Y_0, Z_0, \\omega, \\varphi, \\kappa)$ (m, radians). Return "
              "the new $q + \\widehat{{dq}}$ after **one** Gauss–Newton step: linearise "
              "$x' = -c\\,k_x/N$, $y' = -c\\,k_y/N$ with $(k_x, k_y, N) = R^T(X - X_0)$, "
              "$R = R_\\omega R_\\varphi R_\\kappa$ at `q`, solve the normal equations "
              "$A^TA\\,\\widehat{{dq}} = A^T l$ with $l = x'_{{obs}} - x'(q)$. Raise a "
              "`ValueError` when fewer than 3 control points are given or all lie on one "
              "line (then the orientation is not determined). Tested on hidden control fields, "
              "clean and noisy; accepted to 1e-4 (m, rad).",
    # float32 work moves the result by up to 1e-5 (m, rad); the nearest mistake is ≥ 0.8 away;
    # c is a datum of the task, exact as printed
    parameters=_gn_params, reference=_gn_reference, cases=_gn_cases, rtol=0.0, atol=1e-4,
    exact=("c_mm",),
    mistakes=(
        Mistake("transposed", "(kx, ky, N) = Rᵀ(X − X0): R and Rᵀ are swapped",
                _gn_wrong(transpose=True)),
        Mistake("sign", "the step goes the wrong way: with A = ∂x′/∂q the normal equations are "
                        "AᵀA·dq = Aᵀ·(x′obs − x′(q)); a sign in A or in l is reversed",
                _gn_wrong(sign=-1.0)),
        Mistake("degrees", _DEGREES + ": q holds radians", _gn_wrong(degrees=True)),
        Mistake("no-update", "return the updated unknowns q + dq, not the correction dq alone",
                _gn_wrong(update=False)),
    ))


# -- 7. the DLT from >= 6 points (function) -------------------------------------------------------
def _dlt_fn_params(rng):
    X, xy = _dlt_scene(rng, 7, 0.0)
    return {"X": X.tolist(), "xy": xy.tolist(), "X_text": _fmt_rows(X, 4),
            "xy_text": _fmt_rows(xy, 5)}


def _dlt_reference(p):
    import photolib as pl

    def dlt(X, xy):
        return pl.dlt_estimate(X, xy).L
    return dlt


def _dlt_wrong(normalise=True, swap=False):
    def make(p):
        from photolib.dlt import _normaliser

        def dlt(X, xy):
            X, xy = np.asarray(X, float), np.asarray(xy, float)
            sv = np.linalg.svd(X - X.mean(axis=0), compute_uv=False)
            if len(X) < 6 or sv[2] <= 1e-9 * sv[0]:
                raise ValueError("the control points are coplanar or fewer than 6")
            if swap:
                xy = xy[:, ::-1]
            TX = _normaliser(X) if normalise else np.eye(4)
            Tx = _normaliser(xy) if normalise else np.eye(3)
            Xn = np.column_stack([X, np.ones(len(X))]) @ TX.T
            xn = (np.column_stack([xy, np.ones(len(xy))]) @ Tx.T)[:, :2]
            A = np.zeros((2 * len(X), 12))
            A[0::2, 0:4], A[0::2, 8:12] = Xn, -xn[:, :1] * Xn
            A[1::2, 4:8], A[1::2, 8:12] = Xn, -xn[:, 1:] * Xn
            P = np.linalg.svd(A)[2][-1].reshape(3, 4)
            P = np.linalg.inv(Tx) @ P @ TX
            return (P / P[2, 3]).ravel()[:11]
        return dlt
    return make


def _dlt_scene(rng, n, noise, coplanar=False):
    import photolib as pl
    p = _close_range_orientation(rng)
    R = _rotation(p)
    u = np.column_stack([rng.uniform(-0.3, 0.3, (n, 2)), -np.ones(n)])
    d = rng.uniform(0.7, 1.3, n) * abs(p["Y0"])
    X = _centre(p) + (u * d[:, None]) @ R.T
    if coplanar:
        X[:, 1] = 0.0                                  # all on the façade plane Y = 0
    xy = pl.project(X, _centre(p), R, p["c_mm"], p["x0_mm"], p["y0_mm"])
    return np.round(X, 4), np.round(xy + rng.normal(0, noise, (n, 2)), 5)


def _dlt_cases(rng, p):
    return [_dlt_scene(rng, 8, 0.0), _dlt_scene(rng, 8, 0.03), _dlt_scene(rng, 12, 0.03),
            _dlt_scene(rng, 10, 0.0, coplanar=True)]


dlt_estimate = Exercise(
    params_name="p_dltfn",
    id="rdl.dlt-estimate", points=4, kind="function", answer="dlt",
    few_variants="a general method, the same function for everyone: the hidden test fields "
                 "differ per student",
    title="The DLT from six or more points (DLT-Schätzung)",
    statement="Write `dlt(X, xy)` returning the eleven DLT parameters $L_1 \\ldots L_{{11}}$ "
              "(shape (11,), scaled to $L_{{12}} = 1$) from object points `X` (N, 3) in m and "
              "image points `xy` (N, 2) in mm, N ≥ 6: normalise both point sets (centroid 0, "
              "mean distance $\\sqrt 3$ and $\\sqrt 2$), solve the homogeneous system "
              "$x'(L_9X + L_{{10}}Y + L_{{11}}Z + L_{{12}}) = L_1X + L_2Y + L_3Z + L_4$ (and "
              "$y'$ likewise) by SVD (minimum algebraic error), denormalise, scale to "
              "$L_{{12}} = 1$. Raise a `ValueError` when the object points are coplanar (then "
              "the eleven parameters are not determined). Tested on hidden control fields, "
              "clean and noisy (30 µm); accepted to a relative 3e-5 of each $L$. To try "
              "it: your field `p_dltfn.X` = {X_text} (m) with `p_dltfn.xy` = {xy_text} (mm).",
    # float32 work moves L by up to 1.2e-5 relative (6e-6 absolute); the mistakes without
    # normalisation differs by ≥ 2.8 tolerances on the noisy fields (30 µm). Fixing L12 = 1
    # and ordinary least squares (the textbook's direct form) is no declared mistake: it comes
    # within 0.3 tolerances for some fields, so it gets no hint of its own
    parameters=_dlt_fn_params, reference=_dlt_reference, cases=_dlt_cases, rtol=3e-5,
    atol=2e-6,
    mistakes=(
        Mistake("normalisation", "normalise the points before the SVD (centroid 0, mean "
                                 "distance √3 and √2): without it the minimum algebraic error "
                                 "is another, badly conditioned, estimate",
                _dlt_wrong(normalise=False)),
        Mistake("swapped", "x′ belongs to L1 … L4 and y′ to L5 … L8; they are swapped",
                _dlt_wrong(swap=True)),
    ))


# -- 8-10. scenario: redundancy -> DLT -> interior orientation (multi-step) -----------------------
_DLT_CHAIN = "rdl.dlt-chain"


def _chain_draw(rng):
    import photolib as pl
    p = _close_range_orientation(rng)
    n = int(rng.integers(8, 13))
    R = _rotation(p)
    u = np.column_stack([rng.uniform(-0.3, 0.3, (n, 2)), -np.ones(n)])
    X = np.round(_centre(p) + (u * (rng.uniform(0.7, 1.3, n) * abs(p["Y0"]))[:, None]) @ R.T, 3)
    xy = np.round(pl.project(X, _centre(p), R, p["c_mm"], p["x0_mm"], p["y0_mm"]), 3)
    return {"n": n, "X": X.tolist(), "xy": xy.tolist(),
            "X_text": _fmt_rows(X, 3), "xy_text": _fmt_rows(xy, 3)}


def _fmt_rows(values, digits):
    return "[" + ", ".join("(" + ", ".join(f"{v:.{digits}f}" for v in row) + ")"
                           for row in np.asarray(values, float)) + "]"


def _chain_redundancy(p, per_point=2, unknowns=11):
    return float(per_point * p["n"] - unknowns)


dlt_chain = Exercise(
    params_name="p_chain1",
    id="rdl.dlt-chain", scenario=_DLT_CHAIN, points=1, kind="number", answer="r_dlt",
    few_variants="the redundancy 2n − 11 of n = 8 … 12 points: five answers (steps 2 and 3 "
                 "of the scenario draw the points and the camera)",
    title="Step 1 of 3: redundancy of the DLT / Redundanz",
    statement="{n} control points (Passpunkte) of an object are measured in one close-range image (the "
              "points follow in steps 2 and 3). How many redundant observations "
              "$r$ = observations − unknowns does the DLT of this image have?",
    parameters=lambda rng: {"n": _chain_draw(rng)["n"]}, reference=_chain_redundancy,
    rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("unknowns", "the DLT has 11 unknowns (L1 … L11; L12 = 1 fixes the scale), not "
                            "the 6 of the space resection", lambda p: _chain_redundancy(p, unknowns=6)),
        Mistake("unknowns", "the DLT matrix has 12 elements but only 11 unknowns: the scale "
                            "is fixed by L12 = 1", lambda p: _chain_redundancy(p, unknowns=12)),
        Mistake("observations", "each image point gives two observations (x′ and y′), not one",
                lambda p: _chain_redundancy(p, per_point=1)),
    ))


def _chain_L(p):
    import photolib as pl
    return pl.dlt_estimate(np.array(p["X"]), np.array(p["xy"])).L


def _chain_L_wrong(swap=False, sign=False):
    def wrong(p):
        X, xy = np.array(p["X"]), np.array(p["xy"])
        if swap:
            return _chain_L({"X": p["X"], "xy": xy[:, ::-1].tolist()})
        Xh = np.column_stack([X, np.ones(len(X))])
        A = np.zeros((2 * len(X), 12))
        s = 1.0 if sign else -1.0
        A[0::2, 0:4], A[0::2, 8:12] = Xh, s * xy[:, :1] * Xh
        A[1::2, 4:8], A[1::2, 8:12] = Xh, s * xy[:, 1:] * Xh
        L = np.linalg.lstsq(A[:, :11], -A[:, 11], rcond=None)[0]
        return L
    return wrong


dlt_chain_estimate = Exercise(
    params_name="p_chain2",
    id="rdl.dlt-chain-estimate", scenario=_DLT_CHAIN, points=3, kind="array", answer="L_est",
    title="Step 2 of 3: the DLT parameters from the measured points / DLT-Parameter",
    statement="The {n} control points (m) are $X$ = {X_text}; their image coordinates (mm) "
              "are $x'$ = {xy_text}. Estimate the eleven DLT parameters $L_1 \\ldots L_{{11}}$ "
              "(scaled to $L_{{12}} = 1$) as a NumPy array of shape (11,).",
    parameters=_chain_draw, reference=_chain_L, tolerance=PRINTED,
    mistakes=(
        Mistake("swapped", "x′ belongs to L1 … L4 and y′ to L5 … L8; they are swapped",
                _chain_L_wrong(swap=True)),
        Mistake("sign", "x′·(L9X + L10Y + L11Z + 1) = L1X + L2Y + L3Z + L4: the terms "
                        "x′·L9X … enter the design matrix with a minus sign",
                _chain_L_wrong(sign=True)),
    ))


def _chain3_params(rng):
    p = _chain_draw(rng)
    L = _printed(_chain_L(p))
    return {"n": p["n"], "L": L}


dlt_chain_interior = Exercise(
    params_name="p_chain3",
    id="rdl.dlt-chain-interior", scenario=_DLT_CHAIN, points=2, kind="array",
    answer="interior_est",
    title="Step 3 of 3: the interior orientation from the estimated DLT / Zerlegung",
    statement="The correct result of step 2 is $L_1 \\ldots L_{{11}}$ = {L}. Decompose it: "
              "give the principal point $x'_0$, $y'_0$ and the camera constant $c_x$ in mm "
              "as a NumPy array $(x'_0, y'_0, c_x)$ of shape (3,).",
    parameters=_chain3_params, reference=_interior, rtol=0.0, atol=2e-5,
    mistakes=dlt_interior.mistakes)


# -- 11-12. scenario: resection of a real chessboard photograph (multi-step) ----------------------
_REAL = "rdl.real-resection"


def _real_draw(rng):
    from photolib.nb import project as pj
    view = int(rng.integers(14))
    hidden = sorted(int(k) for k in rng.choice(54, int(rng.integers(3, 9)), replace=False))
    r = pj.calibration().result
    return {"view": view, "name": pj.view_name(view), "unused": hidden,
            "c": round(r.c, 3), "x0": round(r.x0, 3), "y0": round(r.y0, 3)}


def _real_resection(p, degrees=False, raw=False):
    from photolib.nb import project as pj
    control = [k for k in range(54) if k not in p["unused"]]
    if raw:
        return _real_raw(p, control)
    q = pj.resect(p["view"], control).params
    return np.r_[q[:3], np.degrees(q[3:])] if degrees else q


def _real_raw(p, control):
    import photolib as pl
    from photolib.nb import project as pj
    from photolib.testfield import plane_start
    r = pj.calibration().result
    X, xy = pj.board_points()[control], pj.calibration().xy[p["view"]][control]
    _, start = plane_start([xy - np.array([r.x0, r.y0])], X[:, :2], c=r.c)
    return pl.space_resection(X, xy, r.c, r.x0, r.y0, initial=start[0], tol=1e-6,
                              max_iter=200, check=False).params


def _real_tolerance(p):
    """One standard deviation of each unknown, from σ0 of the corner measurements."""
    from photolib.nb import project as pj
    control = [k for k in range(54) if k not in p["unused"]]
    return 0.0, pj.resect(p["view"], control).std


real_resection = Exercise(
    params_name="p_real",
    id="rdl.real-resection", scenario=_REAL, points=4, kind="array", answer="q_real",
    title="Step 1 of 2: space resection of a real photograph / Rückwärtsschnitt einer Aufnahme",
    statement="Resect **{name}** (view {view} of `photolib.data.chessboard()`) with the "
              "chapter-05 calibration: $c$ = {c:.3f} px, $x'_0$ = {x0:.3f} px, $y'_0$ = "
              "{y0:.3f} px, distortion corrected. The board corners OpenCV measured, corrected: "
              "`project.image_coordinates({view})` (54 × 2, px), their board positions "
              "`project.board_points()` (mm, Z = 0), with `from photolib.nb import project`. "
              "Corners {unused} are not to be used (say, occluded). Start from the plane "
              "homography (`photolib.testfield.plane_start`) as in the chapter. Give "
              "`q_real` = $(X_0, Y_0, Z_0, \\omega, \\varphi, \\kappa)$ (mm, radians), shape "
              "(6,). Accepted within one standard deviation of each unknown: what the corner "
              "measurement noise (σ0 ≈ 0.15 px) leaves undetermined.",
    parameters=_real_draw, reference=_real_resection, tolerance=_real_tolerance,
    mistakes=(
        Mistake("degrees", "the angles are asked in radians, not degrees",
                lambda p: _real_resection(p, degrees=True)),
        Mistake("distortion", "the measured corners must be corrected for distortion "
                              "(project.image_coordinates does it): this camera's distortion "
                              "reaches 20 px", lambda p: _real_resection(p, raw=True)),
    ))


def _real2_params(rng):
    p = _real_draw(rng)
    q = _real_resection(p)
    return p | {"q": [round(float(v), 3) for v in q[:3]] + [round(float(v), 7) for v in q[3:]],
                "q_text": "(" + ", ".join([f"{v:.3f}" for v in q[:3]]
                                          + [f"{v:.7f}" for v in q[3:]]) + ")"}


def _real_precision(p, how="right"):
    import photolib as pl
    from photolib.nb import project as pj
    control = [k for k in range(54) if k not in p["unused"]]
    X, xy = pj.board_points()[control], pj.image_coordinates(p["view"])[control]
    q = np.array(p["q"])
    R = pl.rotation_opk(*q[3:])
    v = pl.project(X, q[:3], R, p["c"], p["x0"], p["y0"]) - xy
    A = pl.collinearity_jacobian(X, q[:3], R, p["c"], angles=tuple(q[3:]))[:, :, :6].reshape(-1, 6)
    n = len(control)
    r = 2 * n - 6
    s0 = math.sqrt(np.sum(v**2) / (2 * n if how == "2n" else r))
    N = A.T @ A
    if how == "no-sigma0":
        s0 = 1.0
    if how == "no-inverse":
        return s0 / np.sqrt(np.diag(N)[:3])
    return s0 * np.sqrt(np.diag(np.linalg.inv(N))[:3])


real_precision = Exercise(
    params_name="p_real2",
    id="rdl.real-precision", scenario=_REAL, points=3, kind="array", answer="sigma_X0",
    title="Step 2 of 2: precision of the projection centre / Genauigkeit des Projektionszentrums",
    statement="The correct result of step 1 for **{name}** (corners {unused} unused) is "
              "$q$ = {q_text} (mm, radians). At this $q$ form the design matrix $A$ "
              "(∂x′/∂q, `pl.collinearity_jacobian` or your own) and the residuals "
              "$v = x'(q) - x'_{{obs}}$ of the control points ($c$ = {c:.3f} px, $x'_0$ = "
              "{x0:.3f} px, $y'_0$ = {y0:.3f} px), $\\hat\\sigma_0 = \\sqrt{{v^Tv/r}}$. Give "
              "the standard deviations $(\\sigma_{{X_0}}, \\sigma_{{Y_0}}, \\sigma_{{Z_0}})$ "
              "in mm from $\\Sigma_{{qq}} = \\hat\\sigma_0^2 (A^TA)^{{-1}}$, to 3 significant "
              "digits, shape (3,).",
    parameters=_real2_params, reference=_real_precision, rtol=5e-3, atol=0.0,
    mistakes=(
        Mistake("no-sigma0", "Σqq = σ0²·(AᵀA)⁻¹: the factor σ0² is missing",
                lambda p: _real_precision(p, "no-sigma0")),
        Mistake("redundancy", "σ0² = vᵀv/r with the redundancy r = 2n − 6, not the number "
                              "of observations 2n", lambda p: _real_precision(p, "2n")),
        Mistake("no-inverse", "the variances are the diagonal of the inverse (AᵀA)⁻¹, not "
                              "the inverse of the diagonal of AᵀA",
                lambda p: _real_precision(p, "no-inverse")),
    ))


EXERCISES = (redundancy, dlt_vector, dlt_interior, dlt_coefficient, image_point, resection_step,
             dlt_estimate, dlt_chain, dlt_chain_estimate, dlt_chain_interior, real_resection,
             real_precision)

