"""German lecture summary (000_*): digital images and sensors — exposure, CCD/CMOS, pixels.

Derivations from :mod:`photolib.derive.sensors` (and the Airy factor from
:mod:`photolib.derive.optics`). Symbols: ``p`` pixel pitch, ``c`` camera constant, ``H``
distance (flying height), ``g`` ground slope, ``K`` gain in e⁻/DN, ``eta`` quantum
efficiency η, ``FW`` full well (e⁻), ``b`` bit depth, ``o``/``o_ref`` the summary's
"Blendenöffnung" at two settings, ``d`` pupil diameter, ``t`` exposure time.

The summary prints no formula for these items: each transcription is the quoted sentence,
and where a formula is compared, the item says how the sentence is read.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import optics
from photolib.derive import sensors as s
from photolib.errata._record import Evidence, Record, VersionSpec, formula

SRC = "000_5cb9d2460e6d5d8e.txt (German lecture summary)"
o, o_ref = sp.symbols("o o_ref", positive=True)

PIXEL_COND = ("vertical image (ω = φ = 0, any κ) of flat horizontal ground at distance H: "
              "GSD = p·H/c, pixel area GSD² = (p·H/c)²; tilt, terrain slope and the image "
              "position change it")
GAIN_COND = ("quantum efficiency η = 1: the gain K counts electrons per grey level, photons "
             "per grey level are K/η; with the converter range matched to the full well "
             "K = FW/(2^b − 1)")
FW_COND = ("gain set so that the largest grey value 2^b − 1 is reached exactly at saturation, "
           "FW = K·(2^b − 1); otherwise the converter clips first (K·(2^b − 1) < FW) or grey "
           "values stay unused (K·(2^b − 1) > FW)")
EXPOSURE_COND = ("'Blendenöffnung' is the area of the entrance pupil π·d²/4 (∝ 1/k² at fixed "
                 "f; same scene, object at infinity, aplanatic lens); read as the diameter d "
                 "the light grows with d², not d")
CMOS_DR = ("not-checkable: a comparison of device data the summary does not give; dynamic "
           "range FW/σ_r is defined alike for CCD and CMOS and the readout principle does "
           "not fix full well or read noise")
CMOS_OTHER = ("not-checkable: power, cost, addressing and readout speed are properties of "
              "the technology and its circuits, not consequences of a formula")
COLOUR_COND = ("single-chip colour filter mosaic (Bayer: R and B on 1/4, G on 1/2 of the "
               "pixels, R/B sampled at pitch 2p); with one chip per colour channel (also in "
               "the summary) the resolution is not reduced")
AIRY_WHY = ("the formula is only in a picture that is not available; the summary prints no "
            "Airy radius (no 1.22·λ·k)")

PIXEL_DOMAIN = {s.omega: (-0.3, 0.3), s.phi: (-0.3, 0.3), s.g: (-0.3, 0.3),
                s.x: (-0.5, 0.5), s.y: (-0.5, 0.5)}


def _cmos_dr() -> Evidence:
    dr = s.dynamic_range()
    # the derivation has no symbol for the architecture: FW and σ_r are all it depends on
    ok = dr.free_symbols == {s.FW, s.sigma_r}
    return Evidence(CMOS_DR if ok else "wrong", f"DR = {dr}: depends on FW and σ_r only, "
                    "which the summary gives for neither sensor type")


def _colour() -> Evidence:
    mosaic = s.bayer_fractions()
    three_chip = {col: sp.Rational(1) for col in "RGB"}        # one chip per channel
    reduced = all(v < 1 for v in mosaic.values())
    table = [(f"{col} fraction (Bayer)", None, float(mosaic[col]), None, True) for col in "RGB"]
    table += [(f"{col} fraction (3 chips)", None, float(three_chip[col]), None, True)
              for col in "RGB"]
    if reduced and all(v == 1 for v in three_chip.values()):
        return Evidence(f"right-under-condition: {COLOUR_COND}", "every channel is sampled "
                        "on a fraction < 1 of the pixels of a mosaic, on all pixels with three "
                        "chips", table=table)
    return Evidence("wrong", "mosaic fractions not below 1", table=table)


def _fill_factor() -> Evidence:
    frac = s.fill_fraction()
    ok = sp.simplify(frac.subs(s.a_act, s.p)) == 1 and frac.subs({s.a_act: 3, s.p: 5}) < 1
    return Evidence("right" if ok else "wrong", f"registered fraction of a uniform "
                    f"irradiance = {frac} (active area over pixel area) < 1 for a < p; a "
                    "microlens concentrating the flux on the active area raises it")


def _quantisation() -> Evidence:
    var = s.quantisation_variance()
    ok = sp.simplify(var - s.Delta**2 / 12) == 0
    return Evidence("right" if ok else "wrong", f"a definition; its cost: the rounding error "
                    f"is uniform on ±Δ/2 with mean 0 and variance {var} (integrated), "
                    "Δ = full scale/(2^b − 1)")


READING_NOTE = ("The source prints no formula here: the version 'printed' is the catalogue's "
                "reading of the sentence (labelled 'reading' by --id), not a transcription. ")


def records():
    out = []
    out.append(formula(
        "de-summary:pixel-resolution", SRC + ", '(Pixel-) Auflösung', lines 287–288",
        "'Pixelauflösung = Fläche, die ein Pixel im Objektraum abdeckt' — 'über physikalische "
        "Pixelgröße, Kamerakonstante, Abstand zum Objekt berechnet' (no formula printed; read "
        "as A = (p·H/c)²)",
        {"printed": VersionSpec(f"right-under-condition: {PIXEL_COND}",
                                expr=lambda: (s.p * s.H / s.c) ** 2,
                                condition={s.omega: 0, s.phi: 0, s.g: 0},
                                condition_text=PIXEL_COND, claim="right", reading=True)},
        derivation=s.pixel_ground_area, domain=PIXEL_DOMAIN,
        steps=("ray of (x', y'): D = R·(x', y', −c) from the centre at height H (collinearity)",
               "meets the ground Z = g·X at (X, Y) = λ·(D_x, D_y), λ = −H/(D_z − g·D_x)",
               "pixel area = p²·det ∂(X, Y)/∂(x', y')·√(1 + g²)",
               "ω = φ = g = 0: (X, Y) = (H/c)·R_κ(x', y'), area (p·H/c)², GSD = p·H/c"),
        note=READING_NOTE + "The summary defines the pixel resolution as an area; the usual figure is its "
             "side, the ground sampling distance GSD = p·H/c = p·m_b."))
    out.append(formula(
        "de-summary:gain", SRC + ", 'CCD-Sensoren', line 263",
        "'Anzahl an Photonen, die eine Grauwertstufe definieren: Gain' (read as photons per "
        "grey level = K)",
        {"printed": VersionSpec(f"right-under-condition: {GAIN_COND}", expr=lambda: s.K,
                                condition={s.eta: 1}, condition_text=GAIN_COND,
                                claim="right", reading=True)},
        derivation=s.photons_per_grey_level, domain={s.eta: (0.1, 0.9)},
        steps=("N photons give η·N electrons; the converter codes DN = η·N/K, K in e⁻/DN",
               "photons per grey level = 1/(dDN/dN) = K/η",
               "η = 1: K; a sensor with η = 0.5 needs 2K photons per grey level"),
        note=READING_NOTE + "The system gain (EMVA 1288) is defined in electrons (or DN per electron); "
             "rounding adds the quantisation noise K²/12 e⁻²."))
    out.append(formula(
        "de-summary:full-well", SRC + ", 'CCD-Sensoren', line 262",
        "'Kenngröße Fassungsvermögen: Full-Well > wird zusammen mit Gain und Bildtiefe "
        "bestimmt' (read as FW = K·(2^b − 1))",
        {"printed": VersionSpec(f"right-under-condition: {FW_COND}", expr=lambda: s.FW,
                                condition=lambda: {s.K: s.FW / (2**s.bits - 1)},
                                condition_text=FW_COND, claim="right", reading=True)},
        derivation=s.charge_at_max_dn, domain={s.bits: (8.0, 14.0), s.K: (0.5, 20.0),
                                               s.FW: (1e3, 1e5)},
        steps=("grey value DN stands for the charge K·DN (steps of K electrons)",
               "the largest grey value 2^b − 1 stands for Σ K = K·(2^b − 1)",
               "equal to the full well only when K is chosen as FW/(2^b − 1)"),
        note=READING_NOTE + "The full well is a property of the pixel (its charge capacity); gain and bit "
             "depth are matched to it, not the other way round."))
    out.append(Record(
        id="de-summary:cmos-dynamic-range", source=SRC + ", 'CMOS', line 278",
        item="CMOS advantage over CCD: 'hoher Dynamikumfang'", kind="text",
        specs={"printed": VersionSpec(CMOS_DR, check=_cmos_dr, claim="right")},
        derivation=s.dynamic_range,
        note="DR = FW/σ_r for both. Which sensor is higher depends on the devices compared "
             "(scientific CCDs with large wells and low read noise exceed many CMOS sensors; "
             "modern CMOS with in-pixel gain exceed many CCDs)."))
    out.append(Record(
        id="de-summary:cmos-other-advantages", source=SRC + ", 'CMOS', lines 274–277",
        item="CMOS advantages: lower power, low cost, direct addressing, fast readout",
        kind="text", specs={"printed": VersionSpec(CMOS_OTHER, claim="right")},
        note="Direct addressing follows from the per-pixel readout the summary describes; the "
             "rest are statements about manufacturing and circuits."))
    out.append(formula(
        "de-summary:exposure", SRC + ", 'Optik', line 89",
        "'Die auf den Sensor einfallende Lichtmenge ist proportional der Blendenöffnung und "
        "der Belichtungszeit' (read as Q/Q_ref = (o·t)/(o_ref·t_ref))",
        {"printed": VersionSpec(f"right-under-condition: {EXPOSURE_COND}",
                                expr=lambda: (o * s.t) / (o_ref * s.t_ref),
                                condition=lambda: {o: sp.pi * s.d**2 / 4,
                                                   o_ref: sp.pi * s.d_ref**2 / 4},
                                condition_text=EXPOSURE_COND, claim="right", reading=True)},
        derivation=s.exposure_ratio,
        steps=("irradiance through a cone of half angle u': ∫ L cos θ dΩ = π L sin² u'",
               "sine condition, object at infinity: sin u' = d/(2f)",
               "Q = L·(π d²/4)·A_px·t/f²: pupil area × time; d = f/k gives Q ∝ t/k²"),
        note=READING_NOTE + "Read with the diameter d the printed proportionality is wrong: doubling d "
             "quadruples the light."))
    out.append(Record(
        id="de-summary:colour-resolution", source=SRC + ", 'Digitale Farbbilder', lines "
        "280–283", item="'Farb-Pixel wird in mehrere Sektoren unterteilt … Auflösung ist "
        "reduziert'", kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {COLOUR_COND}", check=_colour,
                                      claim="right")}))
    out.append(Record(
        id="de-summary:fill-factor", source=SRC + ", 'CCD-Anpassungen', line 269",
        item="photons in the gaps between active elements are not registered; microlenses "
             "raise the 'pixel fill factor'", kind="text",
        specs={"printed": VersionSpec("right", check=_fill_factor, claim="right")}))
    out.append(Record(
        id="de-summary:quantisation", source=SRC + ", 'Digitale Fotografie', lines 255–256",
        item="'Radiometrische Informationen werden … in definierte Grauwertstufen abgebildet "
             "> Quantisierung'", kind="text",
        specs={"printed": VersionSpec("right", check=_quantisation, claim="right")},
        derivation=s.quantisation_variance))
    out.append(formula(
        "de-summary:diffraction-airy", SRC + ", 'Beugungsunschärfe', line 168",
        "diffraction blur (Airy radius r = 1.22·λ·k)",
        {"printed": VersionSpec(f"not-checkable: {AIRY_WHY}", claim="right")},
        derivation=lambda: sp.N(optics.airy_radius_factor(15), 15),
        note="Derived for the course: r_A/(λ·k) = j₁,₁/π = 1.21967 (first zero of J1 over π); "
             "'1.22' would be right rounded."))
    return out
