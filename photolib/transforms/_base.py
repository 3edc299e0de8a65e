"""Shared machinery of the plane transformations: input checks, normalisation, composition.

Every transform maps source points ``(x, y)`` to destination points ``(X, Y)`` and has the
same small surface: ``params``, ``__call__``, ``inverse``, ``@`` (composition) and, for the
estimable classes, ``from_estimate(src, dst)`` with ``residuals`` and ``sigma0``.
"""

from __future__ import annotations

import math

import numpy as np

from photolib._validate import as_max_iter, as_point_pairs, as_points, as_tolerance
from photolib.errors import ConvergenceError, DegenerateGeometryError  # noqa: F401 - raised here, defined in one hierarchy

__all__ = [
    "ComposedTransform",
    "ConvergenceError",
    "DegenerateGeometryError",
    "NewtonInverse",
    "PlaneTransform",
    "check_pairs",
    "hartley_normalisation",
]




def hartley_normalisation(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Centroid and scale that move ``points`` (N, 2) to mean distance √2 from the origin.

    The normalised points are ``s·(p − centroid)``. Raises
    :class:`DegenerateGeometryError` if all points coincide.
    """
    centroid = points.mean(axis=0)
    mean_dist = float(np.mean(np.linalg.norm(points - centroid, axis=1)))
    scale_ref = max(1.0, float(np.max(np.abs(points))))
    if mean_dist <= 1e-12 * scale_ref:
        raise DegenerateGeometryError("all points coincide; no transformation is determined")
    return centroid, np.sqrt(2.0) / mean_dist


def collinearity_ratio(points: np.ndarray) -> float:
    """Ratio of the smallest to the largest singular value of the centred points (0 = collinear)."""
    sv = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
    return float(sv[-1] / sv[0]) if sv[0] > 0 else 0.0


def check_pairs(src, dst, min_points: int, name: str):
    """Validated ``(src, dst)`` arrays of shape (N, 2) with equal N ≥ ``min_points``."""
    return as_point_pairs(src, dst, (2, 2), ("src", "dst"), min_points, name, "point pairs")


class PlaneTransform:
    """Base class of the plane transformations ``(x, y) → (X, Y)``.

    Subclasses implement ``_forward(p)`` for an (N, 2) array, ``params`` and ``inverse``.
    Estimated transforms carry ``residuals`` (N, 2) = ``T(src) − dst`` in destination units,
    ``sigma0`` (destination units) and ``redundancy`` ``r = 2N − u``.
    """

    #: number of parameters u
    n_params: int = 0
    residuals: np.ndarray | None = None
    sigma0: float | None = None
    redundancy: int | None = None

    def __call__(self, points) -> np.ndarray:
        """Transform points of shape (N, 2) or (2,); the result has the same shape."""
        p, single = as_points(points, 2, "points")
        out = self._forward(p)
        return out[0] if single else out

    def _forward(self, p: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def jacobian(self, points) -> np.ndarray:
        """∂(X, Y)/∂(x, y) at the points, shape (N, 2, 2) (or (2, 2) for one point)."""
        p, single = as_points(points, 2, "points")
        J = self._jacobian(p)
        return J[0] if single else J

    @property
    def params(self) -> dict[str, float]:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def inverse(self) -> PlaneTransform:  # pragma: no cover - abstract
        raise NotImplementedError

    def _compose(self, first: PlaneTransform) -> PlaneTransform | None:
        """``self ∘ first`` in closed form, or None when this class is not closed under it."""
        return None

    def __matmul__(self, other: PlaneTransform) -> PlaneTransform:
        """``a @ b`` applies ``b`` first, then ``a``: ``(a @ b)(p) == a(b(p))``."""
        if not isinstance(other, PlaneTransform):
            return NotImplemented
        result = self._compose(other)
        return result if result is not None else ComposedTransform(self, other)

    def _set_fit(self, src: np.ndarray, dst: np.ndarray,
                 residuals: np.ndarray | None = None) -> None:
        """Store residuals, redundancy r = 2N − u and σ0 = sqrt(vᵀv / r) (NaN when r = 0).

        ``residuals`` = ``T(src) − dst`` if the estimator has them already (equal to
        rounding), else they are computed."""
        self.residuals = self._forward(src) - dst if residuals is None else residuals
        self.redundancy = 2 * len(src) - self.n_params
        vtv = float(np.sum(self.residuals**2))
        self.sigma0 = math.sqrt(vtv / self.redundancy) if self.redundancy > 0 else float("nan")
        self._src = src

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v:.6g}" for k, v in self.params.items())
        return f"{type(self).__name__}({inner})"


class ComposedTransform(PlaneTransform):
    """``second ∘ first`` for transforms whose class is not closed under composition.

    Examples
    --------
    >>> from photolib.transforms import AffineTransform, BilinearTransform
    >>> t = AffineTransform(a0=1.0) @ BilinearTransform(a3=0.5)
    >>> t([2.0, 2.0]).tolist()
    [5.0, 2.0]
    """

    def __init__(self, second: PlaneTransform, first: PlaneTransform):
        self.second, self.first = second, first
        self.n_params = first.n_params + second.n_params

    def _forward(self, p):
        return self.second._forward(self.first._forward(p))

    def _jacobian(self, p):
        return self.second._jacobian(self.first._forward(p)) @ self.first._jacobian(p)

    @property
    def params(self) -> dict[str, float]:
        """Parameters of both parts, prefixed ``first.`` and ``second.``."""
        out = {f"first.{k}": v for k, v in self.first.params.items()}
        out.update({f"second.{k}": v for k, v in self.second.params.items()})
        return out

    @property
    def inverse(self) -> PlaneTransform:
        """``first⁻¹ ∘ second⁻¹``."""
        return self.first.inverse @ self.second.inverse


class NewtonInverse(PlaneTransform):
    r"""Iterative inverse of a transform without a closed-form inverse.

    Solves ``T(x) = X`` for each point by Newton iteration with Levenberg–Marquardt damping,

    .. math:: x_{k+1} = x_k - (J^T J + μ_k I)^{-1} J^T (T(x_k) - X),

    with μ = 0 (the plain Newton step) while steps reduce the residual, and μ growing
    where they do not or where ``J`` is singular. It stops when
    ``|T(x) − X| ≤ tol·(1 + |X|)``. The start is an affine approximation of ``T⁻¹`` (fitted
    to the estimation points if ``T`` was estimated, else the linearisation at the origin).

    Raises :class:`ConvergenceError` naming the first point that did not converge within
    ``max_iter`` iterations or stalled at a residual above the tolerance (no preimage).
    """

    def __init__(self, forward: PlaneTransform, tol: float = 1e-12, max_iter: int = 50):
        self.forward = forward
        self.tol, self.max_iter = as_tolerance(tol), as_max_iter(max_iter)
        self.n_params = forward.n_params

    @property
    def params(self) -> dict[str, float]:
        """The parameters of the forward transform that is inverted."""
        return dict(self.forward.params)

    @property
    def inverse(self) -> PlaneTransform:
        return self.forward

    def _start(self, X: np.ndarray) -> np.ndarray:
        src = getattr(self.forward, "_src", None)
        if src is not None and len(src) >= 3 and collinearity_ratio(src) > 1e-8:
            # affine fit of T⁻¹ on the estimation points: x ≈ [1, X, Y] · A
            dst = self.forward._forward(src)
            D = np.column_stack([np.ones(len(dst)), dst])
            A = np.linalg.lstsq(D, src, rcond=None)[0]
            return np.column_stack([np.ones(len(X)), X]) @ A
        zero = np.zeros((1, 2))
        J0 = self.forward._jacobian(zero)[0]
        return np.linalg.lstsq(J0, (X - self.forward._forward(zero)).T, rcond=None)[0].T

    def _forward(self, X):
        T = self.forward
        x = self._start(X)
        f = T._forward(x) - X
        res = np.linalg.norm(f, axis=1)
        goal = self.tol * (1.0 + np.linalg.norm(X, axis=1))
        mu = np.zeros(len(X))
        active = res > goal
        stalled = np.zeros(len(X), dtype=bool)
        for _ in range(self.max_iter):
            idx = np.flatnonzero(active)
            if idx.size == 0:
                break
            J = T._jacobian(x[idx])
            JtJ = np.swapaxes(J, 1, 2) @ J
            g = (np.swapaxes(J, 1, 2) @ f[idx][:, :, None])[:, :, 0]
            damp = mu[idx] * (np.trace(JtJ, axis1=1, axis2=2) / 2 + 1e-300)
            A = JtJ + damp[:, None, None] * np.eye(2)
            det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
            ok = np.abs(det) > 1e-14 * np.maximum(np.trace(JtJ, axis1=1, axis2=2) ** 2, 1e-300)
            step = np.zeros_like(g)
            if np.any(ok):
                step[ok] = np.linalg.solve(A[ok], g[ok][:, :, None])[:, :, 0]
            trial = x[idx] - step
            f_trial = T._forward(trial) - X[idx]
            r_trial = np.linalg.norm(f_trial, axis=1)
            better = ok & (r_trial < res[idx])
            acc = idx[better]
            x[acc], f[acc], res[acc] = trial[better], f_trial[better], r_trial[better]
            mu[acc] = 0.0
            rej = idx[~better]
            mu[rej] = np.where(mu[rej] == 0.0, 1e-9, mu[rej] * 10.0)
            tiny = np.linalg.norm(step, axis=1) <= 1e-15 * (1.0 + np.linalg.norm(x[idx], axis=1))
            stalled[idx] = (~better & ok & tiny) | (mu[idx] > 1e12)
            active = (res > goal) & ~stalled
        failed = res > goal
        if np.any(failed):
            bad = int(np.flatnonzero(failed)[0])
            why = ("stalled (no preimage?)" if stalled[bad]
                   else f"not within {self.max_iter} iterations")
            raise ConvergenceError(
                f"inverse of {type(T).__name__}: point {bad} ({X[bad].tolist()}) did not converge "
                f"to |T(x) − X| ≤ {goal[bad]:.3g}: {why}, residual {res[bad]:.3g}")
        return x

    def _jacobian(self, X):
        return np.linalg.inv(self.forward._jacobian(self._forward(X)))

    def __repr__(self) -> str:
        return f"NewtonInverse({self.forward!r}, tol={self.tol:g}, max_iter={self.max_iter})"
