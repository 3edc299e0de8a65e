"""DLT, the reduced collinearity form 4.13, the ∂y'/∂φ of 4.18b and bundle rotation 4.76.

* DLT (Luhmann 4.2x): collinearity with separate camera constants c_x, c_y (course signs,
  ``x' = x'0 − c_x·kx/N``) multiplied out and divided by the constant of the denominator
  ``D = −r3·X0`` (r3 the third column of R) is ``x' = (L1X + L2Y + L3Z + L4)/(L9X + L10Y +
  L11Z + 1)``. So ``L9..L11 = r3/D`` and ``|D| = 1/√(L9² + L10² + L11²)``; the
  orthonormality of R gives ``x'0 = D²(L1L9 + L2L10 + L3L11)`` and
  ``c_x² = D²(L1² + L2² + L3²) − x'0²`` (same for y with L5..L7), and the columns
  ``r1 = D(x'0·L9..11 − L1..3)/c_x``. The sign of D is the one that makes det R = +1.
* 4.13: with ``X0* = −Rᵀ·X0`` (so ``k = Rᵀ·X + X0*``) the collinearity equation divided by
  Z0* is a ratio of linear forms in X, Y, Z.
* 4.18b: ``∂y'/∂φ`` by SymPy's ``diff`` of the collinearity equation (the lead's
  :func:`photolib.derive.collinearity.jacobian`).

Examples
--------
>>> import sympy as sp
>>> L = dlt_from_orientation()
>>> len(L)
11
"""

from __future__ import annotations

import mpmath
import sympy as sp

from photolib.derive import collinearity as col
from photolib.derive.rotation import kappa, omega, phi, rotation_opk

cx, cy = sp.symbols("c_x c_y", positive=True)
Ls = sp.symbols("L1:12", real=True)


def dlt_from_orientation(R=None):
    """The eleven L of the collinearity model with c_x, c_y, x'0, y'0 (symbols of col)."""
    R = col.rotation_symbols() if R is None else R
    Xv = sp.Matrix([col.X, col.Y, col.Z])
    X0v = sp.Matrix([col.X0, col.Y0, col.Z0])
    r1, r2, r3 = R[:, 0], R[:, 1], R[:, 2]
    D = -(r3.T * X0v)[0]
    numx = col.x0 * r3 - cx * r1
    numy = col.y0 * r3 - cy * r2
    L = list(numx / D) + [-(numx.T * X0v)[0] / D] + list(numy / D) \
        + [-(numy.T * X0v)[0] / D] + list(r3 / D)
    # check: the DLT ratio reproduces the collinearity equation with c_x
    xd = (sum(L[i] * Xv[i] for i in range(3)) + L[3]) / (sum(L[8 + i] * Xv[i] for i in range(3)) + 1)
    kx, ky, N = (R.T * (Xv - X0v))
    assert sp.cancel(xd - (col.x0 - cx * kx / N)) == 0
    return tuple(L)


def decompose(L, sign=-1):
    """Interior and exterior orientation from eleven DLT numbers (mpmath, 30 digits).

    Parameters
    ----------
    L : sequence of 11 numbers
    sign : {-1, +1}
        Sign of ``D = ±1/√(L9² + L10² + L11²)``; use :func:`decompose_proper` to choose it
        by ``det R > 0``.

    Returns
    -------
    dict with ``D, x0, y0, cx, cy, X0 (3), R (3×3 mpmath matrix), det``.
    """
    with mpmath.workdps(30):
        L = [mpmath.mpf(str(v)) for v in L]
        L1, L2, L3, L4, L5, L6, L7, L8, L9, L10, L11 = L
        D = sign / mpmath.sqrt(L9**2 + L10**2 + L11**2)
        x0 = D**2 * (L1 * L9 + L2 * L10 + L3 * L11)
        y0 = D**2 * (L5 * L9 + L6 * L10 + L7 * L11)
        c_x = mpmath.sqrt(D**2 * (L1**2 + L2**2 + L3**2) - x0**2)
        c_y = mpmath.sqrt(D**2 * (L5**2 + L6**2 + L7**2) - y0**2)
        r3 = [D * v for v in (L9, L10, L11)]
        r1 = [D * (x0 * a - b) / c_x for a, b in zip((L9, L10, L11), (L1, L2, L3))]
        r2 = [D * (y0 * a - b) / c_y for a, b in zip((L9, L10, L11), (L5, L6, L7))]
        R = mpmath.matrix([[r1[i], r2[i], r3[i]] for i in range(3)])
        A = mpmath.matrix([[L1, L2, L3], [L5, L6, L7], [L9, L10, L11]])
        X0 = mpmath.lu_solve(A, mpmath.matrix([-L4, -L8, -1]))
        return {"D": D, "x0": x0, "y0": y0, "cx": c_x, "cy": c_y,
                "X0": [X0[i] for i in range(3)], "R": R, "det": mpmath.det(R)}


def decompose_proper(L):
    """:func:`decompose` with the sign of D chosen so that ``det R > 0``."""
    out = decompose(L, -1)
    return out if out["det"] > 0 else decompose(L, +1)


def opk_from_matrix(R):
    """``(ω, φ, κ)`` in degrees from the elements r13, r23, r33, r12, r11 of ``R_ω R_φ R_κ``.

    From the symbolic R: ``r13 = sin φ``, ``r23/r33 = −tan ω``, ``r12/r11 = −tan κ``.
    """
    Rs = rotation_opk()
    assert Rs[0, 2] == sp.sin(phi)
    with mpmath.workdps(30):
        w = mpmath.atan2(-R[1, 2], R[2, 2])
        p = mpmath.asin(R[0, 2])
        k = mpmath.atan2(-R[0, 1], R[0, 0])
        return tuple(mpmath.degrees(v) for v in (w, p, k))


def collinearity_413_form():
    """(x', y') = z'·kx/N with ``k = Rᵀ·X + X0*``, as functions of r_ij and X0*.

    Returns ``(x, y, X0star)`` in the general-R symbols of :mod:`photolib.derive.collinearity`
    with ``z' = −c`` and no principal point, and the definition ``X0* = −Rᵀ·X0``.
    """
    R = col.rotation_symbols()
    X0v = sp.Matrix([col.X0, col.Y0, col.Z0])
    xs, ys = col.image_coordinates(R)
    X0star = -R.T * X0v
    return xs.subs(col.x0, 0), ys.subs(col.x0, 0).subs(col.y0, 0), X0star


def dy_dphi():
    """``∂y'/∂φ`` by differentiation of the collinearity equation (R = R_ω R_φ R_κ)."""
    return col.jacobian()["phi"][1]


def k_substitution():
    """``{k_x: …, k_y: …, N: …}`` with ``(k_x, k_y, N) = Rᵀ(X − X0)``, R = R_ω R_φ R_κ."""
    kx, ky, N = sp.symbols("k_x k_y N", real=True)
    k = col.k_vector()
    return {kx: k[0], ky: k[1], N: k[2]}


def composed_rotation_is_rotation():
    """``R(ξ, η, ζ)·A(ω, φ, κ)`` is orthonormal with det 1 (numerically at 30 digits)."""
    xi, eta, zeta = sp.symbols("xi eta zeta", real=True)
    M = rotation_opk(xi, eta, zeta) * rotation_opk(omega, phi, kappa)
    vals = {xi: 0.3, eta: -0.7, zeta: 1.1, omega: 0.2, phi: 0.5, kappa: -0.4}
    Mn = M.evalf(30, subs=vals)
    return (Mn.T * Mn - sp.eye(3)).norm() < 1e-25 and abs(Mn.det() - 1) < 1e-25
