"""Small linear-algebra helpers shared by the fitting routines."""

from __future__ import annotations

import numpy as np


def svd_right(A) -> tuple[np.ndarray, np.ndarray]:
    """Singular values and the full ``Vᵀ`` (n × n) of an (m, n) matrix, without the m × m ``U``.

    ``np.linalg.svd(A)`` builds ``U`` with m² entries: 3.2 GB for the 2·10⁴ rows of a DLT
    with 10⁴ points. The economy SVD drops the null vector when m < n, so such a matrix is
    padded with zero rows first (its singular values then end in zeros).

    Examples
    --------
    >>> sv, Vt = svd_right([[1.0, 1.0, 0.0], [0.0, 1.0, 1.0]])  # null vector (1, −1, 1)/√3
    >>> sv.round(12).tolist(), (Vt[-1] / Vt[-1, 0]).round(12).tolist()
    ([1.732050807569, 1.0, 0.0], [1.0, -1.0, 1.0])
    """
    A = np.asarray(A, dtype=float)
    m, n = A.shape
    if m < n:
        A = np.vstack([A, np.zeros((n - m, n))])
    _, sv, Vt = np.linalg.svd(A, full_matrices=False)
    return sv, Vt
