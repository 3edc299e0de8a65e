"""Origins of the distortion terms, beyond the model of :mod:`photolib.derive.distortion`.

* Radial decomposition: a radial displacement Δr' along the unit vector ``(x, y)/r``
  has components ``x·Δr'/r`` and ``y·Δr'/r``.
* Decentring (tangential) distortion: a cubic radial distortion ``K·|p − e|²·(p − e)``
  about a centre e shifted from the principal point, linearised in e, gives
  ``Δx = B1(r² + 2x²) + 2B2·xy`` and ``Δy = B2(r² + 2y²) + 2B1·xy`` with
  ``B1 = −K·e_x``, ``B2 = −K·e_y`` (Brown's form).
* Affine distortion: any linear image deformation ``[[1 + m11, m12], [m21, 1 + m22]]``
  differs from the course's two-parameter form (C1, C2) by a similarity, which the
  camera constant (scale) and κ (rotation) absorb.

Examples
--------
>>> dx, dy = decentring_linearised()
>>> import sympy as sp
>>> sp.expand(dx - (B1*(x**2 + y**2 + 2*x**2) + 2*B2*x*y)).subs(tangential_parameters())
0
"""

from __future__ import annotations

import sympy as sp

from photolib.derive.distortion import B1, B2, C1, C2, x, y

Kc, ex, ey, eps = sp.symbols("K e_x e_y epsilon", real=True)
dr = sp.symbols("Delta_r", real=True)


def radial_components():
    """``Δr'·(x, y)/r``."""
    r = sp.sqrt(x**2 + y**2)
    return dr * x / r, dr * y / r


def decentring_linearised():
    """First order in ε of ``K|p − εe|²(p − εe)`` minus its value at ε = 0."""
    p = sp.Matrix([x, y])
    e = sp.Matrix([ex, ey])
    q = p - eps * e
    d = Kc * (q.T * q)[0] * q
    first = sp.diff(d, eps).subs(eps, 0)
    return sp.expand(first[0]), sp.expand(first[1])


def tangential_parameters():
    """``{K·e_x: …}`` written as the substitution ``{e_x: −B1/K, e_y: −B2/K}``."""
    return {ex: -B1 / Kc, ey: -B2 / Kc}


def similarity_difference(delta_a, delta_b):
    """``Δa − Δb`` as a 2×2 matrix of a linear map in (x, y); returns (matrix, is_similarity).

    A similarity ``[[s, −t], [t, s]]`` (scale and rotation) is absorbed by c and κ.
    """
    diff = sp.Matrix([sp.expand(delta_a[i] - delta_b[i]) for i in range(2)])
    M = diff.jacobian([x, y])
    assert sp.expand(diff - M * sp.Matrix([x, y])) == sp.zeros(2, 1)
    return M, sp.expand(M[0, 0] - M[1, 1]) == 0 and sp.expand(M[0, 1] + M[1, 0]) == 0


def affine_course():
    """The course's affine distortion ``(C1x + C2y, 0)``."""
    return C1 * x + C2 * y, sp.Integer(0)
