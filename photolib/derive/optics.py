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

import functools

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
    # distribute n2·(u − d) over its square root, leaving the radicands alone: the form
    # sp.simplify returns, in a thousandth of its time
    return sp.expand(dT, multinomial=False, power_base=False, power_exp=False), sin_a, sin_b


def reflection_from_fermat():
    """``dT/du`` for reflection (both points on the same side, n1 = n2 = 1) and the angles.

    Returns ``(dT/du·c0, sin α_in, sin α_out)``; zero means equal angles.
    """
    T = sp.sqrt(h1**2 + u**2) + sp.sqrt(h2**2 + (d_int - u) ** 2)
    return sp.diff(T, u), u / sp.sqrt(h1**2 + u**2), (d_int - u) / sp.sqrt(h2**2 + (d_int - u) ** 2)


def _linear_root(lhs, rhs, x):
    """The root of ``lhs = rhs`` when it is linear in ``x`` after clearing denominators.

    Every equation solved in this module is of that kind; doing it by coefficients is exact
    and some ten times faster than ``sp.solve`` (which the chapter would otherwise wait for).
    """
    num = sp.Poly(sp.numer(sp.together(lhs - rhs)), x)
    if num.degree() != 1:
        raise ValueError(f"{lhs} = {rhs} is not linear in {x} (degree {num.degree()})")
    c1, c0 = num.all_coeffs()
    return -c0 / c1


def _positive_denominators(expr):
    """``expr`` (a product) with a leading minus sign taken out of each denominator factor.

    ``sp.cancel`` and ``sp.factor`` return ``-a/(b − c)`` where ``sp.simplify`` writes
    ``a/(c − b)``; this gives the latter form (the same expression, structurally) without
    simplify's search, which costs the chapter a tenth of a second per call.
    """
    sign, factors = sp.S.One, []
    for term in sp.Mul.make_args(expr):
        base, exp = term.as_base_exp()
        if exp.is_negative and exp.is_integer and isinstance(base, sp.Add) \
                and base.could_extract_minus_sign():
            factors.append((-base) ** exp)
            sign *= (-1) ** exp
        else:
            factors.append(term)
    return sign * sp.Mul(*factors)


def thin_lens_image_distance(obj=a):
    """Image distance a' of an object point at distance ``obj`` on the axis.

    Object point at ``(-obj, H)``. Ray 1 through the lens centre: ``y = -H·z/obj``. Ray 2
    parallel to the axis, refracted at ``(0, H)`` through the focus ``(f, 0)``:
    ``y = H(1 − z/f)``. Their intersection is the image point; its abscissa is returned.
    """
    H, z = sp.symbols("H z", positive=True)
    return sp.together(_linear_root(-H * z / obj, H * (1 - z / f), z))


def imaging_equation_residual():
    """``1/a + 1/a' − 1/f`` with a' from :func:`thin_lens_image_distance` (identically 0)."""
    return 1 / a + 1 / thin_lens_image_distance(a) - 1 / f


def image_scale_number(obj=a):
    """Image scale number ``m_b = a/a'`` (Bildmaßstabszahl); ``M_b = 1 : m_b``."""
    return sp.together(obj / thin_lens_image_distance(obj))


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


@functools.cache
def dof_limits():
    """Near and far limit ``(a_v, a_h)`` where the blur reaches ``u_p``.

    Near: ``blur(a_v) = u_p`` with a'_v > a'; far: ``blur(a_h) = −u_p``.
    """
    near = _linear_root(blur_diameter(ax), up, ax)
    far = _linear_root(blur_diameter(ax), -up, ax)
    return sp.cancel(near), _positive_denominators(sp.cancel(far))


def dof_blur_from_limits():
    """u' as the printed combination ``(a_h − a_v)/(a_h + a_v)·f²/(k(a − f))`` of the limits.

    Returns the derived u' in terms of a_h, a_v (eliminating u' from the two limits gives the
    identity ``(a_h − a_v)/(a_h + a_v) = u'k(a − f)/f²``); the caller compares forms.
    """
    nv, nh = dof_limits()
    ratio = sp.factor((nh - nv) / (nh + nv))
    return sp.cancel(ratio * f**2 / (k * (a - f)))


def dof_depth():
    """Depth of field ``t = a_h − a_v`` in terms of u', k, f and the focus distance a."""
    nv, nh = dof_limits()
    return _positive_denominators(sp.factor(nh - nv))


def dof_depth_in_scale_number(scale=m_b):
    """:func:`dof_depth` with the focus distance written through the scale number m_b.

    From ``m_b = a/a' = (a − f)/f``: ``a = f(1 + m_b)``.
    """
    a_of_m = _linear_root(image_scale_number(a), scale, a)
    num, den = sp.fraction(sp.cancel(dof_depth().subs(a, a_of_m)))
    return sp.factor(num) / den  # as sp.simplify writes it, some ten times faster


def relative_irradiance():
    """``E(τ)/E(0)`` of natural vignetting for a small aperture of area A at distance c."""
    def irradiance(t):
        dist = c_cam / sp.cos(t)
        solid = A_ap * sp.cos(t) / dist**2     # foreshortened aperture / distance²
        return E0 * solid * sp.cos(t)          # oblique incidence on the sensor
    return sp.together(irradiance(tau) / irradiance(0))


# -- extensions for chapter 02: hyperfocal distance, diffraction, dispersion, stereo vision -------
lam, n_glass, n_ref, R1, R2, f_ref = sp.symbols("lambda n n_ref R1 R2 f_ref", positive=True)
v_airy, eps, base, Z_obj, dZ = sp.symbols("v epsilon b Z Delta_Z", positive=True)
d_pin = sp.Symbol("d", positive=True)


def hyperfocal_distance():
    """Focus distance at which the far limit goes to infinity: the denominator of a_h is 0.

    Returns ``H = f + f²/(k u')``.
    """
    _, far = dof_limits()
    den = sp.denom(sp.together(far))
    return sp.expand(_linear_root(den, 0, a))


def airy_first_zero(digits: int = 20):
    """First positive zero j₁,₁ of the Bessel function J1 (mpmath through ``sp.nsolve``)."""
    x = sp.Symbol("x", positive=True)
    return sp.nsolve(sp.besselj(1, x), x, 3.8, prec=digits)


def airy_radius_factor(digits: int = 20):
    """``r_A/(λk) = j₁,₁/π``: the "1.22" of the Airy radius r_A = 1.22·λ·k.

    The Fraunhofer pattern of a circular pupil of diameter d at the image distance f is
    ``(2J1(v)/v)²`` with ``v = π d r/(λ f) = π r/(λ k)``; its first zero is v = j₁,₁.
    """
    return airy_first_zero(digits) / sp.pi


def airy_intensity(v=v_airy):
    """Normalised Airy pattern ``(2 J1(v)/v)²``; its limit at v → 0 is 1."""
    return (2 * sp.besselj(1, v) / v) ** 2


def airy_encircled_energy(v=v_airy):
    """Rayleigh's encircled energy ``1 − J0(v)² − J1(v)²`` (``d/dv = 2J1(v)²/v``)."""
    return 1 - sp.besselj(0, v) ** 2 - sp.besselj(1, v) ** 2


def encircled_energy_rate_residual():
    """``dE/dv − (v/2)·I(v)``: the energy of a ring 2πv dv of the pattern, normalised.

    Zero identically: ``E(v) = ½∫₀ᵛ I(t)·t dt`` — so E is the integral of the PSF.
    """
    rate = sp.diff(airy_encircled_energy(), v_airy)
    rate = rate.rewrite(sp.besselj)
    expr = sp.expand_func(rate - v_airy / 2 * airy_intensity())
    # J0' = −J1 and J1' = J0 − J1/v: reduce to J0, J1 only
    J0, J1 = sp.besselj(0, v_airy), sp.besselj(1, v_airy)
    expr = expr.subs({sp.besselj(2, v_airy): 2 * J1 / v_airy - J0,
                      sp.besselj(-1, v_airy): -J1})
    return sp.together(expr)


SELLMEIER_B = sp.symbols("B1:4", positive=True)
SELLMEIER_C = sp.symbols("C1:4", positive=True)


def sellmeier_index(B=SELLMEIER_B, C=SELLMEIER_C):
    """Sellmeier dispersion ``n(λ) = √(1 + Σ Bᵢλ²/(λ² − Cᵢ))`` (resonances at λ² = Cᵢ)."""
    return sp.sqrt(1 + sum(b * lam**2 / (lam**2 - c) for b, c in zip(B, C)))


def lensmaker_focal_length(n=n_glass):
    """Thin-lens lensmaker equation ``1/f = (n − 1)(1/R1 − 1/R2)`` solved for f."""
    return 1 / ((n - 1) * (1 / R1 - 1 / R2))


def chromatic_focal_length():
    """f(λ) from f at a reference index: ``f_ref·(n_ref − 1)/(n − 1)`` (same R1, R2)."""
    ratio = sp.together(lensmaker_focal_length(n_glass) / lensmaker_focal_length(n_ref))
    return f_ref * ratio


def parallactic_angle(Z=Z_obj):
    """Parallactic angle γ = 2·atan(b/(2Z)) of a point at distance Z seen with base b."""
    return 2 * sp.atan(base / (2 * Z))


def stereo_depth_acuity_exact():
    """ΔZ at which γ has dropped by the acuity ε: ``b/(2 tan((γ − ε)/2)) − Z``."""
    gamma = parallactic_angle(Z_obj)
    return base / (2 * sp.tan((gamma - eps) / 2)) - Z_obj


def stereo_depth_acuity_first_order():
    """First order in ε of :func:`stereo_depth_acuity_exact`: ``ε(Z² + b²/4)/b ≈ Z²ε/b``."""
    exact = stereo_depth_acuity_exact()
    # the Taylor polynomial of degree 1 written out: the same as sp.series(…, eps, 0, 2) and
    # some fifteen times faster
    first = exact.subs(eps, 0) + sp.diff(exact, eps).subs(eps, 0) * eps
    return sp.expand(first)


def pinhole_blur(d=d_pin):
    """Blur of a pinhole camera: the hole ``d`` (geometric) plus the Airy disk 2·1.22·λc/d."""
    return d + 2 * sp.Rational(122, 100) * lam * c_cam / d


def pinhole_optimum():
    """Diameter minimising :func:`pinhole_blur`: ``d* = √(2.44 λ c)``.

    The stationary point: the numerator of ``d(blur)/dd`` is a quadratic in d with one
    positive root. (``sp.solve`` gives the same root, but its first call in a process
    imports ``sympy.physics.units`` for its simplification: a third of a second.)
    """
    num = sp.numer(sp.together(sp.diff(pinhole_blur(), d_pin)))
    (root,) = (r for r in sp.roots(sp.Poly(num, d_pin)) if r.is_positive)
    return root


# -- chromatic aberration through a stop, camera constant at a finite distance -----------------
f_lam, s_stop, rho = sp.symbols("f_lambda s_stop rho", positive=True)
f_1, f_2 = sp.symbols("f_1 f_2", positive=True)


def bundle_height(f_w=f_lam, rho_=rho):
    """Height in the image plane at a' of the ray of a parallel bundle at field angle τ.

    The ray passes the stop (distance ``s_stop`` in front of a thin lens of focal length
    ``f_w`` for its wavelength) at height ρ, meets the lens at ``ρ + s·tan τ``, leaves it
    with slope ``tan τ − h/f_w`` and reaches the plane at a': ``h(1 − a'/f_w) + a'·tan τ``.
    """
    h = rho_ + s_stop * sp.tan(tau)
    return sp.expand(h * (1 - ap / f_w) + ap * sp.tan(tau))


def colour_spot(f_w=f_lam):
    """``(centre, diameter)`` of the spot of one wavelength in the plane at a'.

    The marginal rays pass the stop at ρ = ±d/2 with ``d = f/k``; the centre is the chief
    ray (ρ = 0, through the middle of the stop), the diameter ``d·|1 − a'/f_w|``.

    >>> colour_spot()[1]
    f*Abs(a_p - f_lambda)/(f_lambda*k)
    """
    d = f / k
    top, bottom = bundle_height(f_w, d / 2), bundle_height(f_w, -d / 2)
    centre = sp.expand((top + bottom) / 2)
    return centre, sp.factor(sp.Abs(sp.factor(top - bottom)))


def chromatic_errors():
    """``(longitudinal blur of wavelength 2, lateral shift)`` for two wavelengths f_1, f_2.

    The image plane is focused for wavelength 1 (a' = f_1, object at infinity): the second
    wavelength is blurred by ``(f/k)·|1 − f_1/f_2|`` (the longitudinal error, Längsfehler),
    and the centres of the two spots are apart by ``s·tan τ·(f_2 − f_1)/f_2`` (the lateral
    error, Querfehler), which has no k in it (and vanishes with the stop at the lens, s = 0).

    >>> chromatic_errors()
    (f*Abs(f_1 - f_2)/(f_2*k), -s_stop*(f_1 - f_2)*tan(tau)/f_2)
    """
    c1, _ = colour_spot(f_1)
    c2, blur2 = colour_spot(f_2)
    return sp.factor(blur2.subs(ap, f_1)), sp.factor((c2 - c1).subs(ap, f_1))


# -- diffraction at a straight edge and at a grating ----------------------------------------------
w_edge = sp.Symbol("w", real=True)
t_int = sp.Symbol("t", real=True)
delta_g, theta_g, d_g, lam_g = sp.symbols("delta theta d lambda", positive=True)
m_order = sp.Symbol("m", integer=True)


def edge_intensity(w=w_edge):
    """Intensity behind a straight edge relative to the free wave, from Fresnel–Kirchhoff.

    In the Fresnel approximation the edge only limits the integral across it: the amplitude
    at the point of observation, with the aperture coordinate scaled to ``t`` so that the
    phase is π·t²/2, is ``∫_{−w}^{∞} e^{iπt²/2} dt`` where ``w = x·√(2/(λz))``; the free
    wave is the same integral from −∞, ``1 + i``. Splitting at 0 (the integrand is even):
    ``∫₀^∞ + ∫₀^w`` = ``(½ + C(w)) + i(½ + S(w))``, so ``I/I₀ = ½[(½ + C)² + (½ + S)²]``.
    The integrals are SymPy's own (``integrate`` gives ``fresnelc``, ``fresnels`` and the
    Fresnel limits ½).
    """
    half_c = sp.integrate(sp.cos(sp.pi * t_int**2 / 2), (t_int, 0, sp.oo))
    half_s = sp.integrate(sp.sin(sp.pi * t_int**2 / 2), (t_int, 0, sp.oo))
    C = sp.gammasimp(sp.integrate(sp.cos(sp.pi * t_int**2 / 2), (t_int, 0, w)))
    S = sp.gammasimp(sp.integrate(sp.sin(sp.pi * t_int**2 / 2), (t_int, 0, w)))
    amplitude = (half_c + C) + sp.I * (half_s + S)
    free = 2 * half_c + 2 * sp.I * half_s
    return sp.simplify(sp.expand_complex(amplitude * sp.conjugate(amplitude))
                       / sp.expand_complex(free * sp.conjugate(free)))


def grating_array_factor(n: int):
    """``|Σ_{k<N} e^{ikδ}|² − sin²(Nδ/2)/sin²(δ/2)`` for a given N: zero (returned simplified).

    The waves of N equally spaced slits differ in phase by δ = 2π·d·sin θ/λ; the geometric
    sum of their phasors has this closed form.
    """
    s = sum(sp.exp(sp.I * k * delta_g) for k in range(int(n)))
    power = sp.expand(s * sp.conjugate(s))
    closed = sp.sin(n * delta_g / 2) ** 2 / sp.sin(delta_g / 2) ** 2
    return sp.simplify((power - closed).rewrite(sp.exp))


def grating_maxima():
    """``sin θ_m`` of the principal maxima: the phase step δ = 2π·d·sin θ/λ equal to 2π·m."""
    s = sp.Symbol("s", real=True)
    return sp.solve(sp.Eq(2 * sp.pi * d_g * s / lam_g, 2 * sp.pi * m_order), s)[0]
