"""Bilinear and polynomial plane transformations: linear in their parameters, no closed inverse."""

from __future__ import annotations

from math import comb

import numpy as np

from photolib._validate import as_scalar
from photolib.transforms._base import (
    NewtonInverse,
    PlaneTransform,
    check_pairs,
    hartley_normalisation,
)
from photolib.transforms._matrix import _check_not_collinear, _solve

__all__ = ["BilinearTransform", "PolynomialTransform"]


class _BasisTransform(PlaneTransform):
    """``X = Σ a_ij x^i y^j``, ``Y = Σ b_ij x^i y^j`` over a fixed list of exponents (i, j).

    The exponent list must be closed under lowering an exponent, so that the function space
    is invariant under shifting and scaling the source points (needed to undo normalisation).
    """

    exponents: tuple[tuple[int, int], ...] = ()

    def _set_coefficients(self, a, b):
        k = len(self.exponents)
        a = np.asarray(a, dtype=float).reshape(-1)
        b = np.asarray(b, dtype=float).reshape(-1)
        for name, c in (("a", a), ("b", b)):
            if c.shape != (k,):
                raise ValueError(f"{name} has {c.size} coefficients; expected {k} "
                                 f"for exponents {list(self.exponents)}")
            for i, v in enumerate(c):
                as_scalar(v, f"{name}[{i}]")
        self.a, self.b = a, b
        self.n_params = 2 * k

    def _basis(self, p):
        return np.column_stack([p[:, 0] ** i * p[:, 1] ** j for i, j in self.exponents])

    def _forward(self, p):
        B = self._basis(p)
        return np.column_stack([B @ self.a, B @ self.b])

    def _jacobian(self, p):
        x, y = p[:, 0], p[:, 1]
        dx = np.column_stack([i * x ** max(i - 1, 0) * y**j for i, j in self.exponents])
        dy = np.column_stack([j * x**i * y ** max(j - 1, 0) for i, j in self.exponents])
        J = np.empty((len(p), 2, 2))
        J[:, 0, 0], J[:, 0, 1] = dx @ self.a, dy @ self.a
        J[:, 1, 0], J[:, 1, 1] = dx @ self.b, dy @ self.b
        return J

    def _names(self, letter):
        raise NotImplementedError  # pragma: no cover

    @property
    def params(self) -> dict[str, float]:
        """Coefficients named ``a…`` (for X) and ``b…`` (for Y)."""
        out = dict(zip(self._names("a"), map(float, self.a)))
        out.update(zip(self._names("b"), map(float, self.b)))
        return out

    def inverse_with(self, tol: float = 1e-12, max_iter: int = 50) -> NewtonInverse:
        """Iterative (Newton) inverse with a chosen tolerance and iteration limit."""
        return NewtonInverse(self, tol=tol, max_iter=max_iter)

    @property
    def inverse(self) -> NewtonInverse:
        """Iterative Newton inverse (tolerance 1e-12 relative, 50 iterations); see
        :class:`~photolib.transforms.NewtonInverse`. Raises ``ConvergenceError`` on failure."""
        return NewtonInverse(self)

    def _raw_from_normalised(self, cs, ss):
        """Matrix M with ``coef_raw = M @ coef_norm`` for the basis in ``u = ss·(x − cs)``."""
        idx = {e: k for k, e in enumerate(self.exponents)}
        M = np.zeros((len(idx), len(idx)))
        for col, (i, j) in enumerate(self.exponents):
            # (ss(x − cx))^i (ss(y − cy))^j = ss^(i+j) Σ C(i,k) x^k (−cx)^(i−k) Σ C(j,l) y^l (−cy)^(j−l)
            for k in range(i + 1):
                for m in range(j + 1):
                    M[idx[(k, m)], col] += (ss ** (i + j) * comb(i, k) * (-cs[0]) ** (i - k)
                                            * comb(j, m) * (-cs[1]) ** (j - m))
        return M

    def _estimate(self, src, dst):
        src, dst = check_pairs(src, dst, len(self.exponents), type(self).__name__)
        _check_not_collinear(src, "src", type(self).__name__)
        _check_not_collinear(dst, "dst", type(self).__name__)
        cs, ss = hartley_normalisation(src)
        cd, sd = hartley_normalisation(dst)
        u, U = ss * (src - cs), sd * (dst - cd)
        coef = _solve(self._basis(u), U, type(self).__name__)  # (k, 2)
        raw = self._raw_from_normalised(cs, ss) @ coef / sd
        raw[self.exponents.index((0, 0))] += cd
        self._set_coefficients(raw[:, 0], raw[:, 1])
        self._set_fit(src, dst)
        return self


class BilinearTransform(_BasisTransform):
    r"""8-parameter bilinear transformation.

    .. math::
        X = a_0 + a_1 x + a_2 y + a_3 x y, \qquad Y = b_0 + b_1 x + b_2 y + b_3 x y

    ``a0, b0`` destination units; ``a1, a2, b1, b2`` destination per source unit;
    ``a3, b3`` destination per source unit². The inverse is iterative (Newton).

    Examples
    --------
    >>> t = BilinearTransform(a0=1.0, a3=0.1, b2=2.0)
    >>> t([2.0, 3.0]).tolist()
    [3.6, 6.0]
    >>> np.round(t.inverse([3.6, 6.0]), 12).tolist()
    [2.0, 3.0]
    """

    exponents = ((0, 0), (1, 0), (0, 1), (1, 1))

    def __init__(self, a0=0.0, a1=1.0, a2=0.0, a3=0.0, b0=0.0, b1=0.0, b2=1.0, b3=0.0):
        self._set_coefficients([a0, a1, a2, a3], [b0, b1, b2, b3])

    def _names(self, letter):
        return [f"{letter}{k}" for k in range(4)]

    @classmethod
    def from_estimate(cls, src, dst) -> BilinearTransform:
        """Least-squares estimate from ≥ 4 point pairs (normalised first); ``r = 2N − 8``."""
        return cls()._estimate(src, dst)


class PolynomialTransform(_BasisTransform):
    r"""Polynomial transformation of total degree ``order``.

    .. math::
        X = \sum_{i + j \le n} a_{ij}\, x^i y^j, \qquad Y = \sum_{i + j \le n} b_{ij}\, x^i y^j

    with ``(n + 1)(n + 2)/2`` coefficients each; parameter names ``a{i}{j}``, ``b{i}{j}``
    (power of x first). ``a_ij`` is in destination units per source unit^(i+j). Order 1
    is the affine transformation. The inverse is iterative (Newton).

    Parameters
    ----------
    order : int, 1 ≤ order ≤ 9
    a, b : array_like, shape ((order + 1)(order + 2)/2,), optional
        Coefficients in the order of ``exponents`` (default: the identity).

    Examples
    --------
    >>> t = PolynomialTransform(2)
    >>> t.exponents
    ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
    >>> src = np.array([[x, y] for x in range(3) for y in range(3)], dtype=float)
    >>> dst = np.column_stack([src[:, 0] + 0.1 * src[:, 1] ** 2, src[:, 1] - 0.2 * src[:, 0] ** 2])
    >>> t = PolynomialTransform.from_estimate(src, dst, order=2)
    >>> round(t.params["a02"], 12), round(t.params["b20"], 12)
    (0.1, -0.2)
    """

    def __init__(self, order: int, a=None, b=None):
        if not isinstance(order, (int, np.integer)) or not 1 <= order <= 9:
            raise ValueError(f"order must be an integer 1…9, got {order!r}")
        self.order = int(order)
        self.exponents = tuple((i, d - i) for d in range(order + 1) for i in range(d, -1, -1))
        ident_a = [1.0 if e == (1, 0) else 0.0 for e in self.exponents]
        ident_b = [1.0 if e == (0, 1) else 0.0 for e in self.exponents]
        self._set_coefficients(ident_a if a is None else a, ident_b if b is None else b)

    def _names(self, letter):
        return [f"{letter}{i}{j}" for i, j in self.exponents]

    @classmethod
    def from_estimate(cls, src, dst, order: int = 2) -> PolynomialTransform:
        """Least-squares estimate from ≥ (order+1)(order+2)/2 point pairs (normalised first)."""
        return cls(order)._estimate(src, dst)

    def __repr__(self) -> str:
        return f"PolynomialTransform(order={self.order}, a={self.a.tolist()}, b={self.b.tolist()})"
