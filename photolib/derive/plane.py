"""Plane transformations derived from first principles, and the cross ratio.

* Projective (Luhmann 2.18, the course convention): ``X = (a0 + a1x + a2y)/(1 + c1x + c2y)``,
  ``Y = (b0 + b1x + b2y)/(1 + c1x + c2y)`` is a 3×3 homography with ``h33 = 1``.
  Its inverse is **solved** here (two linear equations in x, y after clearing the
  denominator; Cramer's rule by SymPy), not typed in.
* The inverse is again projective; dividing its numerators and denominator by their common
  constant ``a1b2 − a2b1`` gives the primed coefficients of the normalised form (2.20).
* Helmert (similarity): scale s times the plane rotation of :mod:`photolib.derive.rotation`
  plus a shift. Affine: any linear map plus a shift. Bilinear: linear interpolation of the
  four corners of the unit square, expanded. Polynomial of degree n: count of monomials.
* Cross ratio: a projectivity of a line maps a signed coordinate t to ``(p t + q)/(r t + s)``;
  the invariance of a ratio of signed segments is tested under this map.

Examples
--------
>>> x_inv, y_inv = projective_inverse()
>>> X_, Y_ = projective_forward()
>>> import sympy as sp
>>> sp.cancel(x_inv.subs({X: X_, Y: Y_}, simultaneous=True) - x)
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive.rotation import rotation_2d

x, y, X, Y = sp.symbols("x y X Y", real=True)
a0, a1, a2, b0, b1, b2, c1, c2 = sp.symbols("a0 a1 a2 b0 b1 b2 c1 c2", real=True)
#: primed coefficients of the inverse projective transform (Luhmann 2.20)
ap0, ap1, ap2, bp0, bp1, bp2, cp1, cp2 = sp.symbols(
    "ap0 ap1 ap2 bp0 bp1 bp2 cp1 cp2", real=True)
xs, ys = sp.symbols("x_s y_s", real=True)
s_scale, theta = sp.symbols("s theta", real=True)
P = sp.symbols("P00x P00y P10x P10y P01x P01y P11x P11y", real=True)


def projective_forward():
    """``(X, Y)`` of image point (x, y): a homography normalised to ``h33 = 1``.

    .. math:: X = \\frac{a_0 + a_1 x + a_2 y}{1 + c_1 x + c_2 y}, \\quad
              Y = \\frac{b_0 + b_1 x + b_2 y}{1 + c_1 x + c_2 y}
    """
    H = sp.Matrix([[a1, a2, a0], [b1, b2, b0], [c1, c2, 1]])
    h = H * sp.Matrix([x, y, 1])
    return h[0] / h[2], h[1] / h[2]


def projective_inverse():
    """``(x, y)`` as functions of ``(X, Y)``: solved from :func:`projective_forward`."""
    Xf, Yf = projective_forward()
    eqs = [sp.numer(sp.together(Xf - X)), sp.numer(sp.together(Yf - Y))]
    sol = sp.solve(eqs, [x, y], dict=True)[0]
    return sp.cancel(sol[x]), sp.cancel(sol[y])


def projective_inverse_primed():
    """The substitution ``{ap0: …, …, cp2: …}`` that puts the inverse in the form of 2.20.

    Numerators and denominator of :func:`projective_inverse` are linear in X, Y; dividing
    all three by the constant term of the denominator (``a1b2 − a2b1``, which must not vanish)
    gives ``x = (a'0 + a'1X + a'2Y)/(1 + c'1X + c'2Y)``.
    """
    xi, yi = projective_inverse()
    nx, dx = sp.fraction(sp.cancel(xi))
    ny, dy = sp.fraction(sp.cancel(yi))
    # bring both to the same denominator polynomial
    ratio = sp.cancel(dy / dx)
    ny, dy = sp.expand(ny / ratio), sp.expand(dy / ratio)
    d0 = sp.Poly(dx, X, Y).coeff_monomial(1)

    def coeffs(expr):
        p = sp.Poly(sp.expand(expr), X, Y)
        return [sp.cancel(p.coeff_monomial(m) / d0) for m in (1, X, Y)]

    A, B, C = coeffs(nx), coeffs(ny), coeffs(dx)
    assert sp.simplify(C[0] - 1) == 0
    return {ap0: A[0], ap1: A[1], ap2: A[2], bp0: B[0], bp1: B[1], bp2: B[2],
            cp1: C[1], cp2: C[2]}


def homography_normalised(H=None):
    """``(x', y')`` of a general 3×3 homography divided by its element h33."""
    H = sp.Matrix(3, 3, sp.symbols("h11 h12 h13 h21 h22 h23 h31 h32 h33", real=True)) \
        if H is None else H
    h = H * sp.Matrix([x, y, 1]) / H[2, 2]
    return sp.Matrix([h[0] / h[2], h[1] / h[2]])


def helmert(tx=a0, ty=b0, s=s_scale, t=theta):
    """Similarity ``s·R(t)·(x_s, y_s) + (tx, ty)`` with the plane rotation R of the course."""
    return s * rotation_2d(t) * sp.Matrix([xs, ys]) + sp.Matrix([tx, ty])


def affine():
    """General affine map of (x_s, y_s): six free parameters."""
    A = sp.Matrix(2, 2, sp.symbols("m11 m12 m21 m22", real=True))
    return A * sp.Matrix([xs, ys]) + sp.Matrix(sp.symbols("t_x t_y", real=True))


def bilinear_from_corners():
    """Bilinear map of the unit square (x_s, y_s) onto the quadrilateral of corners P.

    ``P(s, t) = (1−s)(1−t)P00 + s(1−t)P10 + (1−s)t P01 + s t P11``; expanded it is
    ``a0 + a1 s + a2 t + a3 s t`` in each coordinate with four independent coefficients.
    """
    p00, p10, p01, p11 = (sp.Matrix(P[i:i + 2]) for i in range(0, 8, 2))
    u, v = xs, ys
    return sp.expand((1 - u) * (1 - v) * p00 + u * (1 - v) * p10 + (1 - u) * v * p01
                     + u * v * p11)


def bilinear_coefficients():
    """The 4 + 4 coefficients of :func:`bilinear_from_corners` as functions of the corners."""
    m = bilinear_from_corners()
    out = []
    for comp in m:
        p = sp.Poly(comp, xs, ys)
        out.append([p.coeff_monomial(t) for t in (1, xs, ys, xs * ys)])
    return out


def polynomial_parameter_count(n: int) -> int:
    """Parameters of a 2-D polynomial transformation of degree n: 2·(monomials of degree ≤ n).

    Counted by enumerating monomials ``x^i y^j`` with ``i + j ≤ n`` (no closed form used).
    """
    if n < 0:
        raise ValueError(f"degree must be non-negative, got {n}")
    return 2 * sum(1 for i in range(n + 1) for j in range(n + 1 - i))


def free_parameter_count(mapping: sp.Matrix, params) -> int:
    """Rank of the Jacobian of ``mapping`` w.r.t. ``params`` at a generic point.

    The number of independent parameters a transformation family really has (e.g. a
    bilinear form in which one coefficient appears twice has one fewer).
    """
    pts = [(sp.Rational(2, 7), sp.Rational(-3, 5)), (sp.Rational(11, 13), sp.Rational(5, 3)),
           (sp.Rational(-7, 4), sp.Rational(1, 9)), (sp.Rational(3, 2), sp.Rational(-8, 3)),
           (sp.Rational(-1, 5), sp.Rational(-4, 7))]
    rows = []
    for px, py in pts:
        J = sp.Matrix(mapping).jacobian(list(params)).subs({xs: px, ys: py})
        rows.append(J)
    gen = {p: sp.Rational(3 + i, 7 + 2 * i) for i, p in enumerate(params)}
    return sp.Matrix.vstack(*rows).subs(gen).rank()


# ----------------------------------------------------------------------------- cross ratio
t_line = sp.symbols("t_A t_B t_C t_D", real=True)
proj_line = sp.symbols("p q r s_", real=True)


def line_projectivity(t):
    """A projectivity of a line: ``t ↦ (p t + q)/(r t + s)`` (central projection between lines)."""
    p, q, r, s = proj_line
    return (p * t + q) / (r * t + s)


def segment(t_from, t_to):
    """Signed segment ``t_to − t_from`` on a line with coordinate t."""
    return t_to - t_from


def cross_ratio_invariance(expr_of_points):
    """``λ(projected points) − λ(points)`` for a ratio function of four line coordinates.

    ``expr_of_points(tA, tB, tC, tD)`` builds the ratio from signed segments; the result is
    identically zero exactly when the ratio is a projective invariant.
    """
    before = expr_of_points(*t_line)
    after = expr_of_points(*(line_projectivity(t) for t in t_line))
    return sp.cancel(after - before)


# ------------------------------------------------- fiducial centre, orientation, affine forms
#: four fiducial marks F1..F4 in order round the frame (F1–F3 and F2–F4 opposite)
FID = sp.symbols("F1x F1y F2x F2y F3x F3y F4x F4y", real=True)
s_x, s_y = sp.symbols("s_x s_y", positive=True)


def fiducial_points(values=FID):
    """The four marks as column vectors from eight coordinates (default: the symbols FID)."""
    return [sp.Matrix(values[i:i + 2]) for i in range(0, 8, 2)]


def fiducial_centre(values=FID) -> sp.Matrix:
    """Intersection of the lines F1F3 and F2F4 joining opposite fiducials (solved).

    >>> fiducial_centre((0, -100, 100, 0, 0, 110, -100, 0)).T
    Matrix([[0, 0]])
    """
    p1, p2, p3, p4 = fiducial_points(values)
    u, v = sp.symbols("u v", real=True)
    sol = sp.solve(list(p1 + u * (p3 - p1) - p2 - v * (p4 - p2)), [u, v], dict=True)[0]
    return (p1 + sol[u] * (p3 - p1)).applyfunc(sp.cancel)


def fiducial_mean(values=FID) -> sp.Matrix:
    """Arithmetic mean of the four fiducial coordinates.

    >>> fiducial_mean((0, -100, 100, 0, 0, 110, -100, 0)).T
    Matrix([[0, 5/2]])
    """
    return sum(fiducial_points(values), sp.zeros(2, 1)) / 4


def parallelogram_condition() -> dict:
    """``F4 = F1 + F3 − F2``: the marks form a parallelogram (the diagonals bisect each other)."""
    return {FID[6]: FID[0] + FID[4] - FID[2], FID[7]: FID[1] + FID[5] - FID[3]}


def homography_from_orientation(R=None) -> sp.Matrix:
    """3×3 H with ``(X, Y, 1) ∝ H·(x', y', 1)`` for the ground plane Z = 0.

    The ray of the collinearity equations ``X = X0 + λ·R·(x' − x'0, y' − y'0, −c)`` meets
    Z = 0 at ``λ = −Z0/(R·x*)_z``, so ``X·(R·x*)_z = X0·(R·x*)_z − Z0·(R·x*)_x``: linear in
    ``(x', y', 1)`` over linear — a homography ``H = T·R·K`` with
    ``K = [[1, 0, −x'0], [0, 1, −y'0], [0, 0, −c]]``, ``T = [[−Z0, 0, X0], [0, −Z0, Y0], [0, 0, 1]]``.
    R defaults to ``R_ω·R_φ·R_κ``.
    """
    from photolib.derive import collinearity as col
    from photolib.derive.rotation import rotation_opk
    R = rotation_opk() if R is None else R
    Kmat = sp.Matrix([[1, 0, -col.x0], [0, 1, -col.y0], [0, 0, -col.c]])
    T = sp.Matrix([[-col.Z0, 0, col.X0], [0, -col.Z0, col.Y0], [0, 0, 1]])
    return T * R * Kmat


def homography_ray_residual() -> sp.Matrix:
    """Ground point of the ray minus the homography's, for a general matrix R: identically 0.

    >>> homography_ray_residual()
    Matrix([
    [0],
    [0]])
    """
    from photolib.derive import collinearity as col
    R = col.rotation_symbols()
    xstar = sp.Matrix([x - col.x0, y - col.y0, -col.c])
    d = R * xstar
    lam = -col.Z0 / d[2]
    ground = sp.Matrix([col.X0 + lam * d[0], col.Y0 + lam * d[1]])
    h = homography_from_orientation(R) * sp.Matrix([x, y, 1])
    return (ground - sp.Matrix([h[0] / h[2], h[1] / h[2]])).applyfunc(sp.cancel)


def homography_orientation_rank():
    """Rank of the 8 normalised homography coefficients w.r.t. the 9 orientation elements.

    Elements ``(X0, Y0, Z0, ω, φ, κ, c, x'0, y'0)`` at a generic pose; singular values with
    mpmath at 30 digits (below 1e-20 counts as zero). Returns ``(rank, 9, singular values)``.
    """
    import mpmath

    from photolib.derive import collinearity as col
    from photolib.derive.rotation import kappa, omega, phi
    H = homography_from_orientation()
    coeffs = [H[i] / H[8] for i in range(8)]
    params = [col.X0, col.Y0, col.Z0, omega, phi, kappa, col.c, col.x0, col.y0]
    J = sp.Matrix(coeffs).jacobian(params)
    pose = {col.X0: sp.Rational(1, 2), col.Y0: sp.Rational(-1, 3), col.Z0: 10,
            omega: sp.Rational(1, 10), phi: sp.Rational(-1, 5), kappa: sp.Rational(3, 10),
            col.c: sp.Rational(3, 20), col.x0: sp.Rational(1, 100), col.y0: sp.Rational(-1, 50)}
    M = J.subs(pose)
    with mpmath.workdps(30):
        A = mpmath.matrix([[mpmath.mpf(str(sp.N(e, 35))) for e in M.row(i)]
                           for i in range(M.rows)])
        sv = list(mpmath.svd_r(A, compute_uv=False))
    return sum(1 for s in sv if abs(s) > 1e-20), len(params), sv


def scale_rotation_affine(order: str = "scale-first") -> sp.Matrix:
    """A conformal transformation with two scales: ``R(θ)·diag(s_x, s_y)·(x_s, y_s) + t``.

    ``order="rotate-first"`` gives ``diag(s_x, s_y)·R(θ)·(x_s, y_s) + t``. Five parameters
    (two scales, a rotation, two shifts); the general :func:`affine` has six.
    """
    D = sp.diag(s_x, s_y)
    R = rotation_2d(theta)
    A = R * D if order == "scale-first" else D * R
    return A * sp.Matrix([xs, ys]) + sp.Matrix(sp.symbols("t_x t_y", real=True))
