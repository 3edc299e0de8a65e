"""Rotations: elementary rotations, ``R = R_ω·R_φ·R_κ`` and the other named orders.

Conventions (docs/conventions.md): active, right-handed elementary rotations about the
object axes X, Y, Z; R rotates camera (image-space) vectors into the object frame,
``X = X0 + m·R·x*``. Wolf's M is ``Rᵀ``.

The elementary matrices are not typed in: each is the matrix exponential of the
skew-symmetric generator of its axis, ``R_axis(t) = exp(t·[e]×)``, which SymPy evaluates
exactly. So the signs of the sines follow from the right-hand rule, not from a transcription.
"""

from __future__ import annotations

import functools

import sympy as sp

from photolib.derive._spec import GeneratedFunction

omega, phi, kappa = sp.symbols("omega phi kappa", real=True)
alpha = sp.symbols("alpha", real=True)


def skew(v) -> sp.Matrix:
    """Cross-product matrix ``[v]×`` with ``[v]× w = v × w``."""
    v = sp.Matrix(v)
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


@functools.lru_cache(maxsize=256)
def _exp_rotation_cached(axis: int, t) -> sp.ImmutableMatrix:
    e = sp.zeros(3, 1)
    e[axis] = 1
    # exp of a skew matrix (SymPy's Jordan-form exponential); any complex exponentials are
    # rewritten as cos/sin and expanded -- bounded work, no simplify
    m = (skew(e) * t).exp()
    return sp.ImmutableMatrix(m.applyfunc(lambda z: sp.expand_complex(z.rewrite(sp.cos))))


def _exp_rotation(axis: int, t) -> sp.Matrix:
    # the Jordan-form exponential costs ~1 s per call; the errata catalogue and the tests ask
    # for the same few matrices many times, so each (axis, angle) is derived once per process
    # and handed out as a fresh mutable copy
    return sp.Matrix(_exp_rotation_cached(axis, sp.sympify(t)))


def R_omega(t=omega) -> sp.Matrix:
    """Elementary rotation about X (primary axis), ``exp(t·[e_x]×)``."""
    return _exp_rotation(0, t)


def R_phi(t=phi) -> sp.Matrix:
    """Elementary rotation about Y (secondary axis), ``exp(t·[e_y]×)``."""
    return _exp_rotation(1, t)


def R_kappa(t=kappa) -> sp.Matrix:
    """Elementary rotation about Z (tertiary axis), ``exp(t·[e_z]×)``."""
    return _exp_rotation(2, t)


def rotation_opk(w=omega, p=phi, k=kappa) -> sp.Matrix:
    """``R = R_ω · R_φ · R_κ`` (the course convention, Luhmann 2.32)."""
    return R_omega(w) * R_phi(p) * R_kappa(k)


def rotation_pok(w=omega, p=phi, k=kappa) -> sp.Matrix:
    """``R = R_φ · R_ω · R_κ``: the φ-ω-κ order (primary axis Y), used in some aerial software."""
    return R_phi(p) * R_omega(w) * R_kappa(k)


def wolf_m(w=omega, p=phi, k=kappa) -> sp.Matrix:
    """Wolf's orientation matrix ``M = Rᵀ`` (object → image)."""
    return rotation_opk(w, p, k).T


def rotation_2d(t=alpha) -> sp.Matrix:
    """Plane rotation by ``t`` (counter-clockwise, x right, y up): upper-left block of R_κ."""
    return R_kappa(t)[:2, :2]


def angle_rates():
    """Derivatives of R with respect to its angles, as products with skew matrices.

    Returns a dict ``{'omega': S_ω, 'phi': S_φ, 'kappa': S_κ}`` with
    ``∂R/∂ω = [e_x]× R``, ``∂R/∂φ = [R_ω e_y]× R``, ``∂R/∂κ = R [e_z]×``;
    the test suite checks these against ``diff`` of :func:`rotation_opk`.
    """
    R = rotation_opk()
    return {
        "omega": skew([1, 0, 0]) * R,
        "phi": skew(R_omega() * sp.Matrix([0, 1, 0])) * R,
        "kappa": R * skew([0, 0, 1]),
    }


def _elements(M: sp.Matrix, prefix: str):
    return tuple((f"{prefix}{i + 1}{j + 1}", M[i, j]) for i in range(3) for j in range(3))


@functools.cache
def codegen_functions() -> tuple:
    """The functions to generate (built on first use: the Jacobians take a second to derive)."""
    return (
        GeneratedFunction(
            name="rotation_opk_elements",
            args=(omega, phi, kappa),
            outputs=_elements(rotation_opk(), "r"),
            doc="Elements r11..r33 (row-major) of R = R_ω·R_φ·R_κ; angles in radians.",
        ),
        GeneratedFunction(
            name="rotation_pok_elements",
            args=(omega, phi, kappa),
            outputs=_elements(rotation_pok(), "r"),
            doc="Elements r11..r33 (row-major) of R = R_φ·R_ω·R_κ; angles in radians.",
        ),
    )


def __getattr__(name):
    # ``CODEGEN`` is computed lazily so that importing this module (e.g. in a chapter
    # notebook) does not pay for deriving every Jacobian
    if name == "CODEGEN":
        return codegen_functions()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
