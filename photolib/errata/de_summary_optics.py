"""German lecture summary (000_*): optics — refraction, lens, angles, depth of field, cos⁴,
chromatic aberration and the stop, the permissible blur u' = s'/1500.

Symbols: ``a`` focus distance, ``a_p`` image distance a', ``a_v``/``a_h`` near/far limit,
``u_p`` blur diameter u', ``k`` f-number, ``m_b`` image scale number, ``s_p`` format s',
``d_p`` pupil d', ``tau`` τ.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import optics as o
from photolib.errata._record import Evidence, Record, VersionSpec, formula

SRC = "000_5cb9d2460e6d5d8e.txt (German lecture summary)"
alpha, beta, Omega = sp.symbols("alpha beta Omega", positive=True)


def _snell() -> Evidence:
    dT, sa, sb = o.snell_from_fermat()
    law = o.n1 * sa - o.n2 * sb          # printed n1 sin α = n2 sin β, as a residual
    ok = sp.simplify(dT - law) == 0
    return Evidence("right" if ok else "wrong", "c0·dT/du = n1 sin α − n2 sin β (Fermat)")


def _reflection() -> Evidence:
    dT, sa, sb = o.reflection_from_fermat()
    ok = sp.simplify(dT - (sa - sb)) == 0
    return Evidence("right" if ok else "wrong", "dT/du = sin α − sin β: stationary iff α = β")


def _kd() -> Evidence:
    d = sp.Symbol("d", positive=True)
    ok = sp.simplify((d / o.f) * (o.f / d)) == 1
    return Evidence("right" if ok else "wrong", "k = f/d is the reciprocal of the relative "
                    "aperture d/f (definitions)")


def _records_rays() -> list:
    """Refraction, reflection, the imaging equation and scale, the field angle."""
    out = []
    out.append(Record(
        id="de-summary:refraction-snell", source=SRC + ", 'Lichtbrechung'",
        item="n1·sin α = n2·sin β", kind="formula",
        specs={"printed": VersionSpec("right", check=_snell,
                                      expr=lambda: o.n1 * sp.sin(alpha) - o.n2 * sp.sin(beta),
                                      claim="right")},
        steps=("travel time T(u) = (n1√(h1² + u²) + n2√(h2² + (d − u)²))/c0",
               "dT/du = 0 ⇔ n1 sin α = n2 sin β")))
    out.append(Record(
        id="de-summary:refraction-index", source=SRC + ", 'Lichtbrechung'",
        item="n = C_Luft / C_Medium", kind="text",
        specs={"printed": VersionSpec(
            "right-under-condition: index relative to air; the absolute index uses the "
            "vacuum speed (n_air ≈ 1.0003)", check=lambda: Evidence(
                "right-under-condition: index relative to air; the absolute index uses the "
                "vacuum speed (n_air ≈ 1.0003)", "a definition"), claim="right")}))
    out.append(Record(
        id="de-summary:reflection", source=SRC + ", 'Reflektion'", item="α = β",
        kind="formula", specs={"printed": VersionSpec("right", check=_reflection, claim="right")}))
    out.append(formula(
        "de-summary:imaging-equation", SRC + ", 'Abbildungsgleichung und -maßstab'",
        "thin-lens imaging equation 1/a + 1/a' = 1/f",
        {"printed": VersionSpec("not-checkable: the formula is only in a picture that is not "
                                "available", claim="right")},
        derivation=o.imaging_equation_residual,
        steps=("centre ray y = −Hz/a and focal ray y = H(1 − z/f) meet at z = a' = af/(a − f)",
               "so 1/a + 1/a' = 1/f"),
        note="Derived for the course; the summary shows it only as an image."))
    out.append(formula(
        "de-summary:image-scale", SRC + ", 'Abbildungsgleichung und -maßstab'",
        "image scale M_b = 1 : m_b", {"printed": VersionSpec(
            "not-checkable: only the definition M_b = 1:m_b is printed; m_b = a/a' is in a "
            "missing picture", claim="right")}, derivation=o.image_scale_number))
    out.append(formula(
        "de-summary:field-angle", SRC + ", 'Formatwinkel'", "tan Ω = s'/(2c)",
        {"printed": VersionSpec("right-under-condition: Ω is half the format angle (full "
                                "angle 2Ω), s' the format extent",
                                expr=lambda: o.s_fmt / (2 * o.c_cam), claim="right")},
        derivation=o.half_field_angle_tan, note="Half of s' over c in the right triangle."))
    out[-1].specs["printed"].check = lambda: Evidence(
        "right-under-condition: Ω is half the format angle (full angle 2Ω), s' the format "
        "extent" if sp.simplify(o.s_fmt / (2 * o.c_cam) - o.half_field_angle_tan()) == 0
        else "wrong", "tan(half angle) = (s'/2)/c")
    return out


def _records_aperture() -> list:
    """Aperture angle, f-number, depth of field and the circle of confusion."""
    out = []
    out.append(Record(
        id="de-summary:aperture-angle", source=SRC + ", 'Öffnungswinkel'", item="tan α = d'/(2f)",
        kind="formula", specs={"printed": VersionSpec(
            "right-under-condition: α is half the aperture angle, object at infinity (image "
            "at f)", expr=lambda: o.d_pupil / (2 * o.f), check=lambda: Evidence(
                "right-under-condition: α is half the aperture angle, object at infinity "
                "(image at f)" if sp.simplify(o.d_pupil / (2 * o.f)
                                              - o.half_aperture_angle_tan()) == 0 else "wrong",
                "tan(half angle) = (d'/2)/f"), claim="right")}))
    out.append(Record(
        id="de-summary:f-number", source=SRC + ", 'Lichtstärke'", item="relative aperture "
        "d/f and f-number k = f/d", kind="text",
        specs={"printed": VersionSpec("right", check=_kd, claim="right")}))
    out.append(formula(
        "de-summary:depth-of-field-u", SRC + ", 'Schärfentiefe'",
        "u' = (a_h − a_v)/(a_h + a_v)·f²/(k(a − f))",
        {"printed": VersionSpec("right", expr=lambda: (o.a_h - o.a_v) / (o.a_h + o.a_v)
                                * o.f**2 / (o.k * (o.a - o.f)), claim="right")},
        derivation=lambda: o.up,
        given=lambda: dict(zip((o.a_v, o.a_h), o.dof_limits())),
        domain=lambda: {o.a: (2.0, 5.0), o.f: (0.05, 0.1), o.k: (2.0, 8.0), o.up: (1e-5, 3e-5)},
        steps=("blur in the focused plane of an object at a_x: u'(a_x) = d·(a'_x − a')/a'_x, "
               "d = f/k", "solve u'(a_v) = u', u'(a_h) = −u' for the limits",
               "printed combination of a_h, a_v with these limits gives back u'"),
        note="Thin lens, distances from the lens, u' measured in the image plane."))
    out.append(formula(
        "de-summary:depth-of-field-t", SRC + ", 'Schärfentiefe'",
        "t = a_h − a_v = 2u'k(1 + m_b)/(m_b² − (u'k/f)²)",
        {"printed": VersionSpec("wrong", expr=lambda: 2 * o.up * o.k * (1 + o.m_b)
                                / (o.m_b**2 - (o.up * o.k / o.f) ** 2), claim="right")},
        derivation=o.dof_depth_in_scale_number,
        domain=lambda: {o.m_b: (20.0, 80.0), o.f: (0.05, 0.1), o.k: (2.0, 8.0),
                        o.up: (1e-5, 3e-5)},
        steps=("t = a_h − a_v from the limits", "a = f(1 + m_b) from m_b = a/a' = (a − f)/f",
               "t = 2u'k·m_b(1 + m_b)/(1 − (u'k·m_b/f)²)"),
        note="The printed form is right if m_b is the magnification β = 1/m_b (image scale "
             "M_b), not the scale number the summary names (it also says "
             "'Blendenmaßstabszahl'). With the scale number t shrinks with distance."))
    out.append(Record(
        id="de-summary:circle-of-confusion", source=SRC + ", 'Schärfentiefe', line 135",
        item="u' = Zerstreuungskreis = s'/1500", kind="text",
        specs={"printed": VersionSpec(COC, check=_coc, claim="right")},
        note="A rule for the tolerated blur, not a law: other rules use s'/1000 or s'/1730 "
             "(Zeiss); the depth of field scales with the value chosen."))
    return out


def _records_falloff_aberrations() -> list:
    """Light fall-off, the aperture's and the chromatic aberrations, the real image radius."""
    out = []
    out.append(formula(
        "de-summary:vignetting-cos4", SRC + ", 'Lichtabfall'", "E(τ) = E·cos⁴τ",
        {"printed": VersionSpec("right-under-condition: natural vignetting of a small aperture "
                                "(Lambertian, no pupil distortion); mechanical vignetting "
                                "comes on top", expr=lambda: sp.cos(o.tau) ** 4,
                                check=lambda: Evidence(
                                    "right-under-condition: natural vignetting of a small "
                                    "aperture (Lambertian, no pupil distortion); mechanical "
                                    "vignetting comes on top" if sp.simplify(
                                        o.relative_irradiance() - sp.cos(o.tau) ** 4) == 0
                                    else "wrong", "cos² (distance) · cos (aperture) · cos "
                                    "(incidence) = cos⁴"), claim="right")},
        derivation=o.relative_irradiance))
    out.append(Record(
        id="de-summary:aperture-longitudinal-colour", source=SRC + ", 'Einfluss der Blende', "
        "line 142", item="the stop 'kann chromatische Längsfehler verringern'", kind="text",
        specs={"printed": VersionSpec("right", check=_longitudinal, claim="right")},
        derivation=lambda: o.chromatic_errors()[0], steps=CHROM_STEPS))
    out.append(Record(
        id="de-summary:chromatic-aperture", source=SRC + ", 'Chromatische Abberation', line 159",
        item="'Hohe Blende stellt Strahlen stärker parallel > Verringerung des Effekts'",
        kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {CHROM}", check=_chromatic,
                                      claim="right")},
        derivation=o.chromatic_errors, steps=CHROM_STEPS,
        note="The summary itself goes on to distinguish Längs- and Querfehler (lines 164–166); "
             "stopping down shrinks every colour's blur but leaves the colour fringes of the "
             "lateral error where they are."))
    out.append(formula(
        "de-summary:image-radius", SRC + ", 'Reale Optische Abbildung'", "r' = c·tan τ + Δr'",
        {"printed": VersionSpec("right", expr=lambda: o.c_cam * sp.tan(o.tau)
                                + sp.Symbol("Delta_r", real=True), claim="right")},
        derivation=lambda: o.c_cam * sp.tan(o.tau) + sp.Symbol("Delta_r", real=True),
        note="Ideal radius c·tan τ (pinhole at O', τ = τ'), Δr' = distorted − ideal: a "
             "definition consistent with the course's sign."))
    return out


def records():
    """The optics records of the summary, in catalogue order (the groups above)."""
    return _records_rays() + _records_aperture() + _records_falloff_aberrations()


COC = ("not-checkable: a convention for the tolerated blur: s'/1500 seen from a distance equal "
       "to the format s' subtends 1/1500 rad = 2.29′, a chosen tolerance of the eye, not a "
       "consequence of a formula")


def _coc() -> Evidence:
    import mpmath
    arcmin = float(mpmath.degrees(mpmath.mpf(1) / 1500) * 60)
    text = f"1/1500 rad = {arcmin:.2f}′"
    if text not in COC:
        return Evidence("wrong", f"conversion in the verdict text is off: {text}")
    return Evidence(COC, text + "; the rule fixes u', nothing in it can be derived")


CHROM = ("the longitudinal colour error (Längsfehler): the blur of a wavelength focused "
         "elsewhere is (f/k)·|1 − f_1/f_2|, smaller at a higher f-number k; the lateral error "
         "(Querfehler, the colour fringes) is the shift s·tan τ·(f_2 − f_1)/f_2 of the chief "
         "ray through the middle of the stop, which k does not change")
CHROM_STEPS = (
    "thin lens, focal length f_λ per wavelength, stop of diameter d = f/k at s in front",
    "ray of a parallel bundle at field angle τ through the stop at height ρ: height "
    "(ρ + s·tan τ)(1 − a'/f_λ) + a'·tan τ in the image plane at a'",
    "plane focused for f_1 (a' = f_1): wavelength 2 has blur d·|1 − f_1/f_2| (ρ = ±d/2)",
    "spot centres (ρ = 0, chief ray) of the two wavelengths: apart by s·tan τ·(f_2 − f_1)/f_2, "
    "no d in it")
#: a 50 mm lens, f_2 − f_1 = 0.25 mm, stop 10 mm in front, field angle 20°
CHROM_CASE = {o.f: 50, o.f_1: 50, o.f_2: sp.Rational(201, 4), o.s_stop: 10,
              o.tau: sp.pi / 9}


def _chromatic_rows():
    blur, lateral = o.chromatic_errors()
    rows = []
    for kk in (2, 8):
        at = {**CHROM_CASE, o.k: kk}
        rows.append((f"longitudinal blur at k = {kk} (µm)", None,
                     float(sp.N(blur.subs(at))) * 1000, None, True))
        rows.append((f"lateral shift at k = {kk} (µm)", None,
                     float(sp.N(lateral.subs(at))) * 1000, None, True))
    return blur, lateral, rows


def _longitudinal() -> Evidence:
    blur, _, rows = _chromatic_rows()
    falls = sp.simplify(sp.diff(blur, o.k) * o.k / blur) == -1
    if falls:
        return Evidence("right", "blur (f/k)·|1 − f_1/f_2| ∝ 1/k: stopping down (higher k) "
                        "shrinks it, 4× from k = 2 to k = 8", table=rows[::2])
    return Evidence("wrong", f"blur {blur} does not fall with k", table=rows)


def _chromatic() -> Evidence:
    blur, lateral, rows = _chromatic_rows()
    falls = sp.simplify(sp.diff(blur, o.k) * o.k / blur) == -1
    fixed = sp.diff(lateral, o.k) == 0 and lateral.subs(CHROM_CASE) != 0
    if falls and fixed:
        return Evidence(f"right-under-condition: {CHROM}", f"longitudinal blur {blur} ∝ 1/k; "
                        f"lateral shift {lateral}: ∂/∂k = 0 (zero only with the stop at the "
                        "lens, s = 0)", table=rows)
    return Evidence("wrong" if not falls else "right", f"blur {blur}, lateral {lateral}",
                    table=rows)
