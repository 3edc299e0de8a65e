"""Geometric optics of the course, derived from first principles with SymPy.

* Refraction and reflection from Fermat's principle: the travel time of a ray from a point
  at height ``h1`` above an interface to a point ``h2`` below it, crossing at abscissa ``u``,
  is ``T(u) = (n1·√(h1² + u²) + n2·√(h2² + (d − u)²))/c0``; ``dT/du = 0`` is the law.
* Thin lens: a ray through the centre is undeviated, a ray parallel to the axis passes
  through the focal point; intersecting the two rays gives the imaging equation
  ``1/a + 1/a' = 1/f`` (a, a' > 0 measured from the lens) and the image scale a'/a.
* Half field angle of a format s' at camera constant c and half aperture angle of a pupil
  d' at focal length f, by the right triangle on the axis.
* Depth of field: the blur diameter in the focused image plane of an object at distance
  ``a_x`` is ``u'(a_x) = d·|a'_x − a'|/a'_x`` (similar triangles in the light cone of pupil
  diameter ``d = f/k``); solving ``u'(a_v) = u'`` (near) and ``u'(a_h) = u'`` (far) gives
  the limits.
* Natural vignetting: irradiance from a small aperture of area A at an image point seen
  under the angle τ: distance grows as ``c/cos τ`` (inverse square), the aperture is
  foreshortened by ``cos τ`` and the sensor is hit obliquely (``cos τ``).

Examples
--------
>>> import sympy as sp
>>> sp.simplify(imaging_equation_residual())
0
"""

from __future__ import annotations

import sympy as sp

n1, n2, h1, h2, d_int, u, c0 = sp.symbols("n1 n2 h1 h2 d u c0", positive=True)
a, ap, f, k, up, ax = sp.symbols("a a_p f k u_p a_x", positive=True)
a_v, a_h, m_b = sp.symbols("a_v a_h m_b", positive=True)
s_fmt, c_cam, d_pupil, tau = sp.symbols("s_p c d_p tau", positive=True)
E0, A_ap = sp.symbols("E0 A", positive=True)


def fermat_time():
    """Travel time ``T(u)`` across a plane interface (refractive indices n1, n2)."""
    return (n1 * sp.sqrt(h1**2 + u**2) + n2 * sp.sqrt(h2**2 + (d_int - u) ** 2)) / c0


def snell_from_fermat():
    """``c0·dT/du`` rewritten with the angles of incidence α and refraction β.

    With ``sin α = u/√(h1² + u²)`` and ``sin β = (d − u)/√(h2² + (d − u)²)`` the stationarity
    condition reads ``n1 sin α − n2 sin β = 0``. Returns ``(dT/du·c0, sin α, sin β)``.
    """
    dT = sp.diff(fermat_time(), u) * c0
    sin_a = u / sp.sqrt(h1**2 + u**2)
    sin_b = (d_int - u) / sp.sqrt(h2**2 + (d_int - u) ** 2)
    return sp.simplify(dT), sin_a, sin_b


def reflection_from_fermat():
    """``dT/du`` for reflection (both points on the same side, n1 = n2 = 1) and the angles.

    Returns ``(dT/du·c0, sin α_in, sin α_out)``; zero means equal angles.
    """
    T = sp.sqrt(h1**2 + u**2) + sp.sqrt(h2**2 + (d_int - u) ** 2)
    return sp.diff(T, u), u / sp.sqrt(h1**2 + u**2), (d_int - u) / sp.sqrt(h2**2 + (d_int - u) ** 2)


def thin_lens_image_distance(obj=a):
    """Image distance a' of an object point at distance ``obj`` on the axis.

    Object point at ``(-obj, H)``. Ray 1 through the lens centre: ``y = -H·z/obj``. Ray 2
    parallel to the axis, refracted at ``(0, H)`` through the focus ``(f, 0)``:
    ``y = H(1 − z/f)``. Their intersection is the image point; its abscissa is returned.
    """
    H, z = sp.symbols("H z", positive=True)
    sol = sp.solve(sp.Eq(-H * z / obj, H * (1 - z / f)), z)
    return sp.simplify(sol[0])


def imaging_equation_residual():
    """``1/a + 1/a' − 1/f`` with a' from :func:`thin_lens_image_distance` (identically 0)."""
    return 1 / a + 1 / thin_lens_image_distance(a) - 1 / f


def image_scale_number(obj=a):
    """Image scale number ``m_b = a/a'`` (Bildmaßstabszahl); ``M_b = 1 : m_b``."""
    return sp.simplify(obj / thin_lens_image_distance(obj))


def half_field_angle_tan():
    """``tan`` of half the field (format) angle: half the format s' over the camera constant."""
    return (s_fmt / 2) / c_cam


def half_aperture_angle_tan():
    """``tan`` of half the aperture angle: half the pupil d' over the focal length."""
    return (d_pupil / 2) / f


def blur_diameter(obj_x):
    """Blur diameter u' in the plane focused on distance a, for an object at ``obj_x``."""
    apx = thin_lens_image_distance(obj_x)
    apf = thin_lens_image_distance(a)
    d = f / k
    return d * (apx - apf) / apx


def dof_limits():
    """Near and far limit ``(a_v, a_h)`` where the blur reaches ``u_p``.

    Near: ``blur(a_v) = u_p`` with a'_v > a'; far: ``blur(a_h) = −u_p``.
    """
    near = sp.solve(sp.Eq(blur_diameter(ax), up), ax)
    far = sp.solve(sp.Eq(blur_diameter(ax), -up), ax)
    return sp.simplify(near[0]), sp.simplify(far[0])


def dof_blur_from_limits():
    """u' as the printed combination ``(a_h − a_v)/(a_h + a_v)·f²/(k(a − f))`` of the limits.

    Returns the derived u' in terms of a_h, a_v (eliminating u' from the two limits gives the
    identity ``(a_h − a_v)/(a_h + a_v) = u'k(a − f)/f²``); the caller compares forms.
    """
    nv, nh = dof_limits()
    ratio = sp.simplify((nh - nv) / (nh + nv))
    return sp.simplify(ratio * f**2 / (k * (a - f)))


def dof_depth():
    """Depth of field ``t = a_h − a_v`` in terms of u', k, f and the focus distance a."""
    nv, nh = dof_limits()
    return sp.simplify(nh - nv)


def dof_depth_in_scale_number(scale=m_b):
    """:func:`dof_depth` with the focus distance written through the scale number m_b.

    From ``m_b = a/a' = (a − f)/f``: ``a = f(1 + m_b)``.
    """
    a_of_m = sp.solve(sp.Eq(image_scale_number(a), scale), a)[0]
    return sp.simplify(dof_depth().subs(a, a_of_m))


def relative_irradiance():
    """``E(τ)/E(0)`` of natural vignetting for a small aperture of area A at distance c."""
    def irradiance(t):
        dist = c_cam / sp.cos(t)
        solid = A_ap * sp.cos(t) / dist**2     # foreshortened aperture / distance²
        return E0 * solid * sp.cos(t)          # oblique incidence on the sensor
    return sp.simplify(irradiance(tau) / irradiance(0))
