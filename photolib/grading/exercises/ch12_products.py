"""Chapter 12-products: graded exercises on orthophotos, true orthophotos and height models.

* ``prd.relief-displacement`` (number): Δr = r·Δh/H of a tower in a vertical image, in mm;
* ``prd.ortho-to-image`` (function): image coordinates of an ortho pixel on a sloping DTM
  (the first steps of differential rectification);
* ``prd.dtm-accuracy`` (number): the DTM height accuracy an orthophoto tolerance needs;
* ``prd.product`` (choice): which product fits a task;
* ``prd.occluded-length`` (number): the ground hidden behind a building, d·h/(H − h).

Course conventions (docs/conventions.md): ``(kx, ky, N) = Rᵀ(X − X0)``,
``x' = x'0 − c·kx/N``, ``R = R_ω·R_φ·R_κ``, c > 0. References come from
:func:`photolib.relief_displacement`, :func:`photolib.project` and
:mod:`photolib.derive.products`.

>>> [ex.id for ex in EXERCISES]
['prd.relief-displacement', 'prd.ortho-to-image', 'prd.dtm-accuracy', 'prd.product', 'prd.occluded-length']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import aerial_camera

CHAPTER = "12-products"

_MM_M = ("the result is 1000 times off: r is in mm, Δh and H in m, so Δr = r·Δh/H comes out "
         "in mm without any conversion")


# -- 1. relief displacement (number) --------------------------------------------------------------
def _relief_params(rng):
    # drawn again until the foot-formula mistake, Δr·Δh/(H − Δh) off, lies well outside the
    # rounding of the printed Δh and r (0.01 m, 0.01 mm: Δh/H ≥ 0.5 %) and of an answer
    # given to 0.001 mm (≥ 0.0015 mm)
    cam = aerial_camera(rng)
    H = cam["h_m"]
    while True:
        dh = round(float(rng.uniform(10.0, min(150.0, 0.1 * H) + 10.0)), 1)
        r = round(float(rng.uniform(20.0, 110.0)), 2)
        if dh >= 0.005 * H and r * dh * dh / (H * (H - dh)) >= 0.0015:
            return {"c_mm": cam["c_mm"], "H": H, "dh": dh, "r_mm": r}


def _relief(p):
    import photolib as pl
    return pl.relief_displacement(p["r_mm"], p["dh"], p["H"])


relief = Exercise(
    params_name="p_relief",
    id="prd.relief-displacement", points=2, kind="number", answer="dr",
    title="Relief displacement / radiale Versetzung",
    statement="A vertical aerial image (camera constant c = {c_mm:.2f} mm) is taken {H} m above "
              "the ground. The top of a chimney {dh:.2f} m high appears {r_mm:.2f} mm from the "
              "principal point (= nadir point). By how much (in mm, image) is it displaced "
              "radially from its foot?",
    # the rounding of the printed r, Δh, H (Δh and r to 0.01), at least an answer's rounding
    # to 0.001 mm (the old 1e-6 rejected it), kept off the foot-formula mistake
    parameters=_relief_params, reference=_relief, tolerance=PRINTED, atol=5e-4,
    mistakes=(
        Mistake("units-mm-m", _MM_M, lambda p: _relief(p) * 1e-3),
        Mistake("units-mm-m", _MM_M, lambda p: _relief(p) * 1e3),
        Mistake("foot-formula", "r·Δh/(H − Δh) is the form for the radial distance of the "
                                "foot; r here is measured to the displaced top: Δr = r·Δh/H",
                lambda p: p["r_mm"] * p["dh"] / (p["H"] - p["dh"])),
        Mistake("ground", "that is the displacement on the ground (Δr·H/c, in m); the task "
                          "asks for Δr in the image, in mm",
                lambda p: _relief(p) * p["H"] / p["c_mm"]),
    ))




# -- 2. ortho pixel → image coordinates (function) ------------------------------------------------
_ANGLES = ("omega_deg", "phi_deg", "kappa_deg")


def _ortho_params(rng):
    cam = aerial_camera(rng)
    return {"c_mm": cam["c_mm"], "X0": round(float(rng.uniform(1000.0, 5000.0)), 2),
            "Y0": round(float(rng.uniform(1000.0, 5000.0)), 2),
            "Z0": round(float(rng.uniform(100.0, 400.0)) + cam["h_m"], 2),
            "omega_deg": round(float(rng.uniform(-3.0, 3.0)), 3),
            "phi_deg": round(float(rng.uniform(-3.0, 3.0)), 3),
            "kappa_deg": round(float(rng.uniform(0.0, 360.0)), 3),
            "a": round(float(rng.uniform(100.0, 400.0)), 2),
            "b": round(float(rng.uniform(-0.08, 0.08)), 4),
            "d": round(float(rng.uniform(-0.08, 0.08)), 4), "h_m": cam["h_m"]}


def _ortho_function(transpose=False, flat=False, c_sign=1.0):
    def make(p):
        import photolib as pl
        R = pl.rotation_opk(*[math.radians(p[n]) for n in _ANGLES])
        R = R.T if transpose else R
        X0 = np.array([p["X0"], p["Y0"], p["Z0"]])

        def image_point(X, Y):
            Z = 0.0 if flat else p["a"] + p["b"] * (X - p["X0"]) + p["d"] * (Y - p["Y0"])
            return c_sign * pl.project(np.array([float(X), float(Y), float(Z)]), X0, R, p["c_mm"])
        return image_point
    return make


def _ortho_cases(rng, p):
    reach = 0.3 * p["h_m"]
    return [(round(p["X0"] + float(rng.uniform(-reach, reach)), 2),
             round(p["Y0"] + float(rng.uniform(-reach, reach)), 2)) for _ in range(6)]


ortho_to_image = Exercise(
    params_name="p_ortho",
    id="prd.ortho-to-image", points=3, kind="function", answer="image_point",
    title="Ortho pixel → image point (differentielle Entzerrung, indirect)",
    statement="An aerial image has c = {c_mm} mm, no distortion, principal point at the "
              "origin, projection centre X0 = ({X0}, {Y0}, {Z0}) m and ω = {omega_deg}°, "
              "φ = {phi_deg}°, κ = {kappa_deg}° (R = R_ω·R_φ·R_κ). The DTM is the plane "
              "Z = {a} + {b}·(X − {X0}) + {d}·(Y − {Y0}) m. Write image_point(X, Y) returning "
              "the image coordinates (x', y') in mm (NumPy array of shape (2,)) of the ortho "
              "pixel whose centre lies at plan position (X, Y) — the point the indirect "
              "differential rectification takes its grey value from.",
    parameters=_ortho_params, reference=_ortho_function(), tolerance=PRINTED, cases=_ortho_cases,
    # 1 µm: float32 loses up to 0.13 µm (X ≈ 5000 m); the old 1e-7 mm rejected float32 and
    # coordinates rounded to 0.1 µm
    rtol=0.0, atol=1e-3,
    mistakes=(
        Mistake("flat", "the height of the ortho pixel is missing: take Z from the DTM at "
                        "(X, Y), not Z = 0 (that is a plane rectification)",
                _ortho_function(flat=True)),
        Mistake("transposed", "R was used where Rᵀ belongs: (kx, ky, N) = Rᵀ(X − X0)",
                _ortho_function(transpose=True)),
        Mistake("sign-c", "the sign is reversed: x' = −c·kx/N with c > 0 (and N < 0 in front "
                          "of the camera)", _ortho_function(c_sign=-1.0)),
    ))


# -- 3. DTM accuracy for an orthophoto tolerance (number) -----------------------------------------
_FORMATS = {"230 mm × 230 mm (film)": (115.0, 115.0), "68.4 mm × 104 mm (digital, DMC-like)":
            (34.2, 52.0), "53.4 mm × 40 mm (digital, medium format)": (26.7, 20.0)}


def _dtm_params(rng):
    cam = aerial_camera(rng)
    fmt = str(rng.choice(list(_FORMATS)))
    return {"c_mm": cam["c_mm"], "format": fmt, "tol_m": round(float(rng.uniform(0.1, 1.0)), 2)}


def _dtm_accuracy(p, radius=None):
    a, b = _FORMATS[p["format"]]
    r = math.hypot(a, b) if radius is None else radius(a, b)
    return p["tol_m"] * p["c_mm"] / r


dtm_accuracy = Exercise(
    params_name="p_dtm",
    id="prd.dtm-accuracy", points=2, kind="number", answer="dZ",
    title="How good must the DTM be? (Genauigkeit des DGM)",
    statement="An orthophoto is made from vertical images with c = {c_mm} mm and the format "
              "{format}. Its points may be misplaced by at most {tol_m} m anywhere in the image "
              "(first order: a height error dZ moves a point by dZ·r/c, r its radial image "
              "distance). What height error dZ (in m) may the DTM have at most?",
    # the rounding of the printed c and dZ to the mm (the old 1e-6 rejected dZ to 0.001 m);
    # not the rounding of the tolerance (up to 5 %), which would merge the inverted and
    # full-diagonal mistakes where c ≈ √2·r (88 mm, DMC format)
    parameters=_dtm_params, reference=_dtm_accuracy, tolerance=PRINTED, atol=5e-4,
    exact=("tol_m",),
    mistakes=(
        Mistake("half-side", "the largest r is at the corner of the format: half the "
                             "diagonal, not half a side",
                lambda p: _dtm_accuracy(p, lambda a, b: max(a, b))),
        Mistake("full-diagonal", "r is measured from the principal point: half the diagonal, "
                                 "not the whole diagonal",
                lambda p: _dtm_accuracy(p, lambda a, b: 2 * math.hypot(a, b))),
        Mistake("inverted", "dZ = ΔR·c/r_max: the ratio is inverted",
                lambda p: p["tol_m"] * math.hypot(*_FORMATS[p["format"]]) / p["c_mm"]),
    ))




# -- 4. which product (choice) --------------------------------------------------------------------
_PRODUCTS = {
    "a": "orthophoto on the DTM (Orthophoto)",
    "b": "true orthophoto on the DSM (True-Orthophoto)",
    "c": "plane rectification of a single image (ebene Entzerrung)",
    "d": "digital surface model (DSM / DOM)",
    "e": "image mosaic (Bildmosaik) with seamlines",
}
_TASKS = (
    ("the roof outlines of the buildings of a dense city centre must be digitised at their "
     "true plan positions, roofs and streets at one scale, from a block of overlapping "
     "images", "b", "a",
     "an orthophoto on the DTM leaves the roofs displaced by the relief displacement; only "
     "a true orthophoto on the DSM puts them on their footprints, the ground one image "
     "cannot see filled from the overlapping images"),
    ("a flat, almost plane façade is to be measured from one image with four control points",
     "c", "a", "for a plane object plane rectification is exact and needs no height model"),
    ("a map base of open, hilly farmland without buildings, at constant scale", "a", "c",
     "plane rectification ignores the hills: each point is misplaced by its relief "
     "displacement; an orthophoto on the DTM removes it"),
    ("the heights of roofs and tree tops are needed to plan radio links", "d", "b",
     "a true orthophoto is a picture at constant scale; heights of roofs and trees are in "
     "the surface model"),
)


def _product_params(rng):
    i = int(rng.integers(len(_TASKS)))
    return {"task": _TASKS[i][0], "i": i,
            "options": "; ".join(f"({k}) {v}" for k, v in _PRODUCTS.items())}


def _product_mistake(n):
    """Mistake rule of task n: the distractor, for students who got task n."""
    def wrong(p):
        return _TASKS[n][2] if p["i"] == n else None
    return Mistake(f"product-{n}", _TASKS[n][3], wrong)


product = Exercise(
    params_name="p_product",
    id="prd.product",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_product",
    title="Which product? (Welches Produkt?)",
    statement="Task: {task}. Which product fits best? {options}. Set the answer to the letter.",
    parameters=_product_params, reference=lambda p: _TASKS[p["i"]][1], choices=_PRODUCTS,
    mistakes=tuple(_product_mistake(n) for n in range(len(_TASKS))))


# -- 5. occluded length behind a building (number) ------------------------------------------------
def _occluded_params(rng):
    cam = aerial_camera(rng)
    H = min(max(cam["h_m"], 300.0), 1500.0)
    # drawn again until the relief-formula mistake (L·h/H off) lies well outside an answer
    # given to 0.001 m
    while True:
        h = round(float(rng.uniform(8.0, 60.0)), 1)
        d = round(float(rng.uniform(50.0, 400.0)), 1)
        if d * h * h / (H * (H - h)) >= 0.0015:
            return {"H": H, "h": h, "d": d}


def _occluded(p):
    return p["d"] * p["h"] / (p["H"] - p["h"])


occluded = Exercise(
    params_name="p_occluded",
    id="prd.occluded-length", points=2, kind="number", answer="L",
    title="Hidden ground behind a building (sichttote Fläche)",
    statement="A vertical image is taken {H} m above flat ground. The far wall of a building "
              "{h:.2f} m high (flat roof) stands {d:.2f} m (plan distance) from the nadir point, facing "
              "away from it. How long (in m, on the ground, along the radial direction) is "
              "the strip behind the wall that the image cannot see?",
    # the rounding of the printed H, h, d (h and d to 0.01 m), at least an answer's rounding
    # to 0.001 m (the old 1e-6 rejected it)
    parameters=_occluded_params, reference=_occluded, tolerance=PRINTED, atol=5e-4,
    mistakes=(
        Mistake("relief-formula", "d·h/H is too short: the ray over the roof edge (d, h) "
                                  "reaches the ground at d·H/(H − h), so L = d·h/(H − h)",
                lambda p: p["d"] * p["h"] / p["H"]),
        Mistake("total", "that is the distance of the end of the strip from the nadir point, "
                         "d·H/(H − h); the strip itself is d·h/(H − h)",
                lambda p: p["d"] * p["H"] / (p["H"] - p["h"])),
    ))



EXERCISES = (relief, ortho_to_image, dtm_accuracy, product, occluded)
