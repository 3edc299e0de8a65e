"""Input checks shared by the numeric modules: shapes, finiteness, clear messages."""

from __future__ import annotations

import numpy as np


def as_points(values, dim: int, name: str, *, finite: bool = True) -> tuple[np.ndarray, bool]:
    """Return ``(points (N, dim) float array, single)``; ``single`` if a (dim,) point was given.

    Raises ``ValueError`` naming ``name``, the shape and the first non-finite entry. With
    ``finite=False`` the caller checks finiteness itself (block by block, while the block is
    in the cache) and calls :func:`check_finite` on the whole array for the message.
    """
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric with shape (N, {dim}) or ({dim},): {exc}") from None
    single = arr.ndim == 1
    if single:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise ValueError(f"{name} has shape {np.shape(values)}; expected (N, {dim}) or ({dim},)")
    if finite:
        check_finite(arr, name)
    return arr, single


def as_point_pairs(a, b, dims: tuple[int, int], names: tuple[str, str], min_points: int,
                   what: str, unit: str = "points") -> tuple[np.ndarray, np.ndarray]:
    """Validated point arrays ``a`` (N, dims[0]) and ``b`` (N, dims[1]) with equal N ≥ ``min_points``.

    ``what`` names the caller in the message about too few points, ``unit`` what is counted.
    """
    a, _ = as_points(a, dims[0], names[0])
    b, _ = as_points(b, dims[1], names[1])
    if len(a) != len(b):
        raise ValueError(f"{names[0]} has {len(a)} points but {names[1]} has {len(b)}; "
                         "they must pair up")
    if len(a) < min_points:
        raise ValueError(f"{what} needs at least {min_points} {unit}, got {len(a)}")
    return a, b


def check_finite(arr: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` naming the first NaN/inf entry of ``arr``."""
    if not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0]
        where = tuple(int(i) for i in bad)
        raise ValueError(f"{name} contains a non-finite value {float(arr[where])!r} at index {where}")


def as_array(value, name: str, *, positive: bool = False, nonnegative: bool = False,
             finite: bool = True) -> np.ndarray:
    """``value`` as a float array of any shape, checked; ``ValueError`` naming ``name`` otherwise.

    NaN is always refused; ±inf too unless ``finite=False`` (e.g. an object at infinity).
    ``positive`` asks for > 0, ``nonnegative`` for ≥ 0; the message quotes the first bad value.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got {value!r}") from None
    if np.any(np.isnan(arr)):
        raise ValueError(f"{name} must be finite, got NaN" if finite
                         else f"{name} must not be NaN, got NaN")
    if finite and not np.all(np.isfinite(arr)):
        bad = float(arr[~np.isfinite(arr)].ravel()[0])
        raise ValueError(f"{name} must be finite, got {bad!r}")
    if positive and np.any(arr <= 0):
        raise ValueError(f"{name} must be > 0, got {float(arr[arr <= 0].ravel()[0])!r}")
    if nonnegative and np.any(arr < 0):
        raise ValueError(f"{name} must be ≥ 0, got {float(arr[arr < 0].ravel()[0])!r}")
    return arr


def as_scalar(value, name: str, *, positive: bool = False) -> float:
    """A finite float; with ``positive`` it must be > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if not np.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    if positive and v <= 0:
        raise ValueError(f"{name} must be > 0, got {v!r}")
    return v


def as_vector3(value, name: str) -> np.ndarray:
    """A finite (3,) float vector."""
    arr = np.asarray(value, dtype=float)
    if arr.shape != (3,):
        raise ValueError(f"{name} has shape {arr.shape}; expected (3,)")
    check_finite(arr, name)
    return arr


def as_rotation(R, name: str = "R", *, atol: float = 1e-6) -> np.ndarray:
    """A (3, 3) proper rotation matrix (orthonormal within ``atol``, det = +1)."""
    arr = np.asarray(R, dtype=float)
    if arr.shape != (3, 3):
        raise ValueError(f"{name} has shape {arr.shape}; expected (3, 3)")
    check_finite(arr, name)
    err = float(np.max(np.abs(arr.T @ arr - np.eye(3))))
    if err > atol:
        raise ValueError(f"{name} is not orthonormal: max |RᵀR − I| = {err:.3g} > {atol:g}")
    det = float(np.linalg.det(arr))
    if det < 0:
        raise ValueError(f"{name} has det {det:.6f}: a reflection, not a rotation "
                         "(a flipped axis, e.g. OpenCV's y-down image frame?)")
    return arr
