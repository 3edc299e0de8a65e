"""Diffraction at a circular pupil: Bessel functions and the Airy pattern.

Fraunhofer diffraction of a diffraction-limited lens with f-number k; the radius r and the
wavelength λ share one unit. With ``v = π·r/(λ·k)``:

* point spread function ``I(r)/I(0) = (2·J1(v)/v)²``,
* Airy radius (first dark ring) ``r_A = (j₁,₁/π)·λ·k ≈ 1.22·λ·k``,
* encircled energy ``E(r) = 1 − J0(v)² − J1(v)²``.

J_n comes from Bessel's integral (NumPy only, no SciPy).
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_int
from photolib.optics._checks import _array, _finite, _out


#: first positive zero of the Bessel function J1 (the dark ring of the Airy pattern)
J1_FIRST_ZERO = 3.8317059702075125


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
        Order n, an integer ≥ 0 (0 and 1 for the Airy pattern); an integral float such as
        ``2.0`` is accepted, anything else (an array, inf, NaN, 1.5) raises ``ValueError``.
    x : float or array_like, any shape
        Argument, dimensionless, finite (for the Airy pattern ``v = π·r/(λ·k)``).

    Returns
    -------
    float or ndarray
        J_n(x), dimensionless, same shape as ``x`` (a float for scalar ``x``).

    Examples
    --------
    >>> round(bessel_jn(1, J1_FIRST_ZERO), 12)
    0.0
    >>> round(bessel_jn(0, 0.0), 12)
    1.0
    >>> np.round(bessel_jn(0, [0.0, 1.0]), 6).tolist()   # tables: J0(1) = 0.765198
    [1.0, 0.765198]
    """
    n = as_int(n, "order n", minimum=0)
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
    return _out(np.where(v == 0.0, 1.0, (2.0 * np.asarray(bessel_jn(1, safe)) / safe) ** 2))


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
    return _out(1.0 - np.asarray(bessel_jn(0, v)) ** 2 - np.asarray(bessel_jn(1, v)) ** 2)
