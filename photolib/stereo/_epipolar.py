r"""Epipolar geometry: coplanarity, essential and fundamental matrix, normalised images.

* Coplanarity (Komplanarität): the base b = X02 − X01 and the rays ``R1·x*1``, ``R2·x*2`` lie in
  one plane, ``det[b, R1·x*1, R2·x*2] = 0``, i.e. ``x*1ᵀ·E·x*2 = 0`` with the essential matrix
  ``E = R1ᵀ·[b]×·R2`` (course frames: ``x* = (x' − x'0, y' − y'0, −c)``).
* For image coordinates ``h = (x', y', 1)``: ``h1ᵀ·F·h2 = 0`` with ``F = K1ᵀ·E·K2``
  (Luhmann's order, image 1 left); the epipolar lines (Kernlinien) are ``l2 = Fᵀ·h1`` and
  ``l1 = F·h2``, scaled to ``a² + b² = 1``.
* Normalised (epipolar) images (Normalbilder): both images rotated to a common ``Rn`` with x
  along the base form the normal case, corresponding points have equal y'.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import (
    as_float_array,
    as_points,
    as_rotation,
    as_scalar,
    as_vector3,
    check_finite,
)
from photolib.collinearity import PointBehindCameraError
from photolib.stereo._rays import _image_vectors
from photolib.transforms._base import DegenerateGeometryError


# -- coplanarity, essential and fundamental matrix ------------------------------------------------

def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _base(X01, X02, what: str) -> tuple[np.ndarray, float]:
    """The base ``b = X02 − X01`` and its length (without underflow for a tiny base);
    ``DegenerateGeometryError`` for a zero base, or one lost in the rounding of X01, X02."""
    b = X02 - X01
    big = float(np.max(np.abs(b)))
    if big == 0.0:
        raise DegenerateGeometryError(f"X01 = X02: the base is zero, {what}")
    length = big * float(np.linalg.norm(b / big))
    size = max(float(np.max(np.abs(X01))), float(np.max(np.abs(X02))))
    if length <= 1e-12 * size:
        raise DegenerateGeometryError(
            f"the base |X02 − X01| = {length:.3g} is below the rounding of the projection "
            f"centres (coordinates up to {size:.3g}): practically a zero base, {what}")
    return b, length


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
    b, _ = _base(X01, X02, "there is no epipolar geometry")
    return R1.T @ _skew(b) @ R2


def _interior_matrix(c, x0, y0, name):
    c = as_scalar(c, f"c{name}", positive=True)
    return np.array([[1.0, 0.0, -as_scalar(x0, f"x0{name}")],
                     [0.0, 1.0, -as_scalar(y0, f"y0{name}")], [0.0, 0.0, -c]])


#: relative tolerances of the rank tests (σ3 ≤ tol3·σ1: σ3 counts as 0; σ2 ≤ tol1·σ1: rank 1).
#: E is unit-free (an essential matrix has σ1 = σ2 = |b|, σ3 = 0); the singular values of F
#: depend on the image unit (x' → x'/u scales its rows and columns by diag(u, u, 1)), so for
#: F only a clear rank 3 and an unmistakable rank 1 are refused.
_RANK_TOL_E = (1e-6, 1e-6)
_RANK_TOL_F = (1e-3, 1e-12)


def _check_rank_2(M, name, tols, what):
    """``DegenerateGeometryError`` naming ``name`` unless M (3, 3) has rank 2 within ``tols``."""
    tol3, tol1 = tols
    sv = np.linalg.svd(M, compute_uv=False)
    values = f"singular values {sv[0]:.6g}, {sv[1]:.6g}, {sv[2]:.6g}"
    if not sv[0] > 0:
        raise DegenerateGeometryError(f"{name} is zero: {what}")
    if sv[2] > tol3 * sv[0]:
        raise DegenerateGeometryError(f"{name} has rank 3 ({values}; σ3/σ1 = "
                                      f"{sv[2] / sv[0]:.3g} > {tol3:g}): {what}")
    if sv[1] <= tol1 * sv[0]:
        raise DegenerateGeometryError(f"{name} has rank 1 ({values}): {what}")


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

    Raises
    ------
    DegenerateGeometryError
        If E is zero or does not have rank 2 (σ3 > 10⁻⁶·σ1 or σ2 ≤ 10⁻⁶·σ1): it is then no
        essential matrix ``R1ᵀ·[b]×·R2`` (which has σ1 = σ2 = |b| and σ3 = 0).

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
    E = as_float_array(E, "E", " with shape (3, 3)")
    if E.shape != (3, 3):
        raise ValueError(f"E must be a finite (3, 3) matrix, got shape {E.shape}")
    check_finite(E, "E")
    _check_rank_2(E, "E", _RANK_TOL_E, "not an essential matrix R1ᵀ·[b]×·R2 (rank 2)")
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

    Raises
    ------
    DegenerateGeometryError
        If F is zero, has rank 1 (σ2 ≤ 10⁻¹²·σ1) or clearly rank 3 (σ3 > 10⁻³·σ1; the
        singular values of F depend on the image unit, so the tests are loose), or if a
        point is the epipole.

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
    F = as_float_array(F, "F", " with shape (3, 3)")
    if F.shape != (3, 3):
        raise ValueError(f"F must be a finite (3, 3) matrix, got shape {F.shape}")
    check_finite(F, "F")
    _check_rank_2(F, "F", _RANK_TOL_F, "not a fundamental matrix (rank 2), so there are no "
                  "epipolar lines")
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
    b, length = _base(X01, X02, "no normal case")
    ex = b / length  # _base's length does not underflow for a base below 1e-154
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
