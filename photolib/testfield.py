r"""Test-field calibration with a plane test field / Testfeldkalibrierung mit ebenem Testfeld.

A plane field of known points (a chessboard) is imaged M times from different positions. The
bundle adjustment with all field points fixed (control points, Passpunkte) estimates the
exterior orientation of every image and the interior orientation common to all of them —
camera constant / Kamerakonstante c, principal point / Bildhauptpunkt (x'0, y'0) and the
distortion terms — by :func:`photolib.bundle_adjustment` with ``calibrate=…``.

Start values (Näherungswerte) come from the plane: the field's plane Z = 0 and the image are
related by a homography (chapter 07). With the collinearity equations of the course,
``(kx, ky, N) = Rᵀ(X − X0)`` and, for Z = 0,

.. math::
    \begin{pmatrix} x' - x'_0 \\ y' - y'_0 \\ 1 \end{pmatrix} \propto
    \operatorname{diag}(-c, -c, 1)\,[\,a \;\; b \;\; t\,]
    \begin{pmatrix} X \\ Y \\ 1 \end{pmatrix},\qquad
    a = R^T e_x,\; b = R^T e_y,\; t = -R^T X_0 ,

so the homography G of the image (:func:`plane_homography`) gives
``M = diag(−1/c, −1/c, 1)·G ∝ [a b t]`` with ``|a| = |b| = 1`` and ``a ⊥ b``. These two conditions per image give c (Zhang 2000, with the
principal point at the origin of the image coordinates and square pixels):

.. math::
    \frac{g_{11}g_{12} + g_{21}g_{22}}{c^2} + g_{31}g_{32} = 0,\qquad
    \frac{g_{11}^2 + g_{21}^2 - g_{12}^2 - g_{22}^2}{c^2} + g_{31}^2 - g_{32}^2 = 0 ,

linear in ``w = 1/c²`` and solved by least squares over all images. Then per image
``Rᵀ = [a, b, a × b]`` (made orthonormal by SVD) and ``X0 = −R·t``.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_points, as_scalar
from photolib.bundle import bundle_adjustment
from photolib.rotations import opk_from_rotation
from photolib.transforms import ProjectiveTransform
from photolib.transforms._base import DegenerateGeometryError

__all__ = ["DEFAULT_TERMS", "camera_constant_from_homographies", "exterior_from_homography",
           "plane_homography", "plane_start", "plane_field_calibration"]

#: the interior parameters estimated by default: c, principal point, radial A1–A3, tangential
#: B1, B2 (no affinity: square pixels)
DEFAULT_TERMS = ("c", "x0", "y0", "A1", "A2", "A3", "B1", "B2")


def plane_homography(XY, xy) -> np.ndarray:
    """3 × 3 homography G with ``(x', y', 1) ∝ G·(X, Y, 1)`` from ≥ 4 point pairs (chapter 07).

    Parameters
    ----------
    XY : array_like, shape (N, 2)
        Points of the plane test field, object unit (e.g. mm).
    xy : array_like, shape (N, 2)
        Their image coordinates reduced to the principal point, image unit (e.g. px).

    Returns
    -------
    ndarray, shape (3, 3)
        ``G`` scaled to ``G[2, 2] = 1``, the matrix of :class:`photolib.ProjectiveTransform`.
    """
    XY, _ = as_points(XY, 2, "XY")
    xy, _ = as_points(xy, 2, "xy")
    if len(XY) != len(xy):
        raise ValueError(f"XY has {len(XY)} points but xy has {len(xy)}")
    return ProjectiveTransform.from_estimate(XY, xy).matrix


def camera_constant_from_homographies(homographies) -> float:
    """Camera constant c from ≥ 2 plane homographies (orthonormality of a, b; module text).

    Parameters
    ----------
    homographies : sequence of array_like, each (3, 3)
        ``G`` of :func:`plane_homography`, image coordinates reduced to an assumed principal
        point, square pixels.

    Returns
    -------
    float
        c in the image unit, ``c = 1/√w`` with ``w = −Σαβ/Σα²`` over the two conditions of
        every image.

    Raises
    ------
    DegenerateGeometryError
        When the views do not determine c: all image planes parallel to the field (no
        perspective, the g₃ terms vanish) or ``w ≤ 0``.

    Examples
    --------
    >>> from photolib import rotation_opk
    >>> def G(c, R, X0):  # the homography of a camera (module text)
    ...     M = np.column_stack([R.T[:, 0], R.T[:, 1], -R.T @ X0])
    ...     return np.diag([-c, -c, 1.0]) @ M
    >>> Gs = [G(500.0, rotation_opk(0.3, -0.2, 0.1), np.array([50.0, 0.0, 400.0])),
    ...       G(500.0, rotation_opk(-0.2, 0.4, 2.0), np.array([0.0, -80.0, 350.0]))]
    >>> round(camera_constant_from_homographies(Gs), 9)
    500.0
    """
    alpha, beta = [], []
    for k, G in enumerate(homographies):
        G = np.asarray(G, dtype=float)
        if G.shape != (3, 3) or not np.all(np.isfinite(G)):
            raise ValueError(f"homographies[{k}] must be a finite (3, 3) matrix, got shape "
                             f"{G.shape}")
        G = G / np.linalg.norm(G)
        alpha += [G[0, 0] * G[0, 1] + G[1, 0] * G[1, 1],
                  G[0, 0] ** 2 + G[1, 0] ** 2 - G[0, 1] ** 2 - G[1, 1] ** 2]
        beta += [G[2, 0] * G[2, 1], G[2, 0] ** 2 - G[2, 1] ** 2]
    if len(alpha) < 4:
        raise ValueError(f"camera_constant_from_homographies needs ≥ 2 homographies, got "
                         f"{len(alpha) // 2}")
    alpha, beta = np.array(alpha), np.array(beta)
    if np.max(np.abs(beta)) <= 1e-12 * np.max(np.abs(alpha)):
        raise DegenerateGeometryError("all image planes are parallel to the test field (no "
                                      "perspective in any homography): c is not determined; "
                                      "tilt the camera against the field")
    w = -float(alpha @ beta) / float(alpha @ alpha)
    if not w > 0:
        raise DegenerateGeometryError(f"the homographies give 1/c² = {w:.3g} ≤ 0: the views do "
                                      "not determine c (too little tilt, or wrong principal point)")
    return float(1.0 / np.sqrt(w))


def exterior_from_homography(G, c, XY_centre=(0.0, 0.0)):
    """Exterior orientation ``(X0, R)`` of one image of the plane Z = 0 from its homography.

    Parameters
    ----------
    G : array_like, shape (3, 3)
        Homography object (X, Y, 1) → image (x' − x'0, y' − y'0, 1) (:func:`plane_homography`).
    c : float
        Camera constant, image unit, > 0.
    XY_centre : array_like, shape (2,)
        A point of the field (e.g. its centre) that must lie in front of the camera (N < 0):
        it fixes the sign of the homography.

    Returns
    -------
    X0 : ndarray, shape (3,)
        Projection centre, object unit; ``Z0 > 0`` when the camera is on the +Z side.
    R : ndarray, shape (3, 3)
        Rotation camera → object, the nearest rotation to ``[a, b, a × b]ᵀ``.
    """
    c = as_scalar(c, "c", positive=True)
    G = np.asarray(G, dtype=float)
    if G.shape != (3, 3):
        raise ValueError(f"G must have shape (3, 3), got {G.shape}")
    M = np.diag([-1.0 / c, -1.0 / c, 1.0]) @ G
    M = M * 2.0 / (np.linalg.norm(M[:, 0]) + np.linalg.norm(M[:, 1]))
    if (M @ np.r_[np.asarray(XY_centre, dtype=float), 1.0])[2] > 0:  # N must be < 0
        M = -M
    a, b, t = M.T
    U, _, Vt = np.linalg.svd(np.column_stack([a, b, np.cross(a, b)]))
    Rt = U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt
    R = Rt.T
    return -R @ t, R


def plane_start(xy_images, XY, c=None):
    """Start values ``(c, exterior)`` of a plane test-field calibration.

    Parameters
    ----------
    xy_images : sequence of array_like, each (N, 2)
        Image coordinates of the field points in each image, reduced to the assumed principal
        point (e.g. the image centre), image unit.
    XY : array_like, shape (N, 2)
        The field points (object unit), the same order in every image.
    c : float, optional
        Camera constant; default from :func:`camera_constant_from_homographies`.

    Returns
    -------
    c : float
    exterior : ndarray, shape (M, 6)
        ``(X0, Y0, Z0, ω, φ, κ)`` per image (object unit, radians).
    """
    XY, _ = as_points(XY, 2, "XY")
    Gs = [plane_homography(XY, q) for q in xy_images]
    c = camera_constant_from_homographies(Gs) if c is None else as_scalar(c, "c", positive=True)
    ext = []
    for G in Gs:
        X0, R = exterior_from_homography(G, c, XY.mean(axis=0))
        ext.append(np.r_[X0, opk_from_rotation(R)])
    return c, np.array(ext)


def plane_field_calibration(xy_images, object_points, *, terms=DEFAULT_TERMS, r0=0.0,
                          tol: float = 1e-10, max_iter: int = 50):
    """Calibrate a camera from M images of a plane test field (bundle with fixed field points).

    Parameters
    ----------
    xy_images : sequence of array_like, each (N, 2)
        Measured image coordinates (x', y') of the N field points in each image, origin at the
        image centre, x' right, y' up (:func:`photolib.image_from_pixel`), image unit (mm, or px
        when the pixel pitch is unknown).
    object_points : array_like, shape (N, 3)
        The field points, object unit, all with Z = 0.
    terms : sequence of str
        Interior parameters to estimate (:data:`photolib.bundle.INTERIOR_PARAMETERS`).
    r0 : float
        Balancing radius of the radial model (image unit); 0: Seidel's form.
    tol, max_iter
        As :func:`photolib.bundle_adjustment`.

    Returns
    -------
    BundleResult
        With ``c``, ``x0``, ``y0``, ``distortion``, ``interior_covariance`` (order
        ``calibrate``), ``exterior`` (M, 6) and σ0 (image unit). Start values from
        :func:`plane_start` with the principal point at the image centre.

    Raises
    ------
    ValueError
        Object points not on Z = 0, images with different numbers of points, fewer than 2
        images; the errors of :func:`photolib.bundle_adjustment`.
    """
    P, _ = as_points(object_points, 3, "object_points")
    if np.max(np.abs(P[:, 2])) > 0:
        raise ValueError(f"object_points must lie in the plane Z = 0; the largest |Z| is "
                         f"{np.max(np.abs(P[:, 2])):.6g}")
    xy = [as_points(q, 2, f"xy_images[{k}]")[0] for k, q in enumerate(xy_images)]
    if len(xy) < 2:
        raise ValueError(f"a plane test field needs ≥ 2 images (c is not determined by one), "
                         f"got {len(xy)}")
    for k, q in enumerate(xy):
        if len(q) != len(P):
            raise ValueError(f"xy_images[{k}] has {len(q)} points, object_points {len(P)}")
    c0, ext = plane_start(xy, P[:, :2])
    from photolib.distortion import Distortion
    M, N = len(xy), len(P)
    return bundle_adjustment(np.vstack(xy), np.repeat(np.arange(M), N), np.tile(np.arange(N), M),
                             ext, P, c0, 0.0, 0.0, Distortion(r0=r0), control=np.arange(N),
                             calibrate=terms, tol=tol, max_iter=max_iter)
