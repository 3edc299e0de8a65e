"""German lecture summary (000_*): optics — refraction, lens, angles, depth of field, cos⁴.

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


def records():
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
    out.append(formula(
        "de-summary:image-radius", SRC + ", 'Reale Optische Abbildung'", "r' = c·tan τ + Δr'",
        {"printed": VersionSpec("right", expr=lambda: o.c_cam * sp.tan(o.tau)
                                + sp.Symbol("Delta_r", real=True), claim="right")},
        derivation=lambda: o.c_cam * sp.tan(o.tau) + sp.Symbol("Delta_r", real=True),
        note="Ideal radius c·tan τ (pinhole at O', τ = τ'), Δr' = distorted − ideal: a "
             "definition consistent with the course's sign."))
    return out
