"""Chapter 09-stereo: graded exercises on stereo photogrammetry.

* ``st.height`` (number): Z of the normal case from the x-parallax, ``Z = −c·B/px'``;
* ``st.sigma-z`` (number): σ_Z of a stereo pair (Luhmann example 3.7 style) from the σ of
  one image coordinate, ``σ_px' = √2·σ_x'`` for independently measured x'1, x'2;
* ``st.intersection`` (function): forward intersection in the normal case with a principal
  point, ``point(x1, y1, x2, y2) → (X, Y, Z)``;
* ``st.essential`` (array): the essential matrix ``E = R1ᵀ·[b]×·R2`` of an oriented pair
  (``x*1ᵀ·E·x*2 = 0``);
* ``st.unknowns`` (choice): unknowns of relative / absolute orientation and their relatives;
* ``st.rays`` (function): least-squares forward intersection of two oriented rays, ValueError
  for parallel rays;
* ``st.ro-step`` (function): one Gauss–Newton step of the dependent relative orientation,
  ValueError for fewer than 5 points or a singular normal matrix;
* scenario ``st.moto`` (real photographs, the Middlebury motorcycle pair): step 1 measure a
  disparity, step 2 depth from it, step 3 its σ_Z;
* scenario ``st.iro``: step 1 the independent relative orientation of a pair, step 2 the
  model coordinates of a further point.

Course conventions (docs/conventions.md): c > 0, ``R = R_ω·R_φ·R_κ``, image vector
``x* = (x' − x'0, y' − y'0, −c)``; normal case: camera 1 at the origin, camera 2 at (B, 0, 0),
R = I. References come from :mod:`photolib.stereo`.

>>> [ex.id for ex in EXERCISES]
['st.height', 'st.sigma-z', 'st.intersection', 'st.essential', 'st.unknowns', 'st.rays', 'st.ro-step', 'st.moto', 'st.moto-depth', 'st.moto-sigma', 'st.iro', 'st.iro-model']
"""

from __future__ import annotations

import functools
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




# -- 6. forward intersection of two oriented rays (function) --------------------------------------
#: rays meeting at less than this angle (rad) count as parallel: far above the change a
#: rounded printed input makes to an exactly parallel pair, far below the angles of the cases
_PARALLEL = 1e-3
_RAY_ANGLES = ("omega1_deg", "phi1_deg", "kappa1_deg", "omega2_deg", "phi2_deg", "kappa2_deg")


def _rays_params(rng):
    cam = close_range_camera(rng)
    h = round(float(rng.uniform(8.0, 40.0)), 2)
    p = {"c_mm": cam["c_mm"],
         "X02": [round(h * float(rng.uniform(0.2, 0.5)), 3), round(float(rng.uniform(-0.5, 0.5)), 3),
                 round(float(rng.uniform(-0.5, 0.5)), 3)], "h_m": h}
    for name in _RAY_ANGLES:
        p[name] = round(float(rng.uniform(-8.0, 8.0)), 3)
    return p


def _ray_rotations(p, scale=math.pi / 180.0):
    import photolib as pl
    return (pl.rotation_opk(*[p[n] * scale for n in _RAY_ANGLES[:3]]),
            pl.rotation_opk(*[p[n] * scale for n in _RAY_ANGLES[3:]]))


def _rays_function(transposed=False, scale=math.pi / 180.0, c_sign=-1.0):
    def make(p):
        R1, R2 = _ray_rotations(p, scale)
        if transposed:
            R1, R2 = R1.T, R2.T
        X01, X02, c = np.zeros(3), np.array(p["X02"], float), p["c_mm"]

        def intersect(xy1, xy2):
            if not (transposed or scale != math.pi / 180.0 or c_sign > 0):
                import photolib as pl
                return pl.forward_intersection([xy1, xy2], [X01, X02], [R1, R2], c,
                                               min_angle=_PARALLEL).points
            d1 = R1 @ np.array([xy1[0], xy1[1], c_sign * c])
            d2 = R2 @ np.array([xy2[0], xy2[1], c_sign * c])
            d1, d2 = d1 / np.linalg.norm(d1), d2 / np.linalg.norm(d2)
            if np.linalg.norm(np.cross(d1, d2)) < _PARALLEL:
                raise ValueError("the rays are parallel")
            A = np.column_stack([d1, -d2])
            lam = np.linalg.lstsq(A, X02 - X01, rcond=None)[0]
            return (X01 + lam[0] * d1 + X02 + lam[1] * d2) / 2
        return intersect
    return make


def _rays_cases(rng, p):
    import photolib as pl
    R1, R2 = _ray_rotations(p)
    X01, X02 = np.zeros(3), np.array(p["X02"])
    out = []
    for k in range(5):
        X = np.array([p["X02"][0] * float(rng.uniform(-0.2, 1.2)), p["h_m"] * float(rng.uniform(-0.3, 0.3)),
                      -p["h_m"] * float(rng.uniform(0.8, 1.2))])
        a = pl.project(X, X01, R1, p["c_mm"])
        b = pl.project(X, X02, R2, p["c_mm"])
        if k >= 3:                                   # noisy: the rays miss each other
            a, b = a + rng.normal(0, 0.01, 2), b + rng.normal(0, 0.01, 2)
        out.append(([round(float(v), 4) for v in a], [round(float(v), 4) for v in b]))
    # degenerate: the ray of image 2 parallel to that of image 1 (zero parallax)
    a = np.array(out[0][0])
    k = R2.T @ R1 @ np.array([a[0], a[1], -p["c_mm"]])
    out.append((a.tolist(), (-p["c_mm"] * k[:2] / k[2]).tolist()))
    return out


rays = Exercise(
    params_name="p_rays",
    id="st.rays", points=3, kind="function", answer="intersect",
    title="Forward intersection of two rays / Räumlicher Vorwärtsschnitt",
    statement="Two oriented images with $c = {c_mm:.3f}$ mm (principal point at 0): "
              "image 1 at the origin, $\\omega_1 = {omega1_deg:.3f}°$, $\\varphi_1 = {phi1_deg:.3f}°$, "
              "$\\kappa_1 = {kappa1_deg:.3f}°$; $X_{{02}} = {X02}$ m, $\\omega_2 = {omega2_deg:.3f}°$, "
              "$\\varphi_2 = {phi2_deg:.3f}°$, $\\kappa_2 = {kappa2_deg:.3f}°$ "
              "($R = R_\\omega R_\\varphi R_\\kappa$, camera → object). Write `intersect(xy1, xy2)` "
              "that returns the object point (X, Y, Z) in m (NumPy array of shape (3,)) "
              "closest to both rays $X_{{0k}} + \\lambda R_k x^*_k$, $x^* = (x', y', -c)$ "
              "(least squares: the midpoint of their common perpendicular), from the image "
              "coordinates `xy1`, `xy2` (mm) of a point; it must raise a `ValueError` when "
              "the rays are parallel (intersection angle below $10^{{-3}}$ rad). It is tested "
              "on points you do not see, exact ones and ones with measurement noise, to "
              "$10^{{-6}}$ relative.",
    parameters=_rays_params, reference=_rays_function(), tolerance=PRINTED, cases=_rays_cases,
    rtol=1e-6, atol=1e-9,
    mistakes=(
        Mistake("transposed", hints.MESSAGES["transposed"] + ": R turns camera vectors into the "
                "object frame, so the ray direction is R·x*, not Rᵀ·x*",
                _rays_function(transposed=True)),
        Mistake("degrees", "the angles in degrees went into the trigonometric functions as "
                           "radians: convert them first (numpy.radians)",
                _rays_function(scale=1.0)),
        Mistake("sign-c", hints.MESSAGES["sign-c"] + ": the image vector is x* = (x', y', −c)",
                _rays_function(c_sign=1.0)),
    ))


# -- 7. one Gauss–Newton step of the dependent relative orientation (function) ---------------------
def _ro_step_params(rng):
    cam = close_range_camera(rng)
    return {"c_mm": cam["c_mm"], "bx": round(float(rng.uniform(0.5, 2.0)), 3)}


def _ro_step_function(transposed=False, jac_sign=1.0, degrees=False, update=True):
    def make(p):
        c, bx = p["c_mm"], p["bx"]

        def ro_step(xy1, xy2, q):
            from photolib.stereo._orientation import coplanarity_residuals
            a, b, q = (np.asarray(v, float) for v in (xy1, xy2, q))
            if a.shape != b.shape or a.ndim != 2 or a.shape[1] != 2:
                raise ValueError(f"xy1, xy2 must both be (N, 2), got {a.shape} and {b.shape}")
            if len(a) < 5:
                raise ValueError(f"{len(a)} points: the five unknowns need at least 5")
            r1 = np.column_stack([a, np.full(len(a), -c)])
            x2 = np.column_stack([b, np.full(len(b), -c)])
            qq = q.copy()
            if degrees:
                qq[2:] = np.degrees(qq[2:])
            if transposed:
                import photolib as pl
                R2t = pl.rotation_opk(*qq[2:]).T
                f, J = coplanarity_residuals(np.r_[qq[:2], pl.opk_from_rotation(R2t)], r1, x2, bx, c)
            else:
                f, J = coplanarity_residuals(qq, r1, x2, bx, c)
            N = J.T @ J
            s = np.sqrt(np.diag(N))
            if np.any(s == 0) or np.linalg.cond(N / np.outer(s, s)) > 1e12:
                raise ValueError("the normal matrix is singular: the points do not determine "
                                 "the five unknowns (no y-parallax information)")
            dq = -jac_sign * np.linalg.solve(N, J.T @ f)
            return q + dq if update else dq
        return ro_step
    return make


def _ro_step_cases(rng, p):
    import photolib as pl
    c, bx = p["c_mm"], p["bx"]
    out = []
    for k in range(4):
        h = bx * float(rng.uniform(2.5, 4.0))
        X = np.column_stack([rng.uniform(-0.6, 1.6, 9) * bx, rng.uniform(-1.0, 1.0, 9) * bx,
                             -h * rng.uniform(0.85, 1.15, 9)])
        q_true = np.r_[rng.uniform(-0.05, 0.05, 2) * bx, rng.uniform(-0.04, 0.04, 3)]
        a = pl.project(X, np.zeros(3), np.eye(3), c)
        b = pl.project(X, [bx, q_true[0], q_true[1]], pl.rotation_opk(*q_true[2:]), c)
        if k >= 2:
            a, b = a + rng.normal(0, 0.003, a.shape), b + rng.normal(0, 0.003, b.shape)
        # a start away from the solution and from 0 in every component (so that q + Δq and
        # the increment Δq alone differ clearly)
        q0 = rng.choice([-1.0, 1.0], 5) * rng.uniform(0.01, 0.05, 5) * np.r_[bx, bx, 1, 1, 1]
        out.append((np.round(a, 4).tolist(), np.round(b, 4).tolist(), np.round(q0, 5).tolist()))
    a, b, q0 = out[0]
    out.append((a[:4], b[:4], q0))                  # degenerate: 4 points for 5 unknowns
    return out


ro_step = Exercise(
    params_name="p_ro_step",
    id="st.ro-step", points=4, kind="function", answer="ro_step",
    title="One Gauss–Newton step of the relative orientation / Folgebildanschluss",
    statement="Dependent relative orientation (Folgebildanschluss) with $c = {c_mm:.3f}$ mm "
              "(principal point at 0) and $b_x = {bx:.3f}$ fixed: image 1 at the origin with "
              "$R_1 = I$, image 2 at $b = (b_x, b_y, b_z)$ with "
              "$R_2 = R_\\omega(\\omega_2) R_\\varphi(\\varphi_2) R_\\kappa(\\kappa_2)$. The "
              "coplanarity residual of point i is "
              "$v_i = \\det[b,\\, x^*_{{1i}},\\, R_2 x^*_{{2i}}]/(b_x c)$ with "
              "$x^* = (x', y', -c)$. Write `ro_step(xy1, xy2, q)` that takes the image "
              "coordinates (N × 2 arrays, mm) and the current unknowns "
              "$q = (b_y, b_z, \\omega_2, \\varphi_2, \\kappa_2)$ (radians) and returns the "
              "unknowns after one Gauss–Newton step, $q + \\Delta q$ with "
              "$(J^TJ)\\,\\Delta q = -J^Tv$ (NumPy array of shape (5,)). It must raise a "
              "`ValueError` for fewer than 5 points or a singular normal matrix. Tested on "
              "pairs you do not see, to $10^{{-6}}$ relative.",
    parameters=_ro_step_params, reference=_ro_step_function(), tolerance=PRINTED,
    cases=_ro_step_cases, rtol=1e-6, atol=1e-9,
    mistakes=(
        Mistake("transposed", hints.MESSAGES["transposed"] + ": the ray of image 2 in the "
                "frame of image 1 is R2·x*2", _ro_step_function(transposed=True)),
        Mistake("sign", "the step goes the wrong way: the normal equations are "
                        "(JᵀJ)·Δq = −Jᵀv (a wrong sign in the Jacobian or the right-hand side)",
                _ro_step_function(jac_sign=-1.0)),
        Mistake("degrees", "the angles were turned into degrees before the trigonometric "
                           "functions: q holds radians", _ro_step_function(degrees=True)),
        Mistake("update", "this is the increment Δq: the step must return the updated "
                          "unknowns q + Δq", _ro_step_function(update=False)),
    ))


# -- 8–10. scenario st.moto: the real motorcycle pair (Middlebury 2014, scikit-image) ---------------
#: the matcher of the chapter: 11 × 11 templates, NCC along the row, parabola subpixel
_MOTO_HALF = 5


@functools.lru_cache(maxsize=1)
def moto_samples():
    """Textured sample points of the motorcycle pair, their measured and true disparities.

    Returns ``(points (N, 2) col/row, d_measured (N,), d_true (N,), sigma_d)`` for the points
    whose measurement is within 2σ_d of the ground truth (reliable; no occlusion), with
    ``σ_d = 1.4826·MAD(d − d_true)`` over all matched points (px).
    """
    from photolib import data
    from photolib.stereo import match_disparities, textured_points
    pair = data.motorcycle()
    L, R = pair.left.mean(axis=2), pair.right.mean(axis=2)
    gt = pair.disparity
    pts = textured_points(L, 300, half=_MOTO_HALF, spacing=9, valid=np.isfinite(gt), border=70)
    d_range = (float(np.floor(np.nanmin(gt))) - 2.0, float(np.ceil(np.nanmax(gt))) + 2.0)
    d, _, _ = match_disparities(L, R, pts, d_range, half=_MOTO_HALF, lsm=False)
    ok = np.isfinite(d)
    pts, d = pts[ok], d[ok]
    d_true = gt[pts[:, 1].astype(int), pts[:, 0].astype(int)]
    e = d - d_true
    sigma_d = float(1.4826 * np.median(np.abs(e - np.median(e))))
    keep = np.abs(e) < 2 * sigma_d
    return pts[keep], d[keep], d_true[keep], sigma_d


def _moto_base(rng):
    from photolib.data import MOTORCYCLE_CALIBRATION as cal
    pts, d, _, sigma_d = moto_samples()
    i = int(rng.integers(len(pts)))
    return {"u_px": int(pts[i, 0]), "v_px": int(pts[i, 1]), "f_px": cal.f_px,
            "B_mm": cal.baseline_mm, "doffs_px": cal.doffs_px,
            "sigma_d_px": round(sigma_d, 2), "_i": i}


def _moto_params(rng):
    p = _moto_base(rng)
    return {k: p[k] for k in ("u_px", "v_px")}


def _moto_disparity(p):
    pts, d, _, _ = moto_samples()
    i = int(np.flatnonzero((pts[:, 0] == p["u_px"]) & (pts[:, 1] == p["v_px"]))[0])
    return float(d[i])


def _moto_tolerance(p):
    # 3σ_d of the matching (from the ground truth of the pair): another correct matcher
    # (template size, subpixel method) lands within that of photolib's measurement
    return 0.0, round(3.0 * moto_samples()[3], 2)


moto = Exercise(
    params_name="p_moto",
    id="st.moto", points=3, kind="number", answer="d_moto", scenario="st.moto",
    title="Step 1 of 3: measure a disparity / Disparität messen (motorcycle pair)",
    statement="The rectified Middlebury pair `photolib.data.motorcycle()` (grey values: the "
              "mean of R, G, B). Measure the disparity $d = u_1 - u_2$ (px) of the left-image "
              "pixel (column, row) = ({u_px}, {v_px}): correlate an 11 × 11 template centred "
              "there along the same row of the right image (`pl.ncc_match`, subpixel) — in a "
              "rectified pair the epipolar line is the row. Give d in px to 0.1 px; answers "
              "within three times the matching precision of this pair (3σ_d, from its ground "
              "truth) count as correct.",
    parameters=_moto_params, reference=_moto_disparity, tolerance=_moto_tolerance,
    mistakes=(
        Mistake("sign", "the disparity is u_left − u_right > 0: the point is further left in "
                        "the right image", lambda p: -_moto_disparity(p)),
        Mistake("column", "this is the column u2 in the right image; the disparity is the "
                          "difference u1 − u2", lambda p: p["u_px"] - _moto_disparity(p)),
    ))


def _moto_depth_params(rng):
    p = _moto_base(rng)
    p["d_px"] = round(_moto_disparity(p), 2)
    return {k: p[k] for k in ("u_px", "v_px", "d_px", "f_px", "B_mm", "doffs_px")}


def _moto_depth(p, doffs=True, unit=1.0):
    import photolib as pl
    return pl.depth_from_disparity(p["d_px"], p["f_px"], p["B_mm"] * unit,
                                          p["doffs_px"] if doffs else 0.0)


moto_depth = Exercise(
    params_name="p_moto_depth",
    id="st.moto-depth", points=2, kind="number", answer="Z_moto", scenario="st.moto",
    title="Step 2 of 3: depth from the disparity / Tiefe aus der Disparität",
    statement="The point ({u_px}, {v_px}) of step 1 has the disparity $d = {d_px:.2f}$ px (the "
              "correct result of step 1). The pair's calibration: focal length "
              "$f = {f_px}$ px, base $B = {B_mm}$ mm, $d_{{offs}} = {doffs_px}$ px (the "
              "difference $c_{{x2}} - c_{{x1}}$ of the principal points). Give Z of the point "
              "in mm to 0.1 mm in the course's frame (camera 1 at the origin looking down "
              "−Z, so Z < 0).",
    parameters=_moto_depth_params, reference=_moto_depth, tolerance=PRINTED,
    mistakes=(
        Mistake("doffs", "the parallax in the normal case is x'1 − x'2 reduced to each image's "
                         "principal point: d + doffs, not d alone",
                lambda p: _moto_depth(p, doffs=False)),
        Mistake("sign", "Z = −f·B/(d + doffs) is negative: the camera looks down −Z (the "
                        "distance −Z is positive)", lambda p: -_moto_depth(p)),
        Mistake("units-mm-m", "Z has the unit of B, which is given in mm",
                lambda p: _moto_depth(p, unit=1e-3)),
    ))


def _moto_sigma_params(rng):
    p = _moto_base(rng)
    p["d_px"] = round(_moto_disparity(p), 2)
    p["Z_mm"] = round(_moto_depth(p), 1)
    return {k: p[k] for k in ("u_px", "v_px", "d_px", "Z_mm", "f_px", "B_mm", "doffs_px",
                              "sigma_d_px")}


def _moto_sigma(p, square=True):
    import photolib as pl
    if not square:
        return abs(p["Z_mm"]) / p["f_px"] * p["sigma_d_px"]
    return pl.depth_sigma(p["Z_mm"], p["f_px"], p["B_mm"], p["sigma_d_px"])


moto_sigma = Exercise(
    params_name="p_moto_sigma",
    id="st.moto-sigma", points=2, kind="number", answer="sigma_Z_moto", scenario="st.moto",
    title="Step 3 of 3: accuracy of the depth / Tiefengenauigkeit",
    statement="The point of steps 1–2 lies at $Z = {Z_mm:.1f}$ mm (the correct result of step "
              "2; $d = {d_px:.2f}$ px, $f = {f_px}$ px, $B = {B_mm}$ mm, "
              "$d_{{offs}} = {doffs_px}$ px). The disparities of this pair are measured with "
              "$\\sigma_d = {sigma_d_px:.2f}$ px (the robust spread of the chapter's "
              "measurements about the ground truth). Propagate it: give $\\sigma_Z$ in mm to "
              "0.01 mm.",
    parameters=_moto_sigma_params, reference=_moto_sigma, tolerance=PRINTED,
    mistakes=(
        Mistake("doffs", "|∂Z/∂d| = f·B/(d + doffs)² = Z²/(f·B): doffs belongs in the "
                         "denominator", lambda p: p["f_px"] * p["B_mm"] / p["d_px"]**2
                * p["sigma_d_px"]),
        Mistake("square", "σ_Z grows with the square of the distance: σ_Z = Z²/(f·B)·σ_d; "
                          "Z/f·σ_d is the σ of X or Y (the image scale)",
                lambda p: _moto_sigma(p, square=False)),
    ))


# -- 11–12. scenario st.iro: independent relative orientation, then the model ----------------------
_IRO = ("phi1", "kappa1", "omega2", "phi2", "kappa2")


def _iro_base(rng):
    import photolib as pl
    c = round(float(rng.uniform(20.0, 60.0)), 2)
    angles = rng.uniform(-0.06, 0.06, 5)
    R1, R2 = pl.rotation_opk(0.0, *angles[:2]), pl.rotation_opk(*angles[2:])
    X = np.column_stack([rng.uniform(-0.5, 1.5, 7), rng.uniform(-1.0, 1.0, 7),
                         -rng.uniform(2.5, 3.5, 7)])
    X[:6, :2] = [[-0.3, -0.8], [1.3, -0.8], [-0.3, 0.0], [1.3, 0.1], [-0.3, 0.8], [1.3, 0.8]] \
        + rng.uniform(-0.15, 0.15, (6, 2))
    a = np.round(pl.project(X, np.zeros(3), R1, c), 4)
    b = np.round(pl.project(X, [1.0, 0.0, 0.0], R2, c), 4)
    return {"c_mm": c, "xy1": a[:6].tolist(), "xy2": b[:6].tolist(),
            "P1": a[6].tolist(), "P2": b[6].tolist()}


def _iro_params(rng):
    p = _iro_base(rng)
    return {k: p[k] for k in ("c_mm", "xy1", "xy2")}


def _iro(p, swap=False):
    import photolib as pl
    a, b = (p["xy2"], p["xy1"]) if swap else (p["xy1"], p["xy2"])
    return np.degrees(pl.independent_relative_orientation(a, b, p["c_mm"], bx=-1.0 if swap else 1.0).params)


def _iro_dependent(p):
    import photolib as pl
    ro = pl.relative_orientation(p["xy1"], p["xy2"], p["c_mm"], bx=1.0)
    return np.r_[np.degrees(ro.params[2:]), ro.params[:2]][[3, 4, 0, 1, 2]]


iro = Exercise(
    params_name="p_iro",
    id="st.iro", points=3, kind="array", answer="angles_iro", scenario="st.iro",
    title="Step 1 of 2: independent relative orientation / unabhängige Bildpaare",
    statement="Six corresponding points of a pair (mm, principal points at 0, "
              "$c = {c_mm}$ mm): image 1 `xy1 = {xy1}`, image 2 `xy2 = {xy2}`. Orient the "
              "pair by independent relative orientation: base $b = (1, 0, 0)$, "
              "$R_1 = R_\\varphi(\\varphi_1) R_\\kappa(\\kappa_1)$, "
              "$R_2 = R_\\omega(\\omega_2) R_\\varphi(\\varphi_2) R_\\kappa(\\kappa_2)$, "
              "coplanarity $\\det[b, R_1x^*_1, R_2x^*_2] = 0$ with $x^* = (x', y', -c)$, start "
              "at 0. Give $(\\varphi_1, \\kappa_1, \\omega_2, \\varphi_2, \\kappa_2)$ in "
              "degrees to 0.001° (NumPy array of shape (5,)).",
    parameters=_iro_params, reference=_iro, tolerance=PRINTED, rtol=1e-6, atol=5e-4,
    mistakes=(
        Mistake("swapped", "the images are swapped: image 1 is xy1 (left), image 2 is xy2",
                lambda p: _iro(p, swap=True)),
        Mistake("dependent", "these are the angles of the dependent relative orientation "
                             "(R1 = I, the base free): here both images turn and b = (1, 0, 0)",
                _iro_dependent),
        Mistake("radians", "the angles are asked in degrees, not radians",
                lambda p: np.radians(_iro(p))),
    ))


def _iro_model_params(rng):
    p = _iro_base(rng)
    import photolib as pl
    ang = np.degrees(pl.independent_relative_orientation(p["xy1"], p["xy2"], p["c_mm"],
                                                         bx=1.0).params)
    out = {k: p[k] for k in ("c_mm", "P1", "P2")}
    out.update({f"{n}_deg": round(float(v), 6) for n, v in zip(_IRO, ang)})
    return out


def _iro_model(p, R1_identity=False, transposed=False, base_sign=1.0):
    """Model point of P1, P2; None for a wrong orientation whose rays meet behind a camera."""
    import photolib as pl
    a = np.radians([p[f"{n}_deg"] for n in _IRO])
    R1 = np.eye(3) if R1_identity else pl.rotation_opk(0.0, a[0], a[1])
    R2 = pl.rotation_opk(*a[2:])
    if transposed:
        R1, R2 = R1.T, R2.T
    res = pl.forward_intersection([p["P1"], p["P2"]], [[0, 0, 0], [base_sign, 0, 0]], [R1, R2],
                                  p["c_mm"], return_valid=True)
    return res.points if res.valid else None


iro_model = Exercise(
    params_name="p_iro_model",
    id="st.iro-model", points=2, kind="array", answer="P_model", scenario="st.iro",
    title="Step 2 of 2: model coordinates / Modellkoordinaten",
    statement="The pair of step 1 is oriented (the correct result of step 1): "
              "$\\varphi_1 = {phi1_deg}°$, $\\kappa_1 = {kappa1_deg}°$, "
              "$\\omega_2 = {omega2_deg}°$, $\\varphi_2 = {phi2_deg}°$, "
              "$\\kappa_2 = {kappa2_deg}°$, base $b = (1, 0, 0)$, $c = {c_mm}$ mm. A further "
              "point is measured at `P1 = {P1}` (image 1) and `P2 = {P2}` (image 2), mm. Give "
              "its model coordinates (least-squares forward intersection; image 1 at the "
              "origin, image 2 at b) as a NumPy array of shape (3,), in model units (base = 1) "
              "to 0.0001.",
    parameters=_iro_model_params, reference=_iro_model, tolerance=PRINTED, rtol=1e-6, atol=5e-5,
    mistakes=(
        Mistake("rotation", "image 1 is rotated too in the independent orientation: "
                            "R1 = R_φ(φ1)·R_κ(κ1), not I", lambda p: _iro_model(p, R1_identity=True)),
        Mistake("transposed", hints.MESSAGES["transposed"] + ": the rays are R·x*",
                lambda p: _iro_model(p, transposed=True)),
    ))


EXERCISES = (height, sigma_z, intersection, essential, unknowns, rays, ro_step, moto,
             moto_depth, moto_sigma, iro, iro_model)
