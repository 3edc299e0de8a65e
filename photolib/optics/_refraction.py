"""Refraction, reflection and dispersion: Snell's law, total reflection, Sellmeier glasses.

* Snell's law ``n1·sin α = n2·sin β`` for angles (radians) and in vector form
  ``t = η·d + (η·cos α − cos β)·n``, η = n1/n2; beyond the critical angle
  ``sin α_c = n2/n1`` the ray is totally reflected.
* Law of reflection ``r = d − 2(d·n)·n``. Directions are normalised here and the surface
  normal may face either side.
* Dispersion by the Sellmeier formula ``n²(λ) = 1 + Σ B_i·λ²/(λ² − C_i)`` with λ in µm (the
  unit of the glass catalogues), the Abbe number ``V_d = (n_d − 1)/(n_F − n_C)`` and the
  thin lens's longitudinal chromatic aberration ``f(λ) = f_ref·(n(λ_ref) − 1)/(n(λ) − 1)``.
"""

from __future__ import annotations

import numpy as np

from photolib.optics._checks import _array, _finite, _out
from photolib.errors import TotalInternalReflectionError  # noqa: F401 - raised here, defined in one hierarchy


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



# -- refraction and reflection --------------------------------------------------------------------

def refraction_angle(alpha, n1, n2):
    """Angle of refraction β from Snell's law n1·sin α = n2·sin β, radians.

    Parameters
    ----------
    alpha : float or array_like
        Angle of incidence α (Einfallswinkel) against the surface normal, rad, finite,
        |α| ≤ π/2.
    n1 : float or array_like
        Refractive index (Brechzahl) of the medium the ray comes from, dimensionless, > 0.
    n2 : float or array_like
        Refractive index of the medium the ray enters, dimensionless, > 0.

    Returns
    -------
    float or ndarray
        Angle of refraction β (Brechungswinkel) against the normal, rad, in [−π/2, π/2] with
        the sign of α; the broadcast shape of the inputs (a float for scalars).

    Raises
    ------
    TotalInternalReflectionError
        If n1·sin α > n2 (beyond the critical angle).

    Notes
    -----
    .. math:: \\beta = \\arcsin\\left(\\frac{n_1}{n_2}\\sin\\alpha\\right)

    Examples
    --------
    >>> round(float(np.degrees(refraction_angle(np.radians(30.0), 1.0, 1.5))), 4)
    19.4712
    >>> np.degrees(refraction_angle(np.radians([0.0, 30.0]), 1.0, 1.333)).round(4).tolist()
    [0.0, 22.0301]
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

    Parameters
    ----------
    n1 : float or array_like
        Refractive index (Brechzahl) of the optically denser medium the ray comes from,
        dimensionless, > n2.
    n2 : float or array_like
        Refractive index of the optically thinner medium beyond the surface, > 0.

    Returns
    -------
    float or ndarray
        Critical angle α_c against the surface normal, rad, in (0, π/2); rays with α > α_c
        are totally reflected. The broadcast shape of the inputs (a float for scalars).

    Raises
    ------
    ValueError
        If n1 ≤ n2 (no total internal reflection).

    Notes
    -----
    .. math:: \\alpha_c = \\arcsin\\frac{n_2}{n_1}

    Examples
    --------
    >>> round(float(np.degrees(critical_angle(1.5, 1.0))), 4)
    41.8103
    >>> round(float(np.degrees(critical_angle(1.333, 1.0))), 4)   # water → air
    48.6066
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

    Parameters
    ----------
    d : array_like, shape (N, 3) or (3,)
        Incoming ray directions, dimensionless, nonzero (normalised here).
    normal : array_like, shape (N, 3) or (3,)
        Surface normal, nonzero, either side of the surface (normalised here); one normal
        (3,) serves all rays.

    Returns
    -------
    ndarray, shape (N, 3) or (3,)
        Unit directions of the reflected rays, the rank of ``d``.

    Notes
    -----
    Both vectors normalised:

    .. math:: \\mathbf r = \\mathbf d - 2(\\mathbf d\\cdot\\mathbf n)\\,\\mathbf n

    Examples
    --------
    >>> reflect([1.0, 0.0, -1.0], [0.0, 0.0, 1.0]).round(6).tolist()
    [0.707107, 0.0, 0.707107]
    >>> reflect([[1.0, 0.0, -1.0], [0.0, 0.0, -2.0]], [0.0, 0.0, -1.0]).round(6).tolist()
    [[0.707107, 0.0, 0.707107], [0.0, 0.0, 1.0]]
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
    n1, n2 : float or array_like, shape (N,)
        Refractive indices before and after the surface, > 0, finite: one for all rays, or
        one per ray (as :func:`refraction_angle` broadcasts them; a single ray ``d`` (3,)
        with N indices gives N rays).
    on_total_reflection : {"raise", "flag"}
        ``"raise"``: :class:`TotalInternalReflectionError`. ``"flag"``: return
        ``(directions, valid)``; totally reflected rows get the reflected direction and
        ``valid = False``.

    Returns
    -------
    ndarray
        Unit directions, shape of ``d`` (N, 3) or (3,), or (N, 3) for one ray into N media
        (and the ``valid`` flags with ``"flag"``).

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
    n1 = _finite(_array(n1, "refractive index n1", positive=True), "refractive index n1")
    n2 = _finite(_array(n2, "refractive index n2", positive=True), "refractive index n2")
    d, nrm, cos_i, single = _directions(d, normal)
    for arr, name in ((n1, "n1"), (n2, "n2")):     # a scalar, or one per ray like refraction_angle
        if arr.ndim > 1 or (arr.ndim == 1 and len(d) != 1 and arr.shape[0] != len(d)):
            raise ValueError(f"refractive index {name} has shape {arr.shape}; expected a scalar "
                             f"or one index per ray, ({len(d)},)")
    n = max(len(d), n1.size if n1.ndim else 1, n2.size if n2.ndim else 1)
    if n != len(d):                                # one ray into several media
        d, nrm, cos_i = np.broadcast_to(d, (n, 3)), np.broadcast_to(nrm, (n, 3)), cos_i.repeat(n)
    single = single and n1.ndim == 0 and n2.ndim == 0
    eta = np.broadcast_to(n1 / n2, (n,))
    sin2_t = eta**2 * (1.0 - cos_i**2)
    valid = sin2_t <= 1.0
    if on_total_reflection == "raise" and not np.all(valid):
        i = int(np.argmax(sin2_t))
        raise TotalInternalReflectionError(
            f"sin²β = {float(sin2_t[i]):.6g} > 1 (n1 = {float(np.broadcast_to(n1, (n,))[i])}, "
            f"n2 = {float(np.broadcast_to(n2, (n,))[i])}): total internal "
            "reflection; use on_total_reflection='flag' to get the reflected rays")
    cos_t = np.sqrt(np.clip(1.0 - sin2_t, 0.0, None))
    t = eta[:, None] * d + (eta * cos_i - cos_t)[:, None] * nrm
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

    Returns
    -------
    float or ndarray
        Refractive index n(λ) (Brechzahl), dimensionless, ≥ 1; shape of ``wavelength_um``
        (a float for a scalar).

    Raises
    ------
    ValueError
        For an unknown glass, not six coefficients, or a wavelength at an absorption pole.

    Notes
    -----
    .. math:: n^2(\\lambda) = 1 + \\sum_{i=1}^{3} \\frac{B_i\\lambda^2}{\\lambda^2 - C_i}

    Examples
    --------
    >>> round(refractive_index(0.5875618), 5)   # N-BK7 at the d line: catalogue 1.51680
    1.5168
    >>> np.round(refractive_index([F_LINE, C_LINE]), 5).tolist()   # catalogue n_F, n_C
    [1.52238, 1.51432]
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

    Parameters
    ----------
    glass : str or tuple
        A key of :data:`GLASSES` or six Sellmeier coefficients (B1, B2, B3, C1, C2, C3),
        C in µm²; see :func:`refractive_index`.

    Returns
    -------
    float
        V_d, dimensionless; large for low dispersion (crown glass), small for flint glass.

    Notes
    -----
    With the Fraunhofer lines d, F, C (:data:`D_LINE`, :data:`F_LINE`, :data:`C_LINE`,
    587.56, 486.13 and 656.27 nm):

    .. math:: V_d = \\frac{n_d - 1}{n_F - n_C}

    Examples
    --------
    >>> round(abbe_number("N-BK7"), 2)   # catalogue 64.17
    64.17
    >>> round(abbe_number("N-SF11"), 2)   # a dense flint: catalogue 25.68
    25.68
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
        Focal length (Brennweite) at ``reference_um``, > 0, finite (any unit, mm in the
        course; the result has it).
    wavelength_um, reference_um : float or array_like
        Vacuum wavelengths λ and λ_ref in µm (0.55 for 550 nm); λ_ref defaults to the d line.
    glass : str or tuple
        See :func:`refractive_index`.

    Returns
    -------
    float or ndarray
        Focal shift f(λ) − f(λ_ref) in the unit of ``f_ref``, shape of ``wavelength_um``;
        positive (a longer focal length) for red light with normal dispersion.

    Notes
    -----
    .. math:: \\Delta f(\\lambda) = f(\\lambda) - f_\\mathrm{ref}
              = f_\\mathrm{ref}\\left(\\frac{n(\\lambda_\\mathrm{ref}) - 1}{n(\\lambda) - 1}
              - 1\\right)

    Examples
    --------
    >>> round(chromatic_focal_shift(50.0, C_LINE) - chromatic_focal_shift(50.0, F_LINE), 4)
    0.7746
    >>> round(chromatic_focal_shift(50.0, D_LINE), 12)   # at the reference wavelength
    0.0
    """
    f = _finite(_array(f_ref, "focal length f_ref", positive=True), "f_ref")
    n = np.asarray(refractive_index(wavelength_um, glass))
    n0 = refractive_index(reference_um, glass)
    return _out(f * (n0 - 1.0) / (n - 1.0) - f)
