"""Geometric optics of the thin lens: imaging equation, scale, angles, f-number, depth of field.

Derived in :mod:`photolib.derive.optics` (ray construction → imaging equation, similar
triangles → depth of field). Distances a, a' are positive, measured from the lens; every
length argument of one function shares one unit (mm in the course); angles are radians.

* Imaging equation ``1/a + 1/a' = 1/f``, image scale number ``m_b = a/a' = (a − f)/f``.
* Half field angle ``tan Ω = s'/(2c)``, half aperture angle ``tan α = d'/(2f)``,
  f-number ``k = f/d``.
* Blur diameter ``u' = (f/k)·|a'_x − a'|/a'_x``; the depth of field is where u' stays below
  the permissible circle of confusion, up to infinity from the hyperfocal distance
  ``H = f + f²/(k·u')`` on.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib.optics._checks import _array, _finite, _out
from photolib.errors import NoRealImageError  # noqa: F401 - raised here, defined in one hierarchy



class DepthOfField(NamedTuple):
    """Near and far limit of the depth of field, its extent and the hyperfocal distance.

    ``far`` and ``depth`` are ``inf`` when the focus distance is at or beyond the hyperfocal
    distance. Same length unit as the inputs.
    """

    near: float
    far: float
    depth: float
    hyperfocal: float


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
    return _image_distance(a, f, "object distance a")


def _image_distance(a, f, name):
    """:func:`image_distance` with the object distance called ``name`` in the messages."""
    a = _array(a, name, positive=True)
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    if np.any(a <= f):
        bad = np.broadcast_arrays(a, f)
        i = np.argmax((bad[0] <= bad[1]).ravel())
        raise NoRealImageError(f"{name} = {float(bad[0].ravel()[i])!r} is not beyond "
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

    Parameters
    ----------
    format_extent : float or array_like
        Image format extent s' (Bildformat): a side or the diagonal, > 0, finite, image
        unit (mm in the course).
    c : float or array_like
        Camera constant c (Kamerakonstante), > 0, finite, same unit as ``format_extent``.

    Returns
    -------
    float or ndarray
        Half field angle Ω, rad, in (0, π/2); the broadcast shape of the inputs (a float for
        scalars).

    Notes
    -----
    .. math:: \\Omega = \\arctan\\frac{s'}{2c}

    Examples
    --------
    >>> round(float(np.degrees(2 * half_field_angle(np.hypot(36.0, 24.0), 50.0))), 2)
    46.79
    >>> round(float(np.degrees(half_field_angle(36.0, 50.0))), 4)   # along the 36 mm side
    19.7989
    """
    s = _finite(_array(format_extent, "format extent s'", positive=True), "format extent s'")
    c = _finite(_array(c, "camera constant c", positive=True), "camera constant c")
    return _out(np.arctan(s / (2.0 * c)))


def half_aperture_angle(d, f):
    """Half the aperture angle α (Öffnungswinkel): tan α = d'/(2f), radians.

    For an object at infinity (image at f); record ``de-summary:aperture-angle``.

    Parameters
    ----------
    d : float or array_like
        Pupil diameter d' (Pupillendurchmesser), > 0, finite, mm in the course.
    f : float or array_like
        Focal length f (Brennweite), > 0, finite, same unit as ``d``.

    Returns
    -------
    float or ndarray
        Half aperture angle α, rad, in (0, π/2); the full cone is 2α. The broadcast shape of
        the inputs (a float for scalars).

    Notes
    -----
    .. math:: \\alpha = \\arctan\\frac{d'}{2f}

    Examples
    --------
    >>> round(float(np.degrees(half_aperture_angle(25.0, 50.0))), 4)
    14.0362
    >>> round(float(np.degrees(2 * half_aperture_angle(25.0, 50.0))), 4)   # full angle at f/2
    28.0725
    """
    d = _finite(_array(d, "pupil diameter d'", positive=True), "pupil diameter d'")
    f = _finite(_array(f, "focal length f", positive=True), "focal length f")
    return _out(np.arctan(d / (2.0 * f)))


def f_number(f, d):
    """f-number k = f/d (Blendenzahl), the reciprocal of the relative aperture d/f.

    Parameters
    ----------
    f : float or array_like
        Focal length f (Brennweite), > 0, finite, mm in the course.
    d : float or array_like
        Diameter d of the entrance pupil (Eintrittspupille), > 0, finite, same unit as ``f``.

    Returns
    -------
    float or ndarray
        f-number k, dimensionless; the broadcast shape of the inputs (a float for scalars).

    Notes
    -----
    .. math:: k = \\frac{f}{d}

    Examples
    --------
    >>> f_number(50.0, 12.5)
    4.0
    >>> f_number(50.0, np.array([25.0, 12.5])).tolist()   # mm: f/2 and f/4
    [2.0, 4.0]
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

    Parameters
    ----------
    a_x : float or array_like
        Object distance a_x (Gegenstandsweite) of the point imaged, > f; ``inf`` allowed.
        Length unit of ``f`` (mm in the course).
    a : float or array_like
        Focus distance a (Einstellentfernung), > f; ``inf`` allowed; same unit.
    f : float or array_like
        Focal length f (Brennweite), > 0, finite, same unit.
    k : float or array_like
        f-number k (Blendenzahl), dimensionless, > 0, finite.

    Returns
    -------
    float or ndarray
        Blur diameter u' in the image plane, unit of ``f``, ≥ 0 (0 for a point in focus);
        the broadcast shape of the inputs (a float for scalars).

    Raises
    ------
    NoRealImageError
        If ``a_x`` or ``a`` is not beyond the focal length.

    Notes
    -----
    With the image distances a'_x, a' from :func:`image_distance`:

    .. math:: u' = \\frac{f}{k}\\,\\frac{|a'_x - a'|}{a'_x}

    Examples
    --------
    >>> blur_diameter(5000.0, 5000.0, 50.0, 8.0)
    0.0
    >>> round(blur_diameter(np.inf, 5000.0, 50.0, 8.0), 6)   # mm
    0.063131
    >>> round(blur_diameter(3389.371, 5000.0, 50.0, 8.0), 4)   # the near limit: u' = 0.03 mm
    0.03
    """
    k = _finite(_array(k, "f-number k", positive=True), "f-number k")
    apx = np.asarray(_image_distance(a_x, f, "object distance a_x"))
    ap = np.asarray(_image_distance(a, f, "focus distance a"))
    return _out(np.asarray(f, float) / k * np.abs(apx - ap) / apx)


def hyperfocal_distance(f, k, u):
    """Hyperfocal distance H: focused there, the depth of field reaches infinity.

    Parameters
    ----------
    f : float or array_like
        Focal length f (Brennweite), > 0, finite, mm in the course.
    k : float or array_like
        f-number k (Blendenzahl), dimensionless, > 0, finite.
    u : float or array_like
        Permissible blur diameter u' in the image (circle of confusion, Zerstreuungskreis),
        > 0, finite, same unit as ``f``; the lecture summary uses u' = s'/1500.

    Returns
    -------
    float or ndarray
        Hyperfocal distance H (object distance from the lens), unit of ``f``; focused on H
        the depth of field (Schärfentiefe) reaches from H/2 to infinity. The broadcast
        shape of the inputs (a float for scalars).

    Notes
    -----
    .. math:: H = f + \\frac{f^2}{k\\,u'}

    Examples
    --------
    >>> hyperfocal_distance(50.0, 8.0, 0.03)   # mm
    10466.666666666668
    >>> round(hyperfocal_distance(50.0, 2.8, 0.03), 3)   # mm: opened up to f/2.8
    29811.905
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
