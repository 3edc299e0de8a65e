"""Input checks shared by the numeric modules: shapes, finiteness, clear messages."""

from __future__ import annotations

import numbers

import numpy as np


def _brief(value, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters, for messages about large arguments."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def as_float_array(value, name: str, expected: str = "") -> np.ndarray:
    """``np.asarray(value, float)`` that names ``name`` when ``value`` is not real numeric.

    Complex input raises instead of silently losing its imaginary part (NumPy's
    ``ComplexWarning``); strings and other non-numbers raise ``ValueError`` quoting the bad
    value. ``expected`` (e.g. ``" with shape (N, 3) or (3,)"``) is added to the message.
    A float64 array is returned as it is (no copy).
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        return value
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric{expected}: {exc}") from None
    if arr.dtype.kind == "c":
        bad = arr[np.imag(arr) != 0].ravel()
        example = complex(bad[0]) if bad.size else complex(arr.ravel()[0]) if arr.size else ""
        raise ValueError(f"{name} must be real{expected}, got complex values (e.g. {example!r})")
    try:
        return arr.astype(float, copy=False)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric{expected}, {_non_numeric(arr, exc)}") from None


def _non_numeric(arr: np.ndarray, exc: Exception) -> str:
    """``"got 'abc' at index (0, 1)"``: the first entry of ``arr`` that is not a number."""
    for idx, x in np.ndenumerate(arr):
        x = x.item() if isinstance(x, np.generic) else x
        try:
            float(x)
        except (TypeError, ValueError):
            return f"got {_brief(x)}" + (f" at index {idx}" if idx else "")
    return f"got {_brief(arr)} ({exc})"  # pragma: no cover - every entry converts alone


def as_points(values, dim: int, name: str, *, finite: bool = True) -> tuple[np.ndarray, bool]:
    """Return ``(points (N, dim) float array, single)``; ``single`` if a (dim,) point was given.

    Raises ``ValueError`` naming ``name``, the shape and the first non-finite entry. With
    ``finite=False`` the caller checks finiteness itself (block by block, while the block is
    in the cache) and calls :func:`check_finite` on the whole array for the message.
    """
    arr = as_float_array(values, name, f" with shape (N, {dim}) or ({dim},)")
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
    arr = as_float_array(value, name)
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
    if getattr(getattr(value, "dtype", None), "kind", "") == "c":  # float() would drop the imag
        raise ValueError(f"{name} must be a real number, got {value!r}")
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
    arr = as_float_array(value, name, " with shape (3,)")
    if arr.shape != (3,):
        raise ValueError(f"{name} has shape {arr.shape}; expected (3,)")
    check_finite(arr, name)
    return arr


def as_rotation(R, name: str = "R", *, atol: float = 1e-6) -> np.ndarray:
    """A (3, 3) proper rotation matrix (orthonormal within ``atol``, det = +1)."""
    arr = as_float_array(R, name, " with shape (3, 3)")
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


def as_int(value, name: str, *, minimum: int | None = None) -> int:
    """An integer (an ``int``, a NumPy integer or an integral float such as ``30.0``).

    Booleans, strings, NaN and fractional numbers raise ``ValueError`` naming ``name``;
    with ``minimum`` the value must be ≥ it.
    """
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be an integer, got {_brief(value)}")
    if isinstance(value, numbers.Integral):
        v = int(value)
    else:
        f = float(value)
        if not (np.isfinite(f) and f == int(f)):
            raise ValueError(f"{name} must be an integer, got {value!r}")
        v = int(f)
    if minimum is not None and v < minimum:
        raise ValueError(f"{name} must be an integer ≥ {minimum}, got {value!r}")
    return v


def as_max_iter(value, name: str = "max_iter") -> int:
    """An iteration limit: an integer ≥ 1 (``max_iter=0`` would not compute anything)."""
    return as_int(value, name, minimum=1)


def as_tolerance(value, name: str = "tol") -> float:
    """A convergence tolerance: a finite float > 0 (NaN or a negative tol never stops)."""
    return as_scalar(value, name, positive=True)


def as_indices(value, name: str, size: int) -> np.ndarray:
    """Integer indices into a sequence of ``size`` items, any shape, as an ``intp`` array.

    Floats (which would be truncated), booleans and indices outside ``0 … size − 1``
    (negative ones too: no counting from the end) raise ``ValueError`` naming ``name`` and
    the first bad index. An empty sequence gives an empty array.
    """
    a = np.asarray(value)
    if a.size == 0:
        return a.astype(np.intp)
    if a.dtype.kind not in "iu":
        raise ValueError(f"{name} must hold integers, got dtype {a.dtype}")
    bad = (a < 0) | (a >= size)
    if bad.any():
        raise ValueError(f"{name} contains {int(a[bad].flat[0])}, outside 0 … {size - 1}")
    return a.astype(np.intp)
