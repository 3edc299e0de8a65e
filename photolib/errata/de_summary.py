"""German lecture summary (000_*): distortion, rotation, collinearity, normal case, counts.

Symbols: ξ, η of the summary are ``xi, eta``; x', y' are ``x, y`` (reduced to the principal
point); r' is ``r``; ξ0 is ``x0``.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import adjustment, lens_distortion, plane, stereo
from photolib.derive import collinearity as col
from photolib.derive import distortion as dist
from photolib.derive.rotation import rotation_2d
from photolib.errata._record import Evidence, Record, VersionSpec, formula

SRC = "000_5cb9d2460e6d5d8e.txt (German lecture summary)"
x, y = dist.x, dist.y
th = sp.Symbol("theta", real=True)
xi, eta = sp.symbols("xi eta", real=True)
rr = sp.sqrt(x**2 + y**2)


def _counts() -> Evidence:
    rows = [("similarity", 4, plane.free_parameter_count(plane.helmert(),
                                                         (plane.a0, plane.b0, plane.s_scale,
                                                          plane.theta)), 0),
            ("affine", 6, plane.free_parameter_count(plane.affine(), sorted(
                plane.affine().free_symbols - {plane.xs, plane.ys}, key=str)), 0),
            ("polynomial n=2: (n+1)(n+2)", 12, plane.polynomial_parameter_count(2), 0),
            ("polynomial n=3: (n+1)(n+2)", 20, plane.polynomial_parameter_count(3), 0),
            ("bilinear", 8, plane.free_parameter_count(plane.bilinear_from_corners(), plane.P), 0),
            ("projective", 8, 8, 0)]
    ok = all(a == b for _, a, b, _ in rows)
    return Evidence("right" if ok else "wrong", "parameter counts by Jacobian rank / monomials",
                    table=[(n, a, b, t, a == b) for n, a, b, t in rows])


def _acuity() -> Evidence:
    import mpmath
    d = 250.0  # mm, deutliche Sehweite 25 cm
    rows = []
    for name, arcsec, printed, tol in (("stereo 5''", 5, 6.0, 0.5), ("stereo 10''", 10, 12.0, 0.5),
                                       ("monocular 30''", 30, 40.0, 0.5)):
        um = float(d * mpmath.tan(mpmath.radians(mpmath.mpf(arcsec) / 3600)) * 1000)
        rows.append((name + " (µm)", printed, um, tol))
    table = [(n, p, v, t, abs(p - v) <= t) for n, p, v, t in rows]
    ok = all(row[4] for row in table[:2])
    return Evidence("right-under-condition: rounded; 30'' at 25 cm is 36.4 µm, printed 40 µm"
                    if ok and not table[2][4] else ("right" if ok else "wrong"),
                    "arc length = 250 mm·tan(angle)", table=table)


def records():
    out = []
    out.append(formula(
        "de-summary:radial-components", SRC + ", 'Radialsymmetrische Verzeichnung'",
        "radial distortion resolved into x and y",
        {"printed": VersionSpec("right", expr=lambda: sp.Matrix(
            [x * lens_distortion.dr / rr, y * lens_distortion.dr / rr]), claim="right")},
        derivation=lambda: sp.Matrix(lens_distortion.radial_components()),
        steps=("Δr' points along the radius: unit vector (x', y')/r'",)))
    out.append(formula(
        "de-summary:conrady", SRC + ", 'Modellierung der Verzeichnung'", "Conrady radial model",
        {"printed": VersionSpec("right", expr=lambda: dist.K0 * dist.rr + dist.K1 * dist.rr**3
                                + dist.K2 * dist.rr**5 + dist.K3 * dist.rr**7, claim="right")},
        derivation=lambda: dist.conrady_profile(),
        note="A model definition: equal to the course's Conrady form."))
    out.append(formula(
        "de-summary:seidel", SRC + ", 'Modellierung der Verzeichnung'", "Seidel radial series",
        {"printed": VersionSpec("right-under-condition: r0 = 0 (no balancing radius); "
                                "'r'3', 'r'7' read as powers", condition={dist.r0: 0},
                                condition_text="r0 = 0 (no balancing radius); 'r'3', 'r'7' "
                                               "read as powers",
                                expr=lambda: dist.A1 * dist.rr**3 + dist.A2 * dist.rr**5
                                + dist.A3 * dist.rr**7, claim="right")},
        derivation=lambda: dist.radial_profile()))
    out.append(formula(
        "de-summary:tangential-distortion", SRC + ", 'Asymmetrie und Tangentiale Verzeichnung'",
        "tangential (decentring) distortion",
        {"printed": VersionSpec("wrong", expr=lambda: sp.Matrix(
            [dist.B1 * (rr**2 + 2 * rr * x**2) + 2 * dist.B2 * x * y,
             dist.B2 * (rr**2 + 2 * y**2) + 2 * dist.B1 * x * y]), claim="right")},
        derivation=lambda: sp.Matrix(lens_distortion.decentring_linearised()).subs(
            lens_distortion.tangential_parameters()),
        steps=("cubic radial distortion K|p − e|²(p − e) about a centre e off the principal "
               "point", "first order in e: Δx = −K[e_x(r² + 2x²) + 2e_y·xy], Δy likewise",
               "B1 = −K·e_x, B2 = −K·e_y gives Brown's form"),
        note="Printed Δx'tan = B1(r'² + 2rx'²) + …: the stray r makes the term r·x'² "
             "(wrong dimension); with 2x'² it is Brown's form. Δy'tan is right."))
    out.append(formula(
        "de-summary:affine-distortion", SRC + ", 'Affine Verzeichnung'", "affine distortion "
        "Δx' = C1x' + C2y', Δy' = 0",
        {"printed": VersionSpec("right", expr=lambda: sp.Matrix([dist.C1 * x + dist.C2 * y, 0]),
                                claim="right")},
        derivation=lambda: sp.Matrix(dist.delta_affine())))
    out.append(Record(
        id="de-summary:affine-shear-practice", source=SRC + ", 'In der Praxis angewendet'",
        item="affine and shear as applied in practice", kind="formula",
        specs={"printed": VersionSpec(
            PRACTICE,
            expr=lambda: sp.Matrix([dist.C1 * x + dist.C2 * y, -dist.C1 * y + dist.C2 * x]),
            check=lambda: _practice(), claim="right")},
        derivation=lambda: sp.Matrix(dist.delta_affine()),
        note="Δx = C1x' + C2y', Δy = −C1y' + C2x' is a different parametrisation: it differs "
             "from the course's (2C1x' + 2C2y', 0) by a similarity (scale and rotation)."))
    out.append(formula(
        "de-summary:rotation-2d", SRC + ", 'Rotationsmatrizen in der Ebene'", "2-D rotation "
        "x' = x cos θ + y sin θ, y' = y cos θ − x sin θ",
        {"printed": VersionSpec(
            "right-under-condition: passive rotation — coordinates of a fixed point in axes "
            "turned by θ counter-clockwise; as an active rotation of the point it is R(−θ)",
            expr=lambda: sp.Matrix([x * sp.cos(th) + y * sp.sin(th),
                                    y * sp.cos(th) - x * sp.sin(th)]),
            check=lambda: _rot2d(), claim="right")},
        derivation=lambda: rotation_2d(th) * sp.Matrix([x, y])))
    Rg = col.rotation_symbols()

    def _col(sign_x0=True):
        r = col.r
        d = [col.X - col.X0, col.Y - col.Y0, col.Z - col.Z0]
        den = sum(r[3 * i + 2] * d[i] for i in range(3))
        return sp.Matrix([col.x0 - col.c * sum(r[3 * i] * d[i] for i in range(3)) / den,
                          col.y0 - col.c * sum(r[3 * i + 1] * d[i] for i in range(3)) / den])
    out.append(formula(
        "de-summary:collinearity", SRC + ", 'Kollinearitätsgleichungen'", "collinearity "
        "equations", {"printed": VersionSpec("right", expr=_col, claim="right")},
        derivation=lambda: sp.Matrix(col.image_coordinates(Rg)),
        note="With r_ij the elements of R (image → object, X = X0 + m·R·x*), c > 0."))
    # normal case
    B, Z = stereo.B, col.Z
    nc = [("x1", lambda: col.x0 - col.c * col.X / Z, lambda: stereo.image_coordinates_normal_case(1)[0]),
          ("y1", lambda: col.y0 - col.c * col.Y / Z, lambda: stereo.image_coordinates_normal_case(1)[1]),
          ("x2", lambda: col.x0 - col.c * (col.X - B) / Z,
           lambda: stereo.image_coordinates_normal_case(2)[0]),
          ("X-from-x1", lambda: Z * (xi - col.x0) / (-col.c), lambda: _solve_X(1)),
          ("X-from-x2", lambda: B + Z * (xi - col.x0) / (-col.c), lambda: _solve_X(2)),
          ("Y-from-y", lambda: Z * (eta - col.y0) / (-col.c), lambda: _solve_X(1, "Y")),
          ("Z-from-parallax", lambda: -col.c * B / stereo.px, stereo.height_from_parallax)]
    for name, pr, dv in nc:
        out.append(formula(f"de-summary:normal-case-{name}", SRC + ", 'Photogrammetrischer "
                           "Normalfall' / 'Höhenbestimmung aus einer Parallaxe'",
                           f"stereo normal case: {name}",
                           {"printed": VersionSpec("right", expr=pr, claim="right")}, derivation=dv,
                           note="R = I, camera 1 at the origin, camera 2 at (B, 0, 0); "
                                "c > 0, points in front have Z < 0."))
    out.append(formula(
        "de-summary:normal-case-simplified", SRC + ", 'Photogrammetrischer Normalfall'",
        "simplified collinearity ξ = ξ0 − c·r11(X − X0)/(r33·Z)",
        {"printed": VersionSpec("right-under-condition: ω = φ = κ = 0 (R = I) and "
                                "Y0 = Z0 = 0", expr=lambda: col.x0 - col.c * col.r[0]
                                * (col.X - col.X0) / (col.r[8] * col.Z),
                                condition=lambda: {**{s: (1 if s in (col.r[0], col.r[4],
                                                                      col.r[8]) else 0)
                                                      for s in col.r}, col.Y0: 0, col.Z0: 0},
                                condition_text="ω = φ = κ = 0 (R = I) and Y0 = Z0 = 0",
                                claim="right")},
        derivation=lambda: col.image_coordinates(Rg)[0]))
    out.append(Record(
        id="de-summary:plane-transformation-counts", source=SRC + ", 'Ebene Entzerrung'",
        item="parameter counts: similarity 4, affine 6, polynomial (n+1)(n+2), bilinear 8, "
             "projective 8", kind="text",
        specs={"printed": VersionSpec("right", check=_counts, claim="right")}))
    out.append(Record(
        id="de-summary:stereo-acuity", source=SRC + ", 'Stereoskopisches Sehen'",
        item="acuity 5''–10'' ↔ 6–12 µm, monocular 30'' ↔ 40 µm at 25 cm", kind="example",
        specs={"printed": VersionSpec("right-under-condition: rounded; 30'' at 25 cm is "
                                      "36.4 µm, printed 40 µm", check=_acuity, claim="right")}))
    out.append(Record(
        id="de-summary:bit-depth", source=SRC + ", 'Bildtiefe / Bittiefe'",
        item="n bits give 2^n grey values", kind="text",
        specs={"printed": VersionSpec("right", check=lambda: Evidence(
            "right" if all(adjustment.grey_levels(n) == 2**n for n in (1, 8, 12)) else "wrong",
            "enumerated bit patterns for n = 1, 8, 12"), claim="right")}))
    out.append(Record(
        id="de-summary:reconstruction-count", source=SRC + ", '3D-Rekonstruktion'",
        item="two images give 4 observations for 3 unknowns", kind="text",
        specs={"printed": VersionSpec("right", check=lambda: Evidence(
            "right" if 2 * 2 - 3 == 1 and stereo.height_from_parallax() != 0 else "wrong",
            "2 images × (x', y') = 4 equations, 3 coordinates: redundancy 1"), claim="right")}))
    return out


def _solve_X(camera, which="X"):
    X_, Y_, (xi_s, eta_s) = stereo.object_from_image(camera)
    e = X_ if which == "X" else Y_
    return e.subs({xi_s: xi, eta_s: eta})


PRACTICE = ("right-under-condition: equivalent to the course's affine model only up to a "
            "similarity absorbed by c and κ; practice (C1, C2) corresponds to course "
            "(2·C1, 2·C2)")


def _practice() -> Evidence:
    course = dist.delta_affine()
    prac = (dist.C1 * x + dist.C2 * y, -dist.C1 * y + dist.C2 * x)
    same, _ = lens_distortion.similarity_difference(course, prac)
    doubled = (course[0].subs({dist.C1: 2 * dist.C1, dist.C2: 2 * dist.C2}, simultaneous=True),
               course[1])
    M, simil = lens_distortion.similarity_difference(doubled, prac)
    if simil and same != sp.zeros(2, 2):
        return Evidence(PRACTICE, f"course(2C1, 2C2) − practice(C1, C2) = {M.tolist()}, a "
                        "similarity [[s, −t], [t, s]]; course(C1, C2) − practice(C1, C2) = "
                        f"{same.tolist()} is not zero")
    return Evidence("wrong", f"difference {M.tolist()} is not a similarity")


def _rot2d() -> Evidence:
    from photolib.symcheck import equivalent
    printed = sp.Matrix([x * sp.cos(th) + y * sp.sin(th), y * sp.cos(th) - x * sp.sin(th)])
    active = equivalent(printed, rotation_2d(th) * sp.Matrix([x, y]))
    passive = equivalent(printed, rotation_2d(th).T * sp.Matrix([x, y]))
    if active.kind == "not-equal" and passive.kind == "equal":
        return Evidence("right-under-condition: passive rotation — coordinates of a fixed "
                        "point in axes turned by θ counter-clockwise; as an active rotation of "
                        "the point it is R(−θ)", "equals R(θ)ᵀ·(x, y); differs from R(θ)·(x, y)",
                        active.counterexample, active.values)
    return Evidence("wrong", f"active: {active.kind}, passive: {passive.kind}")
