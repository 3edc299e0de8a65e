"""Stereo normal case, height from parallax and its accuracy, from the collinearity equations.

Normal case (Normalfall): both cameras unrotated (ω = φ = κ = 0, so R = I), camera 1 at the
origin, camera 2 at ``(B, 0, 0)``. The collinearity equations of
:mod:`photolib.derive.collinearity` with R = I give the image coordinates; the x-parallax
``px' = x'1 − x'2`` is ``−c·B/Z`` and so ``Z = −c·B/px'`` (c > 0, points in front have
Z < 0). Error propagation of ``Z(px')`` and of ``X = m·x'`` gives the accuracy formulas.

Chapter 09 adds the object point from the parallax (:func:`object_from_parallax`), σ_X for an
independently measured parallax (:func:`sigma_X_full`) and for two measured image coordinates
(:func:`covariance_two_images`, :func:`sigma_X_two_images`), the coplanarity condition and where ``E = R1ᵀ·[b]×·R2`` comes
from (:func:`coplanarity_identity`, :func:`coplanarity_normal_case`) and the unknown counts
5 + 7 = 12 of relative and absolute orientation (:func:`orientation_unknowns`).

Examples
--------
>>> import sympy as sp
>>> sp.simplify(height_from_parallax() - (-c*B/px))
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive.rotation import R_kappa, R_phi, rotation_opk, skew

X, Y, Z, c, x0, y0 = col.X, col.Y, col.Z, col.c, col.x0, col.y0
B = sp.symbols("B", positive=True)
px = sp.symbols("p_x", real=True)
x1, x2, y1 = sp.symbols("x1 x2 y1", real=True)
s_x, s_px, h, b, m = sp.symbols("s_x s_px h b m", positive=True)


def image_coordinates_normal_case(camera: int):
    """``(x', y')`` of camera 1 (at the origin) or 2 (at (B, 0, 0)), R = I."""
    if camera not in (1, 2):
        raise ValueError(f"camera must be 1 or 2, got {camera!r}")
    base = 0 if camera == 1 else B
    xs, ys = col.image_coordinates(sp.eye(3))
    return tuple(sp.simplify(e.subs({col.X0: base, col.Y0: 0, col.Z0: 0})) for e in (xs, ys))


def parallax():
    """``px' = x'1 − x'2`` in the normal case."""
    return sp.simplify(image_coordinates_normal_case(1)[0] - image_coordinates_normal_case(2)[0])


def height_from_parallax():
    """Z solved from ``px' = x'1 − x'2``."""
    return sp.solve(sp.Eq(parallax(), px), Z)[0]


def object_from_image(camera: int):
    """``(X, Y)`` solved from the image coordinates (x', y') of one camera at known Z."""
    xs, ys = image_coordinates_normal_case(camera)
    xi, yi = sp.symbols("xi eta", real=True)
    sol = sp.solve([sp.Eq(xs, xi), sp.Eq(ys, yi)], [X, Y], dict=True)[0]
    return sol[X], sol[Y], (xi, yi)


def parallax_sigma_independent():
    """σ of ``px' = x'1 − x'2`` for independent x'1, x'2 of equal σ ``s_x`` (propagation)."""
    J = sp.Matrix([[sp.diff(x1 - x2, x1), sp.diff(x1 - x2, x2)]])
    return sp.sqrt((J * sp.diag(s_x**2, s_x**2) * J.T)[0])


def sigma_Z():
    """σ_Z from ``Z = −cB/px'`` at ``|Z| = h``, ``h/c = m`` (scale number), base b."""
    dZ = sp.diff(-c * B / px, px)
    # |dZ/dpx| = c·B/px² = Z²/(c·B) = h²/(c·b) = (h/b)·m
    val = sp.Abs(dZ).subs(px, c * B / h).subs({B: b, c: h / m})
    return sp.simplify(val * s_px)


def sigma_XY():
    """σ_X of ``X = m·x'`` for image σ ``s_x`` (scale number m)."""
    return m * s_x


# -- chapter 09: object point from parallax, coplanarity, orientation counts ---------------------

def object_from_parallax():
    """``(X, Y, Z)`` of the normal case in terms of x'1, y'1 (reduced) and ``px' = x'1 − x'2``.

    Solved from the collinearity equations of both cameras (x'0 = y'0 = 0): ``X = B·x'1/px'``,
    ``Y = B·y'1/px'``, ``Z = −c·B/px'``.

    >>> [sp.simplify(e) for e in object_from_parallax()] == [B*x1/px, B*y1/px, -c*B/px]
    True
    """
    xa, ya = image_coordinates_normal_case(1)
    xb, _ = image_coordinates_normal_case(2)
    sub = {x0: 0, y0: 0}
    sol = sp.solve([sp.Eq(xa.subs(sub), x1), sp.Eq(ya.subs(sub), y1),
                    sp.Eq(xa.subs(sub) - xb.subs(sub), px)], [X, Y, Z], dict=True)[0]
    return sol[X], sol[Y], sol[Z]


def sigma_X_full():
    """σ_X of ``X = B·x'1/px'`` with independent σ(x'1) = ``s_x`` and σ(px') = ``s_px``.

    Propagation gives ``(B/px')²·s_x² + (B·x'1/px'²)²·s_px²``; at ``x'1 = 0`` (the nadir)
    it is ``m·s_x`` (``m = h/c = B/px'``), the leading term used by Luhmann.

    Condition: the parallax px' is an observation of its own, measured independently of
    x'1 — with a parallax bar (Parallaxenschraube, Stereomikrometer) or the floating mark of
    a stereo plotter. When x'1 and x'2 are both measured in the two images, px' = x'1 − x'2
    is correlated with x'1 and this formula is wrong (too large below the base); use
    :func:`sigma_X_two_images` then.
    """
    Xf = B * x1 / px
    return sp.sqrt(sp.diff(Xf, x1) ** 2 * s_x**2 + sp.diff(Xf, px) ** 2 * s_px**2)


def object_from_two_images():
    """``(X, Y, Z)`` of the normal case as functions of the measured x'1, y'1 and x'2.

    :func:`object_from_parallax` with the parallax written out, ``px' = x'1 − x'2``: the
    observations of a point measured in both images (reduced to the principal point).

    >>> object_from_two_images()[2]
    -B*c/(x1 - x2)
    """
    return tuple(e.subs(px, x1 - x2) for e in object_from_parallax())


def covariance_two_images():
    """Covariance of ``(X, Y, Z)`` for x'1, y'1, x'2 measured independently with σ ``s_x``.

    Law of error propagation from the image observations ``l = (x'1, y'1, x'2)``:
    ``Σ_XYZ = J·(s_x²·I)·Jᵀ`` with ``J = ∂(X, Y, Z)/∂l``. Because px' = x'1 − x'2 shares x'1
    with ``X = B·x'1/px'``, the two error contributions of x'1 partly cancel.

    >>> C = covariance_two_images()
    >>> sp.factor(C[2, 2])
    2*B**2*c**2*s_x**2/(x1 - x2)**4
    """
    obs = sp.Matrix([x1, y1, x2])
    J = sp.Matrix(object_from_two_images()).jacobian(obs)
    return (J * (s_x**2 * sp.eye(3)) * J.T).applyfunc(sp.factor)


def sigma_X_two_images():
    """σ_X of ``X = B·x'1/(x'1 − x'2)`` for x'1, x'2 measured independently with σ ``s_x``.

    From :func:`covariance_two_images`: ``σ_X = B·s_x·√(x'1² + x'2²)/px'²`` with
    ``px' = x'1 − x'2``, i.e. ``m·s_x·√(x'1² + x'2²)/px'`` (m = B/px' = h/c). It equals
    ``m·s_x`` exactly where ``x'1·x'2 = 0``: a point vertically below one of the projection
    centres (the nadir of image 1 or 2). Below the middle of the base (x'2 = −x'1) it is
    ``m·s_x/√2``; outside the base it grows beyond ``m·s_x``.

    >>> e = sigma_X_two_images()
    >>> sp.simplify(e - B*s_x*sp.sqrt(x1**2 + x2**2)/(x1 - x2)**2)
    0
    >>> a = sp.symbols("a", positive=True)           # below the middle: x'1 = a, x'2 = −a
    >>> sp.simplify(e.subs({x1: a, x2: -a}) - (B/(2*a))*s_x/sp.sqrt(2))
    0
    """
    return sp.sqrt(sp.factor(covariance_two_images()[0, 0]))


#: image vectors x*_1, x*_2 (components) and base components for the coplanarity derivation
xs1 = sp.Matrix(sp.symbols("xi1 eta1 zeta1", real=True))
xs2 = sp.Matrix(sp.symbols("xi2 eta2 zeta2", real=True))
bvec = sp.Matrix(sp.symbols("b_x b_y b_z", real=True))


def coplanarity_identity():
    """``det[b, R1·x*1, R2·x*2] + x*1ᵀ·(R1ᵀ[b]×R2)·x*2`` for general 3×3 R1, R2: expands to 0.

    This is where ``E = R1ᵀ·[b]×·R2`` comes from: the base and both rays lie in one plane
    (the epipolar plane) exactly when the triple product vanishes.

    >>> coplanarity_identity()
    0
    """
    R1 = sp.Matrix(3, 3, sp.symbols("p11:14 p21:24 p31:34", real=True))
    R2 = sp.Matrix(3, 3, sp.symbols("q11:14 q21:24 q31:34", real=True))
    r1, r2 = R1 * xs1, R2 * xs2
    det = sp.Matrix.hstack(bvec, r1, r2).det()
    E = R1.T * skew(bvec) * R2
    return sp.expand(det + (xs1.T * E * xs2)[0])


def coplanarity_normal_case():
    """The coplanarity determinant of the normal case ``det[b, x*1, x*2]/(bx·c)``.

    With b = (bx, 0, 0), x*_i = (x'_i, y'_i, −c) it is ``y'2 − y'1``: the y-parallax, which
    is why a relative orientation removes the y-parallaxes.

    >>> coplanarity_normal_case()
    -y1 + y2
    """
    bx = sp.symbols("b_x", positive=True)
    y2 = sp.symbols("y2", real=True)
    M = sp.Matrix([[bx, x1, x2], [0, y1, y2], [0, -c, -c]])
    return sp.expand(M.det() / (bx * c))


#: the five angles of the independent relative orientation
ro_angles = sp.symbols("phi1 kappa1 omega2 phi2 kappa2", real=True)


def independent_coplanarity():
    """The coplanarity condition of the independent relative orientation, and its gradient.

    ``v = det[b, R1·x*1, R2·x*2]/(bx·c)`` with ``b = (bx, 0, 0)``, ``R1 = R_φ(φ1)·R_κ(κ1)``,
    ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``, ``x*_i = (x'_i, y'_i, −c)``. Returns ``(v, grad)`` with
    the gradient by (φ1, κ1, ω2, φ2, κ2). At the normal case (all angles 0) v is the
    y-parallax and the gradient the classical coefficients of the unabhängige Bildpaare:

    >>> v, grad = independent_coplanarity()
    >>> at0 = {a: 0 for a in ro_angles}
    >>> sp.simplify(v.subs(at0))
    -y1 + y2
    >>> [sp.factor(g.subs(at0)) for g in grad]
    [x1*y2/c, -x1, (c**2 + y1*y2)/c, -x2*y1/c, x2]
    """
    bx, y2 = sp.symbols("b_x", positive=True), sp.symbols("y2", real=True)
    phi1, kappa1, omega2, phi2, kappa2 = ro_angles
    R1 = R_phi(phi1) * R_kappa(kappa1)
    R2 = rotation_opk(omega2, phi2, kappa2)
    r1 = R1 * sp.Matrix([x1, y1, -c])
    r2 = R2 * sp.Matrix([x2, y2, -c])
    v = sp.Matrix.hstack(sp.Matrix([bx, 0, 0]), r1, r2).det() / (bx * c)
    return v, [sp.diff(v, a) for a in ro_angles]


def orientation_unknowns():
    """Unknown counts of a stereo pair: 2 × 6 exterior = 5 relative + 7 absolute.

    The 7 datum parameters (3 shifts, 3 rotations, scale of the model) are what relative
    orientation cannot see, because the coplanarity condition is invariant under a 3-D
    similarity of the whole pair: it is homogeneous in b (scale), and rotating b, R1 and R2
    together leaves ``R1ᵀ[b]×R2`` unchanged (``[Q·b]× = Q·[b]×·Qᵀ``).

    >>> orientation_unknowns()
    {'exterior': 12, 'relative': 5, 'absolute': 7}
    """
    # the invariance, checked exactly on a rational rotation (Cayley transform of a skew matrix)
    S = skew(sp.Matrix([sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 5)]))
    Q = (sp.eye(3) - S).inv() * (sp.eye(3) + S)
    diff = skew(Q * bvec) - Q * skew(bvec) * Q.T
    if diff.applyfunc(sp.expand) != sp.zeros(3, 3):
        raise AssertionError("[Q·b]× ≠ Q·[b]×·Qᵀ")
    return {"exterior": 12, "relative": 12 - 7, "absolute": 7}


# -- chapter 09, real photographs: a rectified pixel pair (Middlebury calibration) ---------------

#: pixel quantities: columns u1, u2 and row v of a point, principal points cx1, cx2, cy, focal
#: length f (px), pixel pitch p (mm/px), disparity d = u1 − u2 and doffs = cx2 − cx1
u1, u2, v_row, cx1, cx2, cy = sp.symbols("u1 u2 v c_x1 c_x2 c_y", real=True)
f_px, pitch = sp.symbols("f p", positive=True)
d_px, doffs = sp.symbols("d d_offs", real=True)
s_d = sp.symbols("sigma_d", positive=True)
Z_depth = sp.symbols("Z_s", negative=True)      #: a depth in front of the camera


def depth_from_disparity():
    """``(X, Y, Z)`` of a rectified pair from pixels, solved from the collinearity equations.

    Camera 1 at the origin, camera 2 at (B, 0, 0), R = I, camera constant ``c = f·p``; the
    image coordinates reduced to each image's principal point are ``x' − x'0 = (u − cx)·p``
    and ``y' − y'0 = −(v − cy)·p`` (rows down, y' up). Eliminating u2 by ``d = u1 − u2``
    and cx2 by ``doffs = cx2 − cx1``: the pitch p cancels.

    >>> Xs, Ys, Zs = depth_from_disparity()
    >>> sp.simplify(Zs + f_px*B/(d_px + doffs)), sp.simplify(Xs - (u1 - cx1)*B/(d_px + doffs))
    (0, 0)
    """
    xa, ya = image_coordinates_normal_case(1)
    xb, _ = image_coordinates_normal_case(2)
    eqs = [sp.Eq(xa - x0, (u1 - cx1) * pitch), sp.Eq(ya - y0, -(v_row - cy) * pitch),
           sp.Eq(xb - x0, (u2 - cx2) * pitch)]
    sol = sp.solve([e.subs(c, f_px * pitch) for e in eqs], [X, Y, Z], dict=True)[0]
    sub = {u2: u1 - d_px, cx2: cx1 + doffs}
    return tuple(sp.simplify(sol[k].subs(sub)) for k in (X, Y, Z))



def sigma_depth_disparity():
    """``σ_Z = |∂Z/∂d|·σ_d`` of ``Z = −f·B/(d + doffs)``, written with Z: ``Z²/(f·B)·σ_d``.

    >>> sp.simplify(sigma_depth_disparity() - Z_depth**2/(f_px*B)*s_d)
    0
    """
    dZ = sp.diff(depth_from_disparity()[2], d_px)
    # at the depth Z_depth: d + doffs = −f·B/Z
    return sp.simplify(sp.Abs(dZ.subs(d_px, -f_px * B / Z_depth - doffs)) * s_d)
