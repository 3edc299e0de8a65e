"""Chapter 02-optics: graded exercises on the optics of the camera.

* ``opt.image-distance`` (number): image distance a' of a thin lens (mm; a given in m);
* ``opt.depth-of-field`` (array): near limit, far limit and depth of field (m), with the
  lecture summary's printed-wrong t formula (``de-summary:depth-of-field-t``) recognised;
* ``opt.airy-radius`` (number): radius of the Airy disk 1.22·λ·k in µm (λ given in nm);
* ``opt.snell`` (number): angle of refraction in degrees;
* ``opt.vignetting-corner`` (number): natural vignetting cos⁴τ at the corner of the format;
* ``opt.dof-limit`` (expression): a depth-of-field limit or the depth, derived with SymPy;
* ``opt.stop-down`` (choice): what stopping down does to depth of field and diffraction;
* ``opt.grating-order`` and ``opt.grating-highest`` (numbers, two steps of one scenario): the
  direction of a grating's order m, and the highest order that exists;
* ``opt.edge-fringe`` (number): the first bright fringe behind a straight edge, in µm.

References come from :mod:`photolib.optics` and :mod:`photolib.derive.optics`.

>>> [ex.id for ex in EXERCISES]  # doctest: +NORMALIZE_WHITESPACE
['opt.image-distance', 'opt.depth-of-field', 'opt.airy-radius', 'opt.snell',
 'opt.vignetting-corner', 'opt.dof-limit', 'opt.stop-down', 'opt.grating-order',
 'opt.grating-highest', 'opt.edge-fringe']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading import hints
from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import CHOICE_KEYS, permuted_options, printed_letter

CHAPTER = "02-optics"

_LENSES = (14.0, 20.0, 24.0, 28.0, 35.0, 50.0, 85.0, 100.0, 135.0, 200.0)
_STOPS = (1.4, 2.0, 2.8, 4.0, 5.6, 8.0, 11.0, 16.0, 22.0)


# -- 1. image distance (number) -------------------------------------------------------------------
def _image_params(rng):
    f = float(rng.choice(_LENSES))
    return {"f_mm": f, "a_m": round(float(rng.uniform(3.0, 60.0) * f * 1e-3), 3)}


def _image_distance(p, sign=-1.0):
    a = p["a_m"] * 1e3
    return a * p["f_mm"] / (a + sign * p["f_mm"])


image_distance = Exercise(
    params_name="p_distance",
    id="opt.image-distance", points=2, kind="number", answer="a_image",
    title="Image distance / Bildweite",
    statement="A thin lens of focal length $f = {f_mm}$ mm is focused on an object at the "
              "distance $a = {a_m}$ m in front of it. How far behind the lens is the sharp "
              "image (image distance a′, in mm)?",
    parameters=_image_params, reference=_image_distance, tolerance=PRINTED, rtol=1e-5, atol=0.0,
    mistakes=(
        Mistake("sign", "the imaging equation is 1/a + 1/a′ = 1/f, so 1/a′ = 1/f − 1/a "
                        "(not + 1/a)", lambda p: _image_distance(p, sign=+1.0)),
        Mistake("approximation", "a′ = f holds only for an object at infinity; here a is "
                                 "finite: a′ = a·f/(a − f)", lambda p: p["f_mm"]),
        Mistake("units-mm-m", "a is in m and f in mm: convert a to mm before using "
                              "the imaging equation",
                lambda p: p["a_m"] * p["f_mm"] / (p["a_m"] - p["f_mm"])),
    ))


# -- 2. depth of field (array) ------------------------------------------------------------------
def _dof_params(rng):
    f = float(rng.choice(_LENSES[3:8]))
    k = float(rng.choice(_STOPS[2:8]))
    u_um = float(rng.choice([20.0, 25.0, 30.0, 33.0]))
    H = f + f * f / (k * u_um * 1e-3)
    return {"f_mm": f, "k": k, "u_um": u_um,
            "a_m": round(float(rng.uniform(0.15, 0.6) * H * 1e-3), 2)}


def _dof(p, u_factor=1.0):
    import photolib.optics as po
    d = po.depth_of_field(p["a_m"] * 1e3, p["f_mm"], p["k"], p["u_um"] * 1e-3 * u_factor)
    return np.array([d.near, d.far, d.depth]) * 1e-3


def _dof_printed_t(expr, p):
    import sympy as sp

    from photolib.derive import optics as do
    f, a = p["f_mm"], p["a_m"] * 1e3
    m_b = (a - f) / f
    t = float(expr.subs({do.m_b: m_b, do.f: f, do.k: p["k"], do.up: p["u_um"] * 1e-3})
              if isinstance(expr, sp.Basic) else expr)
    near, far, _ = _dof(p)
    return np.array([near, far, t * 1e-3])


depth_of_field = Exercise(
    params_name="p_dof",
    id="opt.depth-of-field", points=3, kind="array", answer="dof",
    title="Depth of field / Schärfentiefe",
    statement="A camera with a lens of $f = {f_mm}$ mm at f-number $k = {k}$ is focused on "
              "$a = {a_m}$ m. The permissible circle of confusion is $u' = {u_um}$ µm. Give the "
              "near limit a_v, the far limit a_h and the depth of field t = a_h − a_v, all in "
              "m, as a NumPy array (a_v, a_h, t) of shape (3,).",
    parameters=_dof_params, reference=_dof, tolerance=PRINTED, rtol=1e-4, atol=1e-6,
    mistakes=(
        hints.erratum_version("de-summary:depth-of-field-t", _dof_printed_t, "printed"),
        Mistake("swapped", "the near limit a_v is the smaller distance: a_v = a·f²/(f² + u′k(a − f))",
                lambda p: _dof(p)[[1, 0, 2]] * np.array([1.0, 1.0, -1.0])),
        Mistake("radius", "u′ is the diameter of the circle of confusion, not its radius",
                lambda p: _dof(p, 0.5)),
    ))


# -- 3. Airy radius (number) ----------------------------------------------------------------------
def _airy_params(rng):
    # visible light 400 … 700 nm in 10 nm steps: 31 wavelengths × 9 stops
    return {"wavelength_nm": float(10 * rng.integers(40, 71)),
            "k": float(rng.choice(_STOPS))}


def _airy(p, factor=1.0):
    import photolib.optics as po
    return po.airy_radius(p["wavelength_nm"] * 1e-3, p["k"]) * factor


_NM = ("λ was given in nm and the result read as µm (or the other way round): "
       "1 µm = 1000 nm")

airy_radius = Exercise(
    params_name="p_airy",
    id="opt.airy-radius", points=2, kind="number", answer="r_airy",
    title="Airy disk / Beugungsscheibchen",
    statement="A diffraction-limited lens works at f-number $k = {k}$ in light of wavelength "
              "λ = {wavelength_nm} nm. What is the radius of the Airy disk (the first dark "
              "ring of the diffraction pattern) in the image, in µm?",
    parameters=_airy_params, reference=_airy, tolerance=PRINTED, rtol=1e-3, atol=0.0,
    mistakes=(
        Mistake("units-nm-um", _NM, lambda p: _airy(p, 1e3)),
        Mistake("units-nm-um", _NM, lambda p: _airy(p, 1e-3)),
        Mistake("diameter", "that is the diameter 2·1.22·λ·k; the radius is half of it",
                lambda p: _airy(p, 2.0)),
        Mistake("factor", "the radius of the first dark ring is 1.22·λ·k (the first zero of "
                          "J1 over π); λ·k alone is missing the factor 1.22",
                lambda p: _airy(p, 1.0 / 1.2196698912665045)),
    ))


# -- 4. Snell (number) ----------------------------------------------------------------------------
_MEDIA = {"air": 1.0, "water": 1.333}


def _snell_params(rng):
    medium = str(rng.choice(sorted(_MEDIA)))
    return {"medium": medium, "n1": _MEDIA[medium],
            "n2": round(float(rng.uniform(1.45, 1.8)), 3),
            "alpha_deg": round(float(rng.uniform(10.0, 75.0)), 1)}


def _snell(p, n1=None, n2=None, degrees_as_radians=False):
    n1 = p["n1"] if n1 is None else n1
    n2 = p["n2"] if n2 is None else n2
    alpha = p["alpha_deg"] if degrees_as_radians else math.radians(p["alpha_deg"])
    s = n1 * math.sin(alpha) / n2
    return None if abs(s) > 1 else math.degrees(math.asin(s))


snell = Exercise(
    params_name="p_snell",
    id="opt.snell", points=2, kind="number", answer="beta_deg",
    title="Refraction / Lichtbrechung (Snell)",
    statement="A ray passes from {medium} ($n_1 = {n1:.3f}$) into glass ($n_2 = {n2:.3f}$) at the angle of "
              "incidence α = {alpha_deg:.1f}° to the normal. What is the angle of refraction β "
              "in degrees?",
    parameters=_snell_params, reference=_snell, tolerance=PRINTED, rtol=0.0, atol=1e-4,
    mistakes=(
        Mistake("degrees", "that is β in radians; the question asks for degrees "
                           "(numpy.degrees)", lambda p: math.radians(_snell(p))),
        Mistake("degrees", hints.MESSAGES["degrees"],
                lambda p: _snell(p, degrees_as_radians=True)),
        Mistake("swapped", "n1 and n2 are swapped: n1·sin α = n2·sin β with n1 on the side "
                           "of the incoming ray", lambda p: _snell(p, n1=p["n2"], n2=p["n1"])),
    ))


# -- 5. cos⁴ at the corner (number) ---------------------------------------------------------------
#: the formats, printed to 0.1 mm: "36 mm" would read as good to 0.5 mm only
_FORMATS = {"36.0 mm × 24.0 mm": (36.0, 24.0), "23.5 mm × 15.6 mm": (23.5, 15.6),
            "13.2 mm × 8.8 mm": (13.2, 8.8), "60.0 mm × 45.0 mm": (60.0, 45.0)}


def _corner_params(rng):
    # c drawn again where cos³τ at the corner (power mistake) and cos⁴ at half the width
    # (side mistake) nearly coincide: two hints that must stay apart
    name = str(rng.choice(sorted(_FORMATS)))
    w, h = _FORMATS[name]
    while True:
        p = {"format": name, "width": w, "height": h,
             "c_mm": round(float(rng.uniform(0.5, 1.5) * math.hypot(w, h)), 1)}
        if abs(_corner(p, power=3) - _corner(p, side=True)) >= 0.01:
            return p


def _corner(p, power=4, half=True, side=False):
    r = p["width"] / 2 if side else math.hypot(p["width"], p["height"]) / (2 if half else 1)
    return math.cos(math.atan(r / p["c_mm"])) ** power


vignetting_corner = Exercise(
    params_name="p_vignetting",
    id="opt.vignetting-corner", points=2, kind="number", answer="E_corner",
    title="Natural vignetting at the corner / Lichtabfall in der Bildecke",
    statement="A camera with the format {format} and camera constant $c = {c_mm:.2f}$ mm has an "
              "ideal lens with only natural vignetting. What fraction E(τ)/E(0) of the "
              "irradiance in the image centre reaches a corner of the format?",
    parameters=_corner_params, reference=_corner, tolerance=PRINTED, rtol=1e-5, atol=0.0,
    mistakes=(
        Mistake("power", "the fall-off is cos⁴τ: cos²τ from the distance, one cos τ from "
                         "the foreshortened aperture, one from the oblique incidence",
                lambda p: _corner(p, power=2)),
        Mistake("power", "the fall-off is cos⁴τ, not cos³τ: the oblique incidence on the "
                         "sensor adds the fourth cos τ", lambda p: _corner(p, power=3)),
        Mistake("half", "the corner is half the diagonal from the centre: tan τ = (d/2)/c",
                lambda p: _corner(p, half=False)),
        Mistake("side", "the corner is at half the diagonal, not at half the format width",
                lambda p: _corner(p, side=True)),
    ))


# -- 6. a depth-of-field limit derived (expression) -----------------------------------------------
_QUANTITIES = {
    "near": "the near limit a_v",
    "far": "the far limit a_h",
    "depth": "the depth of field t = a_h − a_v",
}


def _limit_params(rng):
    q = str(rng.choice(sorted(_QUANTITIES)))
    return {"quantity": q, "text": _QUANTITIES[q], "n": int(rng.integers(5, 41))}


def _plain(expr, p):
    import sympy as sp

    from photolib.derive import optics as do
    f = sp.Symbol("f")
    return sp.factor(expr.xreplace({do.f: f, do.k: sp.Symbol("k"), do.up: sp.Symbol("u")})
                     .xreplace({do.a: p["n"] * f}))


def _limit(p, quantity=None):
    from photolib.derive import optics as do
    q = p["quantity"] if quantity is None else quantity
    near, far = do.dof_limits()
    return _plain({"near": near, "far": far, "depth": far - near}[q], p)


def _limit_printed(expr, p):
    """The summary's printed t with its m_b = a/a' − ... = n − 1 (a = n·f)."""
    from photolib.derive import optics as do
    if p["quantity"] != "depth":
        return None
    return _plain(expr.xreplace({do.m_b: p["n"] - 1}), p)


dof_limit = Exercise(
    params_name="p_dof_limit",
    id="opt.dof-limit", points=3, kind="expression", answer="limit", symbols=("f", "k", "u"),
    positive=("f", "k", "u"),  # focal length, f-number and blur are positive quantities
    title="Depth-of-field limits derived / Herleitung der Schärfentiefe",
    statement="A thin lens of focal length f and f-number k is focused on an object at the "
              "distance a = {n}·f from the lens; u is the permissible blur diameter in the "
              "image. An object at a_x focuses at a′_x = a_x·f/(a_x − f) and leaves a blur "
              "circle u′ = (f/k)·|a′_x − a′|/a′_x in the image plane of a. Derive {text} as "
              "a SymPy expression in the symbols f, k, u.",
    parameters=_limit_params, reference=_limit,
    mistakes=(
        hints.erratum_version("de-summary:depth-of-field-t", _limit_printed, "printed"),
        Mistake("swapped", "near and far limit are swapped: the near limit has + u·k(a − f) "
                           "in the denominator, the far limit − u·k(a − f)",
                lambda p: None if p["quantity"] == "depth" else
                _limit(p, "far" if p["quantity"] == "near" else "near")),
        Mistake("sign", "t = a_h − a_v is positive: the far limit minus the near limit",
                lambda p: None if p["quantity"] != "depth" else -_limit(p)),
    ))


# -- 7. stopping down (choice) --------------------------------------------------------------------
_OPTIONS = (
    "the depth of field grows and the Airy disk becomes twice as large",
    "the depth of field shrinks and the Airy disk becomes half as large",
    "the depth of field grows and the Airy disk becomes half as large",
    "the depth of field and the Airy disk stay the same; only the exposure changes",
)


def _choice_params(rng):
    text, _ = permuted_options(rng, _OPTIONS)
    k = float(rng.choice(_STOPS[1:5]))
    return {"k": k, "k2": 2 * k, "options": text}


def _stop_letter(index):
    """The letter printed before ``_OPTIONS[index]`` (read from the text: no answer in ``p``)."""
    return printed_letter(_OPTIONS, index)


stop_down = Exercise(
    params_name="p_stop",
    id="opt.stop-down",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_stop",
    title="Stopping down / Abblenden",
    statement="A photographer stops a lens down from f-number $k = {k}$ to $k = {k2}$ (twice "
              "the f-number) and keeps the focus. Which is right? {options}. Set the answer "
              "to the letter.",
    parameters=_choice_params, reference=_stop_letter(0),
    choices=dict(zip(CHOICE_KEYS, _OPTIONS)),
    mistakes=(
        Mistake("stop", "a larger k means a smaller pupil d = f/k: the light cones get "
                        "narrower, so the depth of field grows; diffraction grows with k "
                        "(r = 1.22·λ·k)", _stop_letter(1)),
        Mistake("stop", "the depth of field does grow, but the Airy radius 1.22·λ·k grows "
                        "with k: twice k, twice the disk", _stop_letter(2)),
    ))


# -- 8./9. a grating, two steps (numbers) ---------------------------------------------------------
def _grating_params(rng):
    """A transmission grating of 300–1200 lines/mm, visible light, an order that exists."""
    while True:
        lines = int(rng.choice([300, 400, 500, 600, 800, 1000, 1200]))
        d_um = round(1000.0 / lines, 4)
        lam_nm = float(rng.integers(400, 701))
        top = math.floor(d_um * 1000.0 / lam_nm)
        if top >= 1:
            break
    m = int(rng.integers(1, top + 1))
    return {"lines_per_mm": lines, "d_um": d_um, "lambda_nm": lam_nm, "m": m}


def _grating_angle(p, m=None, func=math.asin, lam_factor=1e-3):
    return math.degrees(func((p["m"] if m is None else m) * p["lambda_nm"] * lam_factor
                             / p["d_um"]))


def _grating_top(p):
    return float(math.floor(p["d_um"] * 1000.0 / p["lambda_nm"]))


grating_order = Exercise(
    params_name="p_grating", scenario="opt.grating-order",
    id="opt.grating-order", points=2, kind="number", answer="theta_m_deg",
    title="Step 1 of 2: a grating's order / Beugungsordnung eines Gitters",
    statement="A transmission grating (Beugungsgitter) has {lines_per_mm} lines per mm, i.e. the "
              "period $d = {d_um}$ µm. Light of $\\lambda = {lambda_nm:.0f}$ nm falls on it at "
              "normal incidence. In which direction $\\theta_m$ from the normal does the order "
              "$m = {m}$ leave? Give $\\theta_m$ in degrees to 0.01°.",
    # to 0.01°: the rounded answer is within 0.005° (and a float's rounding) of the value
    parameters=_grating_params, reference=_grating_angle, rtol=0.0, atol=0.0051,
    exact=("d_um", "lambda_nm"),     # a grating's period and a line's wavelength, as given
    mistakes=(
        Mistake("degrees", "that is θ in radians; the question asks for degrees "
                           "(numpy.degrees)", lambda p: math.radians(_grating_angle(p))),
        Mistake("order", "that is the first order; the grating equation is d·sin θ = m·λ "
                         "with the order asked for", lambda p: None if p["m"] == 1 else
                _grating_angle(p, m=1)),
        Mistake("tan", "the path difference of neighbouring slits is d·sin θ, not d·tan θ: "
                       "θ = arcsin(m·λ/d)", lambda p: _grating_angle(p, func=math.atan)),
        Mistake("cos", "θ is measured from the normal: the path difference is d·sin θ "
                       "(arcsin), not d·cos θ", lambda p: _grating_angle(p, func=math.acos)),
    ))


grating_highest = Exercise(
    params_name="p_grating_top", scenario="opt.grating-order",
    id="opt.grating-highest", points=1, kind="number", answer="m_max",
    title="Step 2 of 2: the highest order / die höchste Ordnung",
    statement="The same grating ($d = {d_um}$ µm) and light ($\\lambda = {lambda_nm:.0f}$ nm). "
              "What is the highest order $m_{{max}}$ that leaves the grating at all (an integer)?",
    parameters=_grating_params, reference=_grating_top, rtol=0.0, atol=1e-9,
    exact=("d_um", "lambda_nm"),
    few_variants="the answer is an integer order: d/λ of visible light (400–700 nm) and "
                 "300–1200 lines/mm takes only the values 1 to 8",
    mistakes=(
        Mistake("rounded", "an order exists only where |sin θ| = m·λ/d ≤ 1: round d/λ down, "
                           "not to the nearest integer",
                lambda p: None if round(p["d_um"] * 1000.0 / p["lambda_nm"]) == _grating_top(p)
                else float(round(p["d_um"] * 1000.0 / p["lambda_nm"]))),
        Mistake("count", "that counts the orders on both sides and the zeroth (2·m_max + 1); "
                         "the question asks for the highest m",
                lambda p: 2 * _grating_top(p) + 1),
    ))


# -- 10. the first fringe behind an edge (number) -------------------------------------------------
def _fringe_params(rng):
    return {"lambda_nm": float(rng.integers(400, 701)),
            "z_mm": float(rng.choice([0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 500.0]))}


def _fringe(p, scale=0.5):
    """x₁ = w₁·√(λz/2) in µm, w₁ the first root of dI/dw (photolib.optics)."""
    import photolib.optics as po

    return float(po.edge_first_fringe(p["lambda_nm"] * 1e-3, p["z_mm"] * 1e3)
                 * math.sqrt(scale / 0.5))


edge_fringe = Exercise(
    params_name="p_edge",
    id="opt.edge-fringe", points=2, kind="number", answer="x1_um",
    title="Diffraction at an edge / Beugung an einer Kante",
    statement="A plane wave of $\\lambda = {lambda_nm:.0f}$ nm passes a straight opaque edge "
              "(Kante). How far from the geometric shadow line lies the first bright fringe on a "
              "screen $z = {z_mm}$ mm behind the edge? Use the Fresnel approximation: "
              "$w = x\\sqrt{{2/(\\lambda z)}}$, the first fringe at $w_1 = 1.2172$. Give $x_1$ "
              "in µm to 3 significant digits.",
    # 3 significant digits: half a unit of the third digit is at most 0.5/100 of the value
    parameters=_fringe_params, reference=_fringe, rtol=5.1e-3, atol=0.0,
    exact=("lambda_nm", "z_mm"),     # the wavelength and the distance as given
    mistakes=(
        Mistake("factor-2", "w = x·√(2/(λz)), so x₁ = w₁·√(λz/2): the 2 belongs under λz in "
                            "the denominator", lambda p: _fringe(p, scale=2.0)),
        Mistake("factor-2", "w = x·√(2/(λz)), so x₁ = w₁·√(λz/2), not w₁·√(λz)",
                lambda p: _fringe(p, scale=1.0)),
    ))


EXERCISES = (image_distance, depth_of_field, airy_radius, snell, vignetting_corner, dof_limit,
             stop_down, grating_order, grating_highest, edge_fringe)
