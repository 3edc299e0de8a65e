"""Rotation matrices of the course and named conversions to other conventions.

The course convention (docs/conventions.md): ``R = R_ω·R_φ·R_κ`` with active, right-handed
elementary rotations about X, Y, Z; R turns camera vectors into the object frame,
``X = X0 + m·R·x*``. Every other convention has its own named function; there is no
implicit order. The matrix elements come from the generated code of
:mod:`photolib.derive.rotation`.
"""

from __future__ import annotations

import numpy as np

from photolib._docs import shared_doc
from photolib._generated.rotation import rotation_opk_elements, rotation_pok_elements
from photolib._validate import as_float_array, as_rotation, as_vector3, check_finite
from photolib.errors import GimbalLockError  # noqa: F401 - raised here, defined in one hierarchy

__all__ = [
    "GimbalLockError", "rotation_opk", "opk_from_rotation", "rotation_pok", "pok_from_rotation",
    "wolf_m_from_rotation", "rotation_from_wolf_m", "rotation_2d",
    "opencv_pose_from_exterior", "exterior_from_opencv_pose",
]

#: |cos φ| below this is treated as gimbal lock by :func:`opk_from_rotation`
GIMBAL_TOL = 1e-9



#: the end of the parameters and the result of :func:`rotation_opk` and :func:`rotation_pok`
_ROTATION_RESULT = """    Arrays broadcast; the result then has shape ``(..., 3, 3)``.

Returns
-------
R : ndarray, shape (3, 3) or (..., 3, 3)
    Rotation camera → object (dimensionless), ``X = X0 + m·R·x*``."""


def _stack(elements) -> np.ndarray:
    e = np.broadcast_arrays(*elements)
    return np.stack(e, axis=-1).reshape(e[0].shape + (3, 3))


def _angle(value, name):
    a = as_float_array(value, name)
    check_finite(np.atleast_1d(a), name)
    return a


def _angles(omega, phi, kappa):
    out = [_angle(a, name) for a, name in zip((omega, phi, kappa), ("omega", "phi", "kappa"))]
    if any(a.ndim for a in out):
        try:
            np.broadcast_shapes(*(a.shape for a in out))
        except ValueError:
            raise ValueError(f"omega, phi, kappa have shapes {[a.shape for a in out]}, which do "
                             "not broadcast to one shape") from None
    return out


@shared_doc(rotation_result=_ROTATION_RESULT)
def rotation_opk(omega, phi, kappa) -> np.ndarray:
    """Rotation matrix ``R = R_ω·R_φ·R_κ`` (camera → object).

    Parameters
    ----------
    omega, phi, kappa : float or array_like
        Primary (about X), secondary (about Y) and tertiary (about Z) angle, radians.
    {rotation_result}

    Notes
    -----
    .. math::
        R = \\begin{pmatrix} \\cos φ\\cos κ & -\\cos φ\\sin κ & \\sin φ \\\\
        \\cos ω\\sin κ + \\sin ω\\sin φ\\cos κ & \\cos ω\\cos κ - \\sin ω\\sin φ\\sin κ & -\\sin ω\\cos φ \\\\
        \\sin ω\\sin κ - \\cos ω\\sin φ\\cos κ & \\sin ω\\cos κ + \\cos ω\\sin φ\\sin κ & \\cos ω\\cos φ
        \\end{pmatrix}

    Examples
    --------
    >>> R = rotation_opk(0.0, 0.0, np.pi / 2)
    >>> np.round(R @ [1.0, 0.0, 0.0], 12) + 0.0
    array([0., 1., 0.])
    """
    return _stack(rotation_opk_elements(*_angles(omega, phi, kappa)))


@shared_doc(rotation_result=_ROTATION_RESULT)
def rotation_pok(omega, phi, kappa) -> np.ndarray:
    """Rotation matrix in the φ-ω-κ order, ``R = R_φ·R_ω·R_κ`` (primary axis Y).

    Same elementary rotations and angle units (radians) as :func:`rotation_opk`, other order.

    Parameters
    ----------
    omega, phi, kappa : float or array_like
        Secondary (about X), primary (about Y) and tertiary (about Z) angle, radians.
    {rotation_result}

    Notes
    -----
    .. math:: R = R_φ\\,R_ω\\,R_κ

    with the elementary rotations ``R_ω`` (about X), ``R_φ`` (about Y), ``R_κ`` (about Z) of
    :func:`rotation_opk`.

    Examples
    --------
    >>> R = rotation_pok(0.1, 0.2, 0.3)
    >>> bool(np.allclose(R, rotation_opk(0.0, 0.2, 0.0) @ rotation_opk(0.1, 0.0, 0.3)))
    True
    """
    return _stack(rotation_pok_elements(*_angles(omega, phi, kappa)))


def _gimbal(split: str | None, which: str, secondary: float) -> None:
    if split is None:
        raise GimbalLockError(
            f"gimbal lock: {which} = {np.degrees(secondary):+.6f}° (±90°); the other two angles "
            "are not separable. Pass split='kappa-zero' or split='omega-zero' to choose one.")
    if split not in ("kappa-zero", "omega-zero"):
        raise ValueError(f"split must be None, 'kappa-zero' or 'omega-zero', got {split!r}")


def opk_from_rotation(R, *, split: str | None = None, atol: float = 1e-6):
    """Angles ``(omega, phi, kappa)`` of ``R = R_ω·R_φ·R_κ``, radians.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        Proper rotation matrix (orthonormal within ``atol``, det +1).
    split : {None, 'kappa-zero', 'omega-zero'}
        At gimbal lock (|φ| = π/2) only ω ± κ is determined. ``None`` raises
        :class:`GimbalLockError`; otherwise the named angle is set to 0.
    atol : float
        Tolerance (dimensionless, on the matrix elements) of the check that R is orthonormal
        with det +1; a looser check accepts e.g. a matrix read from a file with few digits.

    Returns
    -------
    omega, kappa : float in (−π, π]
    phi : float in [−π/2, π/2]

    Notes
    -----
    .. math:: φ = \\arcsin r_{13},\\quad ω = \\operatorname{atan2}(-r_{23}, r_{33}),
              \\quad κ = \\operatorname{atan2}(-r_{12}, r_{11})

    Examples
    --------
    >>> [round(float(a), 12) for a in opk_from_rotation(rotation_opk(0.1, -0.2, 0.3))]
    [0.1, -0.2, 0.3]
    """
    R = as_rotation(R, atol=atol)
    phi = float(np.arcsin(np.clip(R[0, 2], -1.0, 1.0)))
    cphi = np.hypot(R[0, 0], R[0, 1])
    if cphi < GIMBAL_TOL:
        _gimbal(split, "phi", phi)
        phi = float(np.copysign(np.pi / 2, phi))
        if split == "kappa-zero":  # R = R_ω·R_φ  ⇒  R·R_φᵀ = R_ω
            M = R @ rotation_opk(0.0, phi, 0.0).T
            return float(np.arctan2(M[2, 1], M[1, 1])), phi, 0.0
        M = rotation_opk(0.0, phi, 0.0).T @ R  # R = R_φ·R_κ  ⇒  R_φᵀ·R = R_κ
        return 0.0, phi, float(np.arctan2(M[1, 0], M[0, 0]))
    omega = float(np.arctan2(-R[1, 2], R[2, 2]))
    kappa = float(np.arctan2(-R[0, 1], R[0, 0]))
    return omega, phi, kappa


def pok_from_rotation(R, *, split: str | None = None, atol: float = 1e-6):
    """Angles ``(omega, phi, kappa)`` of ``R = R_φ·R_ω·R_κ`` (see :func:`rotation_pok`).

    ``ω = arcsin(−r23) ∈ [−π/2, π/2]``, ``φ = atan2(r13, r33)``, ``κ = atan2(r21, r22)``;
    gimbal lock at |ω| = π/2 is handled as in :func:`opk_from_rotation`.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        Proper rotation matrix (orthonormal within ``atol``, det +1), camera → object.
    split : {None, 'kappa-zero', 'omega-zero'}
        At gimbal lock (|ω| = π/2) only φ ± κ is determined. ``None`` raises
        :class:`GimbalLockError`; otherwise the named angle is set to 0.
    atol : float
        Tolerance (dimensionless, on the matrix elements) of the orthonormality check.

    Returns
    -------
    omega : float in [−π/2, π/2]
        Secondary angle about X, radians.
    phi, kappa : float in (−π, π]
        Primary angle about Y and tertiary angle about Z, radians.

    Notes
    -----
    .. math:: ω = \\arcsin(-r_{23}),\\quad φ = \\operatorname{atan2}(r_{13}, r_{33}),
              \\quad κ = \\operatorname{atan2}(r_{21}, r_{22})

    Examples
    --------
    >>> [round(float(a), 12) for a in pok_from_rotation(rotation_pok(0.1, -0.2, 0.3))]
    [0.1, -0.2, 0.3]
    """
    R = as_rotation(R, atol=atol)
    omega = float(np.arcsin(np.clip(-R[1, 2], -1.0, 1.0)))
    comega = np.hypot(R[1, 0], R[1, 1])
    if comega < GIMBAL_TOL:
        _gimbal(split, "omega", omega)
        omega = float(np.copysign(np.pi / 2, omega))
        Rw = rotation_opk(omega, 0.0, 0.0)
        if split == "kappa-zero":  # R = R_φ·R_ω  ⇒  R·R_ωᵀ = R_φ
            M = R @ Rw.T
            return omega, float(np.arctan2(M[0, 2], M[0, 0])), 0.0
        M = Rw.T @ R  # R = R_ω·R_κ  ⇒  R_ωᵀ·R = R_κ
        return omega, 0.0, float(np.arctan2(M[1, 0], M[0, 0]))
    phi = float(np.arctan2(R[0, 2], R[2, 2]))
    kappa = float(np.arctan2(R[1, 0], R[1, 1]))
    return omega, phi, kappa


def wolf_m_from_rotation(R) -> np.ndarray:
    """Wolf's orientation matrix ``M = Rᵀ`` (object → image), from the course's R.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        The course's rotation camera → object, ``R = R_ω·R_φ·R_κ`` (:func:`rotation_opk`).

    Returns
    -------
    M : ndarray, shape (3, 3)
        Wolf's rotation object → image (dimensionless), ``x* ∝ M·(X − X0)``.

    Notes
    -----
    .. math:: M = R^T

    Examples
    --------
    >>> bool(np.allclose(wolf_m_from_rotation(rotation_opk(0.1, 0.2, 0.3)) @ rotation_opk(0.1, 0.2, 0.3), np.eye(3)))
    True
    """
    return as_rotation(R).T.copy()


def rotation_from_wolf_m(M) -> np.ndarray:
    """The course's ``R = Mᵀ`` from Wolf's orientation matrix M.

    Parameters
    ----------
    M : array_like, shape (3, 3)
        Wolf's orientation matrix, object → image (proper rotation).

    Returns
    -------
    R : ndarray, shape (3, 3)
        The course's rotation camera → object (dimensionless), ``X = X0 + m·R·x*``.

    Notes
    -----
    .. math:: R = M^T

    Examples
    --------
    >>> M = wolf_m_from_rotation(rotation_opk(0.0, 0.0, 0.5))
    >>> [round(float(a), 12) for a in opk_from_rotation(rotation_from_wolf_m(M))]
    [0.0, 0.0, 0.5]
    >>> bool(np.allclose(rotation_from_wolf_m(wolf_m_from_rotation(np.eye(3))), np.eye(3)))
    True
    """
    return as_rotation(M, "M").T.copy()


def rotation_2d(alpha) -> np.ndarray:
    """Plane rotation by ``alpha`` (radians, counter-clockwise with x right and y up).

    Parameters
    ----------
    alpha : float or array_like
        Rotation angle in radians, positive counter-clockwise (x right, y up). An array gives
        one matrix per angle.

    Returns
    -------
    R : ndarray, shape (2, 2) or (..., 2, 2)
        Active rotation matrix (dimensionless): ``R @ p`` turns the point p by α about the
        origin.

    Notes
    -----
    .. math:: R(α) = \\begin{pmatrix} \\cos α & -\\sin α \\\\ \\sin α & \\cos α \\end{pmatrix}

    Examples
    --------
    >>> np.round(rotation_2d(np.pi / 2) @ [1.0, 0.0], 12) + 0.0
    array([0., 1.])
    """
    R = rotation_opk(0.0, 0.0, _angle(alpha, "alpha"))
    return R[..., :2, :2].copy()


_FLIP = np.diag([1.0, -1.0, -1.0])


def opencv_pose_from_exterior(X0, R):
    """OpenCV's ``(R_cv, t)`` for a camera at ``X0`` with the course's ``R``.

    OpenCV's camera looks along +z with y down: ``R_cv = diag(1, −1, −1)·Rᵀ``,
    ``t = −R_cv·X0``, so that ``x_cam = R_cv·X + t``.

    Parameters
    ----------
    X0 : array_like, shape (3,)
        Projection centre / Projektionszentrum (object unit, e.g. m).
    R : array_like, shape (3, 3)
        The course's rotation camera → object, ``R = R_ω·R_φ·R_κ`` (:func:`rotation_opk`).

    Returns
    -------
    R_cv : ndarray, shape (3, 3)
        OpenCV's rotation object → camera (dimensionless; ``cv2.Rodrigues`` turns it into rvec).
    t : ndarray, shape (3,)
        OpenCV's translation (tvec), object unit: the object origin in camera coordinates.

    Notes
    -----
    .. math:: R_{cv} = \\operatorname{diag}(1, -1, -1)\\,R^T,\\qquad t = -R_{cv}\\,X_0

    Examples
    --------
    >>> Rcv, t = opencv_pose_from_exterior([0.0, 0.0, 10.0], np.eye(3))
    >>> (Rcv @ [0.0, 0.0, 0.0] + t).tolist()
    [0.0, 0.0, 10.0]
    """
    R = as_rotation(R)
    X0 = as_vector3(X0, "X0")
    Rcv = _FLIP @ R.T
    return Rcv, -Rcv @ X0


def exterior_from_opencv_pose(R_cv, t):
    """Inverse of :func:`opencv_pose_from_exterior`: ``(X0, R)``.

    Parameters
    ----------
    R_cv : array_like, shape (3, 3)
        OpenCV's rotation object → camera (camera looks along +z, y down), e.g. from
        ``cv2.Rodrigues(rvec)``.
    t : array_like, shape (3,)
        OpenCV's translation (tvec), object unit, ``x_cam = R_cv·X + t``.

    Returns
    -------
    X0 : ndarray, shape (3,)
        Projection centre / Projektionszentrum (object unit).
    R : ndarray, shape (3, 3)
        The course's rotation camera → object, ``R = R_ω·R_φ·R_κ``.

    Notes
    -----
    .. math:: X_0 = -R_{cv}^T\\,t,\\qquad R = (\\operatorname{diag}(1, -1, -1)\\,R_{cv})^T

    Examples
    --------
    >>> X0, R = exterior_from_opencv_pose(*opencv_pose_from_exterior([1.0, 2.0, 3.0], rotation_opk(0.1, 0.2, 0.3)))
    >>> np.round(X0, 12).tolist()
    [1.0, 2.0, 3.0]
    """
    Rcv = as_rotation(R_cv, "R_cv")
    t = as_vector3(t, "t")
    R = (_FLIP @ Rcv).T
    return -Rcv.T @ t, R
