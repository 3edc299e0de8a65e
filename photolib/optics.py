"""Optics of the camera (Optik): thin lens, depth of field, diffraction, refraction, dispersion.

The formulas are derived in :mod:`photolib.derive.optics` (Fermat → Snell, ray construction →
imaging equation, similar triangles → depth of field, Fraunhofer diffraction → Airy pattern)
and judged against the German lecture summary in :mod:`photolib.errata.de_summary_optics`.

Units: every length argument of one function shares one unit, chosen by the caller (mm in the
course), except where a name says otherwise: Sellmeier wavelengths are in µm (the unit of the
glass catalogues). Angles are radians. Distances a, a' are positive, measured from the lens.

Arrays broadcast: each function accepts scalars or arrays and returns a float for scalar input.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "C_LINE",
    "D_LINE",
    "F_LINE",
    "GLASSES",
    "J1_FIRST_ZERO",
    "DepthOfField",
    "NoRealImageError",
    "TotalInternalReflectionError",
    "abbe_number",
    "airy_encircled_energy",
    "airy_psf",
    "airy_radius",
    "bessel_jn",
    "blur_diameter",
    "chromatic_focal_shift",
    "critical_angle",
    "depth_of_field",
    "f_number",
    "half_aperture_angle",
    "half_field_angle",
    "hyperfocal_distance",
    "image_distance",
    "image_scale_number",
    "natural_vignetting",
    "reflect",
    "refract",
    "refraction_angle",
    "refractive_index",
    "stereo_depth_acuity",
]

#: first positive zero of the Bessel function J1 (the dark ring of the Airy pattern)
J1_FIRST_ZERO = 3.8317059702075125

#: Sellmeier coefficients (B1, B2, B3, C1, C2, C3), C in µm², from the Schott catalogue
#: (N-BK7, N-SF11, F2) and Malitson 1965 (fused silica)
GLASSES = {
    "N-BK7": (1.03961212, 0.231792344, 1.01046945, 0.00600069867, 0.0200179144, 103.560653),
    "N-SF11": (1.73759695, 0.313747346, 1.89878101, 0.013188707, 0.0623068142, 155.23629),
    "F2": (1.34533359, 0.209073176, 0.937357162, 0.00997743871, 0.0470450767, 111.886764),
    "fused silica": (0.6961663, 0.4079426, 0.8974794, 0.0684043**2, 0.1162414**2,
                     9.896161**2),
}

#: Fraunhofer lines d (helium, 587.56 nm), F (hydrogen, 486.13 nm), C (hydrogen, 656.27 nm), µm
D_LINE, F_LINE, C_LINE = 0.5875618, 0.4861327, 0.6562725


class NoRealImageError(ValueError):
    """The object is at or inside the focal length: a thin lens forms no real image."""


class TotalInternalReflectionError(ValueError):
    """Snell's law has no solution: n1·sin α > n2, the ray is totally reflected."""


class DepthOfField(NamedTuple):
    """Near and far limit of the depth of field, its extent and the hyperfocal distance.

    ``far`` and ``depth`` are ``inf`` when the focus distance is at or beyond the hyperfocal
    distance. Same length unit as the inputs.
    """

    near: float
    far: float
    depth: float
    hyperfocal: float


def _array(value, name: str, *, positive: bool = False, nonnegative: bool = False):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got {value!r}") from None
    if np.any(np.isnan(arr)):
        raise ValueError(f"{name} contains NaN: {value!r}")
    if positive and np.any(arr <= 0):
        bad = arr[arr <= 0].ravel()[0]
        raise ValueError(f"{name} must be > 0, got {float(bad)!r}")
    if nonnegative and np.any(arr < 0):
        bad = arr[arr < 0].ravel()[0]
        raise ValueError(f"{name} must be >= 0, got {float(bad)!r}")
    return arr


def _finite(arr: np.ndarray, name: str) -> np.ndarray:
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {float(arr[~np.isfinite(arr)].ravel()[0])!r}")
    return arr


def _out(value):
    value = np.asarray(value, dtype=float)
    return float(value) if value.ndim == 0 else value


# -- thin lens ----------------------------------------------------------------------------------

def image_distance(a, f):
    """Image distance a' of a thin lens (Bildweite) from the imaging equation.

    Parameters
    ----------
    a : float or array_like
        Object distance (Gegenstandsweite) from the lens, > f; ``inf`` gives a' = f.
    f : float or array_like
        Focal length (Brennweite), > 0, same unit as ``a``.

    Returns
    -------
    float or ndarray
        a' in the unit of ``a``.

    Raises
    ------
    NoRealImageError
        If a ≤ f (object at or inside the focal length: a virtual image or none).

    Notes
    -----
    .. math:: \\frac1a + \\frac1{a'} = \\frac1f \\quad\\Rightarrow\\quad a' = \\frac{a f}{a - f}

    Examples
    --------
    >>> image_distance(5000.0, 50.0)   # mm: a camera focused on 5 m
    50.505050505050505
    >>> image_distance(np.inf, 50.0)
    50.0
    """
    a = _array(a, "object distance a", positive=True)
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    if np.any(a <= f):
        bad = np.broadcast_arrays(a, f)
        i = np.argmax((bad[0] <= bad[1]).ravel())
        raise NoRealImageError(f"object distance a = {float(bad[0].ravel()[i])!r} is not beyond "
                               f"the focal length f = {float(bad[1].ravel()[i])!r}: no real image")
    with np.errstate(invalid="ignore"):
        ap = np.where(np.isinf(a), f, a * f / np.where(np.isinf(a), 1.0, a - f))
    return _out(ap)


def image_scale_number(a, f):
    """Image scale number m_b = a/a' (Bildmaßstabszahl); the image scale is M_b = 1 : m_b.

    Parameters
    ----------
    a : float or array_like
        Object distance, > f.
    f : float or array_like
        Focal length, > 0, same unit.

    Returns
    -------
    float or ndarray
        Dimensionless m_b.

    Notes
    -----
    .. math:: m_b = \\frac{a}{a'} = \\frac{a - f}{f}

    Examples
    --------
    >>> image_scale_number(5050.0, 50.0)
    100.0
    """
    ap = image_distance(a, f)
    return _out(np.asarray(a, float) / ap)


def half_field_angle(format_extent, c):
    """Half the field (format) angle Ω (Formatwinkel): tan Ω = s'/(2c), radians.

    ``format_extent`` s' is the side or the diagonal of the format, ``c`` the camera constant
    (same unit); the full angle is 2Ω (errata record ``de-summary:field-angle``).

    .. math:: \\Omega = \\arctan\\frac{s'}{2c}

    >>> round(float(np.degrees(2 * half_field_angle(np.hypot(36.0, 24.0), 50.0))), 2)
    46.79
    """
    s = _finite(_array(format_extent, "format extent s'", positive=True), "format extent s'")
    c = _finite(_array(c, "camera constant c", positive=True), "camera constant c")
    return _out(np.arctan(s / (2.0 * c)))


def half_aperture_angle(d, f):
    """Half the aperture angle α (Öffnungswinkel): tan α = d'/(2f), radians.

    For an object at infinity (image at f); record ``de-summary:aperture-angle``.

    .. math:: \\alpha = \\arctan\\frac{d'}{2f}

    >>> round(float(np.degrees(half_aperture_angle(25.0, 50.0))), 4)
    14.0362
    """
    d = _finite(_array(d, "pupil diameter d'", positive=True), "pupil diameter d'")
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    return _out(np.arctan(d / (2.0 * f)))


def f_number(f, d):
    """f-number k = f/d (Blendenzahl), the reciprocal of the relative aperture d/f.

    .. math:: k = \\frac{f}{d}

    >>> f_number(50.0, 12.5)
    4.0
    """
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    d = _finite(_array(d, "pupil diameter d", positive=True), "pupil diameter d")
    return _out(f / d)


# -- depth of field -------------------------------------------------------------------------------

def _dof_inputs(f, k, u):
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    k = _finite(_array(k, "f-number k", positive=True), "f-number k")
    u = _finite(_array(u, "circle of confusion u'", positive=True), "circle of confusion u'")
    return f, k, u


def blur_diameter(a_x, a, f, k):
    """Blur diameter u' (Zerstreuungskreis) of an object at ``a_x`` when focused on ``a``.

    The light cone of pupil d = f/k converges at a'_x; the sensor sits at a'.

    .. math:: u' = \\frac{f}{k}\\,\\frac{|a'_x - a'|}{a'_x}

    Examples
    --------
    >>> blur_diameter(5000.0, 5000.0, 50.0, 8.0)
    0.0
    >>> round(blur_diameter(np.inf, 5000.0, 50.0, 8.0), 6)   # mm
    0.063131
    """
    k = _finite(_array(k, "f-number k", positive=True), "f-number k")
    apx = np.asarray(image_distance(a_x, f))
    ap = np.asarray(image_distance(a, f))
    return _out(np.asarray(f, float) / k * np.abs(apx - ap) / apx)


def hyperfocal_distance(f, k, u):
    """Hyperfocal distance H: focused there, the depth of field reaches infinity.

    .. math:: H = f + \\frac{f^2}{k\\,u'}

    >>> hyperfocal_distance(50.0, 8.0, 0.03)   # mm
    10466.666666666668
    """
    f, k, u = _dof_inputs(f, k, u)
    return _out(f + f**2 / (k * u))


def depth_of_field(a, f, k, u):
    """Near and far limits of the depth of field (Schärfentiefe) of a thin lens.

    Parameters
    ----------
    a : float or array_like
        Focus distance (Einstellentfernung), > f.
    f : float or array_like
        Focal length, > 0.
    k : float or array_like
        f-number, > 0.
    u : float or array_like
        Permissible blur diameter u' in the image (circle of confusion), > 0; the lecture
        summary uses u' = s'/1500.

    Returns
    -------
    DepthOfField
        ``near`` a_v, ``far`` a_h (``inf`` from the hyperfocal distance on), ``depth`` t,
        ``hyperfocal`` H; one length unit throughout.

    Notes
    -----
    Solving :func:`blur_diameter` = u' in front of and behind the focus:

    .. math:: a_{v,h} = \\frac{a f^2}{f^2 \\pm u' k (a - f)}, \\qquad
              t = \\frac{2 a f^2 u' k (a - f)}{f^4 - u'^2 k^2 (a - f)^2}

    In terms of the scale number m_b = (a − f)/f,
    :math:`t = 2u'k\\,m_b(1 + m_b)/(1 - (u'k\\,m_b/f)^2)`; the summary's print
    ``2u'k(1 + m_b)/(m_b² − (u'k/f)²)`` is wrong (record ``de-summary:depth-of-field-t``).

    Examples
    --------
    >>> dof = depth_of_field(5000.0, 50.0, 8.0, 0.03)
    >>> round(dof.near, 3), round(dof.far, 3), round(dof.depth, 3)
    (3389.371, 9527.439, 6138.068)
    >>> depth_of_field(20000.0, 50.0, 8.0, 0.03).far
    inf
    >>> round(depth_of_field(np.inf, 50.0, 8.0, 0.03).near, 3)   # focus at ∞: near = H − f
    10416.667
    """
    f, k, u = _dof_inputs(f, k, u)
    a = _array(a, "focus distance a", positive=True)
    image_distance(a, f)  # checks a > f
    focus_inf = np.isinf(a)
    a_fin = np.where(focus_inf, 2.0 * f, a)          # placeholder where a = ∞
    g = u * k * (a_fin - f)
    near = np.where(focus_inf, f**2 / (u * k), a_fin * f**2 / (f**2 + g))  # limit a → ∞
    a = a_fin
    with np.errstate(divide="ignore"):
        den = f**2 - g
        far = np.where((den > 0) & ~focus_inf, a * f**2 / np.where(den > 0, den, 1.0), np.inf)
    H = f + f**2 / (k * u)
    return DepthOfField(_out(near), _out(far), _out(far - near), _out(H))


# -- diffraction ----------------------------------------------------------------------------------

def bessel_jn(n: int, x):
    """Bessel function of the first kind J_n(x) of integer order, NumPy only.

    Bessel's integral, evaluated with the trapezoidal rule; the integrand is smooth and
    periodic, so the rule converges exponentially (about N > e|x|/2 + 30 nodes reach machine
    precision, chosen from the largest |x|).

    .. math:: J_n(x) = \\frac1\\pi \\int_0^\\pi \\cos(n\\tau - x\\sin\\tau)\\,d\\tau

    Parameters
    ----------
    n : int
        Order, ≥ 0.
    x : float or array_like
        Argument, finite.

    Examples
    --------
    >>> round(bessel_jn(1, J1_FIRST_ZERO), 12)
    0.0
    >>> round(bessel_jn(0, 0.0), 12)
    1.0
    """
    if int(n) != n or n < 0:
        raise ValueError(f"order n must be an integer >= 0, got {n!r}")
    x = _finite(_array(x, "x"), "x")
    nodes = int(1.4 * float(np.max(np.abs(x), initial=0.0))) + 40 + int(n)
    tau = np.linspace(0.0, np.pi, nodes + 1)
    w = np.full(nodes + 1, 1.0 / nodes)
    w[[0, -1]] *= 0.5
    flat = x.ravel()
    out = np.empty_like(flat)
    step = max(1, 2_000_000 // (nodes + 1))
    for i in range(0, flat.size, step):
        chunk = flat[i:i + step, None]
        out[i:i + step] = np.cos(n * tau - chunk * np.sin(tau)) @ w
    return _out(out.reshape(x.shape))


def airy_radius(wavelength, k):
    """Radius of the Airy disk (Beugungsscheibchen): the first dark ring, same unit as λ.

    .. math:: r_A = \\frac{j_{1,1}}{\\pi}\\,\\lambda k \\approx 1.22\\,\\lambda k

    with j₁,₁ = 3.8317 the first zero of J1 (the 1.22 is rounded: 1.21967).

    >>> round(airy_radius(0.55, 8.0), 4)   # µm for λ = 550 nm at f/8
    5.3665
    """
    lam = _finite(_array(wavelength, "wavelength", positive=True), "wavelength")
    k = _finite(_array(k, "f-number k", positive=True), "f-number k")
    return _out(J1_FIRST_ZERO / np.pi * lam * k)


def _airy_v(r, wavelength, k):
    r = _finite(_array(r, "radius r"), "radius r")
    lam = _finite(_array(wavelength, "wavelength", positive=True), "wavelength")
    k = _finite(_array(k, "f-number k", positive=True), "f-number k")
    return np.pi * np.abs(r) / (lam * k)


def airy_psf(r, wavelength, k):
    """Point spread function of a diffraction-limited lens (Airy pattern), I(r)/I(0).

    Fraunhofer diffraction at a circular pupil; ``r`` and ``wavelength`` in one unit.

    .. math:: \\frac{I(r)}{I_0} = \\left(\\frac{2 J_1(v)}{v}\\right)^2, \\qquad
              v = \\frac{\\pi r}{\\lambda k}

    >>> airy_psf(0.0, 0.55, 8.0)
    1.0
    >>> round(airy_psf(airy_radius(0.55, 8.0), 0.55, 8.0), 12)
    0.0
    """
    v = _airy_v(r, wavelength, k)
    safe = np.where(v == 0.0, 1.0, v)
    return _out(np.where(v == 0.0, 1.0, (2.0 * np.asarray(bessel_jn(1, safe)) / safe) ** 2))


def airy_encircled_energy(r, wavelength, k):
    """Fraction of the light of the Airy pattern inside the radius ``r`` (Rayleigh).

    .. math:: E(r) = 1 - J_0(v)^2 - J_1(v)^2, \\qquad v = \\frac{\\pi r}{\\lambda k}

    >>> round(airy_encircled_energy(airy_radius(0.55, 8.0), 0.55, 8.0), 4)
    0.8378
    """
    v = _airy_v(r, wavelength, k)
    return _out(1.0 - np.asarray(bessel_jn(0, v)) ** 2 - np.asarray(bessel_jn(1, v)) ** 2)


# -- vignetting -----------------------------------------------------------------------------------

def natural_vignetting(xy, c):
    """Relative irradiance E(τ)/E(0) = cos⁴τ of natural vignetting (Lichtabfall).

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Image points reduced to the principal point, mm.
    c : float
        Camera constant, mm, > 0.

    Returns
    -------
    ndarray, shape (N,), or float
        cos⁴τ with tan τ = r'/c.

    Notes
    -----
    .. math:: \\frac{E(\\tau)}{E(0)} = \\cos^4\\tau = \\frac{c^4}{(c^2 + r'^2)^2}

    Right for a small aperture (record ``de-summary:vignetting-cos4``); mechanical
    vignetting comes on top.

    >>> natural_vignetting([0.0, 0.0], 50.0)
    1.0
    >>> natural_vignetting([[50.0, 0.0]], 50.0).round(6).tolist()   # τ = 45°
    [0.25]
    """
    from photolib._validate import as_points

    pts, single = as_points(xy, 2, "xy")
    c = _finite(_array(c, "camera constant c", positive=True), "camera constant c")
    r2 = np.sum(pts**2, axis=1)
    e = c**4 / (c**2 + r2) ** 2
    return float(e[0]) if single else e


# -- refraction and reflection --------------------------------------------------------------------

def refraction_angle(alpha, n1, n2):
    """Angle of refraction β from Snell's law n1·sin α = n2·sin β, radians.

    Raises
    ------
    TotalInternalReflectionError
        If n1·sin α > n2 (beyond the critical angle).

    Notes
    -----
    .. math:: \\beta = \\arcsin\\left(\\frac{n_1}{n_2}\\sin\\alpha\\right)

    >>> round(float(np.degrees(refraction_angle(np.radians(30.0), 1.0, 1.5))), 4)
    19.4712
    """
    alpha = _finite(_array(alpha, "angle of incidence alpha"), "angle of incidence alpha")
    if np.any(np.abs(alpha) > np.pi / 2):
        raise ValueError(f"angle of incidence must be within ±π/2 rad, got {alpha!r}")
    n1 = _finite(_array(n1, "refractive index n1", positive=True), "refractive index n1")
    n2 = _finite(_array(n2, "refractive index n2", positive=True), "refractive index n2")
    s = n1 * np.sin(alpha) / n2
    if np.any(np.abs(s) > 1.0):
        raise TotalInternalReflectionError(
            f"n1·sin α / n2 = {float(np.max(np.abs(s))):.6g} > 1: total internal reflection")
    return _out(np.arcsin(s))


def critical_angle(n1, n2):
    """Critical angle of total internal reflection (Grenzwinkel), n1 > n2: sin α_c = n2/n1.

    >>> round(float(np.degrees(critical_angle(1.5, 1.0))), 4)
    41.8103
    """
    n1 = _finite(_array(n1, "refractive index n1", positive=True), "refractive index n1")
    n2 = _finite(_array(n2, "refractive index n2", positive=True), "refractive index n2")
    if np.any(n1 <= n2):
        raise ValueError(f"a critical angle needs n1 > n2, got n1 = {n1!r}, n2 = {n2!r}")
    return _out(np.arcsin(n2 / n1))


def _directions(d, normal):
    from photolib._validate import as_points

    d, single = as_points(d, 3, "direction d")
    nrm, _ = as_points(normal, 3, "normal")
    for arr, name in ((d, "direction d"), (nrm, "normal")):
        length = np.linalg.norm(arr, axis=1)
        if np.any(length == 0):
            raise ValueError(f"{name} has a zero vector")
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    d, nrm = np.broadcast_arrays(d, nrm)
    cos_i = -np.sum(d * nrm, axis=1)
    # the normal must face the incoming ray; turn it where it does not
    nrm = np.where(cos_i[:, None] < 0, -nrm, nrm)
    return d, nrm, np.abs(cos_i), single


def reflect(d, normal):
    """Direction of a specularly reflected ray (law of reflection α = β).

    .. math:: \\mathbf r = \\mathbf d - 2(\\mathbf d\\cdot\\mathbf n)\\,\\mathbf n

    ``d`` (N, 3) or (3,), the incoming directions, ``normal`` the surface normal (either
    side); both are normalised. Returns unit vectors of the same shape as ``d``.

    >>> reflect([1.0, 0.0, -1.0], [0.0, 0.0, 1.0]).round(6).tolist()
    [0.707107, 0.0, 0.707107]
    """
    d, nrm, cos_i, single = _directions(d, normal)
    r = d + 2.0 * cos_i[:, None] * nrm
    return r[0] if single else r


def refract(d, normal, n1, n2, *, on_total_reflection: str = "raise"):
    """Direction of a refracted ray, Snell's law in vector form.

    Parameters
    ----------
    d : array_like, shape (N, 3) or (3,)
        Incoming ray directions (normalised here).
    normal : array_like, shape (N, 3) or (3,)
        Surface normal, either side (it is turned to face the incoming ray).
    n1, n2 : float
        Refractive indices before and after the surface.
    on_total_reflection : {"raise", "flag"}
        ``"raise"``: :class:`TotalInternalReflectionError`. ``"flag"``: return
        ``(directions, valid)``; totally reflected rows get the reflected direction and
        ``valid = False``.

    Returns
    -------
    ndarray
        Unit directions, shape of ``d`` (and the ``valid`` flags with ``"flag"``).

    Notes
    -----
    With η = n1/n2, cos α = −n·d and cos β = √(1 − η²(1 − cos²α)):

    .. math:: \\mathbf t = \\eta\\,\\mathbf d + (\\eta\\cos\\alpha - \\cos\\beta)\\,\\mathbf n

    Examples
    --------
    >>> d = [np.sin(np.radians(30.0)), 0.0, -np.cos(np.radians(30.0))]
    >>> t = refract(d, [0.0, 0.0, 1.0], 1.0, 1.5)
    >>> round(float(np.degrees(np.arcsin(t[0]))), 4)
    19.4712
    """
    if on_total_reflection not in ("raise", "flag"):
        raise ValueError(f"on_total_reflection must be 'raise' or 'flag', got {on_total_reflection!r}")
    n1 = float(_finite(_array(n1, "refractive index n1", positive=True), "n1"))
    n2 = float(_finite(_array(n2, "refractive index n2", positive=True), "n2"))
    d, nrm, cos_i, single = _directions(d, normal)
    eta = n1 / n2
    sin2_t = eta**2 * (1.0 - cos_i**2)
    valid = sin2_t <= 1.0
    if on_total_reflection == "raise" and not np.all(valid):
        raise TotalInternalReflectionError(
            f"sin²β = {float(np.max(sin2_t)):.6g} > 1 (n1 = {n1}, n2 = {n2}): total internal "
            "reflection; use on_total_reflection='flag' to get the reflected rays")
    cos_t = np.sqrt(np.clip(1.0 - sin2_t, 0.0, None))
    t = eta * d + (eta * cos_i - cos_t)[:, None] * nrm
    r = d + 2.0 * cos_i[:, None] * nrm
    out = np.where(valid[:, None], t, r)
    out = out / np.linalg.norm(out, axis=1, keepdims=True)
    if on_total_reflection == "flag":
        return (out[0], bool(valid[0])) if single else (out, valid)
    return out[0] if single else out


# -- dispersion and chromatic aberration ----------------------------------------------------------

def refractive_index(wavelength_um, glass="N-BK7"):
    """Refractive index n(λ) of a glass by the Sellmeier dispersion formula.

    Parameters
    ----------
    wavelength_um : float or array_like
        Vacuum wavelength in µm (0.55 for 550 nm), > 0 and away from the poles √C_i.
    glass : str or tuple
        A key of :data:`GLASSES` or six coefficients (B1, B2, B3, C1, C2, C3), C in µm².

    Notes
    -----
    .. math:: n^2(\\lambda) = 1 + \\sum_{i=1}^{3} \\frac{B_i\\lambda^2}{\\lambda^2 - C_i}

    Examples
    --------
    >>> round(refractive_index(0.5875618), 5)   # N-BK7 at the d line: catalogue 1.51680
    1.5168
    """
    lam = _finite(_array(wavelength_um, "wavelength_um", positive=True), "wavelength_um")
    if isinstance(glass, str):
        if glass not in GLASSES:
            raise ValueError(f"unknown glass {glass!r}; known: {sorted(GLASSES)}")
        coeff = GLASSES[glass]
    else:
        coeff = tuple(float(v) for v in glass)
        if len(coeff) != 6:
            raise ValueError(f"Sellmeier coefficients must be 6 numbers, got {len(coeff)}")
    B, C = np.array(coeff[:3]), np.array(coeff[3:])
    l2 = lam[..., None] ** 2
    n2 = 1.0 + np.sum(B * l2 / (l2 - C), axis=-1)
    if np.any(n2 < 1.0):
        raise ValueError(f"wavelength_um {lam!r} is at an absorption pole of the Sellmeier model")
    return _out(np.sqrt(n2))


def abbe_number(glass="N-BK7"):
    """Abbe number V_d = (n_d − 1)/(n_F − n_C) (Abbesche Zahl) of a glass.

    >>> round(abbe_number("N-BK7"), 2)   # catalogue 64.17
    64.17
    """
    nd, nF, nC = (refractive_index(w, glass) for w in (D_LINE, F_LINE, C_LINE))
    return (nd - 1.0) / (nF - nC)


def chromatic_focal_shift(f_ref, wavelength_um, reference_um=D_LINE, glass="N-BK7"):
    """Longitudinal chromatic aberration of a thin lens: f(λ) − f(λ_ref).

    By the lensmaker equation 1/f = (n − 1)(1/R1 − 1/R2) the curvatures are fixed, so

    .. math:: f(\\lambda) = f_\\mathrm{ref}\\,\\frac{n(\\lambda_\\mathrm{ref}) - 1}{n(\\lambda) - 1}

    Parameters
    ----------
    f_ref : float
        Focal length at ``reference_um``, > 0 (any unit; the result has it).
    wavelength_um, reference_um : float or array_like
        Wavelengths in µm.
    glass : str or tuple
        See :func:`refractive_index`.

    Examples
    --------
    >>> round(chromatic_focal_shift(50.0, C_LINE) - chromatic_focal_shift(50.0, F_LINE), 4)
    0.7746
    """
    f = _finite(_array(f_ref, "focal length f_ref", positive=True), "f_ref")
    n = np.asarray(refractive_index(wavelength_um, glass))
    n0 = refractive_index(reference_um, glass)
    return _out(f * (n0 - 1.0) / (n - 1.0) - f)


# -- stereoscopic vision --------------------------------------------------------------------------

def stereo_depth_acuity(distance, base, acuity):
    """Smallest depth difference seen stereoscopically (Tiefenauflösung), exact and small-angle.

    Parameters
    ----------
    distance : float or array_like
        Distance Z of the object from the eyes (or cameras), > 0.
    base : float or array_like
        Eye base b (Augenbasis, about 65 mm), > 0, same unit.
    acuity : float or array_like
        Stereoscopic acuity ε (smallest perceivable difference of the parallactic angle),
        radians, > 0 (5''–10'' for the eye).

    Returns
    -------
    float or ndarray
        ΔZ such that the parallactic angle γ = 2·arctan(b/(2Z)) drops by ε from Z to Z + ΔZ;
        ``inf`` where γ ≤ ε (beyond the range of stereo vision).

    Notes
    -----
    .. math:: Z + \\Delta Z = \\frac{b}{2\\tan\\frac{\\gamma - \\varepsilon}{2}}
              \\qquad\\approx\\qquad \\Delta Z \\approx \\frac{Z^2\\varepsilon}{b}

    Examples
    --------
    >>> eps = np.radians(10.0 / 3600.0)
    >>> round(stereo_depth_acuity(1000.0, 65.0, eps), 3)   # mm at 1 m
    0.747
    """
    Z = _finite(_array(distance, "distance", positive=True), "distance")
    b = _finite(_array(base, "base b", positive=True), "base b")
    eps = _finite(_array(acuity, "acuity", positive=True), "acuity")
    gamma = 2.0 * np.arctan(b / (2.0 * Z))
    with np.errstate(divide="ignore"):
        half = np.tan((gamma - eps) / 2.0)
        far = np.where(gamma > eps, b / (2.0 * np.where(gamma > eps, half, 1.0)), np.inf)
    return _out(far - Z)
