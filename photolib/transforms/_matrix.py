"""Helmert, affine and projective plane transformations: the homogeneous-matrix family.

All three are ``(X, Y, 1)ᵀ ∝ H·(x, y, 1)ᵀ`` with a 3×3 matrix ``H``; they have closed-form
inverses and composition is the matrix product (the result takes the more general class).
"""

from __future__ import annotations

import math

import numpy as np

from photolib._validate import as_max_iter, as_scalar
from photolib.transforms._homography import (
    RANK_TOL,
    four_point_homography,
    many_point_homography,
)
from photolib.transforms._base import (
    DegenerateGeometryError,
    PlaneTransform,
    check_pairs,
    collinearity_ratio,
    hartley_normalisation,
)

__all__ = ["AffineTransform", "HelmertTransform", "ProjectiveTransform"]



def _norm_matrix(centroid, scale) -> np.ndarray:
    """Homogeneous matrix of ``p ↦ scale·(p − centroid)``."""
    return np.array([[scale, 0.0, -scale * centroid[0]],
                     [0.0, scale, -scale * centroid[1]],
                     [0.0, 0.0, 1.0]])


def _check_not_collinear(points, name, cls):
    if len(points) >= 3 and collinearity_ratio(points) < 1e-9:
        raise DegenerateGeometryError(
            f"{cls}: the {name} points are collinear; the transformation is not determined")


def _solve(A, b, cls):
    """Least-squares solution of ``A·x = b`` with a rank check naming the class."""
    sv = np.linalg.svd(A, compute_uv=False)
    if sv[-1] <= RANK_TOL * sv[0]:
        raise DegenerateGeometryError(
            f"{cls}: degenerate point geometry (design matrix has condition "
            f"{sv[0] / max(sv[-1], 1e-300):.3g}); the parameters are not determined")
    return np.linalg.lstsq(A, b, rcond=None)[0]


class _MatrixTransform(PlaneTransform):
    _rank = 0  # 0 Helmert, 1 affine, 2 projective: the class of a composition is the max

    @property
    def matrix(self) -> np.ndarray:
        """The homogeneous 3×3 matrix ``H`` with ``(X, Y, 1)ᵀ ∝ H·(x, y, 1)ᵀ``."""
        raise NotImplementedError  # pragma: no cover

    def _forward(self, p):
        H = self.matrix
        return p @ H[:2, :2].T + H[:2, 2]

    def _jacobian(self, p):
        return np.broadcast_to(self.matrix[:2, :2], (len(p), 2, 2)).copy()

    def _compose(self, first):
        if not isinstance(first, _MatrixTransform):
            return None
        cls = max(type(self), type(first), key=lambda c: c._rank)
        return cls._from_matrix(self.matrix @ first.matrix)

    @classmethod
    def _from_matrix(cls, H):  # pragma: no cover - abstract
        raise NotImplementedError


class HelmertTransform(_MatrixTransform):
    r"""4-parameter similarity (Helmert) transformation: shift, rotation, uniform scale.

    .. math::
        X = a_0 + a_1 x - b_1 y, \qquad Y = b_0 + b_1 x + a_1 y,

    with :math:`a_1 = m\cos α`, :math:`b_1 = m\sin α` (scale m, rotation α counter-clockwise
    with x right and y up). The Polish exercise notes write the rotation with the opposite
    sign of :math:`b_1`. ``a0, b0`` are in destination units, ``a1, b1`` destination per
    source unit.

    Parameters
    ----------
    a0, b0 : float
        Shift.
    a1, b1 : float
        Scaled cosine and sine of the rotation angle.

    Examples
    --------
    >>> t = HelmertTransform(a0=10.0, b0=0.0, a1=0.0, b1=2.0)   # 90°, scale 2
    >>> t([1.0, 0.0]).tolist()
    [10.0, 2.0]
    >>> round(t.scale, 12), round(float(np.degrees(t.rotation)), 12)
    (2.0, 90.0)
    >>> src = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> est = HelmertTransform.from_estimate(src, t(src))
    >>> {k: round(v, 12) + 0.0 for k, v in est.params.items()}
    {'a0': 10.0, 'b0': 0.0, 'a1': 0.0, 'b1': 2.0}
    """

    n_params = 4
    _rank = 0

    def __init__(self, a0=0.0, b0=0.0, a1=1.0, b1=0.0):
        self.a0, self.b0 = as_scalar(a0, "a0"), as_scalar(b0, "b0")
        self.a1, self.b1 = as_scalar(a1, "a1"), as_scalar(b1, "b1")

    @property
    def params(self) -> dict[str, float]:
        """``{'a0', 'b0', 'a1', 'b1'}``."""
        return {"a0": self.a0, "b0": self.b0, "a1": self.a1, "b1": self.b1}

    @property
    def scale(self) -> float:
        """Scale factor ``m = sqrt(a1² + b1²)``."""
        return float(np.hypot(self.a1, self.b1))

    @property
    def rotation(self) -> float:
        """Rotation angle ``α = atan2(b1, a1)``, radians."""
        return float(np.arctan2(self.b1, self.a1))

    @property
    def matrix(self):
        return np.array([[self.a1, -self.b1, self.a0], [self.b1, self.a1, self.b0], [0, 0, 1.0]])

    @classmethod
    def _from_matrix(cls, H):
        return cls(a0=H[0, 2], b0=H[1, 2], a1=H[0, 0], b1=H[1, 0])

    @property
    def inverse(self) -> HelmertTransform:
        """Closed form: ``x = (a1(X − a0) + b1(Y − b0))/m²``, ``y = (a1(Y − b0) − b1(X − a0))/m²``."""
        m2 = self.a1**2 + self.b1**2
        if m2 == 0.0:
            raise ValueError("HelmertTransform with a1 = b1 = 0 (scale 0) has no inverse")
        a1, b1 = self.a1 / m2, -self.b1 / m2
        return HelmertTransform(a0=-(a1 * self.a0 - b1 * self.b0), b0=-(b1 * self.a0 + a1 * self.b0),
                                a1=a1, b1=b1)

    @classmethod
    def from_estimate(cls, src, dst) -> HelmertTransform:
        """Least-squares estimate from ≥ 2 point pairs ``src`` (N, 2) → ``dst`` (N, 2).

        Points are normalised (centroid to 0, mean distance √2) before the linear least
        squares; residuals ``T(src) − dst``, ``sigma0`` and ``redundancy = 2N − 4`` are stored.
        """
        src, dst = check_pairs(src, dst, 2, cls.__name__)
        cs, ss = hartley_normalisation(src)
        cd, sd = hartley_normalisation(dst)
        u, U = ss * (src - cs), sd * (dst - cd)
        n = len(u)
        A = np.zeros((2 * n, 4))
        A[0::2] = np.column_stack([np.ones(n), np.zeros(n), u[:, 0], -u[:, 1]])
        A[1::2] = np.column_stack([np.zeros(n), np.ones(n), u[:, 1], u[:, 0]])
        a0, b0, a1, b1 = _solve(A, U.reshape(-1), cls.__name__)
        Hn = np.array([[a1, -b1, a0], [b1, a1, b0], [0, 0, 1.0]])
        out = cls._from_matrix(np.linalg.inv(_norm_matrix(cd, sd)) @ Hn @ _norm_matrix(cs, ss))
        out._set_fit(src, dst)
        return out


class AffineTransform(_MatrixTransform):
    r"""6-parameter affine transformation.

    .. math::
        X = a_0 + a_1 x + a_2 y, \qquad Y = b_0 + b_1 x + b_2 y

    ``a0, b0`` in destination units, the others destination per source unit.

    Examples
    --------
    >>> t = AffineTransform(a0=1.0, a1=2.0, a2=0.5, b0=-1.0, b1=0.0, b2=3.0)
    >>> t([[1.0, 1.0]]).tolist()
    [[3.5, 2.0]]
    >>> np.round(t.inverse(t([[1.0, 1.0]])), 12).tolist()
    [[1.0, 1.0]]
    """

    n_params = 6
    _rank = 1

    def __init__(self, a0=0.0, a1=1.0, a2=0.0, b0=0.0, b1=0.0, b2=1.0):
        names = ("a0", "a1", "a2", "b0", "b1", "b2")
        for k, v in zip(names, (a0, a1, a2, b0, b1, b2)):
            setattr(self, k, as_scalar(v, k))

    @property
    def params(self) -> dict[str, float]:
        """``{'a0', 'a1', 'a2', 'b0', 'b1', 'b2'}``."""
        return {k: getattr(self, k) for k in ("a0", "a1", "a2", "b0", "b1", "b2")}

    @property
    def matrix(self):
        return np.array([[self.a1, self.a2, self.a0], [self.b1, self.b2, self.b0], [0, 0, 1.0]])

    @classmethod
    def _from_matrix(cls, H):
        return cls(a0=H[0, 2], a1=H[0, 0], a2=H[0, 1], b0=H[1, 2], b1=H[1, 0], b2=H[1, 1])

    @property
    def inverse(self) -> AffineTransform:
        r"""Closed form with :math:`D = a_1 b_2 - a_2 b_1`:
        :math:`x = (b_2 (X - a_0) - a_2 (Y - b_0))/D`, :math:`y = (a_1 (Y - b_0) - b_1 (X - a_0))/D`."""
        D = self.a1 * self.b2 - self.a2 * self.b1
        if D == 0.0:
            raise ValueError("AffineTransform is singular (a1·b2 − a2·b1 = 0); it has no inverse")
        a1, a2, b1, b2 = self.b2 / D, -self.a2 / D, -self.b1 / D, self.a1 / D
        return AffineTransform(a0=-(a1 * self.a0 + a2 * self.b0), a1=a1, a2=a2,
                               b0=-(b1 * self.a0 + b2 * self.b0), b1=b1, b2=b2)

    @classmethod
    def from_estimate(cls, src, dst) -> AffineTransform:
        """Least-squares estimate from ≥ 3 non-collinear point pairs (normalised first)."""
        src, dst = check_pairs(src, dst, 3, cls.__name__)
        _check_not_collinear(src, "src", cls.__name__)
        _check_not_collinear(dst, "dst", cls.__name__)
        cs, ss = hartley_normalisation(src)
        cd, sd = hartley_normalisation(dst)
        u, U = ss * (src - cs), sd * (dst - cd)
        A = np.column_stack([np.ones(len(u)), u])
        (a0, b0), (a1, b1), (a2, b2) = _solve(A, U, cls.__name__)
        Hn = np.array([[a1, a2, a0], [b1, b2, b0], [0, 0, 1.0]])
        out = cls._from_matrix(np.linalg.inv(_norm_matrix(cd, sd)) @ Hn @ _norm_matrix(cs, ss))
        out._set_fit(src, dst)
        return out


class ProjectiveTransform(_MatrixTransform):
    r"""8-parameter projective transformation (Luhmann 2.18).

    .. math::
        X = \frac{a_0 + a_1 x + a_2 y}{1 + c_1 x + c_2 y}, \qquad
        Y = \frac{b_0 + b_1 x + b_2 y}{1 + c_1 x + c_2 y}

    Units: ``a0, b0`` destination units; ``a1, a2, b1, b2`` destination per source unit;
    ``c1, c2`` per source unit. The homogeneous matrix is
    ``H = [[a1, a2, a0], [b1, b2, b0], [c1, c2, 1]]``. Points on the vanishing line
    ``1 + c1·x + c2·y = 0`` are mapped to infinity and raise ``ValueError``.

    Examples
    --------
    >>> src = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> dst = np.array([[0.0, 0.0], [2.0, 0.0], [1.5, 1.0], [0.5, 1.0]])
    >>> t = ProjectiveTransform.from_estimate(src, dst)
    >>> np.round(t(src), 12).tolist() == dst.tolist()
    True
    >>> round(t.params["c2"], 12)  # (1 + c2)·0.5 = a2 and (a1 + a2)/(1 + c2) = 1.5 with a1 = 2
    1.0
    """

    n_params = 8
    _rank = 2
    _names = ("a0", "a1", "a2", "b0", "b1", "b2", "c1", "c2")

    def __init__(self, a0=0.0, a1=1.0, a2=0.0, b0=0.0, b1=0.0, b2=1.0, c1=0.0, c2=0.0):
        for k, v in zip(self._names, (a0, a1, a2, b0, b1, b2, c1, c2)):
            setattr(self, k, as_scalar(v, k))

    @property
    def params(self) -> dict[str, float]:
        """``{'a0', 'a1', 'a2', 'b0', 'b1', 'b2', 'c1', 'c2'}``."""
        return {k: getattr(self, k) for k in self._names}

    @property
    def matrix(self):
        return np.array([[self.a1, self.a2, self.a0], [self.b1, self.b2, self.b0],
                         [self.c1, self.c2, 1.0]])

    @classmethod
    def _from_matrix(cls, H):
        """From a finite 3 × 3 H (array or nested lists), scaled to h33 = 1; ``None`` if
        h33 = 0 (the src origin maps to infinity: not in Luhmann's form)."""
        (a1, a2, a0), (b1, b2, b0), (c1, c2, h33) = H.tolist() if hasattr(H, "tolist") else H
        if abs(h33) <= 1e-12 * max(abs(a1), abs(a2), abs(a0), abs(b1), abs(b2), abs(b0),
                                   abs(c1), abs(c2), abs(h33)):
            return None  # compose generically
        out = cls.__new__(cls)  # the values are finite floats: no re-validation
        for k, v in zip(cls._names, (a0, a1, a2, b0, b1, b2, c1, c2)):
            setattr(out, k, v / h33)
        return out

    def _denominator(self, p):
        w = 1.0 + self.c1 * p[:, 0] + self.c2 * p[:, 1]
        scale = 1.0 + np.abs(self.c1 * p[:, 0]) + np.abs(self.c2 * p[:, 1])
        bad = np.abs(w) <= 1e-14 * scale
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"point {i} {p[i].tolist()} lies on the vanishing line "
                             f"1 + c1·x + c2·y = 0 and maps to infinity")
        return w

    def _forward(self, p):
        w = self._denominator(p)
        X = (self.a0 + self.a1 * p[:, 0] + self.a2 * p[:, 1]) / w
        Y = (self.b0 + self.b1 * p[:, 0] + self.b2 * p[:, 1]) / w
        return np.column_stack([X, Y])

    def _jacobian(self, p):
        w = self._denominator(p)
        XY = self._forward(p)
        J = np.empty((len(p), 2, 2))
        J[:, 0, 0] = (self.a1 - XY[:, 0] * self.c1) / w
        J[:, 0, 1] = (self.a2 - XY[:, 0] * self.c2) / w
        J[:, 1, 0] = (self.b1 - XY[:, 1] * self.c1) / w
        J[:, 1, 1] = (self.b2 - XY[:, 1] * self.c2) / w
        return J

    @property
    def inverse(self) -> ProjectiveTransform:
        r"""The inverse, again projective (Luhmann 2.19/2.20 as corrected in the errata).

        With :math:`D = a_1 b_2 - a_2 b_1` (the parameters are the adjugate of H divided by D):

        .. math::
            a'_0 = \frac{a_2 b_0 - a_0 b_2}{D},\; a'_1 = \frac{b_2 - b_0 c_2}{D},\;
            a'_2 = \frac{a_0 c_2 - a_2}{D},\;
            b'_0 = \frac{a_0 b_1 - a_1 b_0}{D},\; b'_1 = \frac{b_0 c_1 - b_1}{D},\;
            b'_2 = \frac{a_1 - a_0 c_1}{D},\;
            c'_1 = \frac{b_1 c_2 - b_2 c_1}{D},\; c'_2 = \frac{a_2 c_1 - a_1 c_2}{D}

        Raises ``ValueError`` if ``det H = 0`` (singular) or ``D = 0`` (the destination
        origin is the image of the source's line at infinity, so the inverse has no
        denominator ``1 + …``).
        """
        a0, a1, a2, b0, b1, b2, c1, c2 = (getattr(self, k) for k in self._names)
        det = a1 * (b2 - b0 * c2) - a2 * (b1 - b0 * c1) + a0 * (b1 * c2 - b2 * c1)
        size = max(1.0, float(np.abs(self.matrix).max())) ** 3
        if abs(det) <= 1e-14 * size:
            raise ValueError(f"ProjectiveTransform is singular (det H = {det:.3g}); no inverse")
        D = a1 * b2 - a2 * b1
        if abs(D) <= 1e-14 * size:
            raise ValueError("inverse not representable in the form of Luhmann 2.18: "
                             f"a1·b2 − a2·b1 = {D:.3g} (dst origin maps to infinity)")
        return ProjectiveTransform(
            a0=(a2 * b0 - a0 * b2) / D, a1=(b2 - b0 * c2) / D, a2=(a0 * c2 - a2) / D,
            b0=(a0 * b1 - a1 * b0) / D, b1=(b0 * c1 - b1) / D, b2=(a1 - a0 * c1) / D,
            c1=(b1 * c2 - b2 * c1) / D, c2=(a2 * c1 - a1 * c2) / D)

    @classmethod
    def from_estimate(cls, src, dst, max_iter: int = 20) -> ProjectiveTransform:
        r"""Least-squares estimate from ≥ 4 point pairs, no three of four collinear.

        Both point sets are normalised (centroid 0, RMS distance √2). Four pairs determine
        H exactly, in closed form from the four triangle determinants of each set
        (:mod:`photolib.transforms._homography`). With more pairs the normalised DLT (the
        eigenvector of the smallest eigenvalue of AᵀA) starts a Gauss–Newton adjustment of
        the observation equations 2.18 (residuals in dst, minimum-norm steps ``hᵀdh = 0``,
        the 9 × 9 normal equations from per-point weighted moments), until the change of
        the unit vector h is below 1e-12 (or ``max_iter`` steps), so the result minimises
        ``Σ|T(src) − dst|²``:

        .. math:: X = \frac{h_1 x + h_2 y + h_3}{h_7 x + h_8 y + h_9},\quad
                  Y = \frac{h_4 x + h_5 y + h_6}{h_7 x + h_8 y + h_9}

        Raises :class:`DegenerateGeometryError` for collinear points (all of them, or three
        of four, naming them) and for a solution that sends a point to infinity.
        """
        src, dst = check_pairs(src, dst, 4, cls.__name__)
        name = cls.__name__
        if len(src) == 4:
            H, residuals = four_point_homography(src, dst, name)
        else:
            H, residuals = many_point_homography(src, dst, as_max_iter(max_iter), name)
        if not math.isfinite(sum(map(sum, H))):
            raise DegenerateGeometryError(f"{name}: the estimate is not finite; the point "
                                          "geometry does not determine the transformation")
        out = cls._from_matrix(H)
        if out is None:
            raise DegenerateGeometryError(
                "the estimated homography maps the src origin to infinity, which the form of "
                "Luhmann 2.18 (denominator 1 + c1·x + c2·y) cannot express; shift the src origin")
        out._set_fit(src, dst, residuals)
        return out
