"""Diffraction at a circular pupil: Bessel functions and the Airy pattern.

Fraunhofer diffraction of a diffraction-limited lens with f-number k; the radius r and the
wavelength λ share one unit. With ``v = π·r/(λ·k)``:

* point spread function ``I(r)/I(0) = (2·J1(v)/v)²``,
* Airy radius (first dark ring) ``r_A = (j₁,₁/π)·λ·k ≈ 1.22·λ·k``,
* encircled energy ``E(r) = 1 − J0(v)² − J1(v)²``.

J0 and J1 come from SciPy (``scipy.special.jv``, imported on first use).
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_int
from photolib.optics._checks import _array, _finite, _out


#: first positive zero of the Bessel function J1 (the dark ring of the Airy pattern)
J1_FIRST_ZERO = 3.8317059702075125


# -- diffraction ----------------------------------------------------------------------------------

def _jn(n: int, v):
    """J_n(v) of integer order n ≥ 0 from SciPy (``scipy.special.jv``), for the Airy formulas."""
    from scipy.special import jv

    return jv(n, v)


def bessel_jn(n: int, x):
    """Bessel function of the first kind J_n(x) of integer order (deprecated).

    .. deprecated:: 0.1.0
        Use ``scipy.special.jv(n, x)``; this name delegates to it and is removed in the next
        release. It was Bessel's integral by the trapezoidal rule while the library was
        NumPy-only.

    .. math:: J_n(x) = \\frac1\\pi \\int_0^\\pi \\cos(n\\tau - x\\sin\\tau)\\,d\\tau

    Parameters
    ----------
    n : int
        Order n, an integer ≥ 0; an integral float such as ``2.0`` is accepted, anything
        else (an array, inf, NaN, 1.5) raises ``ValueError``.
    x : float or array_like, any shape
        Argument, dimensionless, finite.

    Returns
    -------
    float or ndarray
        J_n(x), dimensionless, same shape as ``x`` (a float for scalar ``x``).
    """
    import warnings

    warnings.warn("photolib.bessel_jn is deprecated and will be removed in the next release; "
                  "use scipy.special.jv(n, x)", DeprecationWarning, stacklevel=2)
    n = as_int(n, "order n", minimum=0)
    x = _finite(_array(x, "x"), "x")
    return _out(_jn(n, x))


def airy_radius(wavelength, k):
    """Radius of the Airy disk (Beugungsscheibchen): the first dark ring, same unit as λ.

    Parameters
    ----------
    wavelength : float or array_like
        Wavelength λ (Wellenlänge), > 0, finite; any length unit, the result has it
        (µm in the course: 0.55 for 550 nm).
    k : float or array_like
        f-number k = f/d (Blendenzahl), dimensionless, > 0, finite; broadcasts with
        ``wavelength``.

    Returns
    -------
    float or ndarray
        Airy radius r_A in the image plane, unit of ``wavelength``; the broadcast shape of the
        inputs (a float for scalars).

    Notes
    -----
    .. math:: r_A = \\frac{j_{1,1}}{\\pi}\\,\\lambda k \\approx 1.22\\,\\lambda k

    with j₁,₁ = 3.8317 the first zero of J1 (the 1.22 is rounded: 1.21967).

    Examples
    --------
    >>> round(airy_radius(0.55, 8.0), 4)   # µm for λ = 550 nm at f/8
    5.3665
    >>> round(airy_radius(0.55, 2.8), 4)   # µm at f/2.8
    1.8783
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

    Parameters
    ----------
    r : float or array_like
        Radial distance from the centre of the pattern in the image plane, finite, same unit
        as ``wavelength`` (µm in the course); the sign is ignored (|r| is used).
    wavelength : float or array_like
        Wavelength λ (Wellenlänge), > 0, finite.
    k : float or array_like
        f-number k = f/d (Blendenzahl), dimensionless, > 0, finite.

    Returns
    -------
    float or ndarray
        Relative intensity I(r)/I(0), dimensionless in [0, 1], 1 at the centre and 0 on the
        dark rings; the broadcast shape of the inputs (a float for scalars).

    Notes
    -----
    .. math:: \\frac{I(r)}{I_0} = \\left(\\frac{2 J_1(v)}{v}\\right)^2, \\qquad
              v = \\frac{\\pi r}{\\lambda k}

    Examples
    --------
    >>> airy_psf(0.0, 0.55, 8.0)
    1.0
    >>> round(airy_psf(airy_radius(0.55, 8.0), 0.55, 8.0), 12)
    0.0
    >>> np.round(airy_psf([0.0, 2.0], 0.55, 8.0), 4).tolist()   # µm: 2 µm off the centre
    [1.0, 0.5865]
    """
    v = _airy_v(r, wavelength, k)
    safe = np.where(v == 0.0, 1.0, v)
    return _out(np.where(v == 0.0, 1.0, (2.0 * _jn(1, safe) / safe) ** 2))


def airy_encircled_energy(r, wavelength, k):
    """Fraction of the light of the Airy pattern inside the radius ``r`` (Rayleigh).

    Parameters
    ----------
    r : float or array_like
        Radius of the circle about the centre of the pattern in the image plane, finite,
        same unit as ``wavelength`` (µm in the course); the sign is ignored.
    wavelength : float or array_like
        Wavelength λ (Wellenlänge), > 0, finite.
    k : float or array_like
        f-number k = f/d (Blendenzahl), dimensionless, > 0, finite.

    Returns
    -------
    float or ndarray
        Encircled energy E(r), the dimensionless fraction of the total light in [0, 1];
        the broadcast shape of the inputs (a float for scalars).

    Notes
    -----
    .. math:: E(r) = 1 - J_0(v)^2 - J_1(v)^2, \\qquad v = \\frac{\\pi r}{\\lambda k}

    Examples
    --------
    >>> round(airy_encircled_energy(airy_radius(0.55, 8.0), 0.55, 8.0), 4)   # Airy disk: 84 %
    0.8378
    >>> round(airy_encircled_energy(1000.0, 0.55, 8.0), 3)   # µm: 1 mm holds nearly all
    0.999
    """
    v = _airy_v(r, wavelength, k)
    return _out(1.0 - _jn(0, v) ** 2 - _jn(1, v) ** 2)


# -- diffraction at a straight edge and at a grating ----------------------------------------------

def edge_diffraction(x, wavelength, distance):
    """Fresnel diffraction behind a straight edge (Beugung an einer Kante): I(x)/I₀.

    A plane wave falls on an opaque half-plane; the intensity is observed on a screen at
    ``distance`` behind it, at ``x`` from the geometric shadow line (x > 0 on the lit side,
    x < 0 in the shadow). Unobstructed light has I₀ = 1.

    Parameters
    ----------
    x : float or array_like
        Distance from the geometric shadow line on the screen, finite, same unit as
        ``wavelength`` and ``distance`` (µm in the course's examples).
    wavelength : float or array_like
        Wavelength λ (Wellenlänge), > 0, finite.
    distance : float or array_like
        Distance z of the screen behind the edge, > 0, finite.

    Returns
    -------
    float or ndarray
        Relative intensity I/I₀, dimensionless: 1/4 on the shadow line, falling
        monotonically into the shadow, oscillating on the lit side about 1 with the first
        maximum 1.37 at w = 1.22; the broadcast shape of the inputs.

    Notes
    -----
    With the Fresnel integrals C, S and the dimensionless :math:`w = x\\sqrt{2/(\\lambda z)}`
    (:func:`photolib.derive.optics.edge_intensity` derives it from the Fresnel–Kirchhoff
    integral over the open half-plane):

    .. math:: \\frac{I}{I_0} = \\tfrac12\\Big[\\big(\\tfrac12 + C(w)\\big)^2
              + \\big(\\tfrac12 + S(w)\\big)^2\\Big]

    Examples
    --------
    >>> edge_diffraction(0.0, 0.55, 1e6)        # on the shadow line: a quarter of the light
    0.25
    >>> round(edge_diffraction(1.2172 * (0.55 * 1e6 / 2) ** 0.5, 0.55, 1e6), 3)  # first fringe
    1.37
    """
    from scipy.special import fresnel

    x = _finite(_array(x, "x"), "x")
    lam = _finite(_array(wavelength, "wavelength", positive=True), "wavelength")
    z = _finite(_array(distance, "distance", positive=True), "distance")
    S, C = fresnel(x * np.sqrt(2.0 / (lam * z)))
    return _out(0.5 * ((0.5 + C) ** 2 + (0.5 + S) ** 2))


def edge_first_fringe(wavelength, distance):
    """Distance of the first bright fringe from the shadow line behind a straight edge.

    Parameters
    ----------
    wavelength, distance : float or array_like
        λ and the screen distance z, > 0, finite, one length unit.

    Returns
    -------
    float or ndarray
        ``x₁ = w₁·√(λz/2)`` in the unit of the inputs, with w₁ = 1.2172 the first root of
        ``dI/dw = (½ + C)·cos(πw²/2) + (½ + S)·sin(πw²/2) = 0`` (solved here, not tabulated).

    Examples
    --------
    >>> round(edge_first_fringe(0.55, 1e6), 1)  # µm: λ = 550 nm, screen 1 m behind
    638.3
    """
    lam = _finite(_array(wavelength, "wavelength", positive=True), "wavelength")
    z = _finite(_array(distance, "distance", positive=True), "distance")
    return _out(_first_fringe_w() * np.sqrt(lam * z / 2.0))


def _first_fringe_w() -> float:
    from scipy.optimize import brentq
    from scipy.special import fresnel

    def slope(w):
        S, C = fresnel(w)
        return (0.5 + C) * np.cos(np.pi * w * w / 2) + (0.5 + S) * np.sin(np.pi * w * w / 2)
    return float(brentq(slope, 0.5, 1.6, xtol=1e-15))


def grating_angles(pitch, wavelength, orders):
    """Directions of the diffraction orders of a grating (Beugungsgitter), in radians.

    Parameters
    ----------
    pitch : float
        Grating period d (Gitterkonstante), > 0, finite, same unit as ``wavelength``.
    wavelength : float
        Wavelength λ, > 0, finite.
    orders : int or array_like of int
        Orders m (0, ±1, ±2 …) at normal incidence.

    Returns
    -------
    float or ndarray
        θ_m = arcsin(m·λ/d), radians, the shape of ``orders``.

    Raises
    ------
    ValueError
        For an order that does not exist, |m|·λ > d (it would leave at more than 90°); the
        message names the order and the highest one that exists.

    Notes
    -----
    Neighbouring slits send waves whose path difference is d·sin θ; they add in phase for
    d·sin θ = m·λ (:func:`photolib.derive.optics.grating_maxima`).

    Examples
    --------
    >>> round(float(np.degrees(grating_angles(1.6, 0.55, 1))), 3)   # µm: a 1.6 µm grating
    20.106
    """
    d = float(_finite(_array(pitch, "pitch d", positive=True), "pitch d"))
    lam = float(_finite(_array(wavelength, "wavelength", positive=True), "wavelength"))
    m = np.asarray(orders)
    if m.dtype.kind not in "iu" and not (m.dtype.kind == "f" and np.all(m == np.round(m))):
        raise ValueError(f"orders must be integers, got {orders!r}")
    s = m * lam / d
    if np.any(np.abs(s) > 1.0):
        top = int(np.floor(d / lam))
        bad = int(np.ravel(m)[np.argmax(np.abs(np.ravel(s)) > 1.0)])
        raise ValueError(f"order m = {bad} does not exist for d = {d:g} and λ = {lam:g}: "
                         f"|m|·λ/d = {abs(bad) * lam / d:.4g} > 1; the highest order is {top}")
    return _out(np.arcsin(s))


def grating_intensity(theta, wavelength, pitch, slit_width, n_slits):
    """Fraunhofer pattern of N slits of width a and period d, normalised to 1 at θ = 0.

    Parameters
    ----------
    theta : float or array_like
        Direction θ from the grating normal, radians, finite.
    wavelength, pitch, slit_width : float
        λ, the period d and the slit width a (0 < a ≤ d), > 0, one length unit.
    n_slits : int
        Number of slits N ≥ 1.

    Returns
    -------
    float or ndarray
        I(θ)/I(0), dimensionless, the shape of ``theta``.

    Notes
    -----
    .. math:: \\frac{I}{I_0} = \\operatorname{sinc}^2\\beta\\,
              \\left(\\frac{\\sin N\\gamma}{N\\sin\\gamma}\\right)^2,\\quad
              \\beta = \\frac{\\pi a\\sin\\theta}{\\lambda},\\;
              \\gamma = \\frac{\\pi d\\sin\\theta}{\\lambda}

    the single-slit envelope times the array factor |Σ e^{i n δ}|² = sin²(Nδ/2)/sin²(δ/2)
    with δ = 2γ (:func:`photolib.derive.optics.grating_array_factor`).

    Examples
    --------
    >>> round(grating_intensity(grating_angles(1.6, 0.55, 1), 0.55, 1.6, 0.4, 10), 4)
    0.8106
    """
    from photolib._validate import as_int

    th = _finite(_array(theta, "theta"), "theta")
    lam = float(_finite(_array(wavelength, "wavelength", positive=True), "wavelength"))
    d = float(_finite(_array(pitch, "pitch d", positive=True), "pitch d"))
    a = float(_finite(_array(slit_width, "slit width a", positive=True), "slit width a"))
    n = as_int(n_slits, "number of slits N", minimum=1)
    if a > d:
        raise ValueError(f"slit width a = {a:g} is larger than the period d = {d:g}")
    beta = np.pi * a * np.sin(th) / lam
    gamma = np.pi * d * np.sin(th) / lam
    envelope = np.sinc(beta / np.pi) ** 2
    sg = np.sin(gamma)
    near = np.abs(sg) < 1e-12                   # a principal maximum: the limit is 1
    factor = np.where(near, 1.0, np.sin(n * gamma) / (n * np.where(near, 1.0, sg))) ** 2
    return _out(envelope * factor)
