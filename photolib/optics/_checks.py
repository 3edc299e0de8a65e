"""Input checks and output conversion shared by the modules of :mod:`photolib.optics`.

``_array`` is :func:`photolib._validate.as_array` with infinite values allowed,
``_finite`` rejects infinite values, ``_out`` returns a float for a 0-d result and the
array otherwise, so each function accepts scalars or arrays and broadcasts.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_array


def _array(value, name: str, *, positive: bool = False, nonnegative: bool = False):
    # optics takes infinite distances (an object at infinity), so only NaN is refused here
    return as_array(value, name, positive=positive, nonnegative=nonnegative, finite=False)


def _finite(arr: np.ndarray, name: str) -> np.ndarray:
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {float(arr[~np.isfinite(arr)].ravel()[0])!r}")
    return arr


def _out(value):
    value = np.asarray(value, dtype=float)
    return float(value) if value.ndim == 0 else value
