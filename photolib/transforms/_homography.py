r"""Estimation of the projective transformation (homography) H from point pairs.

Two routes, both in normalised coordinates (each point set moved to centroid 0 and scaled):

* **Four pairs** determine H exactly, in closed form. With the homogeneous points
  :math:`\tilde s_i = (x_i, y_i, 1)` and the triangle determinants
  :math:`D(a, b, c) = \det[\tilde s_a, \tilde s_b, \tilde s_c]`, the point
  :math:`\tilde s_3 = \sum_{i<3} λ_i \tilde s_i` with :math:`λ_0 ∝ D(3, 1, 2)`,
  :math:`λ_1 ∝ D(0, 3, 2)`, :math:`λ_2 ∝ D(0, 1, 3)` (Cramer's rule), so
  :math:`B_s = [λ_0 \tilde s_0, λ_1 \tilde s_1, λ_2 \tilde s_2]` maps the unit points
  :math:`e_i` and :math:`(1, 1, 1)` onto the four src points. With the same :math:`μ_i` of
  dst, :math:`H ∝ B_d B_s^{-1}`, and because the rows of :math:`\operatorname{adj}[\tilde
  s_0, \tilde s_1, \tilde s_2]` are the lines :math:`\ell_0 = \tilde s_1 × \tilde s_2`,
  :math:`\ell_1 = \tilde s_2 × \tilde s_0`, :math:`\ell_2 = \tilde s_0 × \tilde s_1`,

  .. math:: H ∝ \sum_{i=0}^{2} \frac{μ_i}{λ_i}\, \tilde d_i\, \ell_i^T .

  The same four determinants decide whether three of the points are collinear: the
  scatter matrix of three points has :math:`\det S = D^2/3` and
  :math:`\operatorname{tr} S = \tfrac13 \sum |p_a - p_b|^2`.

* **More pairs**: the normalised DLT (the eigenvector of the smallest eigenvalue of
  :math:`A^TA`) starts a Gauss–Newton adjustment of the geometric residuals. Both normal
  matrices are sums of :math:`\tilde u \tilde u^T` (normalised src, 6 distinct products)
  weighted per point: with the rows :math:`[\tilde u, 0, -X \tilde u]/w` and
  :math:`[0, \tilde u, -Y \tilde u]/w` of the Jacobian,

  .. math::
      J^TJ = \begin{bmatrix} M_0 & 0 & -M_1 \\ 0 & M_0 & -M_2 \\ -M_1 & -M_2 & M_3
      \end{bmatrix},\quad M_k = \sum_n α_{k,n} \tilde u_n \tilde u_n^T,\quad
      α = \frac{1}{w^2}\,(1,\ X,\ Y,\ X^2 + Y^2)

  (:math:`w = 1` and the observed X, Y for the DLT's :math:`A^TA`), and
  :math:`J^Tr = \sum_n \tilde u_n \otimes (r_X, r_Y, -(X r_X + Y r_Y))/w`: one 4 × N by
  N × 6 product per iteration instead of a 2N × 9 Jacobian.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla

from photolib.transforms._base import DegenerateGeometryError

#: ratio σ_min/σ_max of a centred point set below which it counts as collinear
COLLINEAR = 1e-9
#: relative singular-value threshold below which a design matrix counts as rank deficient
#: (this DLT and the other transforms' least squares in ``_matrix.py``)
RANK_TOL = 1e-10
#: Gauss–Newton stops when the (predicted) remaining change of the unit vector h is below this
STEP_TOL = 1e-12

# the 9 × 9 normal matrix (and the 10 × 10 bordered one) as one gather from
# v = [moments (4, 6) | −moments (4, 6) | h (9) | 0]: entry (i, j) of a 3 × 3 block k
# is the product number SYM[i][j] of [x², xy, y², x, y, 1]
_SYM = ((0, 1, 3), (1, 2, 4), (3, 4, 5))
_BLOCKS = ((0, None, -1), (None, 0, -2), (-1, -2, 3))  # M0, 0, −M1 / 0, M0, −M2 / −M1, −M2, M3


def _gather_map(bordered: bool) -> np.ndarray:
    size = 10 if bordered else 9
    zero = 48 + 9
    out = np.full((size, size), zero)
    for bi, row in enumerate(_BLOCKS):
        for bj, blk in enumerate(row):
            if blk is None:
                continue
            base = 6 * blk if blk >= 0 else 24 + 6 * -blk
            for i in range(3):
                for j in range(3):
                    out[3 * bi + i, 3 * bj + j] = base + _SYM[i][j]
    if bordered:
        out[9, :9] = out[:9, 9] = 48 + np.arange(9)
    return out


_MAP9, _MAP10 = _gather_map(False), _gather_map(True)
_NO_H = np.zeros(10)


def _ratio_td(tr: float, det: float) -> float:
    """σ_min/σ_max of a centred point set from the trace and determinant of its 2 × 2
    scatter matrix (closed form of the eigenvalues); 0 for coincident points."""
    big = 0.5 * (tr + math.sqrt(max(tr * tr - 4.0 * det, 0.0)))
    return math.sqrt(max(det, 0.0)) / big if big > 0 else 0.0


def _ratio(a: float, b: float, c: float) -> float:
    """:func:`_ratio_td` from the scatter sums a = Σx², b = Σxy, c = Σy²."""
    return _ratio_td(a + c, a * c - b * b)


def _check_spread(which: str, name: str, a: float, b: float, c: float, n: int,
                  centroid, spread: float) -> float:
    """The RMS distance of a centred point set from its scatter sums, after the checks:
    ``DegenerateGeometryError`` if it is collinear (ratio < COLLINEAR) or coincident."""
    if _ratio(a, b, c) < COLLINEAR:
        raise DegenerateGeometryError(
            f"{name}: the {which} points are collinear; the transformation is not determined")
    rms = math.sqrt((a + c) / n)
    if rms <= 1e-12 * max(1.0, abs(centroid[0]), abs(centroid[1]), spread):
        raise DegenerateGeometryError("all points coincide; no transformation is determined")
    return rms


def _denormalise(Hn, cs, ss: float, cd, sd: float) -> list:
    """``H = T_d⁻¹ Hn T_s`` for the normalisations ``T = [[s, 0, −s·cx], [0, s, −s·cy],
    [0, 0, 1]]`` (3 × 3 as nested lists)."""
    g = [(ss * r[0], ss * r[1], r[2] - ss * (cs[0] * r[0] + cs[1] * r[1])) for r in Hn]
    w = g[2]
    return [[g[0][k] / sd + cd[0] * w[k] for k in range(3)],
            [g[1][k] / sd + cd[1] * w[k] for k in range(3)], list(w)]


# ------------------------------------------------------------------------------ four pairs
def _normalise4(p, which: str, name: str):
    """Four points (list of (x, y)) centred and scaled to RMS distance √2, with the
    checks of :func:`_check_spread`: the normalised points, the centroid and the scale."""
    (x0, y0), (x1, y1), (x2, y2), (x3, y3) = p
    cx, cy = 0.25 * (x0 + x1 + x2 + x3), 0.25 * (y0 + y1 + y2 + y3)
    x0, x1, x2, x3 = x0 - cx, x1 - cx, x2 - cx, x3 - cx
    y0, y1, y2, y3 = y0 - cy, y1 - cy, y2 - cy, y3 - cy
    a = x0 * x0 + x1 * x1 + x2 * x2 + x3 * x3
    b = x0 * y0 + x1 * y1 + x2 * y2 + x3 * y3
    c = y0 * y0 + y1 * y1 + y2 * y2 + y3 * y3
    spread = max(abs(x0), abs(x1), abs(x2), abs(x3), abs(y0), abs(y1), abs(y2), abs(y3))
    s = math.sqrt(2.0) / _check_spread(which, name, a, b, c, 4, (cx, cy), spread)
    return [(s * x0, s * y0), (s * x1, s * y1), (s * x2, s * y2), (s * x3, s * y3)], (cx, cy), s


#: the ordered triples of λ_0, λ_1, λ_2 and of det[s̃0, s̃1, s̃2]: triple k omits point k
_TRIPLE_ORDER = ((3, 1, 2), (0, 3, 2), (0, 1, 3), (0, 1, 2))


def _check_triples(p, which: str, name: str) -> list:
    """The determinants det[p̃_a, p̃_b, p̃_c] (twice the signed triangle areas) of the
    ``_TRIPLE_ORDER``, after the check that no three points are collinear: the ratio of
    :func:`_ratio_td` with det S = D²/3 and tr S = Σ|p_a − p_b|²/3 of each triple
    (``DegenerateGeometryError`` naming the first such three points)."""
    dets = []
    for a, b, c in _TRIPLE_ORDER:
        (xa, ya), (xb, yb), (xc, yc) = p[a], p[b], p[c]
        D = (xb - xa) * (yc - ya) - (xc - xa) * (yb - ya)
        tr = ((xb - xa) ** 2 + (yb - ya) ** 2 + (xc - xa) ** 2 + (yc - ya) ** 2
              + (xc - xb) ** 2 + (yc - yb) ** 2) / 3.0
        # ratio ≥ |D|/(√3·tr): the closed form only where that bound is not conclusive
        if abs(D) < 1.7320508075688772 * COLLINEAR * tr and _ratio_td(tr, D * D / 3.0) < COLLINEAR:
            i, j, m = sorted((a, b, c))
            raise DegenerateGeometryError(
                f"{name}: degenerate point geometry, three of the points collinear "
                f"({which} points {i}, {j}, {m}); with only four point pairs the 8 "
                "parameters are then not determined")
        dets.append(D)
    return dets


def four_point_homography(src: np.ndarray, dst: np.ndarray, name: str):
    """The exact H (3 × 3 nested lists, not scaled) of four point pairs (validated (4, 2)
    arrays), in closed form (the module's formula), and the residuals ``T(src) − dst``
    (4, 2), after the checks: neither set collinear, no three points of either set
    collinear (named)."""
    s_pts, d_pts = src.tolist(), dst.tolist()
    us, cs, ss = _normalise4(s_pts, "src", name)
    ud, cd, sd = _normalise4(d_pts, "dst", name)
    Ds, Dd = _check_triples(us, "src", name), _check_triples(ud, "dst", name)
    (x0, y0), (x1, y1), (x2, y2) = us[0], us[1], us[2]
    lines = ((y1 - y2, x2 - x1, x1 * y2 - x2 * y1),  # ℓ_0 = s̃_1 × s̃_2
             (y2 - y0, x0 - x2, x2 * y0 - x0 * y2),  # ℓ_1 = s̃_2 × s̃_0
             (y0 - y1, x1 - x0, x0 * y1 - x1 * y0))  # ℓ_2 = s̃_0 × s̃_1
    Hn = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    for (X, Y), (l0, l1, l2), ds, dd in zip(ud, lines, Ds, Dd):  # Σ c_i d̃_i ℓ_iᵀ
        c = dd / ds
        cX, cY = c * X, c * Y
        Hn[0][0] += cX * l0
        Hn[0][1] += cX * l1
        Hn[0][2] += cX * l2
        Hn[1][0] += cY * l0
        Hn[1][1] += cY * l1
        Hn[1][2] += cY * l2
        Hn[2][0] += c * l0
        Hn[2][1] += c * l1
        Hn[2][2] += c * l2
    H = _denormalise(Hn, cs, ss, cd, sd)
    (h0, h1, h2), (h3, h4, h5), (h6, h7, h8) = H
    res = []
    for (x, y), (X, Y) in zip(s_pts, d_pts):
        w = h6 * x + h7 * y + h8
        res.append(((h0 * x + h1 * y + h2) / w - X, (h3 * x + h4 * y + h5) / w - Y))
    return H, np.array(res)


# ------------------------------------------------------------------------------ more pairs
def _normalise_many(src, dst, name):
    """Both point sets centred and scaled to RMS distance √2, with the checks of
    :func:`_check_spread`: a (4, N) array of the rows x, y (src) and X, Y (dst), the
    centroids and the scales."""
    n = len(src)
    T = np.empty((4, n))
    T[:2], T[2:] = src.T, dst.T
    cen = T.sum(axis=1) / n
    T -= cen[:, None]
    S = (T @ T.T).tolist()  # the two 2 × 2 scatter matrices are its diagonal blocks
    scales = []
    for q, which in ((0, "src"), (2, "dst")):
        a, b, c = S[q][q], S[q][q + 1], S[q + 1][q + 1]
        rms = _check_spread(which, name, a, b, c, n, cen[q:q + 2], math.sqrt(a + c))
        scales.append(math.sqrt(2.0) / rms)
    T[:2] *= scales[0]
    T[2:] *= scales[1]
    cen = cen.tolist()
    return T, (cen[:2], cen[2:]), scales


def _dlt_start(R6, X, Y, name):
    """The normalised DLT: the unit eigenvector of the smallest eigenvalue of AᵀA (9 × 9,
    from the moments). If the two smallest are not well apart (ratio ≤ 1e-12: a rank
    question the squared matrix cannot answer), the SVD of the 2N × 9 A decides."""
    W = np.empty((4, len(X)))
    W[0], W[1], W[2] = 1.0, X, Y
    np.add(X * X, Y * Y, out=W[3])
    mom = (W @ R6.T).ravel()
    ev, V = np.linalg.eigh(np.concatenate((mom, -mom, _NO_H))[_MAP9])
    if ev[1] > 1e-12 * ev[8]:
        return V[:, 0]
    x, y = R6[3], R6[4]
    A = np.zeros((2 * len(X), 9))
    A[0::2, 0], A[0::2, 1], A[0::2, 2] = x, y, 1.0
    A[1::2, 3], A[1::2, 4], A[1::2, 5] = x, y, 1.0
    A[0::2, 6], A[0::2, 7], A[0::2, 8] = -X * x, -X * y, -X
    A[1::2, 6], A[1::2, 7], A[1::2, 8] = -Y * x, -Y * y, -Y
    sv, Vt = np.linalg.svd(np.linalg.qr(A, mode="r"))[1:]
    if sv[7] <= RANK_TOL * sv[0]:
        raise DegenerateGeometryError(
            f"{name}: degenerate point geometry (three of the points collinear?); "
            "the 8 parameters are not determined")
    return Vt[-1]


def _images(h, uh):
    """``T_h(u)`` (rows X, Y) and w of the normalised src (rows x, y, 1 of ``uh``)."""
    P = h.reshape(3, 3) @ uh
    return P[0] / P[2], P[1] / P[2], P[2]


def _check_finite_images(h, w, uh, src, name):
    """``DegenerateGeometryError`` naming the first src point that h maps to infinity
    (``|w| ≤ 1e-12·(|h7 x| + |h8 y| + |h9|)``)."""
    x, y = uh[0], uh[1]
    at_infinity = ~(np.abs(w) > 1e-12 * (abs(h[6]) * np.abs(x) + abs(h[7]) * np.abs(y)
                                         + abs(h[8])))
    if at_infinity.any():
        k = int(np.flatnonzero(at_infinity)[0])
        raise DegenerateGeometryError(
            f"{name}: the linear solution maps src point {k} {src[k].tolist()} to "
            "infinity (denominator w = 0): the point geometry is degenerate (e.g. three "
            "points collinear in src but not in dst, or the other way round)")


def _gauss_newton(h, R6, X, Y, src, max_iter, name):
    """Gauss–Newton on the geometric residuals in normalised units: the bordered normal
    equations ``[[JᵀJ, h], [hᵀ, 0]] [dh, λ] = [−Jᵀr, 0]`` (minimum-norm steps, h kept at
    unit norm) from the module's moments (one (7, N) × (N, 6) product: the four weights of
    JᵀJ and the three of Jᵀr). Stops when ‖dh‖ ≤ STEP_TOL or when the steps shrink by
    ρ < 1 and the predicted rest ‖dh‖·ρ/(1 − ρ) is ≤ STEP_TOL. The start h must not send a
    src point to infinity (checked: :func:`_check_finite_images`)."""
    uh = R6[3:]
    WC = np.empty((7, len(X)))
    bordered = np.zeros(10)
    last = None
    _check_finite_images(h, h[6:] @ uh, uh, src, name)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # checked: mom[5]
        for _ in range(max_iter):
            Xp, Yp, w = _images(h, uh)
            iw = 1.0 / w
            rX, rY = Xp - X, Yp - Y
            np.multiply(iw, iw, out=WC[0])
            np.multiply(WC[0], Xp, out=WC[1])
            np.multiply(WC[0], Yp, out=WC[2])
            np.multiply(WC[0], Xp * Xp + Yp * Yp, out=WC[3])
            np.multiply(rX, iw, out=WC[4])
            np.multiply(rY, iw, out=WC[5])
            np.multiply(Xp * rX + Yp * rY, -iw, out=WC[6])
            prod = WC @ R6.T  # (7, 6): moments of JᵀJ, then Jᵀr in the columns x, y, 1
            mom = prod[:4].ravel()
            bordered[:9] = -prod[4:, 3:].ravel()
            if not math.isfinite(mom[5]):  # Σ 1/w²: a point at (or near) infinity
                raise DegenerateGeometryError(
                    f"{name}: the adjustment sends a src point to infinity (w = 0); the "
                    "point geometry does not determine a projective transformation")
            K = np.concatenate((mom, -mom, h, (0.0,)))[_MAP10]
            *_, sol, info = sla.lapack.dsysv(K, bordered)
            if info:
                raise DegenerateGeometryError(
                    f"{name}: the normal equations are singular (LAPACK dsysv info {info}); "
                    "the point geometry does not determine a projective transformation")
            dh = sol[:9]
            h = h + dh
            h /= math.sqrt(h @ h)
            step = math.sqrt(dh @ dh)
            if not math.isfinite(step):
                raise DegenerateGeometryError(
                    f"{name}: the adjustment diverged (non-finite step); the point geometry "
                    "does not determine a projective transformation")
            if step <= STEP_TOL:
                break
            if last is not None and step < last and step * step / (last - step) <= STEP_TOL:
                break
            last = step
    return h


def many_point_homography(src: np.ndarray, dst: np.ndarray, max_iter: int, name: str):
    """The least-squares H (3 × 3, not scaled) of N > 4 point pairs (validated arrays) and
    the residuals ``T(src) − dst`` (N, 2) in dst units: normalised DLT, then Gauss–Newton
    (the module's formulas). ``DegenerateGeometryError`` for collinear sets, a rank-deficient
    DLT and a solution that sends a point to infinity."""
    T, (cs, cd), (ss, sd) = _normalise_many(src, dst, name)
    x, y, X, Y = T
    R6 = np.empty((6, len(x)))
    np.multiply(x, x, out=R6[0])
    np.multiply(x, y, out=R6[1])
    np.multiply(y, y, out=R6[2])
    R6[3], R6[4], R6[5] = x, y, 1.0
    h = _dlt_start(R6, X, Y, name)
    h = _gauss_newton(h, R6, X, Y, src, max_iter, name)
    Xp, Yp, _ = _images(h, R6[3:])
    residuals = np.empty((len(x), 2))
    residuals[:, 0], residuals[:, 1] = Xp - X, Yp - Y
    residuals /= sd
    return _denormalise(h.reshape(3, 3).tolist(), cs, ss, cd, sd), residuals
