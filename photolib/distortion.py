"""Lens distortion / Objektivverzeichnung: the course model, its inversion and OpenCV conversion.

Model (derived in :mod:`photolib.derive.distortion`, generated into
:mod:`photolib._generated.distortion`): ``Δ = distorted − ideal`` evaluated at the **measured**
image coordinates reduced to the principal point,

.. math::
    Δx' &= x\\,[A_1(r^2-r_0^2) + A_2(r^4-r_0^4) + A_3(r^6-r_0^6)] + B_1(r^2+2x^2) + 2B_2xy + C_1x + C_2y \\\\
    Δy' &= y\\,[A_1(r^2-r_0^2) + A_2(r^4-r_0^4) + A_3(r^6-r_0^6)] + B_2(r^2+2y^2) + 2B_1xy

Correcting a measurement is direct, ``x_ideal = x_meas − Δ(x_meas)``; the measured position of an
ideal point solves ``x − Δ(x) = x_ideal`` by fixed-point or Newton iteration (Luhmann p. 163/164).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from photolib._generated.distortion import (
    distortion_delta,
    distortion_delta_and_jacobian,
    distortion_jacobian_params,
)
from photolib._validate import as_int, as_max_iter, as_points, as_scalar, as_tolerance
from photolib.errors import ConvergenceError

__all__ = ["Distortion", "ConvergenceReport", "DistortionDivergenceError", "OpenCVFit"]

#: points per block in :meth:`Distortion.distort`
_BLOCK = 4096

_NAMES = ("A1", "A2", "A3", "r0", "B1", "B2", "C1", "C2")


@dataclass(frozen=True)
class ConvergenceReport:
    """How an iterative inversion ended.

    Attributes
    ----------
    method : str
        ``'newton'`` or ``'fixed-point'``.
    converged : bool
        Every point's last step was below ``tol``.
    iterations : int
        Iterations used by the slowest point (each point stops at its own last step).
    max_step : float
        Largest last step over all points (image unit).
    history : tuple of float
        Largest step per iteration, for convergence plots.
    """

    method: str
    converged: bool
    iterations: int
    max_step: float
    history: tuple = field(default=())


def _shrinking(history) -> bool:
    """Were the last two (largest) steps of a run shrinking?"""
    return len(history) >= 2 and history[-2] > 0 and 0.0 < history[-1] / history[-2] < 1.0


def _slow_advice(history, tol: float) -> str:
    """For a run stopped by ``max_iter``: whether its largest steps were still shrinking.

    A contraction (the ratio q of the last two steps below 1) converges, only slowly: about
    ``log(tol/step)/log(q)`` more iterations reach ``tol``. Otherwise the iteration is not
    contracting there and more iterations will not help.

    >>> _slow_advice((1e-3, 4e-4, 1.6e-4), 1e-10)
    '; the steps still shrink (×0.4 per iteration): it converges slowly, not diverges — about 16 more iterations would reach tol (raise max_iter, or use Newton)'
    >>> _slow_advice((1e-3, 2e-3), 1e-10)
    '; the steps do not shrink: the iteration is not contracting there'
    """
    if len(history) < 2 or not history[-2] > 0:
        return ""
    if not _shrinking(history):
        return "; the steps do not shrink: the iteration is not contracting there"
    q = history[-1] / history[-2]
    more = int(np.ceil(np.log(tol / history[-1]) / np.log(q))) if history[-1] > tol else 0
    return (f"; the steps still shrink (×{q:.2g} per iteration): it converges slowly, not "
            f"diverges — about {more} more iterations would reach tol (raise max_iter, or use "
            "Newton)")


class DistortionDivergenceError(ConvergenceError):
    """The inversion did not converge; ``.report`` and ``.index`` (first bad point) tell more.

    ``.converging`` is True when the run was stopped by ``max_iter`` while its steps were
    still shrinking: a slow contraction (raise ``max_iter``), not a divergence.
    ``.beyond_fold`` is True when the iteration converged to a root that is not the measured
    position (beyond the fold of ``x − Δ(x)``): no measured position exists for that point.
    """

    def __init__(self, message: str, report: ConvergenceReport, index: int,
                 converging: bool = False, beyond_fold: bool = False):
        super().__init__(message)
        self.report = report
        self.index = index
        self.converging = converging
        self.beyond_fold = beyond_fold


@dataclass(frozen=True)
class OpenCVFit:
    """Result of a conversion between the course model and OpenCV's ``(k1, k2, p1, p2, k3)``.

    ``rms_um`` and ``max_um`` are the position residuals over the sampled format, in µm
    when the image unit is mm; ``exact`` is True when they vanish (≤ 1e-6 µm).
    """

    coefficients: tuple
    rms_um: float
    max_um: float
    exact: bool


class Distortion:
    """Distortion parameters of the course model (image unit: mm).

    Parameters
    ----------
    A1, A2, A3 : float
        Radial coefficients (mm⁻², mm⁻⁴, mm⁻⁶).
    r0 : float
        Radius of the zero crossing (balanced distortion), mm, ≥ 0; 0 gives Seidel's form.
    B1, B2 : float
        Tangential (decentring) coefficients, mm⁻¹.
    C1, C2 : float
        Affinity and shear, dimensionless.

    Examples
    --------
    >>> d = Distortion(A1=-1e-4)
    >>> d.delta([10.0, 0.0]).round(9).tolist()
    [-0.1, 0.0]
    >>> measured = d.distort([10.0, 0.0])
    >>> d.correct(measured).round(9).tolist()
    [10.0, 0.0]
    """

    PARAMETERS = _NAMES

    def __init__(self, A1=0.0, A2=0.0, A3=0.0, r0=0.0, B1=0.0, B2=0.0, C1=0.0, C2=0.0):
        values = dict(zip(_NAMES, (A1, A2, A3, r0, B1, B2, C1, C2)))
        self._p = {k: as_scalar(v, k) for k, v in values.items()}
        if self._p["r0"] < 0:
            raise ValueError(f"r0 must be >= 0 (a radius), got {self._p['r0']!r}")

    # -- parameters ---------------------------------------------------------------------
    @property
    def params(self) -> dict:
        """The parameters as a dict ``{'A1': …, …, 'C2': …}``."""
        return dict(self._p)

    def _args(self):
        return tuple(self._p[k] for k in _NAMES)

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v!r}" for k, v in self._p.items() if v != 0.0)
        return f"Distortion({inner})"

    def __eq__(self, other) -> bool:
        return isinstance(other, Distortion) and self._p == other._p

    def __hash__(self):
        return hash(tuple(self._p.items()))

    @property
    def is_zero(self) -> bool:
        """True when every coefficient (r0 aside) is zero."""
        return all(v == 0.0 for k, v in self._p.items() if k != "r0")

    @property
    def conrady(self) -> dict:
        """Conrady's ``K0…K3`` of the radial part: ``K0 = −(A1 r0² + A2 r0⁴ + A3 r0⁶)``, ``Ki = Ai``.

        >>> Distortion(A1=1e-4, r0=10.0).conrady['K0']
        -0.01
        """
        p = self._p
        r0 = p["r0"]
        return {"K0": -(p["A1"] * r0**2 + p["A2"] * r0**4 + p["A3"] * r0**6),
                "K1": p["A1"], "K2": p["A2"], "K3": p["A3"]}

    @property
    def fold_radius(self) -> float:
        r"""Radius (mm) where the radial map ``r ↦ r − Δr'(r)`` stops increasing (∞ if never).

        With Conrady's form ``Δr' = K0 r + K1 r³ + K2 r⁵ + K3 r⁷``,

        .. math:: \frac{d}{dr}(r - Δr') = 1 - K_0 - 3K_1 r^2 - 5K_2 r^4 - 7K_3 r^6 = 0

        at its smallest positive root: beyond it the radial map folds back, and a root of
        ``x − Δ(x) = x_ideal`` there is not the measured position of the ideal point (it is
        not connected to the centre). Used by :meth:`distort` with the local check.

        >>> round(Distortion(A1=1e-3).fold_radius, 6), round(float(1 / np.sqrt(3e-3)), 6)
        (18.257419, 18.257419)
        >>> Distortion(A1=-1e-3).fold_radius
        inf
        """
        k = self.conrady
        c0 = 1.0 - k["K0"]
        if c0 <= 0.0:
            return 0.0
        coeffs = [-7.0 * k["K3"], -5.0 * k["K2"], -3.0 * k["K1"], c0]
        while coeffs and coeffs[0] == 0.0:
            coeffs.pop(0)
        if len(coeffs) < 2:
            return float("inf")
        s = [float(z.real) for z in np.roots(coeffs) if abs(z.imag) <= 1e-12 * abs(z) and z.real > 0]
        return float(np.sqrt(min(s))) if s else float("inf")

    @classmethod
    def from_conrady(cls, K0=0.0, K1=0.0, K2=0.0, K3=0.0, *, B1=0.0, B2=0.0, C1=0.0, C2=0.0):
        """Exact conversion from Conrady's ``Δr' = K0 r + K1 r³ + K2 r⁵ + K3 r⁷``.

        ``r0`` is the positive root of ``K1 r0² + K2 r0⁴ + K3 r0⁶ = −K0`` (0 when K0 = 0);
        if there is none, K0 cannot be written with a zero-crossing radius and a
        ``ValueError`` says so.

        >>> d = Distortion.from_conrady(-0.01, 1e-4)
        >>> round(d.params['r0'], 9), d.conrady['K0']
        (10.0, -0.01)
        """
        K0, K1, K2, K3 = (as_scalar(v, n) for v, n in zip((K0, K1, K2, K3), ("K0", "K1", "K2", "K3")))
        r0 = 0.0
        if K0 != 0.0:
            roots = np.roots([K3, K2, K1, K0] if K3 else ([K2, K1, K0] if K2 else [K1, K0]))
            good = sorted(float(z.real) for z in roots if abs(z.imag) < 1e-12 and z.real > 0)
            if not good:
                raise ValueError(f"K0 = {K0!r} has no zero-crossing radius r0 with K1..K3 = "
                                 f"{(K1, K2, K3)!r}: K1 r0² + K2 r0⁴ + K3 r0⁶ = −K0 has no root r0² > 0")
            r0 = float(np.sqrt(good[0]))
        return cls(A1=K1, A2=K2, A3=K3, r0=r0, B1=B1, B2=B2, C1=C1, C2=C2)

    def radial_profile(self, r):
        """``Δr'(r) = A1 r(r² − r0²) + A2 r(r⁴ − r0⁴) + A3 r(r⁶ − r0⁶)`` (mm), for curves.

        >>> float(Distortion(A1=1e-4, r0=10.0).radial_profile(10.0))
        0.0
        """
        r = np.asarray(r, dtype=float)
        dx, _ = distortion_delta(r, 0.0, *self._args()[:4], 0.0, 0.0, 0.0, 0.0)
        return dx

    # -- evaluation ---------------------------------------------------------------------
    def delta(self, xy) -> np.ndarray:
        """``(Δx', Δy')`` at measured coordinates reduced to the principal point.

        Parameters
        ----------
        xy : array_like, shape (N, 2) or (2,), mm

        Returns
        -------
        ndarray, same shape as ``xy``, mm

        Examples
        --------
        >>> Distortion(B1=1e-5).delta([[10.0, 0.0], [0.0, 10.0]]).round(9).tolist()
        [[0.003, 0.0], [0.001, 0.0]]
        """
        pts, single = as_points(xy, 2, "xy")
        dx, dy = distortion_delta(pts[:, 0], pts[:, 1], *self._args())
        out = np.column_stack(np.broadcast_arrays(dx, dy))
        return out[0] if single else out

    def correct(self, xy) -> np.ndarray:
        """Ideal coordinates of measured points, ``x_ideal = x_meas − Δ(x_meas)`` (direct).

        >>> Distortion(A1=-1e-4).correct([10.0, 0.0]).round(9).tolist()
        [10.1, 0.0]
        """
        pts, single = as_points(xy, 2, "xy")
        out = pts - self.delta(pts)
        return out[0] if single else out

    def jacobian_xy(self, xy) -> np.ndarray:
        """``∂(Δx', Δy')/∂(x, y)``, shape (N, 2, 2) or (2, 2), dimensionless.

        >>> Distortion(A1=1e-4).jacobian_xy([10.0, 0.0]).round(9).tolist()   # ∂Δx/∂x = 3·A1·x²
        [[0.03, 0.0], [0.0, 0.01]]
        """
        pts, single = as_points(xy, 2, "xy")
        _, _, a, b, c, d = distortion_delta_and_jacobian(pts[:, 0], pts[:, 1], *self._args())
        J = np.stack(np.broadcast_arrays(a, b, c, d), axis=-1).reshape(-1, 2, 2)
        return J[0] if single else J

    def jacobian_params(self, xy) -> np.ndarray:
        """``∂(Δx', Δy')/∂(A1, A2, A3, B1, B2, C1, C2)``, shape (N, 2, 7) or (2, 7), for
        self-calibration (mm per unit of each parameter; r0 held fixed).

        >>> Distortion().jacobian_params([2.0, 0.0])[0].round(9).tolist()   # ∂Δx/∂(A1 … C2)
        [8.0, 32.0, 128.0, 12.0, 0.0, 2.0, 0.0]
        """
        pts, single = as_points(xy, 2, "xy")
        cols = distortion_jacobian_params(pts[:, 0], pts[:, 1], *self._args())
        J = np.stack(np.broadcast_arrays(*cols), axis=-1).reshape(-1, 7, 2).transpose(0, 2, 1)
        return J[0] if single else J.copy()

    # -- inversion ----------------------------------------------------------------------
    def distort(self, xy, method: str = "newton", *, tol: float = 1e-10, max_iter: int = 50,
                return_report: bool = False):
        """Measured (distorted) position of ideal points: solve ``x − Δ(x) = x_ideal``.

        Parameters
        ----------
        xy : array_like, shape (N, 2) or (2,)
            Ideal image coordinates reduced to the principal point, mm.
        method : {'newton', 'fixed-point'}
            Newton: ``x ← x − (I − ∂Δ/∂x)⁻¹ (x − Δ(x) − x_ideal)`` (quadratic convergence);
            fixed point: ``x ← x_ideal + Δ(x)`` (Luhmann p. 163/164; linear, converges
            only where ‖∂Δ/∂x‖ < 1).
        tol : float
            A point stops iterating when its own step is below ``tol`` (mm); Newton's error
            after a step ``s`` is about ``C·s²``, far below ``tol``.
        max_iter : int
            Iteration limit; not converging by then raises.
        return_report : bool
            Also return a :class:`ConvergenceReport`.

        Raises
        ------
        DistortionDivergenceError
            If any point has not converged after ``max_iter`` steps or the iteration
            blows up (NaN, singular ``I − ∂Δ/∂x``), or if Newton lands on a root beyond the fold
            of ``x − Δ(x)``; the message names the first such point.

        Examples
        --------
        >>> d = Distortion(A1=-5e-5, B2=2e-6)
        >>> m, report = d.distort([[15.0, 10.0]], return_report=True)
        >>> report.converged, report.iterations <= 6
        (True, True)
        >>> bool(abs(d.correct(m) - [[15.0, 10.0]]).max() < 1e-9)
        True
        """
        pts, single = as_points(xy, 2, "xy")
        if method not in ("newton", "fixed-point"):
            raise ValueError(f"method must be 'newton' or 'fixed-point', got {method!r}")
        tol = as_tolerance(tol)
        max_iter = as_max_iter(max_iter)
        if self.is_zero or len(pts) == 0:  # nothing to iterate: (0, 2) in, (0, 2) out
            report = ConvergenceReport(method, True, 0, 0.0, ())
            out = pts[0].copy() if single else pts.copy()
            return (out, report) if return_report else out
        args = self._args()
        n = len(pts)
        out = np.empty_like(pts)
        steps = np.zeros(n)
        # Newton only: det and trace of I − ∂Δ/∂x at each point's last iterate, for the fold check
        det_last = np.empty(n) if method == "newton" else None
        trace_last = np.empty(n) if method == "newton" else None
        history = np.zeros(max_iter)
        iterations = 0
        # blocks of contiguous x and y keep every temporary in the CPU cache
        for s in range(0, n, _BLOCK):
            it = _invert_block(pts, np.arange(s, min(s + _BLOCK, n)), args, method, tol, max_iter,
                               out, steps, det_last, trace_last, history)
            iterations = max(iterations, it)
        history = tuple(history[:iterations].tolist())
        x = out
        report = ConvergenceReport(method, bool(np.all(steps < tol)), iterations,
                                   float(np.max(steps)), history)
        if not report.converged:
            i = int(np.argmax(steps >= tol))
            raise DistortionDivergenceError(
                f"{method} iteration did not converge for {int(np.sum(steps >= tol))} of {n} points "
                f"within max_iter={max_iter} (first: point {i}, ideal {pts[i].tolist()}, last step "
                f"{steps[i]:.3g} > tol={tol:g}){_slow_advice(history, tol)}", report, i,
                converging=_shrinking(history))
        _check_valid_sheet(pts, x, args, method, det_last, trace_last, self.fold_radius,
                           ConvergenceReport(method, False, iterations, float(np.max(steps)),
                                             history))
        out = x[0] if single else x
        return (out, report) if return_report else out

    # -- OpenCV ---------------------------------------------------------------------
    def opencv_form(self, c: float) -> tuple:
        """OpenCV coefficients of the *same functional form*: ``k1 = A1c², k2 = A2c⁴, k3 = A3c⁶,
        p1 = −B2·c, p2 = B1·c``.

        Exact as a map of formulas, but OpenCV evaluates at the ideal point and the course at the
        measured one, so as distortions they differ by the second-order term; this naive
        conversion is what :meth:`to_opencv` improves on. r0, C1, C2 have no OpenCV term.

        >>> [round(v, 9) + 0.0 for v in Distortion(A1=1e-4, B1=1e-5).opencv_form(c=10.0)]
        [0.01, 0.0, 0.0, 0.0001, 0.0]
        """
        c = as_scalar(c, "c", positive=True)
        p = self._p
        return (p["A1"] * c**2, p["A2"] * c**4, -p["B2"] * c, p["B1"] * c, p["A3"] * c**6)

    def to_opencv(self, c: float, half_width: float, half_height: float, *, n: int = 25,
                  unit_to_um: float = 1000.0) -> OpenCVFit:
        """Fit OpenCV's ``(k1, k2, p1, p2, k3)`` to this distortion over the image format.

        Ideal points on an n×n grid over ``[−half_width, half_width] × [−half_height, half_height]``
        (mm) are distorted with :meth:`distort`; OpenCV's model, linear in its coefficients for
        given ideal points, is fitted by least squares in normalised coordinates
        ``(x/c, −y/c)``. Residuals are reported in µm (``unit_to_um`` µm per image unit).

        >>> fit = Distortion(A1=-1e-4).to_opencv(c=24.0, half_width=18.0, half_height=12.0)
        >>> fit.exact, fit.max_um < 5.0
        (False, True)
        """
        c = as_scalar(c, "c", positive=True)
        u = _grid(half_width, half_height, n)
        m = self.distort(u)
        un = np.column_stack([u[:, 0] / c, -u[:, 1] / c])
        mn = np.column_stack([m[:, 0] / c, -m[:, 1] / c])
        A = _opencv_design(un)
        coef, *_ = np.linalg.lstsq(A, (mn - un).reshape(-1), rcond=None)
        res = (A @ coef - (mn - un).reshape(-1)).reshape(-1, 2) * c * unit_to_um
        return _fit_result(tuple(float(v) for v in coef), res)

    @classmethod
    def from_opencv(cls, coefficients, c: float, half_width: float, half_height: float, *,
                    r0: float = 0.0, n: int = 25, unit_to_um: float = 1000.0):
        """Fit the course model to OpenCV's ``(k1, k2, p1, p2, k3)`` over the image format.

        OpenCV's forward model gives the measured point ``m`` of each ideal grid point ``u``;
        ``m − u = Δ(m)`` is linear in A1, A2, A3, B1, B2 (r0 held fixed) and is solved by
        least squares. Returns ``(Distortion, OpenCVFit)``; the fit's ``coefficients`` are the
        fitted ``(A1, A2, A3, B1, B2)``.

        >>> d, fit = Distortion.from_opencv((-0.05, 0, 0, 0, 0), 24.0, 18.0, 12.0)
        >>> d.params['A1'] < 0, fit.max_um < 5.0
        (True, True)
        """
        c = as_scalar(c, "c", positive=True)
        k = np.asarray(coefficients, dtype=float).reshape(-1)
        if k.shape != (5,) or not np.all(np.isfinite(k)):
            raise ValueError(f"coefficients must be 5 finite numbers (k1, k2, p1, p2, k3), got {coefficients!r}")
        u = _grid(half_width, half_height, n)
        un = np.column_stack([u[:, 0] / c, -u[:, 1] / c])
        mn = un + (_opencv_design(un) @ k).reshape(-1, 2)
        m = np.column_stack([mn[:, 0] * c, -mn[:, 1] * c])
        # Δ is linear in A1..B2 with no constant term (r0 fixed): columns of ∂Δ/∂p
        J = cls(r0=r0).jacobian_params(m)[:, :, :5].reshape(-1, 5)
        coef, *_ = np.linalg.lstsq(J, (m - u).reshape(-1), rcond=None)
        d = cls(A1=coef[0], A2=coef[1], A3=coef[2], r0=r0, B1=coef[3], B2=coef[4])
        res = (m - d.delta(m) - u) * unit_to_um
        return d, _fit_result(tuple(float(v) for v in coef), res)


def _grid(half_width, half_height, n):
    hw = as_scalar(half_width, "half_width", positive=True)
    hh = as_scalar(half_height, "half_height", positive=True)
    n = as_int(n, "n", minimum=3)
    gx, gy = np.meshgrid(np.linspace(-hw, hw, n), np.linspace(-hh, hh, n))
    return np.column_stack([gx.ravel(), gy.ravel()])


def _opencv_design(un):
    """Rows of OpenCV's distortion, linear in (k1, k2, p1, p2, k3), at normalised ideal points."""
    x, y = un[:, 0], un[:, 1]
    r2 = x * x + y * y
    A = np.zeros((len(x), 2, 5))
    A[:, 0, 0], A[:, 1, 0] = x * r2, y * r2
    A[:, 0, 1], A[:, 1, 1] = x * r2**2, y * r2**2
    A[:, 0, 2], A[:, 1, 2] = 2 * x * y, r2 + 2 * y * y
    A[:, 0, 3], A[:, 1, 3] = r2 + 2 * x * x, 2 * x * y
    A[:, 0, 4], A[:, 1, 4] = x * r2**3, y * r2**3
    return A.reshape(-1, 5)


def _fit_result(coef, res_um):
    dist = np.hypot(res_um[:, 0], res_um[:, 1])
    rms, mx = float(np.sqrt(np.mean(dist**2))), float(np.max(dist))
    return OpenCVFit(coef, rms, mx, mx <= 1e-6)


def _invert_block(pts, idx, args, method, tol, max_iter, out, steps, det_last, trace_last,
                  history) -> int:
    """Iterate one block of points of :meth:`Distortion.distort`; return the iterations used.

    Solves ``x − Δ(x) = x_ideal`` for the ideal points ``pts[idx]`` (mm) by Newton
    (``x ← x − (I − ∂Δ/∂x)⁻¹ (x − Δ(x) − x_ideal)``, started from one fixed-point step) or by
    fixed point (``x ← x_ideal + Δ(x)``). A point leaves the iteration as soon as its own step
    is below ``tol`` (active set); at ``max_iter`` all remaining points leave. Writes, in place,
    the result to ``out[idx]``, the last step length (mm) to ``steps[idx]``, for Newton det and
    trace of ``I − ∂Δ/∂x`` at the last iterate to ``det_last[idx]``, ``trace_last[idx]``, and
    keeps in ``history[k]`` the largest step (mm) of iteration k + 1 over all blocks.

    Raises :class:`DistortionDivergenceError` naming the first point whose step is not finite
    or above 1e12 mm.
    """
    tol2 = tol * tol
    ix = np.ascontiguousarray(pts[idx, 0])
    iy = np.ascontiguousarray(pts[idx, 1])
    if method == "newton":  # start from one fixed-point step: x ≈ x_ideal + Δ(x_ideal)
        dx, dy = distortion_delta(ix, iy, *args)
        xa, ya = ix + dx, iy + dy
    else:
        xa, ya = ix.copy(), iy.copy()
    for it in range(1, max_iter + 1):
        if method == "newton":
            dx, dy, a, b, c, d = distortion_delta_and_jacobian(xa, ya, *args)
            fx = xa - dx - ix
            fy = ya - dy - iy
            j11, j22 = 1.0 - a, 1.0 - d
            det = j11 * j22 - b * c
            with np.errstate(divide="ignore", invalid="ignore"):
                sx = (j22 * fx + b * fy) / det
                sy = (j11 * fy + c * fx) / det
            xa = xa - sx
            ya = ya - sy
        else:
            dx, dy = distortion_delta(xa, ya, *args)
            sx, sy = ix + dx - xa, iy + dy - ya
            xa = xa + sx
            ya = ya + sy
        step2 = sx * sx + sy * sy
        smax = float(np.sqrt(np.max(step2)))
        history[it - 1] = max(history[it - 1], smax)
        if not np.isfinite(smax) or smax > 1e12:
            step = np.sqrt(step2)
            bad = ~np.isfinite(step) | (step > 1e12)
            i = int(idx[np.argmax(bad)])
            rep = ConvergenceReport(method, False, it, float("inf"),
                                    tuple(history[:it].tolist()))
            raise DistortionDivergenceError(
                f"{method} iteration diverged at point {i} (ideal {pts[i].tolist()}) after "
                f"{it} iterations; the distortion is not invertible there "
                "(outside the calibrated format?)", rep, i)
        done = step2 < tol2
        last = it == max_iter
        if last or done.all():
            done = np.ones(len(idx), bool)
        if done.any():
            j = idx[done]
            out[j, 0] = xa[done]
            out[j, 1] = ya[done]
            steps[j] = np.sqrt(step2[done])
            if method == "newton":
                det_last[j] = det[done]
                trace_last[j] = (j11 + j22)[done]
            if done.all():
                break
            keep = ~done
            idx, ix, iy, xa, ya = idx[keep], ix[keep], iy[keep], xa[keep], ya[keep]
    return it


def _check_valid_sheet(pts, x, args, method, det_last, trace_last, fold_radius, report) -> None:
    """Raise if a root ``x`` (mm) of ``x − Δ(x) = x_ideal`` lies beyond the fold of the map.

    A root beyond the fold solves the equation but is not the measured point: it lies on the
    mirrored sheet, e.g. on the other side of the centre. Valid sheet (connected to the
    centre, where ``I − ∂Δ/∂x = I``): both eigenvalues of ``I − ∂Δ/∂x`` keep a positive real
    part ⇔ det > 0 and trace > 0. Newton has them at the last iterate (``det_last``,
    ``trace_last``), within tol of the result; near the fold (det or trace ≤ 0.05, or after
    fixed-point iteration, ``det_last is None``) they are evaluated at the result itself.
    Along the ray, a root at ``r' ≥ fold_radius`` (mm, :attr:`Distortion.fold_radius`) is on
    an outer sheet even where ``I − ∂Δ/∂x`` is positive again there (e.g. A1 > 0 with A2 < 0).
    ``report`` is attached to the :class:`DistortionDivergenceError`, which names the first
    such point.
    """
    n = len(x)
    if method == "newton":
        near = (det_last <= 0.05) | (trace_last <= 0.05)
    else:
        near = np.ones(n, bool)
        det_last, trace_last = np.empty(n), np.empty(n)
    if near.any():
        _, _, a, b, c, d = distortion_delta_and_jacobian(x[near, 0], x[near, 1], *args)
        det_last[near] = (1.0 - a) * (1.0 - d) - b * c
        trace_last[near] = (1.0 - a) + (1.0 - d)
    folded = (det_last <= 0.0) | (trace_last <= 0.0) | (np.hypot(x[:, 0], x[:, 1])
                                                         >= fold_radius)
    if folded.any():
        i = int(np.argmax(folded))
        why = ("I − ∂Δ/∂x not positive there" if det_last[i] <= 0.0 or trace_last[i] <= 0.0
               else f"outside the radial fold at r' = {fold_radius:.6g} mm")
        raise DistortionDivergenceError(
            f"{method} iteration for point {i} (ideal {pts[i].tolist()}) reached a root beyond "
            f"the fold of x − Δ(x) at {x[i].round(6).tolist()} ({why}): this ideal "
            "point has no measured position on the valid sheet of the distortion model",
            report, i, beyond_fold=True)
