"""German lecture summary (000_*): distortion, rotation, collinearity, normal case, counts,
image vector, exterior orientation, attitude angles, metric camera, stereo fusion.

Symbols: ξ, η of the summary are ``xi, eta``; x', y' are ``x, y`` (reduced to the principal
point); r' is ``r``; ξ0 is ``x0``; Δξ, Δη are ``Delta_xi, Delta_eta``; the unspecified
"Korrekturen" of the image vector are ``K_x, K_y, K_z``.
"""

from __future__ import annotations

import mpmath
import sympy as sp

from photolib.derive import adjustment, lens_distortion, orientation, plane, stereo
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


def _records_distortion() -> list:
    """Radial, Conrady, Seidel, tangential and affine distortion (the summary's 'Verzeichnung')."""
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
    return out


def _records_rotation_2d() -> list:
    """The plane rotation of 'Rotationsmatrizen in der Ebene': printed lines and commented-out pair."""
    out = []
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
    out.append(formula(
        "de-summary:rotation-2d-comment", SRC + ", 'Rotationsmatrizen in der Ebene', lines 357 "
        "and 359 (inside an HTML comment)", "2-D rotation (x', y') = M·(x, y) and its inverse "
        "(x, y) = M⁻¹·(x', y'), each matrix printed as one column cos θ, sin θ | −sin θ, cos θ",
        {"printed": VersionSpec(ROT2D_COMMENT, expr=lambda: _rot2d_comment("rows"),
                                check=_rot2d_comment_evidence, claim="right")},
        derivation=_rot2d_passive_pair,
        steps=("coordinates of a fixed point in axes turned by θ: (x', y') = R(θ)ᵀ·(x, y), "
               "back: (x, y) = R(θ)·(x', y') (R(θ) the course's plane rotation)",
               "the comment stacks four entries in one column with a '|' in the middle: "
               "read as two rows or as two columns",
               "both readings compared with the derivation, and the two matrices multiplied"),
        note="The layout is ambiguous: the source writes each 2×2 matrix as a single column "
             "'cos θ, sin θ | −sin θ, cos θ'. Read row by row (the expression shown), the "
             "first matrix is the one of the summary's own lines 345 and 353; read column by "
             "column it is R(θ), the active rotation, and contradicts them. Under either "
             "reading the second matrix is the inverse of the first."))
    return out


def _records_collinearity() -> list:
    """Collinearity equations and the stereo normal case with its simplified ξ and η lines."""
    out = []
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
          ("y2", lambda: col.y0 - col.c * col.Y / Z,
           lambda: stereo.image_coordinates_normal_case(2)[1]),
          ("X-from-x1", lambda: Z * (xi - col.x0) / (-col.c), lambda: _solve_X(1)),
          ("X-from-x2", lambda: B + Z * (xi - col.x0) / (-col.c), lambda: _solve_X(2)),
          ("Y-from-y", lambda: Z * (eta - col.y0) / (-col.c), lambda: _solve_X(1, "Y")),
          ("Y-from-y2", lambda: Z * (eta - col.y0) / (-col.c), lambda: _solve_X(2, "Y")),
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
        {"printed": VersionSpec(f"right-under-condition: {NORMAL_CASE_XI}",
                                expr=lambda: col.x0 - col.c * col.r[0]
                                * (col.X - col.X0) / (col.r[8] * col.Z),
                                condition=lambda: {**{s: (1 if s in (col.r[0], col.r[4],
                                                                      col.r[8]) else 0)
                                                      for s in col.r}, col.Z0: 0},
                                condition_text=NORMAL_CASE_XI, claim="right")},
        derivation=lambda: col.image_coordinates(Rg)[0],
        steps=("ξ = ξ0 − c·(r11ΔX + r21ΔY + r31ΔZ)/(r13ΔX + r23ΔY + r33ΔZ) (collinearity)",
               "R = I: ξ = ξ0 − c·(X − X0)/(Z − Z0); Y0 does not occur",
               "Z0 = 0: ξ = ξ0 − c·r11(X − X0)/(r33·Z), the printed line"),
        note="Unlike the η line (de-summary:normal-case-simplified-eta), the ξ line needs no "
             "Y0 = 0: with R = I the ΔY term drops out of both numerator and denominator."))
    out.append(formula(
        "de-summary:normal-case-simplified-eta", SRC + ", 'Photogrammetrischer Normalfall', "
        "line 565", "simplified collinearity η = η0 − c·r22·Y/(r33·Z)",
        {"printed": VersionSpec(f"right-under-condition: {NORMAL_CASE}",
                                expr=lambda: col.y0 - col.c * col.r[4] * col.Y
                                / (col.r[8] * col.Z), condition=_normal_case_condition,
                                condition_text=NORMAL_CASE, claim="right")},
        derivation=lambda: col.image_coordinates(Rg)[1],
        steps=("η = η0 − c·(r12ΔX + r22ΔY + r32ΔZ)/(r13ΔX + r23ΔY + r33ΔZ) (collinearity)",
               "R = I: r12 = r32 = r13 = r23 = 0, so η = η0 − c·(Y − Y0)/(Z − Z0)",
               "Y0 = Z0 = 0 for both cameras of the normal case: η = η0 − c·r22·Y/(r33·Z)"),
        note="The same reduction as the ξ line (de-summary:normal-case-simplified): right for "
             "both cameras under the conditions the summary lists just before (lines "
             "557–559); in general the other terms of R and Y0, Z0 are missing."))
    return out


def _records_counts() -> list:
    """Parameter counts, stereo acuity, fusion limit, bit depth, count of a 3-D reconstruction."""
    out = []
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
        id="de-summary:fusion-limit", source=SRC + ", 'Stereoskopisches Sehen', line 65",
        item="stereoscopic parallax not larger than 1.3 gon, otherwise fore- or background "
             "falls apart into two images", kind="text",
        specs={"printed": VersionSpec(FUSION, check=_fusion, claim="right")},
        note="The fusion limit (Panum's area) is measured on observers; the catalogue only "
             "converts the number (1.3 gon = 1.17° = 70.2′)."))
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


def records():
    """The summary's records, in catalogue order: the groups above, then the orientation ones."""
    return (_records_distortion() + _records_rotation_2d() + _records_collinearity()
            + _records_counts() + _orientation_records())


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


ROT2D_COMMENT = ("right-under-condition: the stacked entries read row by row "
                 "(cos θ, sin θ / −sin θ, cos θ), as in the summary's own x' = x cos θ + "
                 "y sin θ, y' = y cos θ − x sin θ (lines 345, 353): the passive rotation and "
                 "its inverse; read column by column the first matrix is R(θ) (active) and "
                 "contradicts those lines. The second matrix is the inverse of the first "
                 "under either reading")
xp, yp = sp.symbols("x_p y_p", real=True)   # x', y' of the comment


def _rot2d_comment_matrices(reading: str):
    """The two matrices of lines 357/359, entries (a, b | c, d) read as rows or as columns."""
    c, s_ = sp.cos(th), sp.sin(th)
    first, second = (c, s_, -s_, c), (c, -s_, s_, c)      # top to bottom, as printed
    if reading == "rows":
        return tuple(sp.Matrix([[e[0], e[1]], [e[2], e[3]]]) for e in (first, second))
    if reading == "columns":
        return tuple(sp.Matrix([[e[0], e[2]], [e[1], e[3]]]) for e in (first, second))
    raise ValueError(f"reading must be 'rows' or 'columns', got {reading!r}")


def _rot2d_comment(reading: str) -> sp.Matrix:
    M, Minv = _rot2d_comment_matrices(reading)
    return sp.Matrix.vstack(M * sp.Matrix([x, y]), Minv * sp.Matrix([xp, yp]))


def _rot2d_passive_pair() -> sp.Matrix:
    R = rotation_2d(th)
    return sp.Matrix.vstack(R.T * sp.Matrix([x, y]), R * sp.Matrix([xp, yp]))


def _rot2d_comment_evidence() -> Evidence:
    from photolib.symcheck import equivalent
    target = _rot2d_passive_pair()
    rows = equivalent(_rot2d_comment("rows"), target)
    cols = equivalent(_rot2d_comment("columns"), target)
    inverse = all(sp.simplify(N * M - sp.eye(2)) == sp.zeros(2, 2)
                  for M, N in map(_rot2d_comment_matrices, ("rows", "columns")))
    if rows.kind == "equal" and cols.kind == "not-equal" and inverse:
        return Evidence(ROT2D_COMMENT, "row-wise: equal to R(θ)ᵀ and R(θ) ("
                        f"{rows.method}); column-wise: differs ({cols.method}); "
                        "M⁻¹·M = I for both readings (simplify); the counterexample is of the "
                        "column-wise reading",
                        cols.counterexample, cols.values)
    return Evidence("wrong", f"rows {rows.kind}, columns {cols.kind}, inverse {inverse}")


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


# -- image vector, exterior orientation, attitude angles, metric camera, stereo fusion ----------

NORMAL_CASE = "ω = φ = κ = 0 (R = I) and Y0 = Z0 = 0"
NORMAL_CASE_XI = "ω = φ = κ = 0 (R = I) and Z0 = 0 (Y0 does not enter the ξ line)"


def _normal_case_condition():
    return {**{s: (1 if s in (col.r[0], col.r[4], col.r[8]) else 0) for s in col.r},
            col.Y0: 0, col.Z0: 0}


FUSION = ("not-checkable: an empirical limit of binocular fusion (Panum's area), a property of "
          "human vision and not a consequence of a formula; 1.3 gon = 1.17° = 70.2′")


def _fusion() -> Evidence:
    deg = sp.Rational(13, 10) * sp.Rational(360, 400)          # 400 gon = 360°
    text = f"1.3 gon = {float(deg):.2f}° = {float(deg * 60):.1f}′"
    if text not in FUSION:
        return Evidence("wrong", f"conversion in the verdict text is off: {text}")
    return Evidence(FUSION, text + " (400 gon = 360°); the limit itself is measured, not derived")


Kx, Ky, Kz = sp.symbols("K_x K_y K_z", real=True)
INTERIOR = ("'Korrekturen' = −(x'0 + Δx', y'0 + Δy', c): the reduction to the principal point "
            "and the camera constant besides the distortion (line 323 names only distortion "
            "and image-plane deformation)")
EO_COUNT = ("six parameters of one exposure (X0, Y0, Z0, ω, φ, κ: the Jacobian of the "
            "collinearity equations has rank 6); the '+1', the time t, is the epoch of the "
            "exposure, a parameter only where the orientation is a function of time (moving "
            "platform, line scanner, image sequence); it does not enter the collinearity "
            "equations of one image")
ATTITUDE = ("X axis along the flight line, Z vertical (near-vertical image): ω, φ, κ turn about "
            "the flight line, the wing axis and the vertical; exactly so for one angle at a "
            "time, to first order otherwise (the course's R_ω·R_φ·R_κ and the yaw-pitch-roll "
            "sequence R_κ·R_φ·R_ω of an inertial system differ in second order)")


def _eo_count() -> Evidence:
    rank, n, sv = orientation.exterior_orientation_rank(with_time=True)
    rigid = adjustment.rigid_motion_parameters()
    table = [("parameters printed (6 + 1) vs independent ones of one exposure (Jacobian rank)",
              7, rank, 0, rank == 7),
             ("rigid motions: rotation generators + shifts", 6, rigid, 0, rigid == 6)]
    if rank == 6 == rigid and n == 7 and abs(sv[-1]) < 1e-20:
        return Evidence(f"right-under-condition: {EO_COUNT}", "∂(x', y')/∂(X0, Y0, Z0, ω, φ, "
                        "κ, t) of four points has rank 6: the column of t is zero (smallest "
                        f"singular value {mpmath.nstr(sv[-1], 3)}, next "
                        f"{mpmath.nstr(sv[-2], 3)})",
                        table=table)
    return Evidence("wrong", f"rank {rank} of {n}", table=table)


def _attitude() -> Evidence:
    axes = orientation.attitude_axes()
    want = {"omega": sp.Matrix([1, 0, 0]), "phi": sp.Matrix([0, 1, 0]),
            "kappa": sp.Matrix([0, 0, 1])}
    D = orientation.yaw_pitch_roll_difference()
    w, p, k = orientation.ANGLES
    zero = dict.fromkeys(orientation.ANGLES, 0)
    first = all(sp.diff(D, a).subs(zero) == sp.zeros(3, 3) for a in orientation.ANGLES)
    second = sp.diff(D, w, p).subs(zero)
    at = {w: sp.Rational(1, 10), p: sp.Rational(1, 5), k: sp.Rational(3, 10)}
    big = max(abs(float(e)) for e in D.subs(at).evalf(20))
    opk = orientation.rotation_opk().subs(at)
    ypr = (orientation.R_kappa() * orientation.R_phi() * orientation.R_omega()).subs(at)
    if axes == want and first and second != sp.zeros(3, 3) and big > 1e-3:
        return Evidence(f"right-under-condition: {ATTITUDE}", "∂R/∂ω, ∂R/∂φ, ∂R/∂κ at 0 are "
                        "[e_X]×, [e_Y]×, [e_Z]×: roll (about the flight line) is ω only if X "
                        "is the flight direction (flying along Y, roll would be φ); "
                        "R_ω·R_φ·R_κ − R_κ·R_φ·R_ω has zero first derivatives at 0, "
                        f"∂²/∂ω∂φ = {second.tolist()}, and its largest element at (ω, φ, κ) = "
                        f"(0.1, 0.2, 0.3) is {big:.4f}", counterexample=at,
                        values=(float(opk[0, 1]), float(ypr[0, 1])))
    return Evidence("wrong", f"axes {axes}, first order zero: {first}")


METRIC = ("the implication 'distortion-free lens (Δr' < 4 µm) > principal point = image "
          "centre' does not hold: the distortion is a function of the coordinates reduced "
          "to the principal point and does not contain x'0, y'0")


def _metric_camera() -> Evidence:
    params = [getattr(dist, n) for n in dist.PARAMETERS] + [dist.r0]
    free = sp.Matrix(dist.delta()).subs(dict.fromkeys(params, 0))
    dr = dist.radial_profile().subs(dict.fromkeys(params, 0))
    axis = orientation.axis_image_point()
    independent = not ({col.x0, col.y0} & sp.Matrix(dist.delta()).free_symbols)
    ce = {col.x0: sp.Rational(1, 50), col.y0: 0}
    pp = tuple(e.subs(ce) for e in axis)
    if free == sp.zeros(2, 1) and dr == 0 and independent and pp != (0, 0):
        return Evidence("wrong", f"{METRIC}: with every distortion parameter zero (Δr' = 0 "
                        "< 4 µm) the camera axis is imaged at (x'0, y'0) = (0.02 mm, 0), not "
                        "at the image centre (0, 0)", counterexample={**ce, **dict.fromkeys(
                            params, 0)}, values=((0, 0), tuple(float(v) for v in pp)))
    return Evidence("right", "distortion and principal point are tied")


def _orientation_records():
    out = []
    out.append(formula(
        "de-summary:image-vector-interior", SRC + ", 'Innere Orientierung', line 385",
        "P' = (x'P, y'P, −c) = (xP, yP, 0) + Korrekturen",
        {"printed": VersionSpec(f"right-under-condition: {INTERIOR}",
                                expr=lambda: sp.Matrix([xi + Kx, eta + Ky, Kz]),
                                condition=lambda: {Kx: -col.x0 - orientation.d_xi,
                                                   Ky: -col.y0 - orientation.d_eta,
                                                   Kz: -col.c},
                                condition_text=INTERIOR, claim="right")},
        derivation=orientation.image_vector,
        steps=("X − X0 = m·R·x* with the third component of x* equal to −c (collinearity)",
               "x* = −c·Rᵀ(X − X0)/N = (x' − x'0, y' − y'0, −c), x' the ideal coordinate",
               "measured ξ = x' + Δξ: x* = (ξ − ξ0 − Δξ, η − η0 − Δη, −c)",
               "(ξ, η, 0) + K equals it for K = −(ξ0 + Δξ, η0 + Δη, c)"),
        note="Right once the 'Korrekturen' are the interior orientation the section lists "
             "(principal point, camera constant, distortion); the measured (xP, yP, 0) "
             "themselves are not the camera-frame vector."))
    out.append(formula(
        "de-summary:image-vector-comment", SRC + ", 'Bildrauminformationen', line 520 (inside "
        "an HTML comment)", "P' = (ξ0 − ξ − Δξ, η0 − η − Δη, −c)",
        {"printed": VersionSpec("wrong", expr=lambda: sp.Matrix(
            [col.x0 - xi - orientation.d_xi, col.y0 - eta - orientation.d_eta, -col.c]),
            claim="right")},
        derivation=orientation.image_vector,
        steps=("x* = (ξ − ξ0 − Δξ, η − η0 − Δη, −c), derived as for "
               "de-summary:image-vector-interior",
               "printed first components ξ0 − ξ − Δξ: the sign of ξ − ξ0 is reversed",
               "X − X0 = m·R·P' would give ξ = ξ0 + c·kx/N − Δξ, against the summary's own "
               "collinearity ξ = ξ0 − c·kx/N (line 496)"),
        note="At ξ = 1, ξ0 = 0, Δξ = 0 the printed first component is −1, the ray needs +1. "
             "It contradicts the summary's own P'(x'P | y'P | −c) (line 319) and its "
             "collinearity equations; the line is commented out of the rendered page."))
    out.append(Record(
        id="de-summary:exterior-orientation-count", source=SRC + ", 'Äußere Orientierung', "
        "lines 398–401", item="exterior orientation: '6 + 1 Parameter' (X0, Y0, Z0, three "
        "angles, time t)", kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {EO_COUNT}", check=_eo_count,
                                      claim="right")},
        derivation=lambda: orientation.exterior_orientation_rank()[0],
        steps=("x', y' of four object points from the collinearity equations, R = R_ω·R_φ·R_κ",
               "Jacobian w.r.t. (X0, Y0, Z0, ω, φ, κ, t) at a generic pose: 8 × 7",
               "singular values (mpmath, 30 digits): six non-zero, the seventh zero (t)"),
        note="A frame image has six orientation parameters (a rigid motion: three rotation "
             "generators, three shifts). The time stamps the exposure; it becomes a parameter "
             "only when the orientation is modelled along a trajectory."))
    out.append(Record(
        id="de-summary:flight-attitude", source=SRC + ", 'Fluglageparameter', lines 440–442",
        item="Querneigung (roll) ω, Längsneigung (pitch) φ, Kantung (yaw) κ", kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {ATTITUDE}", check=_attitude,
                                      claim="right")},
        derivation=orientation.attitude_axes,
        steps=("∂R/∂angle at zero is [axis]× of the axis the angle turns about",
               "ω about X, φ about Y, κ about Z (R = R_ω·R_φ·R_κ)",
               "roll/pitch/yaw turn about the longitudinal axis, the wing axis, the vertical",
               "R_ω·R_φ·R_κ vs R_κ·R_φ·R_ω: equal first derivatives at 0, different second"),
        note="The naming fits the usual aerial set-up (X along the strip). An INS reports "
             "roll, pitch, yaw in its own body frame and order; converting them to ω, φ, κ "
             "needs the boresight rotation and the change of sequence."))
    out.append(Record(
        id="de-summary:metric-camera-principal-point", source=SRC + ", 'Messkamera', line 461",
        item="'Verzeichnungsfreies Objektiv (Δr' < 4 µm) > Bildhauptpunkt = Bildmittelpunkt'",
        kind="text", specs={"printed": VersionSpec("wrong", check=_metric_camera,
                                                   claim="right")},
        derivation=orientation.axis_image_point,
        steps=("distortion model Δ(x, y) in coordinates reduced to the principal point: no "
               "x'0, y'0 in it; all parameters 0 gives Δ = 0",
               "the point on the camera axis is imaged at (x'0, y'0) (collinearity)",
               "x'0 = 0.02 mm with zero distortion: distortion-free, principal point not at "
               "the image centre"),
        note="Read as two separate properties of a metric camera (a nearly distortion-free "
             "lens; a principal point close to the fiducial centre, by construction and "
             "calibration) both hold; the summary writes the second as a consequence of the "
             "first ('>'), and that does not follow."))
    return out
