"""Polish exercise notes (004_*): fiducial transformations, the bundle unknown count, the
projective rectification, VSD's palette and image pyramid, interior orientation.

Symbols: x_s, y_s are the comparator coordinates x_s, y_s of the notes; F1x … F4y the
coordinates of the four fiducial marks (F1–F3 and F2–F4 opposite).
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import adjustment, optics, plane, sensors
from photolib.errata._record import Evidence, Record, VersionSpec, formula, numbers_evidence

SRC = "004_81219dec3a1f2881.txt (Polish exercise notes)"
xs, ys = plane.xs, plane.ys
a0, a1, a2, a3, b0, b1, b2, b3 = sp.symbols("a0 a1 a2 a3 b0 b1 b2 b3", real=True)
A = sp.symbols("A11 A12 A13 A21 A22 A23 A31 A32", real=True)
H = sp.Matrix(3, 3, sp.symbols("h11 h12 h13 h21 h22 h23 h31 h32 h33", real=True))


def _helmert_printed():
    return sp.Matrix([a0 + a1 * xs + b1 * ys, b0 + a1 * ys - b1 * xs])


def _bilinear_printed():
    return sp.Matrix([a0 + a1 * xs + a2 * ys + a3 * xs * ys, b0 + b1 * ys + b2 * xs + b2 * xs * ys])


def _bilinear_general():
    return sp.Matrix([a0 + a1 * xs + a2 * ys + a3 * xs * ys, b0 + b1 * ys + b2 * xs + b3 * xs * ys])


def _bilinear_evidence() -> Evidence:
    from photolib.symcheck import equivalent
    n_printed = plane.free_parameter_count(_bilinear_printed(), (a0, a1, a2, a3, b0, b1, b2))
    n_true = plane.free_parameter_count(plane.bilinear_from_corners(), plane.P)
    v = equivalent(_bilinear_printed(), _bilinear_general())
    if n_printed < n_true and v.kind == "not-equal":
        return Evidence("wrong", f"printed form has {n_printed} independent parameters, the "
                        f"bilinear map of a quadrilateral {n_true}; b2 appears twice (b3 "
                        "missing)", v.counterexample, v.values)
    return Evidence("right", f"{n_printed} parameters")


def _projective():
    den = A[6] * xs + A[7] * ys + 1
    return sp.Matrix([(A[0] * xs + A[1] * ys + A[2]) / den, (A[3] * xs + A[4] * ys + A[5]) / den])


def _bundle() -> Evidence:
    rows = []
    for images, points in ((2, 10), (12, 150), (1, 0)):
        printed = 6 * images + 3 * points
        rows.append((f"{images} images, {points} points", printed,
                     adjustment.bundle_unknowns(images, points), 0))
    ok = all(a == b for _, a, b, _ in rows)
    return Evidence("right-under-condition: interior orientation fixed (as the notes say); "
                    "every point with three unknown coordinates" if ok else "wrong",
                    "6 = dim of rigid motions (3 skew generators + 3 shifts), 3 per point",
                    table=[(n, a, b, t, a == b) for n, a, b, t in rows])


def _profile() -> Evidence:
    """ΔX = ΔY along a profile at azimuth α: solved for α on [0, 2π)."""
    alpha = sp.Symbol("alpha", real=True)
    step = sp.Symbol("s", positive=True)
    dX, dY = step * sp.cos(alpha), step * sp.sin(alpha)
    equal_at = sorted(sp.solveset(sp.Eq(dX, dY), alpha, sp.Interval.Ropen(0, 2 * sp.pi)),
                      key=float)
    if not equal_at:
        return Evidence("right", "ΔX ≠ ΔY for every azimuth")
    a = equal_at[0]
    deg = ", ".join(f"{float(v * 180 / sp.pi):g}°" for v in equal_at)
    return Evidence("wrong", f"ΔX = ΔY at α = {deg} (solveset of s·cos α = s·sin α); at "
                    f"α = {a}, s = 1: ΔX = ΔY = {dX.subs({alpha: a, step: 1})}",
                    {alpha: a, step: 1})


def records():
    out = []
    out.append(formula(
        "pl-notes:helmert", SRC + ", 'transformacja Hellmerta'", "4-parameter similarity "
        "(Helmert)", {"printed": VersionSpec("right", expr=_helmert_printed, claim="right")},
        derivation=lambda: plane.helmert(),
        given=lambda: {a1: plane.s_scale * sp.cos(plane.theta),
                       b1: -plane.s_scale * sp.sin(plane.theta)},
        steps=("similarity: s·R(θ)·(x_s, y_s) + (a0, b0) with the plane rotation of the course",
               "a1 = s·cos θ, b1 = −s·sin θ turns it into the printed form"),
        note="Any a1, b1 correspond to s = √(a1² + b1²), θ = atan2(−b1, a1)."))
    out.append(Record(
        id="pl-notes:bilinear", source=SRC + ", 'Transformację bilinearną'",
        item="bilinear transformation", kind="formula",
        specs={"printed": VersionSpec("wrong", expr=_bilinear_printed, check=_bilinear_evidence,
                                      claim="right")},
        derivation=plane.bilinear_from_corners,
        steps=("linear interpolation of four corners: a0 + a1 s + a2 t + a3 s t per coordinate",
               "eight independent coefficients (Jacobian rank 8)"),
        note="y = b0 + b1y_s + b2x_s + b2x_sy_s repeats b2; it must be b3·x_s·y_s."))
    out.append(formula(
        "pl-notes:projective", SRC + ", 'Transformację rzutową'", "projective transformation "
        "with A33 = 1",
        {"printed": VersionSpec("right-under-condition: homography normalised by h33 ≠ 0 "
                                "(A_ij = h_ij/h33)", expr=_projective,
                                condition=lambda: {A[i]: H[i // 3, i % 3] / H[2, 2]
                                                   for i in range(8)},
                                condition_text="homography normalised by h33 ≠ 0 "
                                               "(A_ij = h_ij/h33)", claim="right")},
        derivation=lambda: plane.homography_normalised(H).subs({plane.x: xs, plane.y: ys})))
    out.append(Record(
        id="pl-notes:affine", source=SRC + ", 'Transformację afiniczną'",
        item="affine transformation", kind="text",
        specs={"printed": VersionSpec("not-checkable: the formula is cut off after "
                                      "'x = a1 + a2xs + a3y...'", claim="right")},
        note="The claim that parallel lines stay parallel follows from the linear part."))
    out.append(Record(
        id="pl-notes:bundle-unknowns", source=SRC + ", 'METODA WIĄZEK'",
        item="unknowns = 6·images + 3·points", kind="text",
        specs={"printed": VersionSpec("right-under-condition: interior orientation fixed (as "
                                      "the notes say); every point with three unknown "
                                      "coordinates", check=_bundle, claim="right")}))
    out.extend(_more_records())
    return out


# -- projective rectification, VSD palette and pyramid, interior orientation, affine text ------

PROJ_ORIENT = ("plane object (the terrain a plane Z = const): the ray of the collinearity "
               "equations meets it where a homography says, and the 8 parameters are "
               "functions of the 9 elements X0, Y0, Z0, ω, φ, κ, c, x'0, y'0 (Jacobian rank 8: "
               "contained, not all recoverable from them); radial distortion bends straight "
               "lines, which no projective map does")
CK = ("object far enough that the image lies in the focal plane (a → ∞, as the notes say in "
      "line 227): c = a' = a·f/(a − f) → f; closer, c > f (a = 10·f: c = 1.111·f)")
FIDUCIAL = ("the four marks form a parallelogram (F1 + F3 = F2 + F4: a symmetric layout or an "
            "affine image of one), so that the lines joining opposite marks bisect each other; "
            "otherwise the mean is not the intersection: marks (0, −100), (100, 0), (0, 110), "
            "(−100, 0) give the intersection (0, 0) and the mean (0, 2.5)")
FID_EXAMPLE = (0, -100, 100, 0, 0, 110, -100, 0)


def _projective_orientation() -> Evidence:
    ray_ok = plane.homography_ray_residual() == sp.zeros(2, 1)
    rank, n, sv = plane.homography_orientation_rank()
    # three collinear image points on y = 1/2, radial distortion x·(1 + K1·r²), K1 = 1/10
    k1 = sp.Rational(1, 10)
    pts = [(sp.Integer(-1), sp.Rational(1, 2)), (sp.Integer(0), sp.Rational(1, 2)),
           (sp.Integer(1), sp.Rational(1, 2))]
    moved = [(px * (1 + k1 * (px**2 + py**2)), py * (1 + k1 * (px**2 + py**2))) for px, py in pts]
    det_before = sp.Matrix([[px, py, 1] for px, py in pts]).det()
    det_after = sp.Matrix([[px, py, 1] for px, py in moved]).det()
    table = [("parameters of the projective transformation (rank over the 9 elements)", 8,
              rank, 0, rank == 8),
             ("three points on a line: det before distortion", 0, float(det_before), 0,
              det_before == 0),
             ("the same after radial distortion K1 = 0.1 (not collinear)", None,
              float(det_after), None, True)]
    if ray_ok and rank == 8 and n == 9 and det_before == 0 and det_after != 0:
        return Evidence(f"right-under-condition: {PROJ_ORIENT}", "ray ∩ plane Z = 0 equals "
                        "H·(x', y', 1) with H = T·R·K identically; the smallest of the 8 "
                        f"singular values is {float(sv[-1]):.3g}: rank 8 of 9 elements",
                        table=table)
    return Evidence("wrong", f"ray identity {ray_ok}, rank {rank}", table=table)


def _palette() -> Evidence:
    return numbers_evidence(
        [("VSD palette: 248 image colours + 8 reserved", 256, 248 + 8, 0),
         ("entries an 8-bit index can address (enumerated bit patterns)", 256,
          adjustment.grey_levels(8), 0)],
        reason_ok="248 + 8 = 256 = 2⁸: the whole 8-bit palette of an indexed TIFF")


def _pyramid_levels(size=10_000, half_screen=512):
    """Levels of a pyramid halving (rounding up) until the image fits on half the screen."""
    n = 0
    while size > half_screen:
        size = -(-size // 2)
        n += 1
    return n, size


def _pyramid() -> Evidence:
    n, last = _pyramid_levels()
    rows = [("all levels: 100·Σ 4^−i (%)", 33, 100 * sensors.pyramid_overhead(), 0.5),
            (f"{n} levels, 10 000 px down to {last} px (half of a 1024-px screen) (%)", 33,
             100 * sensors.pyramid_overhead(n), 0.5)]
    return numbers_evidence(rows, reason_ok="each level has a quarter of the pixels of the one "
                            "before: Σ_{i≥1} 4^−i = 1/3 exactly (SymPy summation); a finite "
                            "pyramid stays just below, 'ok. 33 %' rounds both")


def _camera_constant() -> Evidence:
    a, f = optics.a, optics.f
    image = optics.thin_lens_image_distance(a)
    limit = sp.limit(image / f, a, sp.oo)
    at10 = sp.cancel(image.subs(a, 10 * f) / f)
    aerial = float(image.subs({a: 1000, f: sp.Rational(153, 1000)}) - sp.Rational(153, 1000))
    table = [("c/f for a → ∞", 1, float(limit), 0, limit == 1),
             ("c/f at a = 10·f", 1, float(at10), 0.001, abs(float(at10) - 1) <= 0.001),
             ("c − f at a = 1000 m, f = 153 mm (µm)", None, aerial * 1e6, None, True)]
    if limit == 1 and at10 == sp.Rational(10, 9):
        return Evidence(f"right-under-condition: {CK}", f"a' = {image} from the thin lens "
                        "(1/a + 1/a' = 1/f); lim a'/f = 1 as a → ∞", table=table)
    return Evidence("wrong", f"lim a'/f = {limit}", table=table)


def _fiducials() -> Evidence:
    from photolib.symcheck import equivalent
    v = equivalent(plane.fiducial_mean(), plane.fiducial_centre(),
                   assumptions=plane.parallelogram_condition())
    cen, mean = plane.fiducial_centre(FID_EXAMPLE), plane.fiducial_mean(FID_EXAMPLE)
    # a symmetric square layout mapped by an affine film deformation
    A = sp.Matrix([[sp.Rational(101, 100), sp.Rational(1, 50)],
                   [sp.Rational(-1, 100), sp.Rational(99, 100)]])
    t = sp.Matrix([5, -3])
    square = [sp.Matrix(p) for p in ((0, -100), (100, 0), (0, 100), (-100, 0))]
    warped = [e for p in square for e in (A * p + t)]
    cen_w, mean_w = plane.fiducial_centre(warped), plane.fiducial_mean(warped)
    table = [("example (0,−100), (100,0), (0,110), (−100,0): mean x vs intersection x",
              float(mean[0]), float(cen[0]), 1e-9, mean[0] == cen[0]),
             ("example: mean y vs intersection y", float(mean[1]), float(cen[1]), 1e-9,
              mean[1] == cen[1]),
             ("affine image of a square: mean x vs intersection x", float(mean_w[0]),
              float(cen_w[0]), 1e-9, mean_w[0] == cen_w[0]),
             ("affine image of a square: mean y vs intersection y", float(mean_w[1]),
              float(cen_w[1]), 1e-9, mean_w[1] == cen_w[1])]
    if v.kind == "equal-under-condition" and mean != cen and mean_w == cen_w:
        return Evidence(f"right-under-condition: {FIDUCIAL}", "intersection of F1F3 and "
                        "F2F4 solved by SymPy; equal to the mean exactly when F4 = F1 + F3 − "
                        f"F2 ({v.method})", counterexample=dict(zip(plane.FID, FID_EXAMPLE)),
                        values=(tuple(mean), tuple(cen)), table=table)
    return Evidence("wrong" if v.kind == "not-equal" else "right", v.detail, table=table)


AFFINE_TEXT = ("the description (a conformal transformation with different scales in x and "
               "y, a shift and a rotation) has 5 parameters; the affine transformation has 6 "
               "(its cut-off formula x = a1 + a2xs + a3ys …, and the German summary's count): "
               "the non-orthogonality (shear) of the axes is missing")


def _affine_description() -> Evidence:
    counts = {}
    for order in ("scale-first", "rotate-first"):
        m = plane.scale_rotation_affine(order)
        counts[order] = plane.free_parameter_count(
            m, sorted(m.free_symbols - {plane.xs, plane.ys}, key=str))
    gen = plane.affine()
    n_aff = plane.free_parameter_count(gen, sorted(gen.free_symbols - {plane.xs, plane.ys},
                                                   key=str))
    # R·D has (R·D)ᵀ(R·D) = D², D·R has (D·R)(D·R)ᵀ = D²: both diagonal, for every θ
    D, R = sp.diag(plane.s_x, plane.s_y), plane.rotation_2d(plane.theta)
    gram = [sp.trigsimp(((R * D).T * (R * D))[0, 1]), sp.trigsimp(((D * R) * (D * R).T)[0, 1])]
    shear = sp.Matrix([[1, sp.Rational(1, 10)], [0, 1]])
    s_gram = [(shear.T * shear)[0, 1], (shear * shear.T)[0, 1]]
    table = [("parameters: scales, then rotation, shift", 6, counts["scale-first"], 0,
              counts["scale-first"] == 6),
             ("parameters: rotation, then scales, shift", 6, counts["rotate-first"], 0,
              counts["rotate-first"] == 6),
             ("parameters: general affine x = a1 + a2xs + a3ys, y = b1 + b2xs + b3ys", 6,
              n_aff, 0, n_aff == 6)]
    if counts == {"scale-first": 5, "rotate-first": 5} and n_aff == 6 and gram == [0, 0] \
            and all(g != 0 for g in s_gram):
        m11, m12, m21, m22 = sp.symbols("m11 m12 m21 m22", real=True)
        return Evidence("wrong", f"{AFFINE_TEXT}. The shear x = xs + 0.1·ys, y = ys is affine "
                        "(parallels stay parallel) but not of the described form: that needs "
                        "AᵀA or AAᵀ diagonal, the shear has off-diagonal 0.1 in both",
                        counterexample={m11: 1, m12: sp.Rational(1, 10), m21: 0, m22: 1},
                        values=(0, s_gram[0]), table=table)
    return Evidence("right", f"counts {counts}, affine {n_aff}", table=table)


def _more_records():
    out = []
    out.append(Record(
        id="pl-notes:projective-orientation", source=SRC + ", 'TRANSFORMACJA RZUTOWA', line 9",
        item="'W parametrach transformacji zawarte są elementy orientacji zewnętrznej i "
             "wewnętrznej za wyjątkiem dystorsji' (8 parameters)", kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {PROJ_ORIENT}",
                                      check=_projective_orientation, claim="right")},
        derivation=plane.homography_from_orientation,
        steps=("ray X = X0 + λ·R·(x' − x'0, y' − y'0, −c) meets Z = 0 at λ = −Z0/(R·x*)_z",
               "(X, Y, 1) ∝ T·R·K·(x', y', 1): a homography, 8 parameters after dividing by h33",
               "Jacobian of the 8 w.r.t. (X0, Y0, Z0, ω, φ, κ, c, x'0, y'0): rank 8",
               "radial distortion moves three collinear points off their line: not projective"),
        note="The notes add 'onto the terrain surface'; only a flat terrain makes the "
             "rectification exact (relief displaces the points radially)."))
    out.append(Record(
        id="pl-notes:palette", source=SRC + ", 'VSD AGH', line 193",
        item="palettes reduced to 248 entries, 8 colours reserved for the vector map and labels "
             "(256-colour palette)", kind="text",
        specs={"printed": VersionSpec("right", check=_palette, claim="right")}))
    out.append(Record(
        id="pl-notes:pyramid-overhead", source=SRC + ", 'VSD AGH', line 199",
        item="image pyramid with the resolution halved per level needs 'ok. 33 %' more disk",
        kind="example",
        specs={"printed": VersionSpec("right", check=_pyramid, claim="right")},
        derivation=sensors.pyramid_overhead,
        steps=("level i has (1/2)^i of the rows and of the columns: 4^−i of the pixels",
               "overhead Σ_{i=1}^{n} 4^−i = (1 − 4^−n)/3, 1/3 for n → ∞ (SymPy summation)",
               "10 000 px down to half a 1024-px screen: 5 levels, 33.30 %")))
    out.append(Record(
        id="pl-notes:camera-constant", source=SRC + ", 'ORIENTACJA WEWNĘTRZNA ZDJĘĆ', lines 219 "
        "and 227", item="f = Ck: the distance of the projection centre from the image plane "
        "equals the focal length when the image is formed in the focal plane", kind="text",
        specs={"printed": VersionSpec(f"right-under-condition: {CK}", check=_camera_constant,
                                      claim="right")},
        derivation=lambda: optics.thin_lens_image_distance(optics.a),
        steps=("thin lens: a' = a·f/(a − f) (centre ray and focal ray intersected)",
               "the camera constant is the image distance of the focused plane",
               "a → ∞: a' → f; a = 10·f: a' = 1.111·f")))
    out.append(Record(
        id="pl-notes:principal-point-fiducials", source=SRC + ", 'ORIENTACJA WEWNĘTRZNA "
        "ZDJĘĆ', lines 223 and 257", item="principal point as the intersection of the lines "
        "joining opposite fiducials (line 223) and as the mean of the fiducial coordinates "
        "(corrected by Δx0, Δy0, line 257)", kind="formula",
        specs={"printed": VersionSpec(f"right-under-condition: {FIDUCIAL}",
                                      expr=plane.fiducial_mean, check=_fiducials,
                                      claim="right")},
        derivation=plane.fiducial_centre,
        steps=("intersection of F1 + u(F3 − F1) and F2 + v(F4 − F2): two linear equations "
               "in u, v, solved by SymPy",
               "the mean (F1 + F2 + F3 + F4)/4 compared with it: equal after F4 = F1 + F3 − F2",
               "affine maps keep midpoints and intersections: a deformed symmetric layout "
               "still agrees"),
        note="Both give the fiducial centre; the principal point differs from it by the "
             "calibrated offsets Δx0, Δy0, which line 257 adds and line 223 leaves out."))
    out.append(Record(
        id="pl-notes:profile-dx-dy", source=SRC + ", stereo digitising (stereodigitalizacja), "
        "line 73", item="'dla dowolnie zorientowanego profilu ΔX ≠ ΔY': along a profile of "
        "any orientation ΔX ≠ ΔY", kind="text",
        specs={"printed": VersionSpec("wrong", check=_profile, claim="right")},
        steps=("a step of length s along a profile at azimuth α from the X axis: "
               "ΔX = s·cos α, ΔY = s·sin α",
               "ΔX − ΔY = s(cos α − sin α) = √2·s·cos(α + π/4): zero at α = π/4 and 5π/4 "
               "(SymPy solveset on [0, 2π))",
               "a profile at 45° has ΔX = ΔY for every step"),
        note="Read literally the statement fails for profiles at 45° and 225°. The notes "
             "probably mean that X and Y both vary along a profile (unlike a contour, where "
             "the operator holds Z); that too fails for profiles parallel to an axis, where "
             "ΔY = 0 or ΔX = 0."))
    out.append(Record(
        id="pl-notes:affine-description", source=SRC + ", 'Transformację afiniczną', line 299",
        item="affine transformation described as a conformal transformation with different "
             "x, y scales, plus a shift of the origin and a rotation", kind="text",
        specs={"printed": VersionSpec("wrong", check=_affine_description, claim="right")},
        derivation=plane.affine,
        steps=("described map: R(θ)·diag(s_x, s_y)·(x_s, y_s) + t (or diag·R): Jacobian rank 5",
               "general affine A·(x_s, y_s) + t: rank 6",
               "R·D gives (R·D)ᵀ(R·D) = D² diagonal; a shear gives off-diagonal entries"),
        note="The text follows Wolf's description of the affine transformation but drops "
             "its last clause, the compensation of non-orthogonal axes (shear); parallels "
             "stay parallel under both."))
    return out
