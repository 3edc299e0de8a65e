"""Chapter 12-products: graded exercises on orthophotos, true orthophotos and height models.

* ``prd.relief-displacement`` (number): Δr = r·Δh/H of a tower in a vertical image, in mm;
* ``prd.ortho-to-image`` (function): image coordinates of an ortho pixel on a sloping DTM
  (the first steps of differential rectification);
* ``prd.dtm-accuracy`` (number): the DTM height accuracy an orthophoto tolerance needs;
* ``prd.product`` (choice): which product fits a task;
* ``prd.occluded-length`` (number): the ground hidden behind a building, d·h/(H − h);
* ``prd.diff-rect`` (function): differential rectification of a small grid, raising
  ``ValueError`` for a cell behind the camera or outside the image;
* scenario ``prd.cell-height`` (3 steps): one ortho cell — DTM height, image point, grey value;
* scenario ``prd.tie-affine`` (3 steps, real aerial images ``photolib.data.mosaic()``): an
  affine transformation from ORB tie points, the residual of another tie point, and a ground
  point found in the other image, accepted within 3√2·σ of ORB's measurement.

Course conventions (docs/conventions.md): ``(kx, ky, N) = Rᵀ(X − X0)``,
``x' = x'0 − c·kx/N``, ``R = R_ω·R_φ·R_κ``, c > 0. References come from
:func:`photolib.relief_displacement`, :func:`photolib.project` and
:mod:`photolib.derive.products`.

>>> [ex.id for ex in EXERCISES][5:]
['prd.diff-rect', 'prd.cell-height', 'prd.cell-image', 'prd.cell-grey', 'prd.tie-affine', 'prd.tie-residual', 'prd.tie-point']
"""

from __future__ import annotations

import functools
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



# -- 6. differential rectification of a small grid (function, with degenerate cases) -------------
_DR_SIZE = (80, 60)          # image width, height (px)


def _dr_params(rng):
    return {"c_mm": round(float(rng.uniform(40.0, 60.0)), 2), "pixel_mm": 0.05,
            "x0_mm": round(float(rng.uniform(-0.2, 0.2)), 3),
            "y0_mm": round(float(rng.uniform(-0.2, 0.2)), 3),
            # the projection centre near (500, 500) and tilts within ±0.1°, so that the
            # public test grid below lies in the small image of every variant (the variant
            # count runs one student's inputs through all variants' references)
            "X0": round(float(rng.uniform(499.5, 500.5)), 2),
            "Y0": round(float(rng.uniform(499.5, 500.5)), 2),
            "Z0": round(float(rng.uniform(180.0, 260.0)), 2),
            "omega_deg": round(float(rng.uniform(-0.1, 0.1)), 3),
            "phi_deg": round(float(rng.uniform(-0.1, 0.1)), 3),
            "kappa_deg": round(float(rng.uniform(0.0, 360.0)), 3),
            "width": _DR_SIZE[0], "height": _DR_SIZE[1]}


def _dr_function(transpose=False, swap=False, constant_n=False, no_pp=False):
    def make(p):
        import photolib as pl
        from photolib.orthophoto import DTM, FrameCamera
        from photolib.rectify import sample_image
        R = pl.rotation_opk(*[math.radians(p[n]) for n in _ANGLES])
        R = R.T if transpose else R
        X0 = np.array([p["X0"], p["Y0"], p["Z0"]])
        x0, y0 = (0.0, 0.0) if no_pp else (p["x0_mm"], p["y0_mm"])
        cam = FrameCamera(X0, R, p["c_mm"], p["width"], p["height"], p["pixel_mm"], x0, y0)

        def orthophoto(image, heights, origin, spacing):
            img = np.asarray(image, dtype=float)
            Z = np.asarray(heights, dtype=float)
            if Z.shape[0] < 2 or Z.shape[1] < 2:
                raise ValueError(f"heights has shape {Z.shape}; expected at least 2 × 2 cells")
            dtm = DTM(Z, origin, spacing)
            if constant_n:
                # the mistake: one scale c/H for every point instead of each point's own N
                XY = pl.rectify.output_grid(Z.shape, origin, spacing)
                XYZ = np.concatenate([XY, Z[..., None]], -1).reshape(-1, 3)
                k = (XYZ - X0) @ R
                N = -p["Z0"]                       # the flying height above the datum
                xy = np.column_stack([x0 - p["c_mm"] * k[:, 0] / N, y0 - p["c_mm"] * k[:, 1] / N])
                cr = pl.pixel_from_image(xy, p["width"], p["height"], p["pixel_mm"])
                cr = cr.reshape(Z.shape + (2,))
            else:
                cr, _ = pl.ortho_pixel_positions(cam, dtm, Z.shape, origin, spacing)
            if swap:
                cr = cr[..., ::-1]
            W, H = p["width"], p["height"]
            out = (cr[..., 0] < 0) | (cr[..., 0] > W - 1) | (cr[..., 1] < 0) | (cr[..., 1] > H - 1)
            if out.any():
                r, c = (int(v) for v in np.argwhere(out)[0])
                raise ValueError(f"ground cell (row {r}, col {c}) falls outside the image at "
                                 f"(col, row) = {cr[r, c].round(2).tolist()}")
            return sample_image(img, cr)
        return orthophoto
    return make


def _dr_cases(rng, p):
    cols, rows = np.meshgrid(np.arange(p["width"]), np.arange(p["height"]))
    a, b = rng.uniform(0, 2 * np.pi, 2)
    image = np.round(110 + 60 * np.sin(cols / 9.0 + a) * np.cos(rows / 7.0 + b) + 0.4 * cols, 1)
    gsd = p["pixel_mm"] * (p["Z0"] - 20.0) / p["c_mm"]
    spacing = round(0.8 * gsd, 2)
    shape = (5, 6)
    # the grid some 10 px beside the image centre (0.35 of the half height of the footprint),
    # on ground 15–45 m above the datum (so that one N for all points is visibly wrong)
    half = 0.5 * (p["height"] - 1) * p["pixel_mm"] * (p["Z0"] - 30.0) / p["c_mm"]
    origin = (round(p["X0"] + 0.35 * half - 2.5 * spacing, 2),
              round(p["Y0"] + 2.0 * spacing, 2))
    g0 = float(rng.uniform(15.0, 35.0))
    ci, ri = np.meshgrid(np.arange(shape[1]), np.arange(shape[0]))
    plane = np.round(g0 + 1.6 * ci - 1.0 * ri, 2)
    noisy = np.round(plane + rng.normal(0.0, 0.5, shape), 2)
    far = (round(origin[0] + 40.0 * gsd * 10, 2), origin[1])
    above = np.full(shape, round(p["Z0"] + 10.0, 2))
    return [(image, plane, origin, spacing), (image, noisy, origin, spacing),
            (image, plane, far, spacing), (image, above, origin, spacing)]


diff_rect = Exercise(
    params_name="p_diffrect",
    id="prd.diff-rect", points=4, kind="function", answer="orthophoto",
    title="Differential rectification of a small grid (differentielle Entzerrung)",
    statement="A small aerial image of {width} × {height} pixels of {pixel_mm} mm has "
              "$c = {c_mm:.2f}$ mm, principal point $x'_0 = {x0_mm:.3f}$ mm, "
              "$y'_0 = {y0_mm:.3f}$ mm, no distortion, projection centre "
              "$X_0 = ({X0:.2f}, {Y0:.2f}, {Z0:.2f})$ m and $\\omega = {omega_deg:.3f}°$, "
              "$\\varphi = {phi_deg:.3f}°$, $\\kappa = {kappa_deg:.3f}°$ "
              "($R = R_\\omega R_\\varphi R_\\kappa$). Pixel (col, row) has (0, 0) at the centre "
              "of the top-left pixel, $x' = (col - (W-1)/2)\\cdot s$, "
              "$y' = ((H-1)/2 - row)\\cdot s$. Write `orthophoto(image, heights, origin, "
              "spacing)`: `image` is the (H, W) array of grey values, `heights` a (rows, cols) "
              "array of the ground heights Z (m) of the ortho cells, `origin` = (X, Y) of the "
              "centre of the top-left cell, cell (col, row) at $X = X_{{orig}} + col\\cdot Δ$, "
              "$Y = Y_{{orig}} - row\\cdot Δ$ with Δ = `spacing`. Return the (rows, cols) "
              "array of grey values, each by bilinear interpolation at the cell's image "
              "position (collinearity, then pixel). If a cell's ground point is behind the "
              "camera or its image position is outside the image (col outside [0, W − 1] or "
              "row outside [0, H − 1]), raise a `ValueError` naming the cell.",
    parameters=_dr_params, reference=_dr_function(), cases=_dr_cases, tolerance=PRINTED,
    rtol=1e-6, atol=1e-6, exact=("pixel_mm",),
    mistakes=(
        Mistake("transposed", "R was used where Rᵀ belongs: (kx, ky, N) = Rᵀ(X − X0)",
                _dr_function(transpose=True)),
        Mistake("swapped", "col and row are swapped: the grey value of image position "
                           "(col, row) is image[row, col]; bilinear interpolation needs col "
                           "along the columns", _dr_function(swap=True)),
        Mistake("constant-N", "each ground point has its own N = r₃ᵀ(X − X0): divide kx and "
                              "ky by the N of that point, not by one flying height Z0 for all",
                _dr_function(constant_n=True)),
        Mistake("principal-point", "the principal point is missing: x' = x'0 − c·kx/N, "
                                   "y' = y'0 − c·ky/N", _dr_function(no_pp=True)),
    ))


# -- 7. scenario: one ortho cell step by step (three steps) ---------------------------------------
def _cell_params(rng):
    import photolib as pl
    # drawn again until the swapped and nearest-neighbour mistakes lie well away from the
    # answers (Z by ≥ 0.05 m, the grey value by ≥ 2)
    while True:
        p = _dr_params(rng)
        d = 2.0
        XA = round(p["X0"] + float(rng.uniform(-3, 3)), 1)
        YA = round(p["Y0"] + float(rng.uniform(-2, 2)), 1)
        Zc = [round(float(rng.uniform(5.0, 30.0)), 2) for _ in range(4)]   # Z00 Z10 Z01 Z11
        u, v = round(float(rng.uniform(0.1, 0.9)), 3), round(float(rng.uniform(0.1, 0.9)), 3)
        X, Y = round(XA + u * d, 3), round(YA - v * d, 3)
        Z = (1 - u) * (1 - v) * Zc[0] + u * (1 - v) * Zc[1] + (1 - u) * v * Zc[2] + u * v * Zc[3]
        Z = round(Z, 3)
        R = pl.rotation_opk(*[math.radians(p[n]) for n in _ANGLES])
        xy = pl.project(np.array([X, Y, Z]), np.array([p["X0"], p["Y0"], p["Z0"]]), R,
                        p["c_mm"], p["x0_mm"], p["y0_mm"])
        xs, ys = round(float(xy[0]), 4), round(float(xy[1]), 4)
        g = [round(float(rng.uniform(20, 230)), 0) for _ in range(4)]
        q = dict(p, XA=XA, YA=YA, d=d, Z00=Zc[0], Z10=Zc[1], Z01=Zc[2], Z11=Zc[3], X=X, Y=Y,
                 x_img=xs, y_img=ys, g00=g[0], g10=g[1], g01=g[2], g11=g[3])
        if (abs(_cell_height(q, True) - _cell_height(q)) >= 0.05
                and abs(_cell_grey(q, swap=True) - _cell_grey(q)) >= 2.0
                and abs(_cell_grey(q, nearest=True) - _cell_grey(q)) >= 2.0):
            break
    p.update({"XA": XA, "YA": YA, "d": d, "Z00": Zc[0], "Z10": Zc[1], "Z01": Zc[2],
              "Z11": Zc[3], "X": X, "Y": Y, "Z": Z, "x_img": xs, "y_img": ys,
              "g00": g[0], "g10": g[1], "g01": g[2], "g11": g[3]})
    return p


def _cell_height(p, swap=False):
    u = (p["X"] - p["XA"]) / p["d"]
    v = (p["YA"] - p["Y"]) / p["d"]
    if swap:
        u, v = v, u
    return ((1 - u) * (1 - v) * p["Z00"] + u * (1 - v) * p["Z10"] + (1 - u) * v * p["Z01"]
            + u * v * p["Z11"])


def _cell_image(p, transpose=False, no_pp=False):
    import photolib as pl
    R = pl.rotation_opk(*[math.radians(p[n]) for n in _ANGLES])
    R = R.T if transpose else R
    x0, y0 = (0.0, 0.0) if no_pp else (p["x0_mm"], p["y0_mm"])
    return pl.project(np.array([p["X"], p["Y"], p["Z"]]), np.array([p["X0"], p["Y0"], p["Z0"]]),
                      R, p["c_mm"], x0, y0)


def _cell_grey(p, swap=False, nearest=False):
    import photolib as pl
    col, row = pl.pixel_from_image(np.array([p["x_img"], p["y_img"]]), p["width"], p["height"],
                                   p["pixel_mm"])
    u, v = col - math.floor(col), row - math.floor(row)
    if swap:
        u, v = v, u
    if nearest:
        u, v = round(u), round(v)
    return ((1 - u) * (1 - v) * p["g00"] + u * (1 - v) * p["g10"] + (1 - u) * v * p["g01"]
            + u * v * p["g11"])


_CELL_CAMERA = ("The image ({width} × {height} pixels of {pixel_mm} mm) has $c = {c_mm:.2f}$ mm, "
                "$x'_0 = {x0_mm:.3f}$ mm, $y'_0 = {y0_mm:.3f}$ mm, projection centre "
                "$X_0 = ({X0:.2f}, {Y0:.2f}, {Z0:.2f})$ m, $\\omega = {omega_deg:.3f}°$, "
                "$\\varphi = {phi_deg:.3f}°$, $\\kappa = {kappa_deg:.3f}°$ "
                "($R = R_\\omega R_\\varphi R_\\kappa$, no distortion). ")

cell_height = Exercise(
    params_name="p_cell_z", scenario="prd.cell-height",
    id="prd.cell-height", points=1, kind="number", answer="Z_cell",
    title="Step 1 of 3: the height of an ortho cell from the DTM",
    statement="An ortho cell's centre lies at $X = {X:.3f}$ m, $Y = {Y:.3f}$ m. It lies in "
              "the DTM mesh whose top-left node is at $({XA:.1f}, {YA:.1f})$ m, mesh width "
              "{d} m (X to the right, Y up, so the rows go down): heights "
              "$Z_{{00}} = {Z00:.2f}$ (top left), $Z_{{10}} = {Z10:.2f}$ (top right), "
              "$Z_{{01}} = {Z01:.2f}$ (bottom left), $Z_{{11}} = {Z11:.2f}$ m (bottom right). "
              "Interpolate $Z(X, Y)$ bilinearly, in m to 0.001 m.",
    parameters=_cell_params, reference=_cell_height, tolerance=PRINTED, atol=5e-4,
    # the mesh's node and the cell centre are grid positions, exact as printed
    exact=("d", "XA", "YA", "X", "Y"),
    mistakes=(
        Mistake("swapped", "u belongs to X (along the columns) and v to Y (down the rows): "
                           "u = (X − X_A)/Δ, v = (Y_A − Y)/Δ", lambda p: _cell_height(p, True)),
    ))

cell_image = Exercise(
    params_name="p_cell_xy", scenario="prd.cell-height",
    id="prd.cell-image", points=2, kind="array", answer="xy_cell",
    title="Step 2 of 3: the ortho cell in the image (collinearity)",
    statement=_CELL_CAMERA + "The ortho cell's ground point is $(X, Y, Z) = ({X:.3f}, {Y:.3f}, "
              "{Z:.3f})$ m (Z from step 1). Compute its image coordinates $(x', y')$ in mm to "
              "0.001 mm as an array of shape (2,).",
    parameters=_cell_params, reference=_cell_image, tolerance=PRINTED, atol=5e-4,
    exact=("pixel_mm",),
    mistakes=(
        Mistake("transposed", "R was used where Rᵀ belongs: (kx, ky, N) = Rᵀ(X − X0)",
                lambda p: _cell_image(p, transpose=True)),
        Mistake("principal-point", "the principal point is missing: x' = x'0 − c·kx/N",
                lambda p: _cell_image(p, no_pp=True)),
    ))

cell_grey = Exercise(
    params_name="p_cell_g", scenario="prd.cell-height",
    id="prd.cell-grey", points=2, kind="number", answer="g_cell",
    title="Step 3 of 3: the grey value by bilinear interpolation",
    statement="The image has {width} × {height} pixels of {pixel_mm} mm; pixel (col, row) has "
              "(0, 0) at the centre of the top-left pixel, $x' = (col - (W-1)/2)\\cdot s$, "
              "$y' = ((H-1)/2 - row)\\cdot s$. The ortho cell's image point is "
              "$(x', y') = ({x_img:.4f}, {y_img:.4f})$ mm (step 2). The four pixels around it, "
              "at (⌊col⌋, ⌊row⌋), (⌊col⌋ + 1, ⌊row⌋), (⌊col⌋, ⌊row⌋ + 1), "
              "(⌊col⌋ + 1, ⌊row⌋ + 1), have the grey values {g00:.0f}, {g10:.0f}, {g01:.0f}, "
              "{g11:.0f}. What grey value does the ortho cell get by bilinear interpolation "
              "(to 0.01)?",
    parameters=_cell_params, reference=_cell_grey, tolerance=PRINTED, atol=5e-3,
    exact=("pixel_mm", "g00", "g10", "g01", "g11"),
    mistakes=(
        Mistake("swapped", "the fraction u of the column weighs the right-hand pixels, v of "
                           "the row the lower ones", lambda p: _cell_grey(p, swap=True)),
        Mistake("nearest", "that is the nearest neighbour; bilinear interpolation weighs all "
                           "four pixels by (1 − u)(1 − v), u(1 − v), (1 − u)v, uv",
                lambda p: _cell_grey(p, nearest=True)),
    ))


# -- 8. scenario on the real aerial images: a tie point of a mosaic pair (two steps) --------------
_TIE_PAIRS = tuple((k, k + 1) for k in range(9))   # aerial2-001…010, consecutive pairs


@functools.lru_cache(maxsize=16)
def _tie_data(pair):
    """ORB tie points (inliers of photolib's projective RANSAC fit) of a reduced pair."""
    from photolib import image_mosaic as im
    from photolib.nb import products_real as pr
    a, b = pr.aerial_images(pair)
    q, p_ = pr.measure_tie_points(a, b)            # q in image k, p in image k + 1
    fit = im.fit_pair(p_, q, model="projective", threshold=pr.THRESHOLD, rng=sum(pair))
    return p_[fit.inliers], q[fit.inliers], fit


def _tie_params(rng):
    k = int(rng.integers(len(_TIE_PAIRS)))
    pair = _TIE_PAIRS[k]
    p_, q, fit = _tie_data(pair)
    # the seventh, checked point: one whose residual is at least 0.1 px in each coordinate,
    # so that the sign mistake (−v) lies well outside an answer rounded to 0.01 px
    v = fit.transform(p_) - q
    big = np.flatnonzero(np.all(np.abs(v) >= 0.1, axis=1))
    sel = rng.choice(len(p_), 6, replace=False)
    sel = np.r_[sel, rng.choice(np.setdiff1d(big, sel))]
    k3 = int(rng.choice(np.setdiff1d(np.arange(len(p_)), sel)))    # step 3's point
    src = [[round(float(v), 1) for v in p_[i]] for i in sel[:6]]
    dst = [[round(float(v), 1) for v in q[i]] for i in sel[:6]]
    T = fit.transform
    # 7 significant digits: they move T(p) by < 1e-4 px here (the answer is asked to 0.01 px),
    # and the estimate's last digits (10th and beyond) are rounding that changes with the CPU
    par = [float(f"{T.params[n]:.7g}") for n in ("a0", "a1", "a2", "b0", "b1", "b2", "c1", "c2")]
    return {"i": pair[0] + 1, "j": pair[1] + 1, "src": src, "dst": dst, "H": par,
            "pc": round(float(p_[sel[6], 0]), 2), "pr": round(float(p_[sel[6], 1]), 2),
            "qc": round(float(q[sel[6], 0]), 2), "qr": round(float(q[sel[6], 1]), 2),
            "pc3": round(float(p_[k3, 0]), 2), "pr3": round(float(p_[k3, 1]), 2), "k3": k3,
            "sigma_px": 0.7}


def _tie_affine(p, inverse=False):
    src, dst = np.array(p["src"]), np.array(p["dst"])
    if inverse:
        src, dst = dst, src
    A = np.column_stack([np.ones(len(src)), src])
    a = np.linalg.lstsq(A, dst[:, 0], rcond=None)[0]
    b = np.linalg.lstsq(A, dst[:, 1], rcond=None)[0]
    return np.r_[a, b]


def _tie_projective(p):
    import photolib as pl
    return pl.ProjectiveTransform(*p["H"])


def _tie_residual(p, sign=1.0, inverse=False):
    T = _tie_projective(p)
    pt, qt = np.array([p["pc"], p["pr"]]), np.array([p["qc"], p["qr"]])
    if inverse:
        return sign * (T.inverse(qt[None])[0] - pt)
    return sign * (T(pt[None])[0] - qt)


tie_affine = Exercise(
    params_name="p_tie_affine", scenario="prd.tie-affine",
    id="prd.tie-affine", points=2, kind="array", answer="affine",
    title="Step 1 of 3: an affine transformation from real tie points",
    statement="ORB measured these tie points in the real aerial images aerial2-{j:03d} "
              "(source, pixels (col, row) of the image reduced 2 × 2) and aerial2-{i:03d} "
              "(target): source {src}, target {dst}. Estimate by least squares the affine "
              "transformation source → target, $col' = a_0 + a_1\\,col + a_2\\,row$, "
              "$row' = b_0 + b_1\\,col + b_2\\,row$, as an array "
              "$(a_0, a_1, a_2, b_0, b_1, b_2)$ of shape (6,), to 4 significant digits.",
    parameters=_tie_params, reference=_tie_affine, tolerance=PRINTED, rtol=1e-4, atol=1e-3,
    exact=("sigma_px",),
    mistakes=(
        Mistake("inverse", "that is the transformation target → source: the source points are "
                           "the ones transformed", lambda p: _tie_affine(p, inverse=True)),
    ))

tie_residual = Exercise(
    params_name="p_tie_res", scenario="prd.tie-affine",
    id="prd.tie-residual", points=2, kind="array", answer="v_tie",
    title="Step 2 of 3: the residual of a tie point under the projective transformation",
    statement="photolib's RANSAC fit on all tie points of the pair aerial2-{j:03d} → "
              "aerial2-{i:03d} (reduced images) is the projective transformation (Luhmann "
              "2.18) $col' = (a_0 + a_1 col + a_2 row)/(1 + c_1 col + c_2 row)$, "
              "$row' = (b_0 + b_1 col + b_2 row)/(1 + c_1 col + c_2 row)$ with "
              "$(a_0, a_1, a_2, b_0, b_1, b_2, c_1, c_2)$ = {H}. Another tie point was measured "
              "at $p = ({pc:.2f}, {pr:.2f})$ in the source and at $q = ({qc:.2f}, {qr:.2f})$ in the "
              "target image. Give its residual "
              "$v = T(p) - q$ (px) as an array of shape (2,), to 0.01 px. (ORB measures to "
              "about σ = {sigma_px} px per coordinate: |v| should be a few tenths of a pixel "
              "to about 2 px.)",
    parameters=_tie_params, reference=_tie_residual, tolerance=PRINTED, atol=5e-3,
    exact=("sigma_px",),
    mistakes=(
        Mistake("sign", "the residual is the transformed minus the measured point, "
                        "v = T(p) − q", lambda p: _tie_residual(p, sign=-1.0)),
    ))


def _tie_point(p, inverse=False, swap=False):
    """Where ORB measured the ground point of step 3 in the target image (col, row), px."""
    if inverse:
        return _tie_projective(p).inverse(np.array([[p["pc3"], p["pr3"]]]))[0]
    if swap:
        return _tie_projective(p)(np.array([[p["pr3"], p["pc3"]]]))[0]
    _, q, _ = _tie_data(_TIE_PAIRS[p["i"] - 1])
    return np.array(q[p["k3"]], dtype=float)


#: 3σ of the difference of two ORB measurements (σ = 0.7 px per coordinate, measured on a
#: known warp of these images in chapter 12 and tests/test_real_mosaic.py): √2·3·0.7 ≈ 3 px
_TIE_ATOL = 3.0

tie_point = Exercise(
    params_name="p_tie_pt", scenario="prd.tie-affine",
    id="prd.tie-point", points=2, kind="array", answer="q_tie",
    title="Step 3 of 3: find a ground point in the other image",
    statement="In the reduced aerial image aerial2-{j:03d} a ground point is seen at "
              "$p = ({pc3:.2f}, {pr3:.2f})$ (col, row, px). Where is it in aerial2-{i:03d}? "
              "Give $(col, row)$ in px as an array of shape (2,): transform it with the "
              "projective transformation of step 2, or measure it yourself in the images "
              "(`photolib.data.mosaic()`, reduced by a 2 × 2 block mean). It is compared with "
              "where ORB measured it and accepted within 3 px: three times the standard "
              "deviation of the difference of two measurements of σ = {sigma_px} px each "
              "(3·√2·σ).",
    parameters=_tie_params, reference=_tie_point, rtol=0.0, atol=_TIE_ATOL,
    exact=("sigma_px",),
    mistakes=(
        Mistake("inverse", "that is the inverse transformation: the projective transformation "
                           "of step 2 maps the source image into the target",
                lambda p: _tie_point(p, inverse=True)),
        Mistake("swapped", "col and row are swapped: the transformation takes (col, row)",
                lambda p: _tie_point(p, swap=True)),
    ))


EXERCISES = (relief, ortho_to_image, dtm_accuracy, product, occluded, diff_rect,
             cell_height, cell_image, cell_grey, tie_affine, tie_residual, tie_point)
