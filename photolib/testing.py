"""Assertion helpers that know the mathematics, for the course's tests and notebooks.

Like ``numpy.testing``, but rotation-aware: angles compare modulo 2π, rotation matrices are
first checked to be rotations, and a failing assert says what kind of difference it found
(transposed, a reflection, degrees for radians).
"""

from __future__ import annotations

import numpy as np

__all__ = ["assert_rotation_matrix", "assert_rotation_equal", "assert_angles_equal",
           "assert_points_close", "rotation_angle_between"]


def rotation_angle_between(R1, R2) -> float:
    """Angle (radians) of the rotation ``R1ᵀ·R2``: 0 when equal.

    >>> rotation_angle_between(np.eye(3), np.eye(3))
    0.0
    """
    R1, R2 = np.asarray(R1, float), np.asarray(R2, float)
    cos = (np.trace(R1.T @ R2) - 1.0) / 2.0
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def assert_rotation_matrix(R, atol: float = 1e-9, name: str = "R") -> None:
    """Assert ``R`` is a 3×3 proper rotation: ``RᵀR = I`` within ``atol`` and ``det R = +1``.

    >>> assert_rotation_matrix(np.eye(3))
    >>> assert_rotation_matrix(np.diag([1.0, 1.0, -1.0]))
    Traceback (most recent call last):
    ...
    AssertionError: R has det -1.000000: a reflection, not a rotation
    """
    R = np.asarray(R, dtype=float)
    if R.shape != (3, 3):
        raise AssertionError(f"{name} has shape {R.shape}; expected (3, 3)")
    if not np.all(np.isfinite(R)):
        raise AssertionError(f"{name} contains non-finite values")
    err = float(np.max(np.abs(R.T @ R - np.eye(3))))
    if err > atol:
        raise AssertionError(f"{name} is not orthonormal: max |RᵀR − I| = {err:.3g} > {atol:g}")
    det = float(np.linalg.det(R))
    if det < 0:
        raise AssertionError(f"{name} has det {det:.6f}: a reflection, not a rotation")


def assert_rotation_equal(actual, desired, atol: float = 1e-9) -> None:
    """Assert two rotation matrices are equal (angle of ``actualᵀ·desired`` ≤ ``atol`` rad).

    The message recognises a transposed matrix.

    >>> from photolib import rotation_opk
    >>> R = rotation_opk(0.1, 0.2, 0.3)
    >>> assert_rotation_equal(R, R)
    >>> assert_rotation_equal(R.T, R)
    Traceback (most recent call last):
    ...
    AssertionError: rotations differ by 0.76313 rad; actual equals desired transposed (Rᵀ instead of R?)
    """
    assert_rotation_matrix(actual, atol=max(atol, 1e-9), name="actual")
    assert_rotation_matrix(desired, atol=max(atol, 1e-9), name="desired")
    ang = rotation_angle_between(actual, desired)
    if ang > atol:
        hint = ""
        if rotation_angle_between(np.asarray(actual).T, desired) <= atol:
            hint = "; actual equals desired transposed (Rᵀ instead of R?)"
        raise AssertionError(f"rotations differ by {ang:.6g} rad{hint}")


def assert_angles_equal(actual, desired, atol: float = 1e-9) -> None:
    """Assert angles (radians) are equal modulo 2π, elementwise.

    >>> assert_angles_equal(np.pi, -np.pi)
    """
    a, d = np.asarray(actual, float), np.asarray(desired, float)
    diff = np.abs((a - d + np.pi) % (2 * np.pi) - np.pi)
    if np.any(diff > atol):
        i = int(np.argmax(diff))
        hint = ""
        if np.allclose(np.radians(a), d, atol=atol):
            hint = " (actual is in degrees?)"
        raise AssertionError(f"angles differ by up to {float(np.max(diff)):.6g} rad at index {i}{hint}")


def assert_points_close(actual, desired, atol: float, name: str = "points") -> None:
    """Assert point sets of equal shape agree within ``atol`` (Euclidean distance per point).

    >>> assert_points_close([[0.0, 0.0]], [[0.0, 1e-12]], atol=1e-9)
    """
    a, d = np.asarray(actual, float), np.asarray(desired, float)
    if a.shape != d.shape:
        raise AssertionError(f"{name}: shapes differ, {a.shape} vs {d.shape}")
    dist = np.linalg.norm(np.atleast_2d(a - d), axis=-1)
    if not np.all(dist <= atol):
        i = int(np.nanargmax(np.where(np.isnan(dist), np.inf, dist)))
        raise AssertionError(f"{name}: point {i} off by {dist[i]:.6g} > atol={atol:g}")
