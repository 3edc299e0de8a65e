"""Digital images and sensors, derived with SymPy: pixel footprint, gain, quantisation, exposure.

* Pixel footprint (Pixelauflösung): the ray of an image point ``(x', y')`` leaves the
  projection centre at height H along ``D = R·(x', y', −c)`` (collinearity,
  :mod:`photolib.derive.collinearity`) and meets the ground plane ``Z = g·X`` (slope g,
  through the nadir point). A pixel of pitch p covers the area element
  ``p²·det ∂(X, Y)/∂(x', y')·√(1 + g²)``; for a vertical image (ω = φ = 0) of flat ground
  (g = 0) this is ``(p·H/c)²`` — similar triangles, GSD = p·H/c.
* Gain and full well: a pixel with quantum efficiency η turns N photons into η·N
  electrons; the converter codes ``DN = η·N/K`` (before rounding) with the gain K in e⁻/DN.
  One grey level therefore takes ``K/η`` photons, and the largest grey value ``2^b − 1``
  stands for the charge ``K·(2^b − 1)`` (the sum of its 2^b − 1 steps).
* Quantisation: the rounding error of a step Δ is uniform on ``[−Δ/2, Δ/2]``; its mean
  is 0 and its variance ``(1/Δ)∫e² de = Δ²/12`` (integrated, not quoted).
* Exposure (Lichtmenge): the irradiance from a Lambertian scene of radiance L through a
  cone of half angle u' is ``∫ L cos θ dΩ = π L sin² u'`` (integrated); with the sine
  condition and the object at infinity ``sin u' = d/(2f)``, so the charge of a pixel of
  area A_px in the time t is ``Q = L·(π d²/4)·A_px·t/f²``: the pupil area times the time.
* Dynamic range: the largest signal over the noise floor, ``FW/σ_r``.
* Image pyramid: every level halves the rows and the columns, so level i has ``4^−i`` of
  the pixels; the levels 1…n together add ``Σ 4^−i = (1 − 4^−n)/3`` (→ 1/3) of the image.

Keep it small: every function here takes well under a second (no unbounded ``simplify``).

Examples
--------
>>> import sympy as sp
>>> quantisation_variance()
Delta**2/12
>>> sp.trigsimp(pixel_ground_area().subs({omega: 0, phi: 0, g: 0}) - (p * H / c)**2)
0
>>> photons_per_grey_level()
K/eta
>>> exposure_ratio()
d**2*t/(d_ref**2*t_ref)
"""

from __future__ import annotations

import sympy as sp

from photolib.derive.rotation import kappa, omega, phi, rotation_opk

__all__ = ["A_px", "FW", "H", "K", "L", "bayer_fractions", "bits", "c", "charge_at_max_dn",
           "d", "d_ref", "dynamic_range", "eta", "exposure", "exposure_ratio", "f",
           "fill_fraction", "g", "gsd_vertical", "kappa", "object_accuracy", "omega", "p",
           "phi", "photons_per_grey_level", "pixel_ground_area", "pyramid_overhead",
           "quantisation_variance",
           "sigma_img", "sigma_r", "t", "t_ref", "x", "y"]

p, c, H = sp.symbols("p c H", positive=True)          # pixel pitch, camera constant, height
x, y, g = sp.symbols("x y g", real=True)              # image point, ground slope
K, eta, FW, bits, sigma_r = sp.symbols("K eta FW b sigma_r", positive=True)
N_ph, Delta, e_q = sp.symbols("N_ph Delta e", positive=True)
L, f, d, t, A_px, u_p = sp.symbols("L f d t A_px u_p", positive=True)
d_ref, t_ref = sp.symbols("d_ref t_ref", positive=True)
m_b, sigma_img, a_act = sp.symbols("m_b sigma_img a", positive=True)


def ground_point(R: sp.Matrix | None = None):
    """``(X − X0, Y − Y0)`` where the ray of ``(x', y')`` meets the plane ``Z = g·(X − X0)``.

    The projection centre is at height H above the nadir point; ``D = R·(x', y', −c)``
    and ``λ = −H/(D_z − g·D_x)`` from ``H + λ·D_z = g·λ·D_x``.
    """
    R = rotation_opk() if R is None else R
    D = R * sp.Matrix([x, y, -c])
    lam = -H / (D[2] - g * D[0])
    return lam * D[0], lam * D[1]


def pixel_ground_area(R: sp.Matrix | None = None):
    """Object-space area covered by a pixel of pitch p at ``(x', y')``: ``p²·det J·√(1 + g²)``."""
    Xg, Yg = ground_point(R)
    det = sp.diff(Xg, x) * sp.diff(Yg, y) - sp.diff(Xg, y) * sp.diff(Yg, x)   # 2 × 2, unexpanded
    return p**2 * det * sp.sqrt(1 + g**2)


def gsd_vertical():
    """Ground sampling distance of a vertical image of flat ground: ``X(x' + p) − X(x')``.

    >>> gsd_vertical()
    H*p/c
    """
    Xg, _ = ground_point(sp.eye(3))
    return sp.cancel((Xg.subs(x, x + p) - Xg).subs(g, 0))


def photons_per_grey_level():
    """Photons per grey level: ``1/(dDN/dN)`` with ``DN = η·N/K`` (K in e⁻/DN)."""
    dn = eta * N_ph / K
    return sp.cancel(1 / sp.diff(dn, N_ph))


def charge_at_max_dn():
    """Charge (e⁻) coded by the largest grey value ``2^b − 1``: the sum of its steps K.

    >>> charge_at_max_dn()
    K*(2**b - 1)
    """
    i = sp.Symbol("i", integer=True, positive=True)
    return sp.factor(sp.Sum(K, (i, 1, 2**bits - 1)).doit())


def quantisation_variance():
    """Variance of a rounding error uniform on ``[−Δ/2, Δ/2]``, by integration."""
    mean = sp.integrate(e_q, (e_q, -Delta / 2, Delta / 2)) / Delta
    assert mean == 0
    return sp.integrate(e_q**2, (e_q, -Delta / 2, Delta / 2)) / Delta


def dynamic_range():
    """Dynamic range: the full well over the read-noise floor, ``FW/σ_r`` (any architecture)."""
    return FW / sigma_r


def exposure():
    """Charge ``Q`` of a pixel: ``t·A_px·∫ L cos θ dΩ`` over the cone, sine condition.

    >>> exposure()
    pi*A_px*L*d**2*t/(4*f**2)
    """
    th, ph = sp.symbols("theta varphi", positive=True)
    irr = sp.integrate(sp.integrate(L * sp.cos(th) * sp.sin(th), (th, 0, u_p)), (ph, 0, 2 * sp.pi))
    irr = sp.expand_trig(irr)                        # π L sin² u'
    irr = irr.subs(sp.sin(u_p), d / (2 * f))         # sine condition, object at infinity
    return sp.factor(irr * A_px * t)


def exposure_ratio():
    """``Q(d, t)/Q(d_ref, t_ref)``: scene, focal length and pixel cancel."""
    Q = exposure()
    return sp.cancel(Q / Q.subs({d: d_ref, t: t_ref}))


def bayer_fractions(pattern=("R", "G", "G", "B")) -> dict:
    """Fraction of the pixels of each colour in a repeated 2 × 2 tile (counted)."""
    return {col: sp.Rational(pattern.count(col), len(pattern)) for col in "RGB"}


def fill_fraction():
    """Fraction of a uniform irradiance on a p × p pixel that falls on its a × a active area."""
    u, v = sp.symbols("u v", real=True)
    on_active = sp.integrate(1, (u, 0, a_act), (v, 0, a_act))
    on_pixel = sp.integrate(1, (u, 0, p), (v, 0, p))
    return on_active / on_pixel


def object_accuracy(sigma_image=sigma_img, scale_number=m_b):
    """Object-space precision of an image measurement: ``σ_X = m_b·σ'`` (the image scale)."""
    return scale_number * sigma_image


def pyramid_overhead(levels=None):
    """Extra storage of an image pyramid (each level halves rows and columns): ``Σ 4^−i``.

    Summed by SymPy over the levels 1…n (``levels=None``: all levels, n → ∞).

    >>> pyramid_overhead()
    1/3
    >>> pyramid_overhead(3)
    21/64
    """
    i = sp.Symbol("i", integer=True, positive=True)
    n = sp.oo if levels is None else levels
    return sp.summation(sp.Rational(1, 4) ** i, (i, 1, n))
