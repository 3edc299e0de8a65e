"""The cross ratio of four points on a line (Luhmann 2.21, corrected)."""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array

__all__ = ["cross_ratio"]


def _as_line_coordinates(a, b, c, d, atol):
    pts = [as_float_array(p, name) for p, name in zip((a, b, c, d), "abcd")]
    shapes = {p.shape for p in pts}
    if len(shapes) != 1:
        raise ValueError(f"a, b, c, d must have the same shape, got {[p.shape for p in pts]}")
    shape = shapes.pop()
    for name, p in zip("abcd", pts):
        if not np.all(np.isfinite(p)):
            raise ValueError(f"{name} contains a non-finite value: {p!r}")
    if shape == ():
        return np.array([float(p) for p in pts])
    if shape not in ((2,), (3,)):
        raise ValueError(f"points have shape {shape}; expected scalars, (2,) or (3,)")
    P = np.stack(pts)
    centred = P - P.mean(axis=0)
    _, sv, Vt = np.linalg.svd(centred)
    if sv[0] == 0.0:
        raise ValueError("the four points coincide")
    off_line = float(np.max(np.abs(centred @ Vt[1:].T)))
    if off_line > atol * sv[0]:
        raise ValueError(f"the points are not collinear: largest distance from the fitted line "
                         f"{off_line:.3g} exceeds {atol:g} × their spread")
    return centred @ Vt[0]


def cross_ratio(a, b, c, d, *, atol: float = 1e-9) -> float:
    r"""Cross ratio of four collinear points A, B, C, D (Luhmann 2.21 as corrected).

    .. math::
        λ = \frac{\overline{AB}}{\overline{BC}} \div \frac{\overline{AD}}{\overline{CD}}
          = \frac{(b - a)(d - c)}{(c - b)(d - a)}

    with signed segments :math:`\overline{PQ} = q - p` measured along the line. λ is
    invariant under every projective map of the line (central projection, 1-D
    homography). It equals :math:`(A, B; C, D) - 1` of the classical cross ratio
    :math:`(A, B; C, D) = \overline{AC}\,\overline{BD} / (\overline{BC}\,\overline{AD})`;
    the printed, uncorrected 2.21 is :math:`1/(A, B; C, D)`, also invariant but another value.

    Parameters
    ----------
    a, b, c, d : float or array_like, shape (2,) or (3,)
        Positions on the line (scalars), or collinear 2-D/3-D points (any length unit).
    atol : float
        Collinearity tolerance relative to the spread of the points.

    Returns
    -------
    float
        λ (dimensionless). Raises ``ValueError`` if the points are not collinear or if
        B = C or A = D (a zero denominator).

    Examples
    --------
    >>> cross_ratio(0.0, 1.0, 2.0, 3.0)
    0.3333333333333333
    >>> cross_ratio([0, 0], [1, 1], [2, 2], [3, 3])  # same points on a diagonal
    0.3333333333333333
    """
    t = _as_line_coordinates(a, b, c, d, atol)
    ta, tb, tc, td = t
    spread = float(np.ptp(t))
    for name, length in (("BC", tc - tb), ("AD", td - ta)):
        if abs(length) <= 1e-15 * max(spread, 1e-300):
            raise ValueError(f"segment {name} has zero length; the cross ratio is undefined")
    return float(((tb - ta) * (td - tc)) / ((tc - tb) * (td - ta)))
