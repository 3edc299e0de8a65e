"""Conversions to and from COLMAP and Agisoft Metashape (docs/conventions.md, last table).

Both programs use OpenCV's camera frame: x right, y **down**, the camera looks along **+z**.
The course's camera looks along −z with y up (``X = X0 + m·R·x*``), so every pose conversion
goes through ``D = diag(1, −1, −1)``:

* **COLMAP** stores world → camera, ``x_cam = R_cv·X + t``, with ``R_cv`` as a Hamilton
  quaternion ``qvec = (qw, qx, qy, qz)`` (scalar first) and ``tvec = t``:
  ``R_cv = D·Rᵀ``, ``t = −R_cv·X0`` (:func:`colmap_pose_from_exterior`). Its pixel coordinates
  ``(u, v)`` have the origin at the top-left **corner**, so the centre of the top-left pixel is
  ``(0.5, 0.5)``; the course's ``(col, row)`` has it at ``(0, 0)``: ``col = u − 0.5``,
  ``row = v − 0.5`` (:func:`pixel_from_colmap`).
* **Metashape** stores camera → chunk, a 4×4 ``T = [[R·D, X0], [0, 1]]``
  (:func:`metashape_transform_from_exterior`), and a frame-camera calibration
  ``(f, cx, cy, b1, b2, k1…k4, p1, p2)`` in pixels, converted by :func:`interior_from_metashape`.

Only NumPy is used, so ``import photolib`` stays light.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_float_array, as_int, as_points, as_rotation, as_scalar, as_vector3
from photolib.distortion import Distortion
from photolib.rotations import exterior_from_opencv_pose, opencv_pose_from_exterior

__all__ = [
    "colmap_pose_from_exterior", "exterior_from_colmap_pose", "pixel_from_colmap",
    "colmap_from_pixel", "metashape_transform_from_exterior",
    "exterior_from_metashape_transform", "interior_from_metashape", "MetashapeInterior",
]

_FLIP = np.diag([1.0, -1.0, -1.0])


# -- quaternions (Hamilton, scalar first) -------------------------------------------------
def _rotation_from_quaternion(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def _quaternion_from_rotation(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (qw, qx, qy, qz) of R with qw ≥ 0 (Shepperd: the largest pivot)."""
    tr = np.trace(R)
    pivots = (tr, R[0, 0], R[1, 1], R[2, 2])
    k = int(np.argmax(pivots))
    if k == 0:
        s = 2.0 * np.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif k == 1:
        s = 2.0 * np.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif k == 2:
        s = 2.0 * np.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    q = np.asarray(q)
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def _unit_quaternion(qvec, atol: float) -> np.ndarray:
    q = as_float_array(qvec, "qvec", " with shape (4,) = (qw, qx, qy, qz)")
    if q.shape != (4,):
        raise ValueError(f"qvec has shape {q.shape}; expected (4,) = (qw, qx, qy, qz)")
    if not np.all(np.isfinite(q)):
        raise ValueError(f"qvec contains a non-finite value: {q.tolist()}")
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > atol:
        raise ValueError(f"qvec {q.tolist()} is not a unit quaternion: |q| = {norm:.9g} "
                         f"(|1 − |q|| > atol = {atol:g}); COLMAP writes unit quaternions")
    return q / norm


# -- COLMAP -------------------------------------------------------------------------------
def colmap_pose_from_exterior(X0, R):
    """COLMAP's ``(qvec, tvec)`` of a camera at ``X0`` with the course's rotation ``R``.

    Parameters
    ----------
    X0 : array_like, shape (3,)
        Projection centre (object unit, e.g. m).
    R : array_like, shape (3, 3)
        Rotation camera → object, ``R = R_ω·R_φ·R_κ`` (proper rotation).

    Returns
    -------
    qvec : ndarray, shape (4,)
        Hamilton unit quaternion ``(qw, qx, qy, qz)`` of ``R_cv``, scalar first, with ``qw ≥ 0``
        (``q`` and ``−q`` are the same rotation; COLMAP accepts either).
    tvec : ndarray, shape (3,)
        Translation (object unit).

    Notes
    -----
    COLMAP maps world → camera, ``x_cam = R_cv·X + t``, camera frame as OpenCV (x right,
    y down, +z forward):

    .. math:: R_{cv} = \\mathrm{diag}(1, -1, -1)\\,R^T, \\qquad t = -R_{cv} X_0

    Examples
    --------
    >>> q, t = colmap_pose_from_exterior([0.0, 0.0, 10.0], np.eye(3))   # nadir, 10 m up
    >>> q.round(12).tolist(), t.tolist()    # 180° about x: y and z flip
    ([0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 10.0])
    """
    Rcv, t = opencv_pose_from_exterior(X0, R)
    return _quaternion_from_rotation(Rcv), t


def exterior_from_colmap_pose(qvec, tvec, *, atol: float = 1e-6):
    """The course's ``(X0, R)`` from COLMAP's ``(qvec, tvec)``; inverse of
    :func:`colmap_pose_from_exterior`.

    Parameters
    ----------
    qvec : array_like, shape (4,)
        Hamilton quaternion ``(qw, qx, qy, qz)``, scalar first (SciPy's ``Rotation.from_quat``
        expects scalar **last** by default). Its norm must be 1 within ``atol``; it is then
        normalised. ``q`` and ``−q`` give the same pose.
    tvec : array_like, shape (3,)
        Translation of world → camera (object unit).
    atol : float
        Tolerance on ``|q| − 1``.

    Returns
    -------
    X0 : ndarray, shape (3,)
        Projection centre, ``X0 = −R_cvᵀ·t``.
    R : ndarray, shape (3, 3)
        ``R = (diag(1, −1, −1)·R_cv)ᵀ``.

    Raises
    ------
    ValueError
        For a wrong shape, NaN/inf or a quaternion whose norm is not 1.

    Examples
    --------
    >>> X0, R = exterior_from_colmap_pose([0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 10.0])
    >>> X0.tolist(), bool(np.allclose(R, np.eye(3)))
    ([0.0, 0.0, 10.0], True)
    """
    q = _unit_quaternion(qvec, as_scalar(atol, "atol", positive=True))
    t = as_vector3(tvec, "tvec")
    return exterior_from_opencv_pose(_rotation_from_quaternion(q), t)


def pixel_from_colmap(uv):
    """The course's pixel position ``(col, row)`` of COLMAP image coordinates ``(u, v)``.

    COLMAP puts the origin at the top-left **corner** of the image, so the centre of the
    top-left pixel is ``(0.5, 0.5)``; the course puts that centre at ``(0, 0)``.

    Parameters
    ----------
    uv : array_like, shape (N, 2) or (2,)
        COLMAP pixel coordinates (x right, y down), px.

    Returns
    -------
    ndarray, same shape: ``(col, row) = (u − 0.5, v − 0.5)``; use
    :func:`photolib.image_from_pixel` for image coordinates in mm.

    Examples
    --------
    >>> pixel_from_colmap([0.5, 0.5]).tolist()
    [0.0, 0.0]
    """
    pts, single = as_points(uv, 2, "uv")
    out = pts - 0.5
    return out[0] if single else out


def colmap_from_pixel(colrow):
    """COLMAP image coordinates ``(u, v) = (col + 0.5, row + 0.5)``; inverse of
    :func:`pixel_from_colmap`.

    Parameters
    ----------
    colrow : array_like, shape (N, 2) or (2,)
        The course's pixel position (col, row), px, (0, 0) at the centre of the top-left pixel,
        row downwards (e.g. from :func:`photolib.pixel_from_image`).

    Returns
    -------
    uv : ndarray, shape (N, 2) or (2,)
        COLMAP pixel coordinates (x right, y down), px, origin at the top-left **corner** of
        the image; the same rank as ``colrow``.

    Notes
    -----
    .. math:: u = col + 0.5, \\qquad v = row + 0.5

    Examples
    --------
    >>> colmap_from_pixel([[0.0, 0.0], [1.0, 2.0]]).tolist()
    [[0.5, 0.5], [1.5, 2.5]]
    """
    pts, single = as_points(colrow, 2, "colrow")
    out = pts + 0.5
    return out[0] if single else out


# -- Metashape pose -------------------------------------------------------------------------
def metashape_transform_from_exterior(X0, R) -> np.ndarray:
    """Metashape's camera → chunk transform ``T`` (4×4) of a camera at ``X0`` with rotation ``R``.

    Metashape's camera frame is OpenCV's (x right, y down, +z forward) and ``camera.transform``
    maps it to the chunk frame: ``X = T·(x_cam, 1)``. With ``D = diag(1, −1, −1)``:

    .. math:: T = \\begin{pmatrix} R\\,D & X_0 \\\\ 0 & 1 \\end{pmatrix}

    Parameters
    ----------
    X0 : array_like, shape (3,)
        Projection centre in the chunk frame (object unit).
    R : array_like, shape (3, 3)
        The course's rotation camera → object.

    Returns
    -------
    T : ndarray, shape (4, 4)

    Examples
    --------
    >>> metashape_transform_from_exterior([1.0, 2.0, 3.0], np.eye(3)).tolist()
    [[1.0, 0.0, 0.0, 1.0], [0.0, -1.0, 0.0, 2.0], [0.0, 0.0, -1.0, 3.0], [0.0, 0.0, 0.0, 1.0]]
    """
    R = as_rotation(R)
    X0 = as_vector3(X0, "X0")
    T = np.eye(4)
    T[:3, :3] = R @ _FLIP
    T[:3, 3] = X0
    return T


def exterior_from_metashape_transform(T, *, atol: float = 1e-6):
    """The course's ``(X0, R)`` from Metashape's camera → chunk transform ``T`` (4×4).

    ``R = T[:3, :3]·diag(1, −1, −1)``, ``X0 = T[:3, 3]``. A chunk transform with a scale
    (``camera.transform`` of a scaled chunk, ``T[:3, :3] = s·Q``) is refused: pass the
    transform in a metric chunk frame, or divide the scale out first.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Metashape's ``camera.transform``, camera (OpenCV frame: x right, y down, +z forward)
        → chunk, ``X = T·(x_cam, 1)``; last row ``(0, 0, 0, 1)``, translation in object unit.
    atol : float
        Tolerance (dimensionless) on the last row and on the orthonormality, det +1, of
        ``T[:3, :3]·diag(1, −1, −1)``.

    Returns
    -------
    X0 : ndarray, shape (3,)
        Projection centre / Projektionszentrum in the chunk frame (object unit).
    R : ndarray, shape (3, 3)
        The course's rotation camera → object, ``R = R_ω·R_φ·R_κ``.

    Raises
    ------
    ValueError
        For a wrong shape, a non-finite value, a last row other than ``(0, 0, 0, 1)`` or a
        rotation part that is not a proper rotation (e.g. a scaled chunk).

    Notes
    -----
    .. math:: R = T_{1:3,1:3}\\,\\operatorname{diag}(1, -1, -1), \\qquad X_0 = T_{1:3,4}

    Examples
    --------
    >>> X0, R = exterior_from_metashape_transform(metashape_transform_from_exterior([1.0, 2.0, 3.0], np.eye(3)))
    >>> X0.tolist(), bool(np.allclose(R, np.eye(3)))
    ([1.0, 2.0, 3.0], True)
    """
    T = as_float_array(T, "T", " with shape (4, 4)")
    if T.shape != (4, 4):
        raise ValueError(f"T has shape {T.shape}; expected (4, 4)")
    if not np.all(np.isfinite(T)):
        raise ValueError("T contains a non-finite value")
    if not np.allclose(T[3], [0.0, 0.0, 0.0, 1.0], atol=atol, rtol=0.0):
        raise ValueError(f"T's last row is {T[3].tolist()}; expected [0, 0, 0, 1]")
    R = as_rotation(T[:3, :3] @ _FLIP, "T[:3, :3]·diag(1, −1, −1)", atol=atol)
    return T[:3, 3].copy(), R


# -- Metashape calibration ------------------------------------------------------------------
@dataclass(frozen=True)
class MetashapeInterior:
    """Interior orientation of the course from a Metashape frame-camera calibration.

    Attributes
    ----------
    c, x0, y0 : float
        Camera constant (> 0) and principal point relative to the image centre, mm; ``y0`` with
        the course's y **up**.
    distortion : Distortion
        Course model (Δ at the measured point).
    rms_um, max_um : float
        Position residuals of ``m − Δ(m) − u`` over the sampled format (ideal point ``u``,
        Metashape's measured point ``m``), µm when the image unit is mm.
    exact : bool
        True when the conversion is exact (``max_um ≤ 1e-6``): no ``k1…k4, p1, p2``.
    approximate : str
        What was fitted, in words ("" when exact).
    """

    c: float
    x0: float
    y0: float
    distortion: Distortion
    rms_um: float
    max_um: float
    exact: bool
    approximate: str


def _metashape_forward(u, f, b1, b2, k, p1, p2, s, c):
    """Metashape's measured point (course mm, reduced to the principal point) of ideal ``u``."""
    xn, yn = u[:, 0] / c, -u[:, 1] / c  # normalised, y down
    r2 = xn * xn + yn * yn
    radial = 1.0 + k[0] * r2 + k[1] * r2**2 + k[2] * r2**3 + k[3] * r2**4
    xd = xn * radial + p1 * (r2 + 2 * xn * xn) + 2 * p2 * xn * yn
    yd = yn * radial + p2 * (r2 + 2 * yn * yn) + 2 * p1 * xn * yn
    du = xd * (f + b1) + yd * b2  # px from the principal point
    dv = yd * f
    return np.column_stack([du * s[0], -dv * s[1]])


def _fit_metashape_lens(m, u, r0, *, k4, affine):
    """Least-squares course distortion for :func:`interior_from_metashape`, and what it fits.

    ``Δ(m) = m − u`` at the measured points ``m`` of the ideal grid ``u`` (mm) is linear in
    ``A1, A2, A3, B1, B2`` (and ``C1, C2`` when ``affine``) for the fixed ``r0`` (mm): the
    columns of :meth:`Distortion.jacobian_params`, scaled to unit norm for the solver.
    Returns the :class:`Distortion` and the text that names the fitted (not exact) terms;
    ``k4`` only decides whether that text names Metashape's r⁸ term.
    """
    J = Distortion(r0=r0).jacobian_params(m)
    cols = list(range(5)) + ([5, 6] if affine else [])
    A = J[:, :, cols].reshape(-1, len(cols))
    scale = np.linalg.norm(A, axis=0)
    scale[scale == 0] = 1.0
    sol, *_ = np.linalg.lstsq(A / scale, (m - u).reshape(-1), rcond=None)
    names = ("A1", "A2", "A3", "B1", "B2", "C1", "C2")
    d = Distortion(r0=r0, **{names[j]: float(v) for j, v in zip(cols, sol / scale)})
    fitted = ["k1…k3, p1, p2 (Metashape evaluates them at the ideal point, the course at "
              "the measured one)"]
    if k4 != 0.0:
        fitted.append("k4 (no r⁸ term in the course model)")
    if affine:
        fitted.append("b1, b2 jointly with the lens terms (exact alone: C1 = b1/(f + b1), "
                      "C2 = −b2/(f + b1))")
    return d, "least-squares fit of " + "; ".join(fitted)


def interior_from_metashape(f, cx, cy, width, height, pixel_size, *, b1=0.0, b2=0.0,
                            k1=0.0, k2=0.0, k3=0.0, k4=0.0, p1=0.0, p2=0.0, r0=0.0,
                            n: int = 25, unit_to_um: float = 1000.0) -> MetashapeInterior:
    """The course's ``c, x'0, y'0`` and :class:`~photolib.Distortion` of a Metashape calibration.

    Metashape's frame camera (manual, appendix "Camera models"), camera frame as OpenCV,
    ``x = X/Z``, ``y = Y/Z``, ``r² = x² + y²``, ``K = 1 + K1r² + K2r⁴ + K3r⁶ + K4r⁸``:

    .. math::
        x_d &= xK + P_1(r^2 + 2x^2) + 2P_2xy, \\qquad y_d = yK + P_2(r^2 + 2y^2) + 2P_1xy \\\\
        u &= w/2 + c_x + x_d(f + B_1) + y_d B_2, \\qquad v = h/2 + c_y + y_d f

    Parameters
    ----------
    f : float
        Focal length, px, > 0 (the y scale; x has ``f + b1``).
    cx, cy : float
        Principal point offset from the image centre, px (y down).
    width, height : int
        Image size w × h, px.
    pixel_size : float or (2,)
        Pixel spacing (x, y), mm.
    b1, b2 : float
        Affinity and skew (non-orthogonality), px.
    k1, k2, k3, k4, p1, p2 : float
        Radial and tangential coefficients of normalised coordinates (Metashape's ``p1``/``p2``
        are OpenCV's ``p2``/``p1``).
    r0 : float
        Zero-crossing radius of the fitted radial model, mm (0: Seidel's form).
    n : int
        The fit samples an n×n grid of ideal points over the image format.
    unit_to_um : float
        µm per image unit, for the residuals.

    Returns
    -------
    MetashapeInterior
        ``c = f·s_y``, ``x'0 = cx·s_x``, ``y'0 = −cy·s_y`` (exact; Metashape's u = w/2 is the
        image centre, the course's ``col = (W−1)/2``, when the centre of its top-left pixel is
        (0.5, 0.5) as in COLMAP), and the distortion with the fit's residuals.

    Notes
    -----
    *Affinity, exact.* With ``a = c·x_d``, ``b = −c·y_d`` (course axes, y up) the measured
    point is ``x_m = k·a − (s_x b2)/(s_y f)·b``, ``y_m = b``, ``k = s_x(f + b1)/(s_y f)``.
    Solving for ``a`` gives the course's ``Δx_aff = C1·x_m + C2·y_m`` (Δ at the measured
    point) with

    .. math:: C_1 = 1 - \\frac{s_y f}{s_x (f + b_1)} \\;\\big(= \\tfrac{b_1}{f + b_1}\\big),
              \\qquad C_2 = -\\frac{b_2}{f + b_1} \\approx -\\frac{b_2}{f}

    **minus**, because Metashape's y points down and the course's up. Without ``k1…p2`` this is
    the whole conversion and it is exact (``exact=True``).

    *Radial and tangential, fitted.* Metashape evaluates them at the ideal point, the course
    at the measured point, and its ``K4 r⁸`` term has no course counterpart, so
    ``A1, A2, A3, B1, B2`` (and ``C1, C2`` when b1, b2 or non-square pixels call for them) are
    fitted by least squares to ``m − u = Δ(m)`` over the grid, exactly as
    :meth:`Distortion.from_opencv` does; with ``k4 = b1 = b2 = 0`` and ``cx = cy = 0`` it is
    ``Distortion.from_opencv((k1, k2, p2, p1, k3), c, w·s_x/2, h·s_y/2, n=n)``.

    Raises
    ------
    ValueError
        For a non-positive ``f``, ``f + b1``, size or pixel size, or a non-finite value.

    Examples
    --------
    >>> io = interior_from_metashape(5000.0, 12.0, -8.0, 6000, 4000, 0.004, b2=5.0)
    >>> io.c, io.x0, io.y0, io.exact
    (20.0, 0.048, 0.032, True)
    >>> io.distortion.params['C2']          # −b2/(f + b1)
    -0.001
    >>> fit = interior_from_metashape(5000.0, 0.0, 0.0, 6000, 4000, 0.004, k1=-0.1, k4=0.01)
    >>> fit.exact, fit.max_um < 1.0
    (False, True)
    """
    from photolib.pixels import _pixel_size  # the same checks as image_from_pixel

    f = as_scalar(f, "f", positive=True)
    cx, cy = as_scalar(cx, "cx"), as_scalar(cy, "cy")
    W = as_scalar(width, "width", positive=True)
    H = as_scalar(height, "height", positive=True)
    s = _pixel_size(pixel_size)
    b1, b2 = as_scalar(b1, "b1"), as_scalar(b2, "b2")
    if f + b1 <= 0:
        raise ValueError(f"f + b1 must be > 0 (the x focal length), got f = {f!r}, b1 = {b1!r}")
    k = tuple(as_scalar(v, name) for v, name in zip((k1, k2, k3, k4), ("k1", "k2", "k3", "k4")))
    p1, p2 = as_scalar(p1, "p1"), as_scalar(p2, "p2")
    r0 = as_scalar(r0, "r0")
    unit_to_um = as_scalar(unit_to_um, "unit_to_um", positive=True)
    n = as_int(n, "n", minimum=3)

    c = f * s[1]
    x0, y0 = cx * s[0], -cy * s[1]
    C1 = 1.0 - s[1] * f / (s[0] * (f + b1))
    C2 = -b2 / (f + b1)

    # ideal points over the format, reduced to the principal point
    hw, hh = W * s[0] / 2, H * s[1] / 2
    gx, gy = np.meshgrid(np.linspace(-hw, hw, n) - x0, np.linspace(-hh, hh, n) - y0)
    u = np.column_stack([gx.ravel(), gy.ravel()])
    m = _metashape_forward(u, f, b1, b2, k, p1, p2, s, c)

    lens = any(v != 0.0 for v in (*k, p1, p2))
    affine = C1 != 0.0 or C2 != 0.0
    if not lens:
        d = Distortion(r0=r0, C1=C1, C2=C2)
        approximate = ""
    else:
        d, approximate = _fit_metashape_lens(m, u, r0, k4=k[3], affine=affine)
    res = (m - d.delta(m) - u) * unit_to_um
    dist = np.hypot(res[:, 0], res[:, 1])
    rms, mx = float(np.sqrt(np.mean(dist**2))), float(np.max(dist))
    return MetashapeInterior(float(c), float(x0), float(y0), d, rms, mx, mx <= 1e-6, approximate)
