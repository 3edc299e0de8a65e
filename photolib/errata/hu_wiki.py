"""Hungarian Wikipedia article "Fotogrammetria" (001_*): collinearity, rotation matrix, accuracy.

The accuracy figures of the analogue and analytical methods are object-space metres only at
an image scale number of about 10⁶: σ_X = m_b·σ' (:func:`photolib.derive.sensors.object_accuracy`)
with the instruments' image accuracies σ' (first-order analogue plotters ≈ 5–10 µm,
analytical plotters ≈ 2–5 µm; these are assumptions of the check, not printed).
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive.rotation import kappa, omega, phi, rotation_opk, wolf_m
from photolib.derive import sensors
from photolib.errata._record import Evidence, Record, VersionSpec, formula

SRC = "001_a18d25e57ee77a17.txt (Hungarian Wikipedia, 'Matematikai alapok')"
ART = "001_a18d25e57ee77a17.txt (Hungarian Wikipedia)"
#: an aerial survey at the edge of the aircraft's ceiling: c = 153 mm from H = 12 km
AERIAL_MB = 12000.0 / 0.153
co, so, cp, spp, ck, sk = (sp.cos(omega), sp.sin(omega), sp.cos(phi), sp.sin(phi),
                           sp.cos(kappa), sp.sin(kappa))


def printed_matrix():
    """R_ωφκ as printed (element (1,1) is cos ω cos κ)."""
    return sp.Matrix([[co * ck, co * sk + so * spp * ck, so * sk - co * spp * ck],
                      [-cp * sk, co * ck - so * spp * sk, so * ck + co * spp * sk],
                      [spp, -so * cp, co * cp]])


def _collinearity_printed(R=None):
    r = col.r if R is None else list(R)
    d = [col.X - col.X0, col.Y - col.Y0, col.Z - col.Z0]
    den = sum(r[3 * i + 2] * d[i] for i in range(3))
    return sp.Matrix([-col.c * sum(r[3 * i] * d[i] for i in range(3)) / den,
                      -col.c * sum(r[3 * i + 1] * d[i] for i in range(3)) / den])


def records():
    out = []
    out.append(formula(
        "hu-wiki:collinearity", SRC, "collinearity equations without principal point",
        {"printed": VersionSpec("right-under-condition: ξ, η reduced to the principal point "
                                "(x'0 = y'0 = 0); r_ij elements of R (image → object)",
                                expr=_collinearity_printed, condition={col.x0: 0, col.y0: 0},
                                condition_text="ξ, η reduced to the principal point "
                                               "(x'0 = y'0 = 0); r_ij elements of R (image → "
                                               "object)", claim="right")},
        derivation=lambda: sp.Matrix(col.image_coordinates(col.rotation_symbols()))))
    out.append(formula(
        "hu-wiki:rotation-matrix", SRC, "rotation matrix R_ωφκ",
        {"printed": VersionSpec("wrong", expr=printed_matrix, claim="right")},
        derivation=wolf_m,
        steps=("R = R_ω·R_φ·R_κ from the matrix exponentials of the axis generators",
               "the printed matrix is laid out as Wolf's M = Rᵀ (object → image)",
               "element (1,1) must be cos φ cos κ; the article prints cos ω cos κ"),
        note="With m11 = cos φ·cos κ the printed matrix equals Rᵀ of the course; as printed it "
             "is not even orthogonal (ω = 0.5, φ = κ = 0 gives m11 = cos 0.5)."))
    out.append(formula(
        "hu-wiki:collinearity-with-printed-matrix", SRC, "the article's collinearity equation "
        "evaluated with the article's own matrix",
        {"printed": VersionSpec("wrong", expr=lambda: _collinearity_printed(printed_matrix()),
                                claim="right")},
        derivation=lambda: sp.Matrix(col.image_coordinates(rotation_opk())).subs(
            {col.x0: 0, col.y0: 0}),
        note="The equation uses r11, r21, r31 (columns of R) but the matrix is laid out as "
             "M = Rᵀ: combining them transposes the rotation. With Rᵀ's elements the sums "
             "must run over rows."))
    out.append(Record(
        id="hu-wiki:accuracy-analogue", source=ART + ", 'Analóg fotogrammetria', line 23",
        item="'A térmodellen mintegy 5-10 méteres pontossággal lehet mérni' (about 5–10 m)",
        kind="example",
        specs={"printed": VersionSpec(ANALOGUE,
                                      check=lambda: _accuracy(ANALOGUE_CASES, (10.0, 10.0),
                                                              ANALOGUE),
                                      claim="right")},
        derivation=lambda: sensors.object_accuracy(),
        steps=("object precision σ_X = m_b·σ' (image scale 1 : m_b)",
               "analogue plotters measure to σ' ≈ 5–10 µm in the image",
               "5–10 m therefore needs m_b = 10⁶ (or 5·10⁵–10⁶ at σ' = 10 µm)",
               "aerial images: m_b ≤ H/c = 12 km/153 mm ≈ 7.8·10⁴, σ_X ≤ 0.8 m"),
        note="The model of an analogue plotter is a reduced copy (kicsinyített modell) a few "
             "decimetres across, so 5–10 m cannot be a model-space figure; the numbers are the "
             "plotters' image accuracies in µm. Right in metres for space photographs at about "
             "1 : 10⁶."))
    out.append(Record(
        id="hu-wiki:accuracy-analytical", source=ART + ", 'Analitikus fotogrammetria', line 27",
        item="'A mérés során 3–5 m pontosság érhető el' (3–5 m)", kind="example",
        specs={"printed": VersionSpec(ANALYTICAL,
                                      check=lambda: _accuracy(ANALYTICAL_CASES, (5.0, 5.0),
                                                              ANALYTICAL),
                                      claim="right")},
        derivation=lambda: sensors.object_accuracy(),
        steps=("object precision σ_X = m_b·σ'",
               "analytical plotters measure to σ' ≈ 2–5 µm in the image",
               "3–5 m therefore needs m_b = 10⁶ (1–1.7·10⁶ at σ' = 3 µm)",
               "aerial images: m_b ≤ 7.8·10⁴, σ_X ≤ 0.4 m"),
        note="Same scale number 10⁶ as the analogue figure: both printed ranges are the "
             "instruments' image accuracies in µm read as metres."))
    out.append(Record(
        id="hu-wiki:digital-accuracy", source=ART + ", 'Digitális fotogrammetria', line 31",
        item="'A mérés pontosságát nagy mértékben a digitális kép felbontása határozza meg'",
        kind="text", specs={"printed": VersionSpec(DIGITAL, check=_digital, claim="right")},
        derivation=lambda: sensors.object_accuracy(sp.Symbol("s", positive=True) * sensors.p,
                                                   sensors.H / sensors.c)))
    out.append(Record(
        id="hu-wiki:history", source=ART + ", 'A fotogrammetria története', lines 15–17",
        item="Meydenbauer 1858 (Wetzlar), the word in 1867, ISP founded in Vienna in 1910",
        kind="text", specs={"printed": VersionSpec(
            "not-checkable: historical dates, no formula to derive", claim="right")}))
    return out


AERIAL_TEXT = "at aerial scales (m_b ≤ 7.8·10⁴: c = 153 mm, H = 12 km) the same σ' is"
ANALOGUE = ("right-under-condition: object-space accuracy at an image scale number m_b ≈ 10⁶ "
            "(σ' = 5–10 µm in the image, 1 µm ↔ 1 m: space photographs); " + AERIAL_TEXT
            + " ≤ 0.8 m, so µm in the image were probably meant")
ANALYTICAL = ("right-under-condition: object-space accuracy at an image scale number m_b ≈ 10⁶ "
              "(σ' = 3–5 µm in the image, 1 µm ↔ 1 m: space photographs); " + AERIAL_TEXT
              + " ≤ 0.4 m, so µm in the image were probably meant")
DIGITAL = ("right-under-condition: 'felbontás' read as the ground pixel size GSD = p·H/c with "
           "a fixed measuring precision in pixels (σ' = s·p): σ_X = s·GSD")


def _accuracy(cases, aerial, verdict) -> Evidence:
    """Rows (quantity, printed m, σ_X = m_b·σ', tolerance): the condition rows must agree,
    the aerial row shows that the figure does not hold at aerial scales."""
    f = sp.lambdify((sensors.sigma_img, sensors.m_b), sensors.object_accuracy())
    rows = [(f"{printed:g} m at m_b = {mb:.4g}, σ' = {um:g} µm", printed, f(um * 1e-6, mb), 0.05)
            for printed, mb, um in cases]
    printed, um = aerial
    rows.append((f"{printed:g} m at aerial m_b = {AERIAL_MB:.4g}, σ' = {um:g} µm", printed,
                 f(um * 1e-6, AERIAL_MB), 0.05))
    table = [(n, float(a), float(b), t, abs(float(a) - float(b)) <= t) for n, a, b, t in rows]
    cond_ok = all(r[4] for r in table[:-1])
    if cond_ok and not table[-1][4]:
        return Evidence(verdict, "σ_X = m_b·σ': the printed metres are the µm of the image "
                        "times 10⁶; at aerial scales they are far too large", table=table)
    return Evidence("right" if cond_ok else "wrong", "σ_X = m_b·σ'", table=table)


#: (printed bound in m, image scale number, image accuracy in µm)
ANALOGUE_CASES = ((5.0, 1e6, 5.0), (10.0, 1e6, 10.0), (5.0, 5e5, 10.0))
ANALYTICAL_CASES = ((3.0, 1e6, 3.0), (5.0, 1e6, 5.0), (5.0, 5e6 / 3, 3.0))


def _digital() -> Evidence:
    s = sensors
    step = sp.Symbol("s", positive=True)
    sig = s.object_accuracy(step * s.p, s.H / s.c)
    ok = sp.simplify(sig - step * s.gsd_vertical()) == 0 and sp.diff(sig, s.p) != 0
    return Evidence(DIGITAL if ok else "wrong", f"σ_X = m_b·σ' = {sig} = s·GSD")
