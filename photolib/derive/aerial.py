"""Earth curvature and atmospheric refraction in a vertical aerial image, derived with SymPy.

Both move an image point radially, along the line from the nadir (the principal point of a
vertical image); both are corrections of the measured image coordinates that are applied
before the collinearity equations, like the distortion (Polish notes: "refrakcja atmosferyczna
i krzywizna Ziemi ... należy je wyeliminować przed rozpoczęciem dalszych obliczeń").

* **Earth curvature (Erdkrümmung).** The camera is at height H above the ground at the nadir; a
  ground point at arc distance D from the nadir on a sphere of radius R lies R(1 − cos θ) below
  the tangent plane (θ = D/R) and R sin θ from the vertical. Its image radius is
  ``r' = c·R sin θ/(H + R(1 − cos θ))``; a point at the same map distance D on the tangent plane
  (the flat object space of the collinearity equations) is imaged at ``r0 = c·D/H``. To first
  order in 1/R, ``r' − r0 = −r0³·H/(2 R c²)``: the curvature moves images towards the nadir.
* **Refraction (Refraktion).** A ray through a horizontally layered atmosphere bends towards the
  denser air; at the camera it arrives from a direction ``dα = K·tan α`` farther from the nadir
  than the straight line to the ground point (α the nadir angle, K the refraction constant of the
  atmosphere between the ground and the camera). With ``r' = c·tan α`` the image moves outwards by
  ``c·(tan(α + dα) − tan α) = K·(r' + r'³/c²)`` to first order in K.
* **The refraction constant from the layers.** Snell's law in horizontal layers keeps
  ``n(z)·sin θ(z)`` constant along the ray; to first order in n − 1 the horizontal run of the
  ray below the camera gives ``K = (1/(H − h))·∫_h^H (n(z) − n(H)) dz``, the mean excess of the
  refractive index over its value at the camera (:func:`refraction_constant_first_order` shows
  the step for a linear index profile, where the integral is exact).

Examples
--------
>>> import sympy as sp
>>> sp.simplify(earth_curvature_displacement() + r**3 * H / (2 * R * c**2))
0
>>> sp.simplify(refraction_displacement() - K * (r + r**3 / c**2))
0
"""

from __future__ import annotations

import sympy as sp

c, H, R, D, r, K, alpha = sp.symbols("c H R D r K alpha", positive=True)
eps = sp.symbols("epsilon", positive=True)          # 1/R, the small quantity of the series
z, h, g = sp.symbols("z h g", positive=True)          # height, ground height, index gradient


def earth_curvature_image_radius():
    """Exact image radius ``r'(D)`` of a ground point on the sphere, and the flat one ``r0``."""
    theta = D / R
    exact = c * R * sp.sin(theta) / (H + R * (1 - sp.cos(theta)))
    flat = c * D / H
    return exact, flat


def earth_curvature_displacement():
    """First-order term (in 1/R) of ``r' − r0``, written with the image radius ``r``.

    The series is taken in ε = 1/R; D is replaced by the image radius, ``D = r·H/c`` (to this
    order r' and r0 are interchangeable in the term).
    """
    exact, flat = earth_curvature_image_radius()
    # sin and cos by their Taylor polynomials to θ⁴ (θ = D·ε): exact to the order wanted, and
    # a rational function in ε, whose derivative at ε = 0 is quick (a series of the
    # trigonometric form takes several times as long)
    th = sp.Symbol("theta")
    poly = {sp.sin(D / R): sp.sin(th).series(th, 0, 5).removeO().subs(th, D * eps),
            sp.cos(D / R): sp.cos(th).series(th, 0, 5).removeO().subs(th, D * eps)}
    diff = sp.cancel((exact.xreplace(poly) - flat).subs(R, 1 / eps))
    assert diff.subs(eps, 0) == 0                       # no zeroth-order term
    term = sp.diff(diff, eps).subs(eps, 0) * eps
    return sp.factor(term.subs({D: r * H / c, eps: 1 / R}))


def refraction_displacement():
    """First-order term (in K) of ``c·tan(α + K tan α) − c·tan α``, with ``tan α = r/c``."""
    shift = c * sp.tan(alpha + K * sp.tan(alpha)) - c * sp.tan(alpha)
    first = sp.series(shift, K, 0, 2).removeO().coeff(K, 1) * K
    return sp.simplify(sp.expand_trig(first).rewrite(sp.tan).subs(sp.tan(alpha), r / c))


def refraction_constant_first_order():
    """K for a linear index profile ``n(z) = n_H + g·(H − z)`` between h and H.

    Returns ``(K from the mean excess, K from the exact horizontal run)``. The run of the ray
    below the camera, ``X = ∫_h^H tan θ(z) dz`` with ``n(z) sin θ(z) = n_H sin θ_H``, gives the
    direction of the chord, ``tan θ_c = X/(H − h)``; to first order in g,
    ``dα = θ_H − θ_c = K·tan θ_H`` with K the mean relative excess
    ``(1/(H − h))·∫ (n − n_H)/n_H dz = g(H − h)/(2 n_H)``. Written with ``t = tan θ_H``.
    """
    nH, t = sp.symbols("n_H t", positive=True)
    n = nH + g * (H - z)
    mean_excess = sp.integrate((n - nH) / nH, (z, h, H)) / (H - h)
    sin_z = nH * (t / sp.sqrt(1 + t**2)) / n
    tan_z = sin_z / sp.sqrt(1 - sin_z**2)
    slope = sp.diff(tan_z, g).subs(g, 0)                     # d tan θ(z)/dg at g = 0
    d_tan_chord = sp.integrate(sp.simplify(slope), (z, h, H)) / (H - h)
    d_alpha = -g * d_tan_chord / (1 + t**2)                   # d atan(u) = du/(1 + u²)
    return sp.simplify(mean_excess), sp.simplify(d_alpha / t)


def boresight_ground_shift():
    """Ground shift of the principal ray of a nadir camera at height H by a boresight (δω, δφ, δκ).

    The ray ``X0 + λ·R_ω(δω)·R_φ(δφ)·R_κ(δκ)·(0, 0, −1)`` from ``X0 = (0, 0, H)`` meets the
    ground Z = 0; returns the exact (X, Y) and their first-order terms.

    >>> exact, first = boresight_ground_shift()
    >>> first
    [-H*delta_phi, H*delta_omega]
    """
    from photolib.derive.rotation import rotation_opk
    dw, dp, dk = sp.symbols("delta_omega delta_phi delta_kappa", real=True)
    ray = rotation_opk(dw, dp, dk) * sp.Matrix([0, 0, -1])
    lam = -H / ray[2]
    ground = sp.Matrix([0, 0, H]) + lam * ray
    exact = [sp.simplify(g) for g in ground[:2]]
    eps_ = sp.symbols("epsilon_b")
    scaled = [e.subs({dw: eps_ * dw, dp: eps_ * dp, dk: eps_ * dk}) for e in exact]
    first = [sp.series(e, eps_, 0, 2).removeO().subs(eps_, 1) for e in scaled]
    return exact, [sp.simplify(f) for f in first]
