"""Distortion model of the course and its Jacobians.

Δ = distorted − ideal, evaluated at the measured image coordinates (x, y) reduced to the
principal point (Luhmann's bundle formulation; docs/conventions.md):

* radial (Seidel with balancing radius r0): ``Δr' = A1·r(r² − r0²) + A2·r(r⁴ − r0⁴) + A3·r(r⁶ − r0⁶)``,
  resolved along the radius: ``Δx_rad = x·Δr'/r``, ``Δy_rad = y·Δr'/r``;
* tangential (Brown): ``Δx_tan = B1(r² + 2x²) + 2B2·xy``, ``Δy_tan = B2(r² + 2y²) + 2B1·xy``;
* affine and shear: ``Δx_aff = C1·x + C2·y``, ``Δy_aff = 0``;
* Conrady's alternative: ``Δr' = K0·r + K1·r³ + K2·r⁵ + K3·r⁷`` (same family:
  ``K1 = A1, K2 = A2, K3 = A3, K0 = −(A1 r0² + A2 r0⁴ + A3 r0⁶)``).

The Jacobian with respect to (x, y) drives Newton's iteration for the inverse problem
(ideal → measured); the Jacobian with respect to the parameters serves self-calibration.
"""

from __future__ import annotations

import sympy as sp

from photolib.derive._spec import GeneratedFunction

x, y = sp.symbols("x y", real=True)
A1, A2, A3, r0, B1, B2, C1, C2 = sp.symbols("A1 A2 A3 r0 B1 B2 C1 C2", real=True)
K0, K1, K2, K3 = sp.symbols("K0 K1 K2 K3", real=True)
#: the parameters of :func:`delta` in the order of the parameter Jacobian
PARAMETERS = ("A1", "A2", "A3", "B1", "B2", "C1", "C2")
_P = {"A1": A1, "A2": A2, "A3": A3, "B1": B1, "B2": B2, "C1": C1, "C2": C2}
rr = sp.symbols("r", nonnegative=True)


def radial_profile(r=rr):
    """``Δr'(r)`` of the A1–A3 model with balancing radius r0."""
    return A1 * r * (r**2 - r0**2) + A2 * r * (r**4 - r0**4) + A3 * r * (r**6 - r0**6)


def conrady_profile(r=rr):
    """``Δr'(r) = K0·r + K1·r³ + K2·r⁵ + K3·r⁷``."""
    return K0 * r + K1 * r**3 + K2 * r**5 + K3 * r**7


def _resolve(profile_over_r):
    # x·Δr'/r: profile_over_r is Δr'/r as a polynomial in r² (no division by r at r = 0)
    return x * profile_over_r, y * profile_over_r


def _r2():
    return x**2 + y**2


def delta_radial():
    """``x·Δr'/r``, ``y·Δr'/r``: Δr'/r is a polynomial in r², so the origin is regular."""
    q = sp.expand(radial_profile(rr) / rr)
    assert not q.has(sp.Pow(rr, -1)), q
    # keep r² as a factor-friendly sub-expression (Horner-like), not expanded powers of x, y
    return _resolve(q.subs(rr, sp.sqrt(_r2())))


def delta_tangential():
    r2 = _r2()
    return B1 * (r2 + 2 * x**2) + 2 * B2 * x * y, B2 * (r2 + 2 * y**2) + 2 * B1 * x * y


def delta_affine():
    return C1 * x + C2 * y, sp.Integer(0)


def delta():
    """``(Δx', Δy')`` of the full model at the reduced measured coordinates (x, y)."""
    parts = (delta_radial(), delta_tangential(), delta_affine())
    return tuple(sum(p[i] for p in parts) for i in range(2))


def delta_conrady():
    """``(Δx', Δy')`` of Conrady's radial model."""
    q = sp.expand(conrady_profile(rr) / rr)
    return _resolve(q.subs(rr, sp.sqrt(_r2())))


def conrady_from_seidel():
    """``{K0: …, K1: …, K2: …, K3: …}`` making :func:`delta_conrady` equal the radial part."""
    sol = sp.solve(sp.Poly(sp.expand(conrady_profile() - radial_profile()), rr).coeffs(),
                   (K0, K1, K2, K3), dict=True)
    return sol[0]


def jacobian_xy():
    """``∂(Δx', Δy')/∂(x, y)`` as a 2×2 matrix."""
    d = sp.Matrix(delta())
    return d.jacobian([x, y])


def jacobian_params():
    """``∂(Δx', Δy')/∂(A1, A2, A3, B1, B2, C1, C2)`` as a 2×7 matrix (r0 held fixed)."""
    d = sp.Matrix(delta())
    return d.jacobian([_P[n] for n in PARAMETERS])


def radial_factor(r2):
    """``q(r²) = Δr'/r`` as a polynomial in r², so that ``Δx_rad = x·q``, ``Δy_rad = y·q``."""
    q = sp.expand(radial_profile(rr) / rr)
    return sp.expand(q.subs(rr, sp.sqrt(r2)))


#: named quantities of the structured (chain-rule) form used for code generation
r2_s, q_s, dq_s = sp.symbols("_r2 _q _dq", real=True)


def structured():
    """Δ and ∂Δ/∂(x, y) written with ``r² = x² + y²``, ``q(r²)`` and ``q'(r²)``.

    Derived, not typed: Δ is written with an undefined function ``Q(x² + y²)`` in place of the
    radial factor, differentiated by SymPy (chain rule), and ``Q``, ``Q'`` and ``x² + y²`` are
    then named. The code generator evaluates q and q' in Horner form, which saves half the
    array operations of the expanded polynomial. Returns ``(intermediates, outputs)``.
    """
    Q = sp.Function("Q")
    r2 = x**2 + y**2
    tx, ty = delta_tangential()
    ax, ay = delta_affine()
    d = sp.Matrix([x * Q(r2) + tx + ax, y * Q(r2) + ty + ay])
    J = d.jacobian([x, y])

    def name(e):
        e = e.doit()
        e = e.replace(lambda z: isinstance(z, sp.Subs), lambda z: dq_s)
        e = e.replace(lambda z: isinstance(z, sp.Derivative), lambda z: dq_s)
        e = e.xreplace({Q(r2): q_s})
        return sp.expand(e).subs(r2, r2_s)

    q = radial_factor(r2_s)
    inter = ((r2_s, x * x + y * y), (q_s, sp.horner(q, r2_s)),
             (dq_s, sp.horner(sp.diff(q, r2_s), r2_s)))
    outs = (("dx", name(d[0])), ("dy", name(d[1])), ("ddx_dx", name(J[0, 0])),
            ("ddx_dy", name(J[0, 1])), ("ddy_dx", name(J[1, 0])), ("ddy_dy", name(J[1, 1])))
    return inter, outs


_ARGS = (x, y, A1, A2, A3, r0, B1, B2, C1, C2)

#: the functions to generate; built on import (polynomials and their Jacobians: 0.15 s, so
#: unlike :mod:`~photolib.derive.rotation` and :mod:`~photolib.derive.collinearity` nothing
#: here is worth deferring)
CODEGEN = (
    GeneratedFunction(
        name="distortion_delta",
        args=_ARGS,
        outputs=(("dx", delta()[0]), ("dy", delta()[1])),
        doc="Δx', Δy' (image unit) at the reduced measured coordinates x, y (image unit).",
    ),
    GeneratedFunction(
        name="distortion_delta_and_jacobian",
        args=_ARGS,
        intermediates=structured()[0],
        outputs=structured()[1],
        doc="Δx', Δy' and their derivatives with respect to x and y (dimensionless), "
            "for Newton's iteration; r² = x² + y², q(r²) and q'(r²) in Horner form.",
    ),
    GeneratedFunction(
        name="distortion_jacobian_params",
        args=_ARGS,
        outputs=tuple((f"d{axis}_d{name}", jacobian_params()[i, j])
                      for j, name in enumerate(PARAMETERS)
                      for i, axis in enumerate(("x", "y"))),
        doc="∂Δx'/∂p, ∂Δy'/∂p for p in (A1, A2, A3, B1, B2, C1, C2), for self-calibration.",
    ),
)
