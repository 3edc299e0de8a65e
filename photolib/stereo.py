r"""Stereo photogrammetry / Stereophotogrammetrie: normal case, intersection, orientations.

Course conventions (``docs/conventions.md``): c > 0, ``R = R_ω·R_φ·R_κ`` rotates camera
vectors into the object frame, the image vector is ``x* = (x' − x'0, y' − y'0, −c)`` and
``(kx, ky, N) = Rᵀ(X − X0)`` with ``N < 0`` in front of the camera. The ray of an image point
is ``X = X0 + λ·R·x*`` with ``λ > 0`` in front.

* Normal case (Normalfall): R1 = R2 = I, camera 1 at the origin, camera 2 at ``(B, 0, 0)``;
  the x-parallax ``px' = x'1 − x'2`` gives ``Z = −c·B/px'`` (derived in
  :mod:`photolib.derive.stereo`), and its accuracy ``σ_Z = (h/B)·m·σ_px'``, ``σ_XY = m·σ_x'``.
* :func:`forward_intersection` (räumlicher Vorwärtsschnitt): least-squares point of two or
  more rays.
* Coplanarity / Komplanarität: ``det[b, R1·x*1, R2·x*2] = x*1ᵀ E x*2 = 0`` with the essential
  matrix ``E = R1ᵀ [b]× R2``; the fundamental matrix for image coordinates, epipolar lines.
* :func:`relative_orientation`: dependent relative orientation (Folgebildanschluss) with the
  five unknowns by, bz, ω2, φ2, κ2 (camera 1 fixed at the origin with R1 = I, bx fixed).
* :func:`absolute_orientation`: 3-D similarity (Helmert, 7 parameters) ``X = X0 + m·R·x``.
* :func:`normal_case_rotation`, :func:`normalised_image_points`: epipolar (normalised) images.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_point_pairs, as_points, as_rotation, as_scalar, as_vector3
from photolib.collinearity import PointBehindCameraError, project
from photolib.rotations import opk_from_rotation, rotation_opk
from photolib.transforms._base import ConvergenceError, DegenerateGeometryError

__all__ = [
    "AbsoluteOrientation",
    "ForwardIntersection",
    "RelativeOrientation",
    "StereoAccuracy",
    "absolute_orientation",
    "epipolar_lines",
    "essential_matrix",
    "forward_intersection",
    "fundamental_matrix",
    "height_from_parallax",
    "normal_case_accuracy",
    "normal_case_points",
    "normal_case_rotation",
    "normalised_image_points",
    "relative_orientation",
]


# -- normal case -----------------------------------------------------------------------------------

def _parallax(px, name="px"):
    px = np.asarray(px, dtype=float)
    if not np.all(np.isfinite(px)):
        raise ValueError(f"{name} contains a non-finite value: {px.ravel().tolist()[:5]}")
    if np.any(px == 0):
        i = int(np.flatnonzero(px.ravel() == 0)[0])
        raise DegenerateGeometryError(f"{name}[{i}] = 0: zero parallax means parallel rays "
                                      "(a point at infinity); Z = −c·B/px' is undefined")
    if np.any(px < 0):
        i = int(np.flatnonzero(px.ravel() < 0)[0])
        raise PointBehindCameraError(
            f"{name}[{i}] = {float(px.ravel()[i])!r} < 0: with camera 2 at (+B, 0, 0) a point in front "
            "has px' = x'1 − x'2 > 0 (negative parallax gives Z > 0, behind the cameras; "
            "are the images swapped?)")
    return px


def height_from_parallax(px, c, B):
    r"""Z of the stereo normal case from the x-parallax / Höhe aus der x-Parallaxe.

    Parameters
    ----------
    px : float or array_like
        x-parallax ``px' = x'1 − x'2`` (image unit, mm), > 0 for points in front.
    c : float
        Camera constant, > 0 (image unit).
    B : float
        Base (Basis): camera 2 at ``(B, 0, 0)`` (object unit), > 0.

    Returns
    -------
    float or ndarray
        Z (object unit), negative: the cameras look down −Z.

    Raises
    ------
    DegenerateGeometryError
        For zero parallax (parallel rays).
    PointBehindCameraError
        For negative parallax.

    Notes
    -----
    .. math:: Z = -\frac{c\,B}{p_x'}

    Examples
    --------
    >>> float(height_from_parallax(2.0, c=100.0, B=20.0))
    -1000.0
    """
    c = as_scalar(c, "c", positive=True)
    B = as_scalar(B, "B", positive=True)
    px = _parallax(px)
    Z = -c * B / px
    return float(Z) if Z.ndim == 0 else Z


def normal_case_points(xy1, xy2, c, B, x0=0.0, y0=0.0):
    r"""Object points of the stereo normal case from both images' coordinates.

    Camera 1 at the origin, camera 2 at ``(B, 0, 0)``, both with R = I and the same interior
    orientation. X and Y come from image 1.

    Parameters
    ----------
    xy1, xy2 : array_like, shape (N, 2) or (2,)
        Image coordinates in image 1 and 2 (image unit).
    c : float
        Camera constant > 0 (image unit).
    B : float
        Base > 0 (object unit).
    x0, y0 : float
        Principal point (image unit).

    Returns
    -------
    ndarray, shape (N, 3) or (3,)

    Notes
    -----
    .. math:: p_x' = x_1' - x_2',\quad X = \frac{B\,(x_1'-x_0')}{p_x'},\quad
              Y = \frac{B\,(y_1'-y_0')}{p_x'},\quad Z = -\frac{c\,B}{p_x'}

    Examples
    --------
    >>> normal_case_points([1.0, 0.5], [-1.0, 0.5], c=100.0, B=20.0).tolist()
    [10.0, 5.0, -1000.0]
    """
    a, single = as_points(xy1, 2, "xy1")
    b, _ = as_points(xy2, 2, "xy2")
    if len(a) != len(b):
        raise ValueError(f"xy1 has {len(a)} points but xy2 has {len(b)}; they must pair up")
    c = as_scalar(c, "c", positive=True)
    B = as_scalar(B, "B", positive=True)
    x0, y0 = as_scalar(x0, "x0"), as_scalar(y0, "y0")
    px = _parallax(a[:, 0] - b[:, 0], "px' = x'1 − x'2")
    out = np.column_stack([B * (a[:, 0] - x0) / px, B * (a[:, 1] - y0) / px, -c * B / px])
    return out[0] if single else out


@dataclass(frozen=True)
class StereoAccuracy:
    """Accuracy of the stereo normal case from :func:`normal_case_accuracy`."""

    m: float  #: image scale number (Bildmaßstabszahl) m = h/c
    base_ratio: float  #: height-to-base ratio h/B (the inverse of the base ratio B/h)
    sigma_XY: float  #: σ_X = σ_Y = m·σ_x', object unit
    sigma_Z: float  #: σ_Z = (h/B)·m·σ_px', object unit


def normal_case_accuracy(h, B, c, sigma_px, sigma_xy) -> StereoAccuracy:
    r"""Standard deviations of X, Y and Z in the normal case (Luhmann example 3.7).

    Parameters
    ----------
    h : float
        Object distance ``h = −Z`` > 0 (object unit).
    B : float
        Base > 0 (object unit).
    c : float
        Camera constant > 0 (image unit).
    sigma_px : float
        σ of the x-parallax (object unit; give c, σ in the same unit, e.g. m, or mm and mm).
    sigma_xy : float
        σ of one image coordinate (same unit as ``sigma_px``). If x'1, x'2 are measured
        independently, ``σ_px' = √2·σ_x'`` by error propagation; stereoscopic measurement of
        the parallax is often assumed better, ``σ_px' = σ_x'/√2`` (errata record
        ``luhmann:example-3.7``). Which one holds is a statement about the measurement.

    Returns
    -------
    StereoAccuracy
        σ in the unit of ``sigma_px`` times ``h/c`` (e.g. mm of image σ → mm·m/mm).

    Notes
    -----
    From :math:`Z = -cB/p_x'`: :math:`|\partial Z/\partial p_x'| = Z^2/(cB)`, so

    .. math:: σ_Z = \frac{h}{B}\,\frac{h}{c}\,σ_{p_x'} = \frac{h}{B}\,m\,σ_{p_x'},\qquad
              σ_{X} = σ_Y = m\,σ_{x'},\quad m = \frac{h}{c}

    (σ_X is the leading term; the part from σ_Z, ``(X/h)·σ_Z``, is left out as in Luhmann.)

    Examples
    --------
    Example 3.7: m = 125, h = 5 m, b = 1.2 m, s_px' = 4 µm (σ in mm; c = h/m = 40 mm):

    >>> acc = normal_case_accuracy(5000.0, 1200.0, 40.0, 0.004, 0.004 * 2**0.5)
    >>> round(acc.m, 6), round(acc.sigma_Z, 4), round(acc.sigma_XY, 4)
    (125.0, 2.0833, 0.7071)
    """
    h = as_scalar(h, "h", positive=True)
    B = as_scalar(B, "B", positive=True)
    c = as_scalar(c, "c", positive=True)
    sigma_px = as_scalar(sigma_px, "sigma_px", positive=True)
    sigma_xy = as_scalar(sigma_xy, "sigma_xy", positive=True)
    m = h / c
    return StereoAccuracy(m=m, base_ratio=h / B, sigma_XY=m * sigma_xy,
                          sigma_Z=(h / B) * m * sigma_px)


# -- forward intersection --------------------------------------------------------------------------

@dataclass(frozen=True)
class ForwardIntersection:
    """Result of :func:`forward_intersection` for N points seen in K images."""

    points: np.ndarray  #: (N, 3) object points (NaN where not valid)
    distances: np.ndarray  #: (N, K) perpendicular distance of each point from each ray
    miss: np.ndarray  #: (N,) 2·RMS of ``distances``: for K = 2 the rays' common perpendicular
    residuals: np.ndarray  #: (N, K, 2) image residuals x'(point) − x'(observed), image unit
    angle: np.ndarray  #: (N,) largest intersection angle between two of the rays, radians
    valid: np.ndarray  #: (N,) False for parallel rays or points behind a camera


def _per_camera(value, K, name):
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(K, float(arr))
    if arr.shape != (K,):
        raise ValueError(f"{name} has shape {arr.shape}; expected a scalar or ({K},)")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains a non-finite value: {arr.tolist()}")
    return arr


def _image_vectors(xy, c, x0, y0):
    """x* = (x' − x'0, y' − y'0, −c) of (N, 2) image points."""
    return np.column_stack([xy[:, 0] - x0, xy[:, 1] - y0, np.full(len(xy), -c)])


def forward_intersection(xy, X0, R, c, x0=0.0, y0=0.0, *, min_angle: float = 1e-6,
                         return_valid: bool = False) -> ForwardIntersection:
    r"""Least-squares intersection of the rays of K ≥ 2 images / räumlicher Vorwärtsschnitt.

    Parameters
    ----------
    xy : array_like, shape (K, N, 2) or (K, 2)
        Image coordinates of N points in each of the K images (image unit).
    X0 : array_like, shape (K, 3)
        Projection centres (object unit).
    R : array_like, shape (K, 3, 3)
        Rotations camera → object, ``R_ω·R_φ·R_κ``.
    c, x0, y0 : float or array_like of shape (K,)
        Interior orientation per image (image unit), c > 0.
    min_angle : float
        Rays meeting at less than this angle (radians) count as parallel (zero parallax).
    return_valid : bool
        If False (default) parallel rays raise ``DegenerateGeometryError`` and points behind
        a camera ``PointBehindCameraError``; if True such points get NaN and ``valid=False``.

    Returns
    -------
    ForwardIntersection

    Notes
    -----
    Each ray is :math:`X_k + λ\,d_k` with :math:`d_k = R_k x^*_k/|R_k x^*_k|`. The point that
    minimises the sum of squared perpendicular distances solves

    .. math:: \Big(\sum_k (I - d_k d_k^T)\Big)\,X = \sum_k (I - d_k d_k^T)\,X_{0k}

    For two rays it is the midpoint of their common perpendicular. The point lies in front of
    camera k when :math:`λ_k = d_k^T(X - X_{0k}) > 0` (equivalently N < 0).

    Examples
    --------
    >>> I = np.eye(3)
    >>> res = forward_intersection([[1.0, 0.5], [-1.0, 0.5]], [[0, 0, 0], [20.0, 0, 0]],
    ...                            [I, I], c=100.0)
    >>> np.round(res.points, 9).tolist(), bool(res.miss[0] < 1e-9)
    ([[10.0, 5.0, -1000.0]], True)
    """
    obs = np.asarray(xy, dtype=float)
    if obs.ndim == 2 and obs.shape[-1] == 2:
        obs = obs[:, None, :]
    if obs.ndim != 3 or obs.shape[-1] != 2:
        raise ValueError(f"xy has shape {np.shape(xy)}; expected (K, N, 2) or (K, 2)")
    K, n = obs.shape[:2]
    if K < 2:
        raise ValueError(f"forward intersection needs at least 2 images, got {K}")
    obs = np.stack([as_points(obs[k], 2, f"xy[{k}]")[0] for k in range(K)])
    centres = np.asarray(X0, dtype=float)
    if centres.shape != (K, 3):
        raise ValueError(f"X0 has shape {centres.shape}; expected ({K}, 3) for {K} images")
    centres = np.stack([as_vector3(centres[k], f"X0[{k}]") for k in range(K)])
    rots = np.asarray(R, dtype=float)
    if rots.shape != (K, 3, 3):
        raise ValueError(f"R has shape {rots.shape}; expected ({K}, 3, 3) for {K} images")
    rots = np.stack([as_rotation(rots[k], f"R[{k}]") for k in range(K)])
    cs = _per_camera(c, K, "c")
    if np.any(cs <= 0):
        raise ValueError(f"c must be > 0 for every image, got {cs.tolist()}")
    x0s, y0s = _per_camera(x0, K, "x0"), _per_camera(y0, K, "y0")
    # unit ray directions d (K, N, 3)
    d = np.stack([_image_vectors(obs[k], cs[k], x0s[k], y0s[k]) @ rots[k].T for k in range(K)])
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    P = np.eye(3) - d[..., :, None] * d[..., None, :]          # (K, N, 3, 3) projectors
    A = P.sum(axis=0)                                            # (N, 3, 3)
    rhs = np.einsum("knij,kj->ni", P, centres)
    cosines = np.clip(np.einsum("anj,bnj->nab", d, d), -1.0, 1.0)
    angle = np.arccos(cosines.min(axis=(1, 2)))
    parallel = angle < min_angle
    points = np.full((n, 3), np.nan)
    ok = ~parallel
    if ok.any():
        points[ok] = np.linalg.solve(A[ok], rhs[ok][..., None])[..., 0]
    lam = np.einsum("knj,knj->kn", d, points[None] - centres[:, None])   # (K, N)
    behind = ok & np.any(~(lam > 0), axis=0)
    if not return_valid:
        if parallel.any():
            i = int(np.flatnonzero(parallel)[0])
            raise DegenerateGeometryError(
                f"the rays of point {i} are parallel (intersection angle {angle[i]:.3g} rad < "
                f"min_angle = {min_angle:g}): zero parallax, the point is at infinity")
        if behind.any():
            i = int(np.flatnonzero(behind)[0])
            k = int(np.flatnonzero(~(lam[:, i] > 0))[0])
            raise PointBehindCameraError(
                f"point {i} intersects at {points[i].tolist()}, behind camera {k} "
                f"(ray parameter λ = {lam[k, i]:.6g} ≤ 0, i.e. N ≥ 0): the rays diverge; "
                "check the orientation or pass return_valid=True")
    valid = ok & ~behind
    points[~valid] = np.nan
    foot = centres[:, None] + lam[..., None] * d
    dist = np.linalg.norm(points[None] - foot, axis=2).T          # (N, K)
    residuals = np.full((n, K, 2), np.nan)
    if valid.any():
        for k in range(K):
            residuals[valid, k] = project(points[valid], centres[k], rots[k], cs[k],
                                          x0s[k], y0s[k]) - obs[k][valid]
    miss = 2.0 * np.sqrt(np.mean(dist**2, axis=1))
    return ForwardIntersection(points=points, distances=dist, miss=miss, residuals=residuals,
                               angle=angle, valid=valid)


# -- coplanarity, essential and fundamental matrix ------------------------------------------------

def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def essential_matrix(X01, R1, X02, R2) -> np.ndarray:
    r"""Essential matrix of an oriented pair in the course's frames (coplanarity condition).

    Parameters
    ----------
    X01, X02 : array_like, shape (3,)
        Projection centres (object unit); the base is ``b = X02 − X01`` (≠ 0).
    R1, R2 : array_like, shape (3, 3)
        Rotations camera → object.

    Returns
    -------
    ndarray, shape (3, 3)
        E with ``x*1ᵀ·E·x*2 = 0`` for corresponding image vectors
        ``x*_i = (x'_i − x'0, y'_i − y'0, −c_i)``.

    Notes
    -----
    The rays :math:`r_i = R_i x^*_i` and the base are coplanar (Komplanaritätsbedingung):

    .. math:: b\cdot(r_1\times r_2) = -\,r_1^T [b]_\times r_2 = 0,\qquad
              E = R_1^T\,[b]_\times\,R_2

    OpenCV's essential matrix (y down, +z viewing, ``p2ᵀ E_cv p1 = 0``) is
    ``E_cv ∝ (D·E·D)ᵀ`` with ``D = diag(1, −1, −1)``.

    Examples
    --------
    >>> E = essential_matrix([0, 0, 0], np.eye(3), [1.0, 0, 0], np.eye(3))
    >>> float(np.array([2.0, 1.0, -10.0]) @ E @ np.array([-3.0, 1.0, -10.0]))
    0.0
    """
    X01, X02 = as_vector3(X01, "X01"), as_vector3(X02, "X02")
    R1, R2 = as_rotation(R1, "R1"), as_rotation(R2, "R2")
    b = X02 - X01
    if np.linalg.norm(b) == 0:
        raise DegenerateGeometryError("X01 = X02: the base is zero, there is no epipolar geometry")
    return R1.T @ _skew(b) @ R2


def _interior_matrix(c, x0, y0, name):
    c = as_scalar(c, f"c{name}", positive=True)
    return np.array([[1.0, 0.0, -as_scalar(x0, f"x0{name}")],
                     [0.0, 1.0, -as_scalar(y0, f"y0{name}")], [0.0, 0.0, -c]])


def fundamental_matrix(E, c1, c2, x01=0.0, y01=0.0, x02=0.0, y02=0.0) -> np.ndarray:
    r"""Fundamental matrix for image coordinates (mm) from the essential matrix.

    Parameters
    ----------
    E : array_like, shape (3, 3)
        From :func:`essential_matrix`.
    c1, c2 : float
        Camera constants > 0 (image unit).
    x01, y01, x02, y02 : float
        Principal points of image 1 and 2.

    Returns
    -------
    ndarray, shape (3, 3)
        F with ``h1ᵀ·F·h2 = 0`` for ``h_i = (x'_i, y'_i, 1)`` (Luhmann's order: image 1 left).

    Notes
    -----
    .. math:: x^*_i = K_i h_i,\quad K_i = \begin{pmatrix}1&0&-x'_{0i}\\0&1&-y'_{0i}\\0&0&-c_i
              \end{pmatrix},\qquad F = K_1^T E K_2

    Examples
    --------
    >>> E = essential_matrix([0, 0, 0], np.eye(3), [1.0, 0, 0], np.eye(3))
    >>> F = fundamental_matrix(E, 10.0, 10.0)
    >>> float(np.array([2.0, 1.0, 1.0]) @ F @ np.array([-3.0, 1.0, 1.0]))
    0.0
    """
    E = np.asarray(E, dtype=float)
    if E.shape != (3, 3) or not np.all(np.isfinite(E)):
        raise ValueError(f"E must be a finite (3, 3) matrix, got shape {E.shape}")
    return _interior_matrix(c1, x01, y01, "1").T @ E @ _interior_matrix(c2, x02, y02, "2")


def epipolar_lines(F, xy, image: int = 2) -> np.ndarray:
    r"""Epipolar lines (Kernlinien) of image points in the other image.

    Parameters
    ----------
    F : array_like, shape (3, 3)
        From :func:`fundamental_matrix` (``h1ᵀ F h2 = 0``).
    xy : array_like, shape (N, 2) or (2,)
        Points in image 1 when ``image=2`` (lines in image 2), points in image 2 when
        ``image=1``.
    image : {1, 2}
        The image in which the lines lie.

    Returns
    -------
    ndarray, shape (N, 3) or (3,)
        ``(a, b, d)`` with ``a·x' + b·y' + d = 0`` and ``a² + b² = 1``, so ``a·x' + b·y' + d``
        is the signed distance of a point from the line.

    Notes
    -----
    .. math:: l_2 = F^T h_1, \qquad l_1 = F\,h_2

    Examples
    --------
    >>> E = essential_matrix([0, 0, 0], np.eye(3), [1.0, 0, 0], np.eye(3))
    >>> epipolar_lines(fundamental_matrix(E, 10.0, 10.0), [2.0, 1.5]).round(12).tolist()
    [0.0, -1.0, 1.5]
    """
    if image not in (1, 2):
        raise ValueError(f"image must be 1 or 2, got {image!r}")
    F = np.asarray(F, dtype=float)
    if F.shape != (3, 3) or not np.all(np.isfinite(F)):
        raise ValueError(f"F must be a finite (3, 3) matrix, got shape {F.shape}")
    pts, single = as_points(xy, 2, "xy")
    h = np.column_stack([pts, np.ones(len(pts))])
    lines = h @ F if image == 2 else h @ F.T
    norm = np.hypot(lines[:, 0], lines[:, 1])
    if np.any(norm == 0):
        i = int(np.flatnonzero(norm == 0)[0])
        raise DegenerateGeometryError(f"xy[{i}] = {pts[i].tolist()} is the epipole: its "
                                      "epipolar line is undefined")
    lines = lines / norm[:, None]
    return lines[0] if single else lines


# -- relative orientation --------------------------------------------------------------------------

@dataclass(frozen=True)
class RelativeOrientation:
    """Dependent relative orientation from :func:`relative_orientation`."""

    base: np.ndarray  #: (3,) (bx, by, bz), model unit
    R2: np.ndarray  #: (3, 3) rotation of image 2 (image 1: R = I)
    omega: float  #: ω2, radians
    phi: float  #: φ2, radians
    kappa: float  #: κ2, radians
    model: np.ndarray  #: (N, 3) model coordinates (forward intersection, NaN if invalid)
    residuals: np.ndarray  #: (N,) coplanarity residual as y-parallax, image unit
    sigma0: float  #: image unit (NaN for 5 points)
    covariance: np.ndarray  #: (5, 5) of (by, bz, ω2, φ2, κ2)
    iterations: int
    converged: bool
    redundancy: int  #: N − 5

    @property
    def params(self) -> np.ndarray:
        """``(by, bz, ω2, φ2, κ2)``."""
        return np.r_[self.base[1:], self.omega, self.phi, self.kappa]


def _rotation_derivatives(w, p, k):
    cw, sw, cp, sp_, ck, sk = np.cos(w), np.sin(w), np.cos(p), np.sin(p), np.cos(k), np.sin(k)
    Rw = np.array([[1, 0, 0], [0, cw, -sw], [0, sw, cw]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    dRw = np.array([[0, 0, 0], [0, -sw, -cw], [0, cw, -sw]])
    dRp = np.array([[-sp_, 0, cp], [0, 0, 0], [-cp, 0, -sp_]])
    dRk = np.array([[-sk, -ck, 0], [ck, -sk, 0], [0, 0, 0]])
    return Rw @ Rp @ Rk, (dRw @ Rp @ Rk, Rw @ dRp @ Rk, Rw @ Rp @ dRk)


def coplanarity_residuals(q, r1, x2, bx, c):
    """Coplanarity residuals ``det[b, r1, R2·x*2]/(bx·c)`` and their Jacobian (N, 5).

    ``q = (by, bz, ω2, φ2, κ2)``; ``r1`` (N, 3) rays of image 1 (R1 = I), ``x2`` (N, 3)
    image vectors of image 2. In the normal case the residual is the y-parallax y'2 − y'1.
    """
    b = np.array([bx, q[0], q[1]])
    R2, dR = _rotation_derivatives(*q[2:])
    r2 = x2 @ R2.T
    cross = np.cross(r1, r2)
    f = cross @ b / (bx * c)
    J = np.empty((len(r1), 5))
    J[:, 0] = cross[:, 1] / (bx * c)
    J[:, 1] = cross[:, 2] / (bx * c)
    for j, D in enumerate(dR):
        J[:, 2 + j] = np.cross(r1, x2 @ D.T) @ b / (bx * c)
    return f, J


def relative_orientation(xy1, xy2, c, bx: float = 1.0, x0=0.0, y0=0.0, initial=None, *,
                         tol: float = 1e-12, max_iter: int = 30,
                         check: bool = True) -> RelativeOrientation:
    r"""Dependent relative orientation (Folgebildanschluss) of a stereo pair by least squares.

    Image 1 is fixed (X01 = 0, R1 = I); image 2 is at ``b = (bx, by, bz)`` with
    ``R2 = R_ω(ω2)·R_φ(φ2)·R_κ(κ2)``; bx is fixed and sets the model scale. Five unknowns
    (by, bz, ω2, φ2, κ2), one coplanarity equation per point: at least 5 points.

    Parameters
    ----------
    xy1, xy2 : array_like, shape (N, 2)
        Corresponding image points (image unit), N ≥ 5.
    c : float
        Camera constant > 0 of both images (image unit).
    bx : float
        Fixed base component (model unit), ≠ 0; its sign says on which side image 2 is.
    x0, y0 : float
        Principal point of both images.
    initial : array_like, shape (5,), optional
        Start (by, bz, ω2, φ2, κ2); default zeros (near the normal case).
    tol, max_iter, check
        Stop when the largest update is below ``tol`` (model units / radians). Not reaching
        it raises ``ConvergenceError`` unless ``check=False``.

    Returns
    -------
    RelativeOrientation

    Notes
    -----
    Gauss–Newton on the coplanarity condition, scaled to a y-parallax (image unit):

    .. math:: v_i = \frac{\det[\,b,\; x^*_{1i},\; R_2 x^*_{2i}\,]}{b_x\,c},\qquad
              σ_0 = \sqrt{\frac{v^Tv}{N-5}}

    The model coordinates are the forward intersection of the oriented rays.

    Examples
    --------
    >>> X = np.array([[0, 0, -10], [2, 1, -11], [-1, 2, -9], [1, -2, -10.5], [3, 3, -12],
    ...               [-2, -1, -10.0]])
    >>> R2 = rotation_opk(0.01, -0.02, 0.03)
    >>> xy1 = project(X, [0, 0, 0], np.eye(3), 50.0)
    >>> xy2 = project(X, [1.0, 0.1, -0.05], R2, 50.0)
    >>> ro = relative_orientation(xy1, xy2, 50.0, bx=1.0)
    >>> np.round(ro.params, 9).tolist(), ro.converged
    ([0.1, -0.05, 0.01, -0.02, 0.03], True)
    """
    a, b2 = as_point_pairs(xy1, xy2, (2, 2), ("xy1", "xy2"), 5, "relative orientation",
                           "point pairs (5 unknowns: by, bz, ω2, φ2, κ2)")
    c = as_scalar(c, "c", positive=True)
    bx = as_scalar(bx, "bx")
    if bx == 0:
        raise ValueError("bx must be ≠ 0: it fixes the scale of the model")
    x0, y0 = as_scalar(x0, "x0"), as_scalar(y0, "y0")
    q = np.zeros(5) if initial is None else np.asarray(initial, dtype=float)
    if q.shape != (5,) or not np.all(np.isfinite(q)):
        raise ValueError(f"initial must be 5 finite values (by, bz, ω2, φ2, κ2), got {q.tolist()}")
    r1 = _image_vectors(a, c, x0, y0)
    x2 = _image_vectors(b2, c, x0, y0)
    converged, it, scale = False, 0, abs(bx)
    for it in range(1, max_iter + 1):
        f, J = coplanarity_residuals(q, r1, x2, bx, c)
        sv = np.linalg.svd(J, compute_uv=False)
        if sv[-1] <= 1e-10 * sv[0]:
            raise DegenerateGeometryError(
                "the coplanarity equations do not determine (by, bz, ω2, φ2, κ2): the points "
                f"are badly distributed (condition {sv[0] / max(sv[-1], 1e-300):.3g}); use ≥ 5 "
                "points spread over the overlap, not on one line")
        dq = np.linalg.lstsq(J, -f, rcond=None)[0]
        if not np.all(np.isfinite(dq)):
            raise ConvergenceError(f"relative orientation diverged in iteration {it}")
        q = q + dq
        if np.max(np.abs(dq[:2])) <= tol * scale and np.max(np.abs(dq[2:])) <= tol:
            converged = True
            break
    if not converged and check:
        raise ConvergenceError(f"relative orientation did not converge in {max_iter} "
                               f"iterations (last update {np.max(np.abs(dq)):.3g})")
    f, J = coplanarity_residuals(q, r1, x2, bx, c)
    n = len(a)
    red = n - 5
    sigma0 = float(np.sqrt(f @ f / red)) if red > 0 else float("nan")
    cov = (sigma0**2 * np.linalg.inv(J.T @ J)) if red > 0 else np.full((5, 5), np.nan)
    R2 = rotation_opk(*q[2:])
    base = np.array([bx, q[0], q[1]])
    inter = forward_intersection(np.stack([a, b2]), np.stack([np.zeros(3), base]),
                                 np.stack([np.eye(3), R2]), c, x0, y0, return_valid=True)
    return RelativeOrientation(base=base, R2=R2, omega=float(q[2]), phi=float(q[3]),
                               kappa=float(q[4]), model=inter.points, residuals=f,
                               sigma0=sigma0, covariance=cov, iterations=it,
                               converged=converged, redundancy=red)


# -- absolute orientation --------------------------------------------------------------------------

@dataclass(frozen=True)
class AbsoluteOrientation:
    """3-D similarity ``X = X0 + m·R·x`` from :func:`absolute_orientation`."""

    m: float  #: scale (object unit per model unit)
    R: np.ndarray  #: (3, 3) rotation model → object, R_ω·R_φ·R_κ
    X0: np.ndarray  #: (3,) translation (object unit)
    residuals: np.ndarray  #: (N, 3) X_control − X(model), object unit
    sigma0: float  #: sqrt(vᵀv/(3N − 7)), NaN without redundancy
    redundancy: int  #: 3N − 7

    @property
    def angles(self) -> tuple[float, float, float]:
        """``(ω, φ, κ)`` of R, radians."""
        return opk_from_rotation(self.R)

    def __call__(self, x) -> np.ndarray:
        """Object coordinates of model points (N, 3) or (3,)."""
        pts, single = as_points(x, 3, "x")
        out = self.X0 + self.m * pts @ self.R.T
        return out[0] if single else out


def absolute_orientation(model, control) -> AbsoluteOrientation:
    r"""Absolute orientation: 7-parameter 3-D similarity (Helmert) from model to object.

    Parameters
    ----------
    model : array_like, shape (N, 3)
        Model coordinates of control points (model unit), N ≥ 3, not collinear.
    control : array_like, shape (N, 3)
        Their object coordinates (object unit).

    Returns
    -------
    AbsoluteOrientation

    Notes
    -----
    Least squares of :math:`\sum_i |X_i - (X_0 + m\,R\,x_i)|^2` in closed form (Horn 1987,
    Umeyama 1991): with centred points :math:`\bar x_i, \bar X_i` and the SVD
    :math:`\sum_i \bar X_i \bar x_i^T = U S V^T`,

    .. math:: R = U\,\mathrm{diag}(1, 1, \det UV^T)\,V^T,\quad
              m = \frac{\mathrm{tr}(S\,\mathrm{diag}(1,1,\det UV^T))}{\sum_i|\bar x_i|^2},\quad
              X_0 = \bar X - m R \bar x

    Seven unknowns (3 translations, 3 angles, 1 scale): two full control points and one
    height, or ≥ 3 non-collinear full points.

    Examples
    --------
    >>> x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> T = absolute_orientation(x, 10 + 2 * x @ rotation_opk(0.1, 0.2, 0.3).T)
    >>> round(T.m, 12), np.round(T.angles, 12).tolist(), np.round(T.X0, 9).tolist()
    (2.0, [0.1, 0.2, 0.3], [10.0, 10.0, 10.0])
    """
    x, X = as_point_pairs(model, control, (3, 3), ("model", "control"), 3,
                          "absolute orientation", "control points (7 unknowns)")
    xm, Xm = x.mean(axis=0), X.mean(axis=0)
    xc, Xc = x - xm, X - Xm
    for pts, name in ((xc, "model"), (Xc, "control")):
        sv = np.linalg.svd(pts, compute_uv=False)
        if sv[0] == 0 or sv[1] <= 1e-9 * sv[0]:
            raise DegenerateGeometryError(
                f"the {name} points are collinear (singular values {np.round(sv, 12).tolist()}): "
                "the rotation about their line is not determined; add a point off the line")
    U, S, Vt = np.linalg.svd(Xc.T @ xc)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    R = U @ D @ Vt
    m = float(np.trace(np.diag(S) @ D) / np.sum(xc**2))
    X0 = Xm - m * R @ xm
    v = X - (X0 + m * x @ R.T)
    red = 3 * len(x) - 7
    sigma0 = float(np.sqrt(np.sum(v**2) / red)) if red > 0 else float("nan")
    return AbsoluteOrientation(m=m, R=R, X0=X0, residuals=v, sigma0=sigma0, redundancy=red)


# -- normalised (epipolar) images ------------------------------------------------------------------

def normal_case_rotation(X01, R1, X02, R2) -> np.ndarray:
    r"""Common rotation of the normalised pair (Normalbilder): x along the base.

    Parameters
    ----------
    X01, X02 : array_like, shape (3,)
    R1, R2 : array_like, shape (3, 3)

    Returns
    -------
    ndarray, shape (3, 3)
        ``Rn`` with columns ``e_x = b/|b|``, ``e_y = e_z × e_x``, ``e_z`` the mean viewing-axis
        direction ``(R1 + R2)·(0, 0, 1)`` made orthogonal to ``e_x``. Both images rotated to
        Rn form the normal case: corresponding points have equal y'.

    Examples
    --------
    >>> Rn = normal_case_rotation([0, 0, 0], np.eye(3), [0, 2.0, 0], np.eye(3))
    >>> Rn[:, 0].tolist()
    [0.0, 1.0, 0.0]
    """
    X01, X02 = as_vector3(X01, "X01"), as_vector3(X02, "X02")
    R1, R2 = as_rotation(R1, "R1"), as_rotation(R2, "R2")
    b = X02 - X01
    nb = np.linalg.norm(b)
    if nb == 0:
        raise DegenerateGeometryError("X01 = X02: zero base, no normal case")
    ex = b / nb
    z = R1[:, 2] + R2[:, 2]
    ez = z - (z @ ex) * ex
    if np.linalg.norm(ez) <= 1e-9 * max(np.linalg.norm(z), 1e-300):
        raise DegenerateGeometryError("the cameras look along the base: a normal case with "
                                      "the base in the image plane is not possible")
    ez /= np.linalg.norm(ez)
    return np.column_stack([ex, np.cross(ez, ex), ez])


def normalised_image_points(xy, R, Rn, c, c_n=None, x0=0.0, y0=0.0) -> np.ndarray:
    r"""Image coordinates in the normalised image (rotated to ``Rn``, same centre).

    Parameters
    ----------
    xy : array_like, shape (N, 2) or (2,)
        Image coordinates in the original image (image unit).
    R, Rn : array_like, shape (3, 3)
        Original and normalised rotation (camera → object).
    c : float
        Camera constant of the original image.
    c_n : float, optional
        Camera constant of the normalised image (default c); principal point at 0.
    x0, y0 : float
        Principal point of the original image.

    Returns
    -------
    ndarray, shape (N, 2) or (2,)

    Notes
    -----
    .. math:: k = R_n^T R\,x^*,\qquad x'_n = -c_n\,k_x/k_z,\quad y'_n = -c_n\,k_y/k_z

    Examples
    --------
    >>> normalised_image_points([1.0, 2.0], np.eye(3), np.eye(3), 50.0).tolist()
    [1.0, 2.0]
    """
    pts, single = as_points(xy, 2, "xy")
    R, Rn = as_rotation(R, "R"), as_rotation(Rn, "Rn")
    c = as_scalar(c, "c", positive=True)
    c_n = c if c_n is None else as_scalar(c_n, "c_n", positive=True)
    k = _image_vectors(pts, c, as_scalar(x0, "x0"), as_scalar(y0, "y0")) @ R.T @ Rn
    if np.any(k[:, 2] >= 0):
        i = int(np.flatnonzero(k[:, 2] >= 0)[0])
        raise PointBehindCameraError(f"xy[{i}] = {pts[i].tolist()} maps behind the normalised "
                                     "image plane: the rotation to the normal case is too large")
    out = -c_n * k[:, :2] / k[:, 2:3]
    return out[0] if single else out
