"""Chapter 03-digital-images: graded exercises on digital images and sensors.

* ``dig.gsd`` (number): ground sampling distance in cm, GSD = p·H/c;
* ``dig.bits`` (number): the smallest bit depth that resolves a sensor's dynamic range;
* ``dig.quant-noise`` (number): the quantisation noise in electrons, K/√12, K = FW/(2^b − 1);
* ``dig.snr-db`` (number): SNR in dB with shot, read and quantisation noise;
* ``dig.bayer-green`` (choice): the share of green pixels in a Bayer mosaic;
* ``dig.gsd-function`` (function): the GSD in cm as a function of the flying height.

Conventions as in :mod:`photolib.sensors`: DN = round(s/Δ), gain K = FW/(2^b − 1) e⁻/DN,
SNR an amplitude ratio, dB = 20·log10. References are computed with :mod:`photolib.sensors`.

>>> [ex.id for ex in EXERCISES]
['dig.gsd', 'dig.bits', 'dig.quant-noise', 'dig.snr-db', 'dig.bayer-green', 'dig.gsd-function']
"""

from __future__ import annotations

import math

from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import CHOICE_KEYS, aerial_camera, permuted_options, printed_letter

CHAPTER = "03-digital-images"

_PIXELS_UM = (3.45, 3.76, 4.0, 4.6, 5.2, 6.0, 7.2, 9.0)


def _camera(rng):
    cam = aerial_camera(rng)
    return {"pixel_um": float(rng.choice(_PIXELS_UM)), "c_mm": cam["c_mm"], "h_m": cam["h_m"]}


# -- 1. GSD (number) ------------------------------------------------------------------------------
def _gsd_cm(p, pixel_factor=1e-3, c_factor=1.0, out=100.0):
    """p·H/c with the pixel in mm (× ``pixel_factor`` from µm), c in mm, H in m → cm."""
    return p["pixel_um"] * pixel_factor * p["h_m"] / (p["c_mm"] * c_factor) * out


gsd = Exercise(
    params_name="p_gsd",
    id="dig.gsd", points=2, kind="number", answer="gsd_cm",
    title="Ground sampling distance / Bodenpixelgröße",
    statement="A digital aerial camera has square pixels of {pixel_um} µm and the camera "
              "constant $c = {c_mm}$ mm. It takes a vertical image from $H = {h_m}$ m above flat "
              "ground. What is the ground sampling distance (GSD) in **cm**?",
    # a pixel pitch is a design value, exact as printed (the sensors of _PIXELS_UM)
    parameters=_camera, reference=_gsd_cm, tolerance=PRINTED, exact=("pixel_um",),
    rtol=1e-3, atol=0.0,
    mistakes=(
        Mistake("units-um", "the pixel pitch is in µm: divide by 1000 to get mm, the unit of c "
                            "(GSD = p·H/c with p and c in the same unit)",
                lambda p: _gsd_cm(p, pixel_factor=1.0)),
        Mistake("units-cm", "this is the GSD in m; the answer is asked in cm",
                lambda p: _gsd_cm(p, out=1.0)),
        Mistake("scale", "GSD = p·m_b with the scale number m_b = H/c, not c/H",
                lambda p: p["pixel_um"] * 1e-3 * (p["c_mm"] * 1e-3) / p["h_m"] * 100.0),
    ))


# -- 2. bits for a dynamic range (number) ---------------------------------------------------------
def _sensor_params(rng):
    return {"full_well": int(rng.integers(8, 120)) * 500,
            "read_noise": round(float(rng.uniform(2.0, 15.0)), 1)}


def _bits(p, rounding=math.ceil, log=math.log2):
    return float(rounding(log(p["full_well"] / p["read_noise"])))


bits = Exercise(
    params_name="p_bits",
    id="dig.bits",
    few_variants="the answer is a bit depth, a whole number from 8 to 16 (392 of 400 statements differ)", points=2, kind="number", answer="b",
    title="Bit depth for a dynamic range / Bittiefe und Dynamikumfang",
    statement="A sensor has a full well (Fassungsvermögen) of {full_well} e⁻ and a read noise "
              "of {read_noise} e⁻. Its dynamic range is DR = full well / read noise. What is "
              "the smallest bit depth b whose 2^b grey values are at least DR?",
    parameters=_sensor_params, reference=_bits, rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("rounding", "rounded down: 2^b must be at least DR, so b = ⌈log2 DR⌉",
                lambda p: _bits(p, rounding=math.floor)),
        Mistake("log10", "2^b grey values need the logarithm to base 2, not 10",
                lambda p: _bits(p, log=math.log10)),
    ))


# -- 3. quantisation noise (number) ---------------------------------------------------------------
def _quant_params(rng):
    return {"full_well": int(rng.integers(10, 80)) * 500, "bits": int(rng.integers(8, 11))}


def _gain(p, levels_minus_one=True):
    return p["full_well"] / (2 ** p["bits"] - (1 if levels_minus_one else 0))


def _sigma_q(p):
    return _gain(p) / math.sqrt(12.0)


quant_noise = Exercise(
    params_name="p_quant",
    id="dig.quant-noise", points=2, kind="number", answer="sigma_q",
    title="Quantisation noise / Quantisierungsrauschen",
    statement="A {bits}-bit camera maps its full well of {full_well} e⁻ onto the largest grey "
              "value 2^b − 1 (gain K = full well/(2^b − 1) e⁻ per DN). Rounding to whole DN "
              "adds quantisation noise. What is its standard deviation in **electrons**?",
    parameters=_quant_params, reference=_sigma_q, rtol=1e-5, atol=0.0,
    mistakes=(
        Mistake("variance", "that is the variance K²/12; the standard deviation is K/√12",
                lambda p: _gain(p) ** 2 / 12.0),
        Mistake("sqrt", "the variance is Δ²/12, so the standard deviation is Δ/√12, not Δ/12",
                lambda p: _gain(p) / 12.0),
        Mistake("units-dn", "1/√12 is the noise in DN; multiply by the gain K to get electrons",
                lambda p: 1.0 / math.sqrt(12.0)),
        Mistake("levels", "the full well maps to the largest DN, 2^b − 1, so "
                          "K = full well/(2^b − 1), not full well/2^b",
                lambda p: _gain(p, levels_minus_one=False) / math.sqrt(12.0)),
    ))


# -- 4. SNR in dB (number) ------------------------------------------------------------------------
#: the tolerance in dB: the inputs are exact, so only rounding of the answer (4 decimals, or a
#: float32 computation: ~1e-6 dB) needs room
SNR_ATOL_DB = 1e-4


def _snr_params(rng):
    """Signal, read noise and a gain large enough that quantisation is visible.

    The gain is drawn through the share q = (K²/12)/(S + σ_r²) of the quantisation variance,
    3 … 30 %: leaving K²/12 out then changes the SNR by 10·log10(1 + q) ≥ 0.12 dB, far more
    than the tolerance, for every variant (a coarse, e.g. 8-bit, converter). σ_r² < S keeps
    the "shot noise missing" and "read noise missing" answers apart; K²/12 is drawn at least
    10 % away from σ_r², so "read noise missing" and "quantisation noise missing" (different
    hints) differ by far more than the printed inputs' rounding.
    """
    signal = int(rng.integers(40, 1500))
    read_noise = round(float(rng.uniform(2.0, 6.0)), 1)
    while True:
        share = float(rng.uniform(0.03, 0.3))
        gain = round(math.sqrt(12.0 * share * (signal + read_noise ** 2)), 2)
        if abs(gain ** 2 / 12.0 - read_noise ** 2) >= 0.1 * read_noise ** 2:
            return {"signal": signal, "read_noise": read_noise, "gain": gain}


def _snr_db(p, shot=True, read=True, quant=True, factor=20.0):
    var = ((p["signal"] if shot else 0.0) + (p["read_noise"] ** 2 if read else 0.0)
           + (p["gain"] ** 2 / 12.0 if quant else 0.0))
    return factor * math.log10(p["signal"] / math.sqrt(var))


snr_db = Exercise(
    params_name="p_snr",
    id="dig.snr-db", points=3, kind="number", answer="snr_db",
    title="Signal-to-noise ratio in dB / Signal-Rausch-Verhältnis",
    statement="A pixel collects a mean signal of $S = {signal}$ e⁻ (photon shot noise: Poisson). "
              "The read noise is {read_noise:.2f} e⁻, the gain $K = {gain:.2f}$ e⁻/DN (quantisation "
              "noise K²/12 in e⁻²), the dark signal negligible. What is the SNR in **dB** "
              "(at least four decimals)?",
    # σ_r and K printed to 0.01 (σ_r is drawn to 0.1: "4.10"): their rounding moves the SNR
    # by some 5e-4 dB, far less than the missing quantisation noise (≥ 0.12 dB)
    parameters=_snr_params, reference=_snr_db, tolerance=PRINTED, rtol=0.0, atol=SNR_ATOL_DB,
    mistakes=(
        Mistake("power-db", "an SNR is a ratio of amplitudes (signal / standard deviation): "
                            "its dB value is 20·log10, not 10·log10",
                lambda p: _snr_db(p, factor=10.0)),
        Mistake("shot-noise", "the photon shot noise is missing: a Poisson signal S has the "
                              "variance S", lambda p: _snr_db(p, shot=False)),
        Mistake("read-noise", "the read noise is missing: add σ_r² to the variance",
                lambda p: _snr_db(p, read=False)),
        Mistake("quant-noise", "the quantisation noise is missing: rounding to whole DN adds "
                               "the variance K²/12 (in e⁻², K in e⁻/DN) to S + σ_r²",
                lambda p: _snr_db(p, quant=False)),
        Mistake("ratio", "this is the SNR as a ratio; give it in dB: 20·log10(SNR)",
                lambda p: 10 ** (_snr_db(p) / 20.0)),
    ))


# -- 5. Bayer green share (choice) ----------------------------------------------------------------
_BAYER_OPTIONS = ("one half", "one quarter", "one third", "three quarters")


def _bayer_params(rng):
    return {"options": permuted_options(rng, _BAYER_OPTIONS)[0]}


def _option(index):
    """The letter printed before option ``index`` (read from the text: no answer in ``p``)."""
    return printed_letter(_BAYER_OPTIONS, index)


bayer_green = Exercise(
    params_name="p_bayer",
    id="dig.bayer-green",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_green",
    title="Bayer mosaic / Bayer-Muster",
    statement="A colour camera has a Bayer filter mosaic (RGGB). Which share of its pixels "
              "carries a green filter: {options}? Set the answer to the letter.",
    parameters=_bayer_params, reference=_option(0),
    choices=dict(zip(CHOICE_KEYS, _BAYER_OPTIONS)),
    mistakes=(
        Mistake("bayer-quarter", "a quarter are red and a quarter blue; each 2 × 2 block has "
                                 "two green pixels", _option(1)),
        Mistake("bayer-third", "not an equal split: the Bayer pattern has twice as many green "
                               "pixels as red or blue (the eye is most sensitive to green)",
                _option(2)),
    ))


# -- 6. GSD as a function of the height (function) ------------------------------------------------
def _gsd_function(pixel_factor=1e-3, out=100.0):
    def make(p):
        def gsd_of_height(H):
            return p["pixel_um"] * pixel_factor * H / p["c_mm"] * out
        return gsd_of_height
    return make


def _height_cases(rng, p):
    return [(round(float(rng.uniform(100.0, 6000.0)), 1),) for _ in range(6)]


gsd_function = Exercise(
    params_name="p_gsd_fn",
    id="dig.gsd-function", points=3, kind="function", answer="gsd_of_height",
    title="GSD as a function of the flying height",
    statement="For a camera with {pixel_um} µm pixels and $c = {c_mm}$ mm write gsd_of_height(H) "
              "that returns the ground sampling distance in **cm** of a vertical image taken H m "
              "above flat ground. It is tested on heights you do not see.",
    parameters=_camera, reference=_gsd_function(), cases=_height_cases, tolerance=PRINTED,
    exact=("pixel_um",), rtol=1e-6, atol=0.0,
    mistakes=(
        Mistake("units-cm", "this is the GSD in m; gsd_of_height must return cm",
                _gsd_function(out=1.0)),
        Mistake("units-um", "the pixel pitch is in µm: divide by 1000 to get mm, the unit of c",
                _gsd_function(pixel_factor=1.0)),
    ))


EXERCISES = (gsd, bits, quant_noise, snr_db, bayer_green, gsd_function)
