"""Chapter 01-introduction: graded exercises on what photogrammetry is.

* ``int.classes`` (choice): single-image, stereo or multi-image photogrammetry for a task;
* ``int.history`` (choice): when and where the ISP (today ISPRS) was founded;
* ``int.scale-number`` (number): the image scale number m_b = H/c of an aerial image;
* ``int.images`` (number): the images of a photo flight over a block
  (:func:`photolib.sensors.flight_block`);
* ``int.ground-size`` (function): the ground size of a square image as a function of H.

>>> [ex.id for ex in EXERCISES]
['int.classes', 'int.history', 'int.scale-number', 'int.images', 'int.ground-size']
"""

from __future__ import annotations

import math

from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import CHOICE_KEYS, aerial_camera, permuted_options, printed_letter

CHAPTER = "01-introduction"


def _permuted(rng, options):
    return permuted_options(rng, options)[0]


_letter = printed_letter


# -- 1. classes (choice) --------------------------------------------------------------------------
_CLASSES = ("single-image photogrammetry (Einzelbildphotogrammetrie)",
            "stereo photogrammetry (Stereophotogrammetrie)",
            "multi-image photogrammetry (Mehrbildphotogrammetrie)",
            "analogue photogrammetry (analoge Photogrammetrie)")
_TASKS = (
    "the plane façade of a house is rectified from one photograph to a true-to-scale elevation",
    "heights of the terrain are measured from pairs of overlapping vertical aerial images taken "
    "in the normal case (parallel axes)",
    "a statue is reconstructed in 3-D from 40 convergent images taken all around it and "
    "oriented together by a bundle adjustment",
)


def _classes_params(rng):
    task = int(rng.integers(0, len(_TASKS)))
    return {"task": _TASKS[task], "options": _permuted(rng, _CLASSES)}


def _class_key(p):
    return _letter(_CLASSES, _TASKS.index(p["task"]))(p)   # task k belongs to class k


def _wrong_class(index):
    return lambda p: None if _TASKS.index(p["task"]) == index else _letter(_CLASSES, index)(p)


classes = Exercise(
    params_name="p_classes",
    id="int.classes",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_class",
    title="Classes of photogrammetry / Einteilung",
    statement="Task: {task}. Which class of photogrammetry by the number of images is this: "
              "{options}? Set the answer to the letter.",
    parameters=_classes_params, reference=_class_key, choices=dict(zip(CHOICE_KEYS, _CLASSES)),
    mistakes=(
        Mistake("class-single", "single-image photogrammetry works with one image: planes, or "
                                "points on a known surface", _wrong_class(0)),
        Mistake("class-stereo", "stereo photogrammetry uses image pairs near the normal case "
                                "and measures parallaxes", _wrong_class(1)),
        Mistake("class-multi", "multi-image photogrammetry orients many images of any "
                               "configuration together (bundle adjustment)", _wrong_class(2)),
        Mistake("class-stage", "analogue / analytical / digital classify by the recording and "
                               "evaluation technique, not by the number of images",
                _letter(_CLASSES, 3)),
    ))


# -- 2. history (choice) --------------------------------------------------------------------------
_HISTORY = ("1910 in Vienna", "1858 in Wetzlar", "1867 in Berlin", "1980 in Hamburg")


def _history_params(rng):
    return {"options": _permuted(rng, _HISTORY)}


history = Exercise(
    params_name="p_history",
    id="int.history",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_history",
    title="History / Geschichte",
    statement="When and where was the International Society for Photogrammetry (ISP, today "
              "ISPRS) founded: {options}? Set the answer to the letter.",
    parameters=_history_params, reference=_letter(_HISTORY, 0),
    choices=dict(zip(CHOICE_KEYS, _HISTORY)),
    mistakes=(
        Mistake("meydenbauer", "1858 in Wetzlar is Meydenbauer's idea at the cathedral, half a "
                               "century before the society", _letter(_HISTORY, 1)),
        Mistake("word", "1867 in Berlin is the first print of the word 'Photogrammetrie' "
                        "(Wochenblatt des Architektenvereins zu Berlin)", _letter(_HISTORY, 2)),
        Mistake("renamed", "1980 (congress in Hamburg) is when the ISP added remote sensing to "
                           "its name; it was founded much earlier", _letter(_HISTORY, 3)),
    ))


# -- 3. image scale number (number) ---------------------------------------------------------------
def _scale_params(rng):
    return dict(aerial_camera(rng))


def _scale_number(p):
    return p["h_m"] / (p["c_mm"] / 1000.0)


scale_number = Exercise(
    params_name="p_scale",
    id="int.scale-number", points=2, kind="number", answer="m_b",
    title="Image scale number / Bildmaßstabszahl",
    statement="An aerial camera with the camera constant $c = {c_mm:.2f}$ mm takes a vertical image "
              "from $H = {h_m}$ m above flat ground. The image scale is 1 : m_b. What is the "
              "image scale number m_b?",
    parameters=_scale_params, reference=_scale_number, tolerance=PRINTED, rtol=1e-4, atol=0.0,
    mistakes=(
        Mistake("units-mm-m", "c is in mm and H in m: convert c to m before m_b = H/c",
                lambda p: p["h_m"] / p["c_mm"]),
        Mistake("inverted", "1 : m_b with m_b = H/c (> 1); c/H is the scale itself",
                lambda p: (p["c_mm"] / 1000.0) / p["h_m"]),
    ))


# -- 4. images of a flight block (number) ---------------------------------------------------------
def _block_params(rng):
    cam = aerial_camera(rng)
    return {"length_km": round(float(rng.uniform(3.0, 12.0)), 1),
            "width_km": round(float(rng.uniform(2.0, 8.0)), 1),
            "h_m": float(round(rng.uniform(800.0, 4000.0) / 50.0) * 50.0),
            "c_mm": cam["c_mm"], "pixel_um": float(rng.choice([3.76, 4.0, 4.6, 5.2, 6.0])),
            "n_along": int(rng.integers(6, 15)) * 1000, "n_across": int(rng.integers(10, 27)) * 1000,
            "overlap_pct": int(rng.choice([60, 70, 80])),
            "sidelap_pct": int(rng.choice([20, 25, 30, 40]))}


def _images(p):
    from photolib.sensors import flight_block

    fb = flight_block(p["length_km"] * 1e3, p["width_km"] * 1e3, p["h_m"], p["c_mm"],
                      p["pixel_um"] * 1e-3, p["n_along"], p["n_across"],
                      p["overlap_pct"] / 100.0, p["sidelap_pct"] / 100.0)
    return float(fb.images)


def _by_hand(p, overlap=None, sidelap=None, swap_pixels=False, per_strip_extra=2,
             simple=False):
    """The stated rule typed out, with a mistake's changes."""
    ov = p["overlap_pct"] / 100.0 if overlap is None else overlap
    sl = p["sidelap_pct"] / 100.0 if sidelap is None else sidelap
    na, nc = (p["n_across"], p["n_along"]) if swap_pixels else (p["n_along"], p["n_across"])
    gsd = p["pixel_um"] * 1e-3 * p["h_m"] / p["c_mm"]
    S_along, S_across = na * gsd, nc * gsd
    B, A = S_along * (1.0 - ov), S_across * (1.0 - sl)
    L, W = p["length_km"] * 1e3, p["width_km"] * 1e3
    if simple:   # the rule of thumb ⌈L/B⌉ + 1 per strip and ⌈W/A⌉ strips
        return float((math.ceil(L / B) + 1) * math.ceil(W / A))
    per_strip = max(2, math.ceil((L - ov * S_along) / B - 1e-9) + per_strip_extra)
    strips = max(1, math.ceil((W - S_across) / A - 1e-9) + 1)
    return float(per_strip * strips)


def _unless_right(wrong):
    """The mistake only where it changes the count (some variants come out the same)."""
    return lambda p: None if wrong(p) == _images(p) else wrong(p)


images = Exercise(
    params_name="p_images",
    id="int.images", points=3, kind="number", answer="n_images",
    title="Planning a photo flight / Bildflugplanung",
    statement="A block of {length_km} km (along the flight) × {width_km} km is flown at "
              "$H = {h_m}$ m with a camera of $c = {c_mm}$ mm and {n_along} × {n_across} pixels "
              "(along × across the flight) of {pixel_um} µm; forward overlap p = "
              "{overlap_pct} %, side lap $q = {sidelap_pct}$ %. With the image's ground size S, "
              "base B = S_along·(1 − p), strip spacing A = S_across·(1 − q): each strip has "
              "⌈(L − p·S_along)/B⌉ + 2 images (at least 2) and there are ⌈(W − S_across)/A⌉ + 1 "
              "strips (at least 1). "
              "How many images are taken in all?",
    parameters=_block_params, reference=_images, rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("models", "that is the number of stereo models; each strip has one image more "
                          "than models", lambda p: _by_hand(p, per_strip_extra=1)),
        Mistake("swapped", "the forward overlap p belongs to the flight direction, the side "
                           "lap q to the strip spacing",
                _unless_right(lambda p: _by_hand(p, overlap=p["sidelap_pct"] / 100.0,
                                                 sidelap=p["overlap_pct"] / 100.0))),
        Mistake("swapped-pixels", "the pixel counts along and across the flight are swapped",
                _unless_right(lambda p: _by_hand(p, swap_pixels=True))),
        Mistake("rule-of-thumb", "the rule of thumb ⌈L/B⌉ + 1 images and ⌈W/A⌉ strips is not "
                                 "the rule given: use ⌈(L − p·S)/B⌉ + 2 and ⌈(W − S)/A⌉ + 1",
                _unless_right(lambda p: _by_hand(p, simple=True))),
    ))


# -- 5. ground size as a function of H (function) -------------------------------------------------
def _ground_params(rng):
    cam = aerial_camera(rng)
    return {"c_mm": cam["c_mm"], "format_mm": float(rng.choice([60.0, 90.0, 230.0]))}


def _ground_size(half=False):
    def make(p):
        def ground_size(H):
            return p["format_mm"] * H / p["c_mm"] * (0.5 if half else 1.0)
        return ground_size
    return make


def _ground_cases(rng, p):
    return [(round(float(rng.uniform(200.0, 6000.0)), 1),) for _ in range(6)]


ground_size = Exercise(
    params_name="p_ground",
    id="int.ground-size", points=2, kind="function", answer="ground_size",
    title="Ground coverage / Bodenabdeckung",
    statement="A camera has a square image format of {format_mm} mm × {format_mm} mm and "
              "$c = {c_mm}$ mm. Write ground_size(H) returning the side length in **m** of the "
              "square ground area of a vertical image taken H m above flat ground.",
    parameters=_ground_params, reference=_ground_size(), tolerance=PRINTED, cases=_ground_cases,
    rtol=1e-6, atol=0.0,   # float32 (2e-7); the old 1e-9 rejected it
    mistakes=(
        Mistake("half", "that is half the side (from the principal point to the edge); the "
                        "side is s'·H/c", _ground_size(half=True)),
    ))


EXERCISES = (classes, history, scale_number, images, ground_size)
