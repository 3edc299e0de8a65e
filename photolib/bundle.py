r"""Bundle adjustment / Bündelblockausgleichung: all images and object points at once.

Observations are image coordinates ``x'_k`` (N, 2) with the image ``j(k)`` and the object
point ``i(k)`` they belong to. Unknowns: the exterior orientation
``(X0, Y0, Z0, ω, φ, κ)`` of every image, the coordinates of every object point that is
not a fixed control point, and optionally interior orientation and distortion common to
all images (self-calibration / Selbstkalibrierung). Gauss–Markov model with equal weights:

.. math::
    v = A\,\hat{dx} - l,\qquad
    N = A^TA = \begin{pmatrix} N_{yy} & N_{yp}\\ N_{py} & N_{pp}\end{pmatrix},\qquad
    (N_{yy} - N_{yp}N_{pp}^{-1}N_{py})\,\hat{dy} = b_y - N_{yp}N_{pp}^{-1}b_p

``N_pp`` is block diagonal (one 3×3 block per point), so the points are eliminated point by
point (Schur complement, reduced normal equations) and back-substituted,
``dp_i = N_ii^{-1}(b_i − N_iy dy)``. N is accumulated in blocks (6×6 per image, 3×3 per
point, 3×6 per observation, the k interior rows), O(N·(6 + k)²); each step solves the reduced
system by LU, its inverse (the covariances) is formed once, after convergence. The datum
(Datum) is fixed by control points (Passpunkte, fixed coordinates) or, for a free network
(freies Netz, *swobodna sieć*), by the seven inner constraints of a spatial similarity on the
object points (minimum norm of their corrections, ``Bᵀ dp = 0``), added by Lagrange multipliers.
Then

.. math::
    σ_0 = \sqrt{\frac{v^Tv}{r}},\quad r = n - u + d,\quad
    r_k = (Q_{vv}P)_{kk} = 1 - (A Q_{xx} A^T)_{kk},\quad \sum_k r_k = r,\quad
    w_k = \frac{v_k}{σ\sqrt{q_{vv,k}}},\ \ τ_k = \frac{v_k}{\hat σ_0\sqrt{q_{vv,k}}}

(d = 7 for a free network, 0 with control points). The distortion is evaluated at the
measured point reduced to the principal point (CONVENTIONS), so the observation equation is
``x' = x'0 − c·kx/N + Δx'(x'_obs − x'0)``. NumPy only.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from photolib._validate import (
    as_indices,
    as_int,
    as_max_iter,
    as_points,
    as_scalar,
    as_tolerance,
    check_finite,
)
from photolib._generated.collinearity import collinearity_jacobian_opk, project_r
from photolib.collinearity import PointBehindCameraError, project  # noqa: F401  (doctest)
from photolib.distortion import Distortion
from photolib.rotations import rotation_opk
from photolib.transforms._base import ConvergenceError

__all__ = ["BundleResult", "DatumError", "IterationRecord", "ReliabilityResult",
           "SnoopingResult", "INTERIOR_PARAMETERS", "bundle_adjustment", "critical_value",
           "data_snooping", "inner_constraints", "non_centrality", "normal_matrix_pattern",
           "reliability", "student_t_cdf"]

#: parameters that self-calibration can estimate, in this order
INTERIOR_PARAMETERS = ("c", "x0", "y0", "A1", "A2", "A3", "B1", "B2", "C1", "C2")
_DIST = ("A1", "A2", "A3", "B1", "B2", "C1", "C2")  # order of Distortion.jacobian_params


class DatumError(ValueError):
    """The datum is not fixed or the normal equations are singular (names the reason)."""


@dataclass(frozen=True)
class IterationRecord:
    """One Gauss–Newton step: the residuals *before* the step and the size of the step."""

    iteration: int
    vtv: float  #: vᵀv at the start of the iteration, image unit²
    max_length_update: float  #: largest |update| of X0 and points, object unit
    max_angle_update: float  #: largest |update| of ω, φ, κ, radians


@dataclass(frozen=True)
class BundleResult:
    """Result of :func:`bundle_adjustment`; covariances already scaled by σ0²."""

    exterior: np.ndarray  #: (M, 6) X0, Y0, Z0 (object unit), ω, φ, κ (rad) per image
    points: np.ndarray  #: (P, 3) object points (control points unchanged)
    c: float
    x0: float
    y0: float
    distortion: Distortion
    calibrate: tuple  #: the interior parameters estimated, in INTERIOR_PARAMETERS order
    sigma0: float  #: a-posteriori σ0 = √(vᵀPv/r) of an image coordinate, image unit (NaN: r = 0)
    n_observations: int  #: n = 2·N
    n_unknowns: int  #: u = 6M + 3·(free points) − (their fixed coordinates) + len(calibrate)
    datum_defect: int  #: d = 7 (free network) or 0
    redundancy: int  #: r = n + n_c − u + d (n_c: weighted control coordinates)
    residuals: np.ndarray  #: (N, 2) v = adjusted − observed, image unit
    qvv: np.ndarray  #: (N, 2) diagonal of Q_vv (P = I), dimensionless
    redundancy_numbers: np.ndarray  #: (N, 2) r_k = (Q_vv P)_kk
    exterior_covariance: np.ndarray  #: (M, 6, 6)
    point_covariance: np.ndarray  #: (P, 3, 3), zero rows/columns for fixed coordinates
    interior_covariance: np.ndarray  #: (k, k) for ``calibrate``
    iterations: int
    converged: bool
    history: tuple = field(default_factory=tuple)  #: IterationRecord per iteration
    n_control_observations: int = 0  #: n_c: control coordinates observed with 0 < σ < ∞
    control_sigma: np.ndarray | None = None  #: (P, 3) σ used: 0 fixed, inf unknown, object unit
    sigma_image: float | None = None  #: a-priori σ of an image coordinate (weights), image unit
    control_residuals: np.ndarray | None = None  #: (P, 3) v = adjusted − observed, object unit
    control_qvv: np.ndarray | None = None  #: (P, 3) q_vv of the control observations, 1/p − Q_cc
    control_redundancy_numbers: np.ndarray | None = None  #: (P, 3) r_c = p·q_vv,c (0: none)

    @property
    def standardized_residuals(self) -> np.ndarray:
        """τ_k = v_k / (σ̂0 √q_vv,k), (N, 2); NaN where q_vv = 0 (uncontrolled)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.qvv > 1e-12, self.residuals / (self.sigma0 * np.sqrt(
                np.maximum(self.qvv, 1e-300))), np.nan)

    @property
    def control_standardized_residuals(self) -> np.ndarray:
        """τ_c = v_c / (σ̂0 √q_vv,c), (P, 3), for the control coordinates observed with
        0 < σ < ∞; NaN elsewhere."""
        q = self.control_qvv
        if q is None:
            return np.full(self.points.shape, np.nan)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(q > 1e-300, self.control_residuals / (self.sigma0 * np.sqrt(
                np.maximum(q, 1e-300))), np.nan)

    @property
    def point_std(self) -> np.ndarray:
        """(P, 3) standard deviations σX, σY, σZ of the object points."""
        return np.sqrt(np.einsum("pii->pi", self.point_covariance))

    def interior(self) -> dict:
        """``{'c': …, 'x0': …, 'y0': …, 'A1': …, …}`` of the adjusted camera."""
        return {"c": float(self.c), "x0": float(self.x0), "y0": float(self.y0)} | {
            k: float(v) for k, v in self.distortion.params.items() if k in _DIST}


@dataclass(frozen=True)
class SnoopingResult:
    """Data snooping (Baarda) on the standardised residuals of a bundle result."""

    test: str  #: 'w' (normal, σ known a priori) or 'tau' (Pope, σ̂0 of the adjustment)
    alpha: float
    critical: float
    statistic: np.ndarray  #: (N, 2)
    flagged: np.ndarray  #: (K, 2) int rows (observation index, 0 = x' / 1 = y'), worst first

    @property
    def worst(self):
        """``(observation, coordinate)`` of the largest |statistic|, or None if none flagged."""
        return tuple(int(v) for v in self.flagged[0]) if len(self.flagged) else None


# -- statistics (NumPy/math only) -----------------------------------------------------------------

def _betainc(a: float, b: float, x: float, y: float) -> float:
    """Regularised incomplete beta I_x(a, b), y = 1 − x given separately (no cancellation),
    by Lentz's continued fraction."""
    if x <= 0.0:
        return 0.0
    if y <= 0.0:
        return 1.0
    if x > (a + 1.0) / (a + b + 2.0):
        return 1.0 - _betainc(b, a, y, x)
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b)
                     + a * math.log(x) + b * math.log(y)) / a
    tiny, f, C, D = 1e-300, 1.0, 1.0, 0.0
    for i in range(400):
        m = i // 2
        if i == 0:
            num = 1.0
        elif i % 2 == 0:
            num = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
        else:
            num = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))
        D = 1.0 + num * D
        D = 1.0 / (D if abs(D) > tiny else tiny)
        C = 1.0 + num / C
        C = C if abs(C) > tiny else tiny
        f *= C * D
        if abs(1.0 - C * D) < 1e-15:
            break
    return front * (f - 1.0)


def _as_dof(dof) -> float:
    """Degrees of freedom: a real number > 0, ``inf`` allowed (the normal distribution)."""
    if isinstance(dof, (str, bytes, bool, np.bool_)) or getattr(
            getattr(dof, "dtype", None), "kind", "") == "c":
        raise ValueError(f"dof must be a real number > 0 (inf: normal), got {dof!r}")
    try:
        v = float(dof)
    except (TypeError, ValueError):
        raise ValueError(f"dof must be a real number > 0 (inf: normal), got {dof!r}") from None
    if not v > 0:
        raise ValueError(f"dof must be > 0, got {dof!r}")
    return v


def _upper_tail(t: float, nu: float) -> float:
    """``P(T_ν > t)`` for t ≥ 0, computed as the tail itself (not 1 − cdf, which loses every
    digit once the tail is below the rounding of 1, about 1e-16)."""
    if math.isinf(nu):
        return 0.5 * math.erfc(t / math.sqrt(2.0))
    a, t2 = nu / 2.0, t * t
    if math.isfinite(t2) and nu / (nu + t2) > 1e-300:
        return 0.5 * _betainc(a, 0.5, nu / (nu + t2), t2 / (nu + t2))
    # t beyond ~1e150: x = ν/t² underflows; I_x(a, ½) = x^a·Γ(a + ½)/(Γ(a)Γ(½)·a)·(1 + O(x))
    log_x = math.log(nu) - 2.0 * math.log(t)
    return 0.5 * math.exp(math.lgamma(a + 0.5) - math.lgamma(a) - math.lgamma(0.5)
                          + a * log_x) / a


def student_t_cdf(t: float, dof: float) -> float:
    r"""CDF of Student's t with ``dof`` degrees of freedom (``dof = inf``: normal).

    .. math:: P(T_ν \le t) = 1 - \tfrac12 I_{ν/(ν+t^2)}(ν/2, 1/2)\quad (t \ge 0)

    with the regularised incomplete beta function :math:`I_x(a, b)` (Lentz's continued
    fraction, NumPy/``math`` only); for t < 0 by symmetry,
    :math:`P(T_ν \le -t) = 1 - P(T_ν \le t)`.

    Parameters
    ----------
    t : float
        Value of the test statistic (dimensionless, e.g. a standardised residual).
    dof : float
        Degrees of freedom / Freiheitsgrade ν, > 0 (not necessarily an integer); ``inf`` gives
        the standard normal distribution.

    Returns
    -------
    float
        :math:`P(T_ν \le t)` in [0, 1] (dimensionless probability).

    Raises
    ------
    ValueError
        If ``dof`` is not a real number > 0 or ``t`` is not a finite number.

    Examples
    --------
    >>> round(student_t_cdf(2.0, 5), 6), round(student_t_cdf(0.0, 3), 12)
    (0.94903, 0.5)
    """
    t = as_scalar(t, "t")
    dof = _as_dof(dof)
    if math.isinf(dof):
        return 0.5 * math.erfc(-t / math.sqrt(2.0))
    tail = 0.5 * _betainc(dof / 2.0, 0.5, dof / (dof + t * t), t * t / (dof + t * t))
    return 1.0 - tail if t >= 0 else tail


def critical_value(alpha: float, test: str = "normal", dof: float = math.inf) -> float:
    r"""Two-sided critical value k with ``P(|T| > k) = alpha``.

    Parameters
    ----------
    alpha : float
        Significance level (Irrtumswahrscheinlichkeit), 0 < alpha < 1.
    test : {'normal', 't', 'tau'}
        ``'normal'``: Baarda's w test (σ known); ``'t'``: Student's t with ``dof``;
        ``'tau'``: Pope's τ with redundancy ``dof`` = r (σ̂0 from the same adjustment),
        :math:`τ_c = t_c\sqrt{r}/\sqrt{r-1+t_c^2}`, t_c of t with r − 1 degrees of freedom.
    dof : float
        Degrees of freedom / Freiheitsgrade (> 0, ``inf`` allowed): ν of Student's t for
        ``'t'``, the redundancy r (finite, > 1) for ``'tau'``; ignored for ``'normal'``.

    Returns
    -------
    float
        Critical value k > 0 (dimensionless, in units of the statistic's σ): an observation
        is flagged when its |statistic| > k.

    Notes
    -----
    .. math:: P(|T| > k) = α \iff P(T > k) = α/2

    solved by bisection on the upper tail.

    Raises
    ------
    ValueError
        For ``alpha`` outside (0, 1), an unknown ``test``, ``dof ≤ 0``, or ``'tau'`` without
        a finite redundancy r > 1.

    Examples
    --------
    >>> round(critical_value(0.001), 4), round(critical_value(0.05, "t", 5), 4)
    (3.2905, 2.5706)

    The root is found on the upper tail ``P(T > k) = alpha/2`` itself, so tiny levels keep
    their digits:

    >>> round(critical_value(1e-20), 4)
    9.336
    """
    return _critical_value(as_scalar(alpha, "alpha"), str(test), _as_dof(dof))


@functools.lru_cache(maxsize=256)
def _critical_value(alpha: float, test: str, dof: float) -> float:
    alpha = as_scalar(alpha, "alpha")
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    if test == "tau":
        if not dof > 1 or math.isinf(dof):
            raise ValueError(f"the τ test needs a finite redundancy r > 1, got {dof!r}")
        t = _critical_value(alpha, "t", dof - 1.0)
        return t * math.sqrt(dof) / math.sqrt(dof - 1.0 + t * t)
    if test not in ("normal", "t"):
        raise ValueError(f"test must be 'normal', 't' or 'tau', got {test!r}")
    nu = math.inf if test == "normal" else float(dof)
    lo, hi, target = 0.0, 1.0, alpha / 2.0
    while _upper_tail(hi, nu) > target:
        hi *= 2.0
    for _ in range(200):  # bisection to the last bit
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (mid, hi) if _upper_tail(mid, nu) > target else (lo, mid)
    return 0.5 * (lo + hi)


def data_snooping(result: BundleResult, alpha: float = 0.001, sigma: float | None = None
                  ) -> SnoopingResult:
    """Test every image coordinate for a gross error (Baarda's data snooping).

    With ``sigma`` (the a-priori σ of an image coordinate) the w test ``w = v/(σ√q_vv)``
    against the normal distribution; without it Pope's τ test ``τ = v/(σ̂0√q_vv)`` against
    the τ distribution with r degrees of freedom. Flagged: |statistic| > critical value.
    Only the worst observation should be removed before adjusting again.

    Parameters
    ----------
    result : BundleResult
        A bundle adjustment with redundancy r > 1 (its ``residuals``, ``qvv``, ``sigma0``).
    alpha : float
        Significance level / Irrtumswahrscheinlichkeit of the two-sided test of each
        coordinate, 0 < alpha < 1 (default 0.1 %).
    sigma : float, optional
        A-priori σ of an image coordinate (image unit, e.g. mm), > 0: w test. None: τ test
        with σ̂0 of the adjustment.

    Returns
    -------
    SnoopingResult
        ``test`` ('w' or 'tau'), ``alpha``, ``critical`` (:func:`critical_value`),
        ``statistic`` (N, 2) (dimensionless, NaN where q_vv = 0) and ``flagged`` (K, 2) rows
        ``(observation, 0 = x' / 1 = y')`` with |statistic| > critical, worst first.

    Notes
    -----
    .. math:: w_k = \\frac{v_k}{σ\\sqrt{q_{vv,k}}},\\qquad
              τ_k = \\frac{v_k}{\\hat σ_0\\sqrt{q_{vv,k}}}

    Examples
    --------
    Two images of six control points; image 0's y' of point 5 carries a blunder of 0.05 mm
    (measuring precision ~1 µm):

    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 3], [3, 7, 1.0]])
    >>> ext = np.array([[3.0, 5, 30, 0, 0, 0], [7.0, 5, 30, 0, 0, 0]])
    >>> obs = np.vstack([project(X, e[:3], rotation_opk(*e[3:]), 20.0) for e in ext])
    >>> obs += np.random.default_rng(1).normal(0.0, 0.001, obs.shape)
    >>> obs[5, 1] += 0.05
    >>> res = bundle_adjustment(obs, np.repeat([0, 1], 6), np.tile(np.arange(6), 2), ext, X,
    ...                         20.0, control=np.arange(6))
    >>> snoop = data_snooping(res)                 # τ test with σ̂0, r = 24 − 12 = 12
    >>> snoop.test, snoop.worst, len(snoop.flagged)
    ('tau', (5, 1), 1)
    """
    if sigma is None:
        test, crit = "tau", critical_value(alpha, "tau", result.redundancy)
        stat = result.standardized_residuals
    else:
        sigma = as_scalar(sigma, "sigma", positive=True)
        test, crit = "w", critical_value(alpha, "normal")
        stat = result.standardized_residuals * (result.sigma0 / sigma)
    mag = np.where(np.isfinite(stat), np.abs(stat), -1.0)
    idx = np.argwhere(mag > crit)
    order = np.argsort(-mag[idx[:, 0], idx[:, 1]], kind="stable") if len(idx) else []
    return SnoopingResult(test, float(alpha), float(crit), stat, idx[order].reshape(-1, 2))


@dataclass(frozen=True)
class ReliabilityResult:
    """Internal and external reliability (Zuverlässigkeit; *wiarygodność*) of a bundle result."""

    alpha: float  #: significance level of the (two-sided) w test
    beta: float  #: power (Teststärke) with which a blunder of size ∇0 is found
    delta0: float  #: non-centrality δ0 = z_{1−α/2} + z_β
    sigma: float  #: σ of an image coordinate used, image unit
    mdb: np.ndarray  #: (N, 2) ∇0 = δ0·σ/√r_k, image unit (inf: r_k = 0, not controlled)
    external: np.ndarray  #: (N, 2) δ̄0 = δ0·√((1 − r_k)/r_k), dimensionless (inf: r_k = 0)
    control_mdb: np.ndarray  #: (P, 3) ∇0 of the control observations, object unit (NaN: none)
    control_external: np.ndarray  #: (P, 3) δ̄0 of the control observations (NaN: none)


def non_centrality(alpha: float = 0.001, beta: float = 0.80) -> float:
    r"""Non-centrality δ0 of Baarda's w test: a blunder of δ0·σ_v is found with power β.

    .. math:: δ_0 = z_{1-α/2} + z_β,\qquad P(Z > z_q) = 1 - q

    from the normal quantiles (:func:`critical_value`), the part of the lower tail beyond
    −z_{1−α/2} neglected, as in Baarda's tables.

    Parameters
    ----------
    alpha : float
        Significance level / Irrtumswahrscheinlichkeit α of the two-sided w test,
        0 < alpha < 1 (default 0.1 %).
    beta : float
        Power / Teststärke β, 0 < beta < 1 (default 80 %): the probability of finding a
        blunder of δ0·σ_v.

    Returns
    -------
    float
        δ0 (dimensionless, in units of σ_v); 4.13 for α = 0.1 %, β = 80 %.

    Raises
    ------
    ValueError
        For ``alpha`` or ``beta`` outside (0, 1).

    Examples
    --------
    >>> round(non_centrality(0.001, 0.80), 2), round(non_centrality(0.05, 0.80), 2)
    (4.13, 2.8)
    """
    alpha, beta = as_scalar(alpha, "alpha"), as_scalar(beta, "beta")
    if not 0.0 < beta < 1.0:
        raise ValueError(f"beta must be in (0, 1), got {beta!r}")
    k = critical_value(alpha, "normal")
    zb = (critical_value(2.0 * (1.0 - beta)) if beta > 0.5 else
          -critical_value(2.0 * beta) if beta < 0.5 else 0.0)
    return k + zb


def reliability(result: BundleResult, alpha: float = 0.001, beta: float = 0.80,
                sigma: float | None = None) -> ReliabilityResult:
    r"""Internal and external reliability from the redundancy numbers (Baarda).

    Internal reliability (innere Zuverlässigkeit, *wewnętrzna wiarygodność*): the minimal
    detectable blunder (kleinster aufdeckbarer grober Fehler) of observation k,

    .. math:: ∇_{0,k} = δ_0\,\frac{σ_k}{\sqrt{r_k}},\qquad
              \bar δ_{0,k} = δ_0\sqrt{\frac{1 - r_k}{r_k}}

    External reliability (äußere Zuverlässigkeit, *zewnętrzna wiarygodność*): an undetected
    blunder ∇0,k moves the unknowns by ∇x = Q_xx Aᵀ P e_k ∇0,k, whose size in the metric
    of the unknowns is ``√(∇xᵀ N ∇x)/σ = δ̄0,k``; equivalently the adjusted observations
    move by ``‖∇l̂‖ = ∇0,k √(1 − r_k)``.

    Parameters
    ----------
    result : BundleResult
    alpha, beta : float
        Significance level and power of the w test (default 0.1 %, 80 %: δ0 = 4.13).
    sigma : float, optional
        A-priori σ of an image coordinate (image unit); default ``result.sigma_image``, or
        σ̂0 if that is None. A control observation has σ_c = control_sigma·σ/σ_image.

    Returns
    -------
    ReliabilityResult

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 3.0]])
    >>> ext = np.array([[3.0, 5, 30, 0, 0, 0], [7.0, 5, 30, 0, 0, 0]])
    >>> obs = [project(X, e[:3], rotation_opk(*e[3:]), 20.0) for e in ext]
    >>> res = bundle_adjustment(np.vstack(obs), np.repeat([0, 1], 5), np.tile(np.arange(5), 2),
    ...                         ext, X, 20.0, control=[0, 1, 2, 3])
    >>> rel = reliability(res, sigma=0.001)
    >>> round(rel.delta0, 3), bool(np.all(rel.mdb >= rel.delta0 * 0.001))
    (4.132, True)
    """
    if not isinstance(result, BundleResult):
        raise TypeError(f"result must be a BundleResult, got {type(result).__name__}")
    d0 = non_centrality(alpha, beta)
    if sigma is None:
        sigma = result.sigma_image if result.sigma_image is not None else result.sigma0
    sigma = as_scalar(sigma, "sigma", positive=True)

    def measures(rk, sk):
        ok = rk > 1e-12
        with np.errstate(divide="ignore", invalid="ignore"):
            mdb = np.where(ok, d0 * sk / np.sqrt(np.where(ok, rk, 1.0)), np.inf)
            ext = np.where(ok, d0 * np.sqrt(np.maximum(1.0 - rk, 0.0) / np.where(ok, rk, 1.0)),
                           np.inf)
        return mdb, ext

    mdb, ext = measures(result.redundancy_numbers, sigma)
    P = len(result.points)
    cm, ce = np.full((P, 3), np.nan), np.full((P, 3), np.nan)
    if result.n_control_observations:
        sig = result.control_sigma
        has = (result.control_qvv > 0) & np.isfinite(sig) & (sig > 0)
        m, e = measures(result.control_redundancy_numbers,
                        np.where(has, sig, 0.0) * sigma / result.sigma_image)
        cm[has], ce[has] = m[has], e[has]
    return ReliabilityResult(float(alpha), float(beta), float(d0), float(sigma), mdb, ext, cm, ce)


# -- structure --------------------------------------------------------------------------------------

def inner_constraints(points) -> np.ndarray:
    r"""Inner constraints B (3P, 7) of a free network: ``Bᵀ dp = 0`` fixes the datum.

    Columns: three translations, three rotations and the scale of the object points
    (coordinates reduced to their centroid): for a point ``X``
    :math:`B_i = [I_3 \mid [X]_\times^T \mid X]`. ``N·G = 0`` for the full similarity G.

    Parameters
    ----------
    points : array_like, shape (P, 3)
        Approximate object points (object unit, e.g. m); reduced to their centroid here.

    Returns
    -------
    B : ndarray, shape (3P, 7)
        Rows ``3i … 3i + 2`` belong to point i (X, Y, Z); columns: translations in X, Y, Z
        (dimensionless), rotations about X, Y, Z and the scale (object unit, the reduced
        coordinates).

    Notes
    -----
    .. math:: B_i = \begin{pmatrix} 1 & 0 & 0 & 0 & \bar Z_i & -\bar Y_i & \bar X_i \\
              0 & 1 & 0 & -\bar Z_i & 0 & \bar X_i & \bar Y_i \\
              0 & 0 & 1 & \bar Y_i & -\bar X_i & 0 & \bar Z_i \end{pmatrix},\qquad
              \bar X_i = X_i - \tfrac1P \sum_j X_j

    Raises
    ------
    DatumError
        For fewer than 3 points, or points on a straight line (their singular values
        σ2 ≤ 10⁻⁹·σ1 about the centroid): a rotation about that line moves none of them, so
        B has rank < 7 and fixes no datum.

    Examples
    --------
    >>> B = inner_constraints([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, -1.0, 0]])
    >>> B.shape, int(np.linalg.matrix_rank(B))
    ((12, 7), 7)
    >>> (B[:3, 5] + 0.0).tolist()   # point (1, 0, 0): a rotation about Z moves it along +Y
    [0.0, 1.0, 0.0]
    >>> (B[:3, 6] + 0.0).tolist()   # the scale moves it away from the centroid
    [1.0, 0.0, 0.0]
    """
    P, single = as_points(points, 3, "points")  # finite: NaN would spread into every row
    if single:
        raise ValueError(f"points has shape {np.shape(points)}; expected (P, 3)")
    if len(P) < 3:
        raise DatumError(f"inner constraints need at least 3 points, got {len(P)}: fewer do not "
                         "fix the 7 datum parameters (translation, rotation, scale)")
    sv = np.linalg.svd(P - P.mean(axis=0), compute_uv=False)
    if sv[1] <= 1e-9 * max(sv[0], 1e-300):
        raise DatumError("the points of the inner constraints lie on a straight line (or "
                         "coincide): the rotation about it is not fixed (B has rank < 7)")
    return _inner_constraints(P)


def _inner_constraints(P: np.ndarray) -> np.ndarray:
    """:func:`inner_constraints` of validated points (P, 3), P ≥ 1, without the datum checks
    (the bundle's own rank test reports a defect in its own words)."""
    Xc = P - P.mean(axis=0)
    x, y, z = Xc.T
    o, one = np.zeros(len(P)), np.ones(len(P))
    cols = [(one, o, o), (o, one, o), (o, o, one), (o, -z, y), (z, o, -x), (-y, x, o), (x, y, z)]
    return np.column_stack([np.column_stack(cc).ravel() for cc in cols])


def normal_matrix_pattern(image_index, point_index, n_images: int, n_points: int,
                          n_interior: int = 0, fixed=(), reduced: bool = False) -> np.ndarray:
    """Non-zero pattern (boolean u×u) of N, order: images (6 each), interior, points (3 each).

    ``fixed`` lists point indices with fixed coordinates (no columns). ``reduced``: the
    pattern of the reduced normal matrix (points eliminated), (6M + k) square: images are
    coupled where they share a new point. For ``matplotlib``'s ``spy``.

    Parameters
    ----------
    image_index, point_index : array_like of int, shape (N,)
        Image j and object point i of each measured image point, as in
        :func:`bundle_adjustment`.
    n_images : int
        Number of images M, ≥ 1.
    n_points : int
        Number of object points P, ≥ 0.
    n_interior : int
        Number k of interior (self-calibration) parameters common to all images, ≥ 0.
    fixed : sequence of int
        Indices of control points with fixed coordinates (no unknowns, no rows/columns).
    reduced : bool
        If True the pattern of the reduced normal matrix (points eliminated).

    Returns
    -------
    ndarray of bool, shape (u, u)
        True where N may be non-zero; ``u = 6M + k + 3·(P − len(fixed))``, or ``6M + k`` if
        ``reduced``.

    Notes
    -----
    .. math:: N = A^TA,\\qquad N_{ab} \\ne 0 \\iff \\text{the unknowns a and b occur in
              one observation (or, reduced, share a new point)}

    Examples
    --------
    >>> normal_matrix_pattern([0, 1], [0, 0], 2, 1).shape
    (15, 15)
    >>> P = normal_matrix_pattern([0, 1], [0, 0], 2, 1, reduced=True)
    >>> P.shape, bool(P[0, 6])       # images 0 and 1 share point 0: coupled
    ((12, 12), True)
    """
    n_images, n_points = as_int(n_images, "n_images", minimum=1), as_int(n_points, "n_points",
                                                                           minimum=0)
    j = as_indices(image_index, "image_index", n_images)
    i = as_indices(point_index, "point_index", n_points)
    if j.shape != i.shape:
        raise ValueError(f"image_index has shape {j.shape} but point_index {i.shape}; they must "
                         "pair up")
    free = np.setdiff1d(np.arange(n_points), as_indices(fixed, "fixed", n_points))
    inc = np.zeros((n_images, n_points), bool)  # incidence: image sees point
    inc[j, i] = True
    inc = inc[:, free]
    M, k = n_images, n_interior
    blocks = np.zeros((M + 1 + len(free),) * 2, bool)  # images, interior, points
    blocks[:M, :M] = np.eye(M, dtype=bool)
    blocks[:M, M] = blocks[M, :M] = k > 0
    blocks[M, M] = k > 0
    blocks[M, M + 1:] = blocks[M + 1:, M] = (k > 0) & inc.any(axis=0)
    blocks[:M, M + 1:] = inc
    blocks[M + 1:, :M] = inc.T
    blocks[M + 1:, M + 1:] = np.eye(len(free), dtype=bool)
    if reduced:
        blocks = blocks[:M + 1, :M + 1]
        blocks[:M, :M] |= (inc.astype(np.float32) @ inc.T.astype(np.float32)) > 0
    sizes = np.r_[np.full(M, 6), k, np.full(len(free), 3)][:len(blocks)]
    return np.repeat(np.repeat(blocks, sizes, axis=0), sizes, axis=1)


# -- the adjustment ---------------------------------------------------------------------------------

def _check_inputs(xy, image_index, point_index, exterior, points, control):
    xy = np.asarray(xy, float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"xy has shape {xy.shape}; expected (N, 2)")
    check_finite(xy, "xy")
    idx = []
    for name, v in (("image_index", image_index), ("point_index", point_index)):
        a = np.asarray(v)
        if a.shape != (len(xy),):
            raise ValueError(f"{name} has shape {a.shape}; expected ({len(xy)},), one per row of xy")
        if not np.issubdtype(a.dtype, np.integer):
            raise ValueError(f"{name} must hold integers, got dtype {a.dtype}")
        idx.append(a.astype(int))
    ext = np.array(exterior, float)
    pts = np.array(points, float)
    if ext.ndim != 2 or ext.shape[1] != 6:
        raise ValueError(f"exterior has shape {ext.shape}; expected (M, 6) = X0, Y0, Z0, ω, φ, κ")
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points has shape {pts.shape}; expected (P, 3)")
    check_finite(ext, "exterior")
    check_finite(pts, "points")
    j = as_indices(idx[0], "image_index", len(ext))
    i = as_indices(idx[1], "point_index", len(pts))
    pairs = j * len(pts) + i
    if len(np.unique(pairs)) != len(pairs):
        k = int(np.flatnonzero(np.bincount(pairs) > 1)[0])
        raise ValueError(f"point {k % len(pts)} is observed twice in image {k // len(pts)}")
    return xy, j, i, ext, pts, _control_mask(control, len(pts))


def _control_mask(control, P):
    """Bool mask (P,) of the control points from indices or a bool mask (P,)."""
    ctrl = np.zeros(P, bool)
    if control is None:
        return ctrl
    c_arr = np.asarray(control)
    if c_arr.dtype == bool:
        if c_arr.shape != (P,):
            raise ValueError(f"control mask has shape {c_arr.shape}; expected ({P},)")
        return c_arr.copy()
    if c_arr.size and c_arr.dtype.kind not in "iu":
        raise ValueError(f"control must hold integer point indices or be a bool mask of length "
                         f"{P}, got dtype {c_arr.dtype}: {c_arr.ravel()[:6].tolist()}")
    k = as_indices(c_arr, "control", P).ravel()
    counts = np.bincount(k, minlength=P)
    if np.any(counts > 1):
        twice = int(np.flatnonzero(counts > 1)[0])
        raise ValueError(f"control lists point {twice} {int(counts[twice])} times: pass each "
                         f"control point's index once, or a bool mask of length {P} (an integer "
                         "0/1 array is read as indices, not as a mask)")
    ctrl[k] = True
    return ctrl


_XYZ = "XYZ"


def _control_sigma(control_sigma, control, ctrl, P):
    """σ (P, 3) per control coordinate: 0 fixed, inf unknown, > 0 observed with that σ.

    Without ``control_sigma`` the ``control`` points are fixed. With ``control`` given,
    ``control_sigma`` is a scalar, (3,) or (K, 3) for the K control points (in the order of
    ``control``; a mask: ascending); without ``control`` it is (P, 3) for all points."""
    if control_sigma is None:
        return np.where(ctrl[:, None], 0.0, np.inf) * np.ones((1, 3))
    if isinstance(control_sigma, (str, bytes)) or getattr(
            getattr(control_sigma, "dtype", None), "kind", "") in ("c", "S", "U"):
        raise ValueError(f"control_sigma must be real numbers (0: fixed, inf: unknown, > 0: σ "
                         f"in object units), got {control_sigma!r}")
    try:
        s = np.array(control_sigma, float)
    except (TypeError, ValueError):
        raise ValueError(f"control_sigma must be real numbers (0: fixed, inf: unknown, > 0: σ in "
                         f"object units), got {control_sigma!r}") from None
    if control is not None:
        c_arr = np.asarray(control)
        order = np.flatnonzero(c_arr) if c_arr.dtype == bool else c_arr.astype(int).ravel()
        K = len(order)
        if s.ndim == 0 or s.shape == (3,):
            s = np.broadcast_to(s, (K, 3))
        elif s.shape != (K, 3):
            raise ValueError(f"control_sigma has shape {s.shape}; with control ({K} points) "
                             f"expected a scalar, (3,) or ({K}, 3) in the order of control — or "
                             f"leave out control and pass ({P}, 3) for all points")
        full = np.full((P, 3), np.inf)
        full[order] = s
    else:
        if s.shape != (P, 3):
            raise ValueError(f"control_sigma has shape {s.shape}; expected ({P}, 3) = σX, σY, σZ "
                             "per point (0: fixed, inf: unknown), or pass control= as well")
        full = s.copy()
    bad = np.argwhere(np.isnan(full) | (full < 0))
    if len(bad):
        p, e = (int(v) for v in bad[0])
        raise ValueError(f"control_sigma of point {p}, coordinate {_XYZ[e]} is "
                         f"{float(full[p, e])!r}: use 0 (fixed), inf (unknown) or a standard deviation > 0 (object unit)")
    return full


def _check_geometry(j, i, ext, pts, sig, datum):
    per_image = np.bincount(j, minlength=len(ext))
    if per_image.min() < 3:
        k = int(np.argmin(per_image))
        raise DatumError(f"image {k} has {per_image[k]} observed points; at least 3 are needed "
                         "for its six orientation unknowns")
    rays = np.bincount(i, minlength=len(pts))
    known = np.isfinite(sig)
    ctrl = known.all(axis=1)
    lonely = np.flatnonzero((rays < 2) & ~known.any(axis=1))
    if len(lonely):
        k = int(lonely[0])
        raise DatumError(f"point {k} is observed in {rays[k]} image(s) and is not a control "
                         "point: a new point needs at least two rays")
    unseen = np.flatnonzero((rays == 0) & ~ctrl)
    if len(unseen):
        k = int(unseen[0])
        raise DatumError(f"point {k} is observed in no image and its coordinate(s) "
                         f"{''.join(_XYZ[e] for e in np.flatnonzero(~known[k]))} are unknown")
    if datum == "control" and np.any(known.any(axis=1) & ~ctrl & (rays > 0)):
        # partial control (e.g. heights only): the known coordinates must fix the 7 parameters
        # of a spatial similarity, i.e. their rows of the inner constraints B have rank 7
        use = known & (rays > 0)[:, None]
        rows = np.flatnonzero(use.any(axis=1))
        X = pts[rows]
        scale = float(np.max(np.ptp(X, axis=0))) or 1.0
        B = _inner_constraints(X).reshape(-1, 3, 7) * np.r_[1, 1, 1, [1 / scale] * 4]
        B = B[use[rows]]
        sv = np.linalg.svd(B, compute_uv=False)
        rank = int(np.sum(sv > 1e-9 * sv[0])) if len(sv) else 0
        if rank < 7:
            n = use.sum(axis=0)
            raise DatumError(f"the known control coordinates ({n[0]} X, {n[1]} Y, {n[2]} Z) fix "
                             f"only {rank} of the 7 datum parameters (e.g. heights alone leave "
                             "the plan shift, the rotation about Z and the scale free): add plan "
                             "control or use datum='free'")
        return
    if datum == "control":
        used = np.flatnonzero(ctrl & (rays > 0))
        if len(used) < 3:
            raise DatumError(f"{len(used)} observed control point(s): the datum (7 parameters) "
                             "needs at least 3 not on a line, or datum='free'")
        C = pts[used] - pts[used].mean(axis=0)
        sv = np.linalg.svd(C, compute_uv=False)
        if sv[1] <= 1e-9 * max(sv[0], 1e-300):
            raise DatumError("the control points lie on a straight line: rotation about it is "
                             "not fixed (datum defect)")


#: a new point's 3 × 3 normal block with λmin/λmax below this counts as singular: its rays
#: meet at less than about 1e-6 rad (the default ``min_angle`` of forward_intersection)
POINT_BLOCK_RCOND = 1e-12


def _check_point_blocks(Npp, free):
    """``DatumError`` naming the new points whose rays are (nearly) parallel: their 3 × 3
    normal blocks ``N_ii = Σ A_iᵀA_i`` are singular, so they cannot be intersected."""
    lam = np.linalg.eigvalsh(Npp)  # ascending, the blocks are symmetric positive semi-definite
    bad = ~(lam[:, 0] > POINT_BLOCK_RCOND * lam[:, 2])  # NaN counts as bad
    if bad.any():
        names = free[bad]
        shown = ", ".join(str(int(k)) for k in names[:10]) + (" …" if len(names) > 10 else "")
        raise DatumError(
            f"object point{'s' if len(names) > 1 else ''} {shown} cannot be intersected: "
            f"{'their' if len(names) > 1 else 'its'} rays are parallel (3 × 3 normal block with "
            f"λmin/λmax = {float(np.nan_to_num(lam[bad][0, 0] / lam[bad][0, 2])):.3g}): zero "
            "base, e.g. images taken from the same projection centre X0, or a point at infinity")


def bundle_adjustment(xy, image_index, point_index, exterior, points, c, x0=0.0, y0=0.0,
                      distortion=None, *, control=None, datum: str = "control",
                      control_sigma=None, sigma_image=None,
                      calibrate=(), tol: float = 1e-10, max_iter: int = 30,
                      check: bool = True, callback=None) -> BundleResult:
    r"""Bundle adjustment of a block by Gauss–Newton on the reduced normal equations.

    Parameters
    ----------
    xy : array_like, shape (N, 2)
        Measured image coordinates (image unit, e.g. mm), all of equal precision.
    image_index, point_index : array_like of int, shape (N,)
        Image j and object point i of each measurement.
    exterior : array_like, shape (M, 6)
        Approximate ``(X0, Y0, Z0, ω, φ, κ)`` per image (object unit, radians).
    points : array_like, shape (P, 3)
        Approximate object points; the rows of control points hold their control coordinates
        (fixed or observed), and approximate values for their unknown coordinates.
    c, x0, y0 : float
        Camera constant (> 0) and principal point (image unit), common to all images.
    distortion : Distortion, optional
        Starting (or fixed) distortion, evaluated at the measured points; ``r0`` is kept.
    control : array_like of int or bool mask (P,), optional
        Control points (Passpunkte), held fixed: their indices (0 … P − 1, each once) or a
        bool mask of length P.
    datum : {'control', 'free'}
        ``'control'``: datum by the control points (≥ 3, not on a line; with partial control
        the known coordinates must fix all seven similarity parameters); ``'free'``: free
        network with the seven inner constraints on all object points (``control`` and
        ``control_sigma`` ignored).
    control_sigma : array_like, optional
        Control per coordinate (Passpunkte als Beobachtungen, Lage- und Höhenpasspunkte),
        object unit: ``0`` the coordinate is fixed (error-free), ``inf`` unknown, ``σ > 0``
        observed with standard deviation σ (a pseudo-observation ``X_i,e = points[i, e]``
        with weight ``p = (σ_image/σ)²``, image observations having weight 1). Shape (P, 3)
        for all points when ``control`` is None; with ``control`` a scalar, (3,) or (K, 3)
        for its K points in its order (the other points unknown). Default: ``control``
        points fixed. E.g. a height control point (Höhenpasspunkt) is ``(inf, inf, 0)``, a
        plan control point (Lagepasspunkt) ``(0, 0, inf)``, a GNSS point ``(0.02,) * 3``.
    sigma_image : float, optional
        A-priori σ of an image coordinate (image unit, e.g. 0.003 mm), > 0: sets the weights
        of the control observations. Needed only when ``control_sigma`` has a value
        0 < σ < ∞; it changes no result of an adjustment without such observations (σ0 is
        always the a-posteriori σ of an image coordinate, the weight-1 observation).
    calibrate : iterable of str
        Interior parameters to estimate (self-calibration), from ``INTERIOR_PARAMETERS``.
    tol : float
        Stop when the update is below ``tol`` (angles, rad) and ``tol·extent`` (lengths).
    max_iter : int
        Iteration limit; reaching it raises ``ConvergenceError`` unless ``check=False``.
    check : bool
        If True (default) no convergence within ``max_iter`` raises ``ConvergenceError``;
        False returns the last iterate with ``converged=False`` (its σ0 and covariances
        are those of that iterate, not of an adjusted block).
    callback : callable, optional
        ``callback(record)`` with an :class:`IterationRecord` after each iteration.

    Returns
    -------
    BundleResult

    Notes
    -----
    With control observations the model is ``v = A dx − l`` with weights
    ``P = diag(1 (image), p_c = σ_image²/σ_c² (control))``; they add ``p_c`` to the diagonal
    of the point's 3 × 3 block ``N_ii`` and ``−p_c·v_c`` to ``b_i``, so the Schur complement
    keeps its shape. A fixed coordinate of a partially known point has no unknown (its column
    of A is dropped). Then ``σ̂0² = (vᵀv + Σ p_c v_c²)/r``, ``r = n + n_c − u + d`` and the
    control redundancy numbers ``r_c = 1 − p_c (Q_xx)_cc`` with
    ``Σ_k r_k + Σ_c r_c = r``.

    Raises
    ------
    ValueError
        Shapes, NaN, indices out of range (``control`` too: integer indices, each once, or a
        bool mask of length P), unknown parameters, ``max_iter < 1``, ``tol ≤ 0``;
        ``control_sigma`` of the wrong shape, negative or NaN; ``sigma_image`` missing or
        not > 0 when it is needed.
    DatumError
        Datum not fixed, image with < 3 points, a new point seen once, a new point whose rays
        are parallel (zero base), singular normal matrix.
    ConvergenceError
        Divergence (points behind a camera, non-finite steps) or no convergence.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 3.0]])
    >>> ext = np.array([[3.0, 5, 30, 0, 0, 0], [7.0, 5, 30, 0, 0, 0]])
    >>> obs = [project(X, e[:3], rotation_opk(*e[3:]), 20.0) for e in ext]
    >>> res = bundle_adjustment(np.vstack(obs), np.repeat([0, 1], 5), np.tile(np.arange(5), 2),
    ...                         ext + 0.01, X, 20.0, control=[0, 1, 2, 3])
    >>> res.redundancy, bool(np.allclose(res.exterior, ext)), bool(np.allclose(res.points, X))
    (5, True, True)

    Point 4 as a height control point (Z fixed), points 0–3 observed with σ = 1 cm
    (σ_image = 1 µm): r = n + n_c − u = 20 + 12 − (12 + 12 + 2) = 6:

    >>> sig = np.array([[0.01] * 3] * 4 + [[np.inf, np.inf, 0.0]])
    >>> res = bundle_adjustment(np.vstack(obs), np.repeat([0, 1], 5), np.tile(np.arange(5), 2),
    ...                         ext + 0.01, X, 20.0, control_sigma=sig, sigma_image=0.001)
    >>> res.n_control_observations, res.n_unknowns, res.redundancy
    (12, 26, 6)
    >>> round(float(res.redundancy_numbers.sum() + res.control_redundancy_numbers.sum()), 9)
    6.0
    """
    xy, j, i, ext, pts, ctrl = _check_inputs(xy, image_index, point_index, exterior, points,
                                             control)
    if datum not in ("control", "free"):
        raise ValueError(f"datum must be 'control' or 'free', got {datum!r}")
    sig = _control_sigma(control_sigma, control, ctrl, len(pts))
    if datum == "free":
        ctrl[:] = False
        sig[:] = np.inf
    weighted = np.isfinite(sig) & (sig > 0)
    if weighted.any():
        if sigma_image is None:
            raise ValueError("sigma_image (the a-priori σ of an image coordinate, image unit) is "
                             "needed to weight control coordinates observed with 0 < σ < inf")
        sigma_image = as_scalar(sigma_image, "sigma_image", positive=True)
    elif sigma_image is not None:
        sigma_image = as_scalar(sigma_image, "sigma_image", positive=True)
    tol, max_iter = as_tolerance(tol), as_max_iter(max_iter)
    calib = (calibrate,) if isinstance(calibrate, str) else tuple(calibrate)
    unknown = [n for n in calib if n not in INTERIOR_PARAMETERS]
    if unknown or len(set(calib)) != len(calib):
        raise ValueError(f"calibrate {calib!r}: each name once, from {INTERIOR_PARAMETERS}")
    calib = tuple(n for n in INTERIOR_PARAMETERS if n in calib)
    if distortion is not None and not isinstance(distortion, Distortion):
        raise TypeError(f"distortion must be a photolib.Distortion or None, got "
                        f"{type(distortion).__name__}")
    interior = {"c": as_scalar(c, "c", positive=True), "x0": as_scalar(x0, "x0"),
                "y0": as_scalar(y0, "y0")}
    r0 = 0.0 if distortion is None else distortion.params["r0"]
    interior |= {k: (0.0 if distortion is None else distortion.params[k]) for k in _DIST}
    _check_geometry(j, i, ext, pts, sig, datum)

    M, P, k = len(ext), len(pts), len(calib)
    rays = np.bincount(i, minlength=P)
    # points without unknowns: all coordinates fixed, or known and in no image (nothing to adjust)
    ctrl = np.all(sig == 0, axis=1) | (np.all(np.isfinite(sig), axis=1) & (rays == 0))
    free = np.flatnonzero(~ctrl)
    slot = np.full(P, -1)
    slot[free] = np.arange(len(free))
    fixc = sig[free] == 0  # (Pf, 3) fixed coordinates of partially known points
    wts = np.zeros((len(free), 3))  # weights p_c of the control observations (0: none)
    wts[weighted[free]] = (sigma_image / sig[free][weighted[free]]) ** 2
    partial, observed = bool(fixc.any()), bool(np.any(wts > 0))
    colmask = (sig != 0).astype(float)  # (P, 3): 0 drops the column of a fixed coordinate
    diag_extra = wts + fixc  # added to the diagonal of N_ii
    control_obs = pts[free].copy()  # the observed control coordinates
    n_obs, n_c = 2 * len(xy), int(np.count_nonzero(wts))
    u = 6 * M + 3 * len(free) - int(fixc.sum()) + k
    d = 7 if datum == "free" else 0
    r = n_obs + n_c - u + d
    if r < 0:
        raise DatumError(f"more unknowns than observations: n = {n_obs} + {n_c} (control), "
                         f"u = {u}, d = {d}")
    extent = float(np.max(np.ptp(pts, axis=0))) or 1.0
    ny = 6 * M + k + d
    cols = np.column_stack([6 * np.arange(M)[:, None] + np.arange(6),  # of image a, interior
                            np.broadcast_to(6 * M + np.arange(k), (M, k))]).astype(int)
    # observations sorted by image and (new points only) by point: sums by np.add.reduceat
    by_image = np.argsort(j, kind="stable")
    image_start = np.searchsorted(j[by_image], np.arange(M))
    m = np.flatnonzero(~ctrl[i])
    s, jm = slot[i[m]], j[m]
    by_point = np.argsort(s, kind="stable")
    point_start = np.searchsorted(s[by_point], np.arange(len(free)))
    probe = np.random.default_rng(0).standard_normal((ny, 2))  # condition estimate, solve_reduced

    def linearise(ext, pts, interior):
        """v (N, 2); A (N, 2, 6 + k): ∂/∂ own image, ∂/∂ interior; Ap (N, 2, 3): ∂/∂ point."""
        dist = Distortion(r0=r0, **{n: interior[n] for n in _DIST})
        pp = np.array([interior["x0"], interior["y0"]])
        red = xy - pp
        E, X = ext[j].T, pts[i].T
        R = rotation_opk(*ext[:, 3:].T).reshape(M, 9)[j].T
        x, y, depth = project_r(*X, *E[:3], *R, interior["c"], *pp)
        if not np.all(depth < 0):
            q = int(np.argmin(depth < 0))
            raise PointBehindCameraError(f"object point {i[q]} is not in front of image {j[q]}: "
                                         f"N = {depth[q]:.6g} ≥ 0")
        proj = np.column_stack([x, y])
        v = proj - xy
        dJ = collinearity_jacobian_opk(*X, *E, interior["c"])
        J = np.stack(np.broadcast_arrays(*dJ), axis=-1).reshape(-1, 9, 2).transpose(0, 2, 1)
        A = np.concatenate([J[:, :, :6], np.zeros((len(xy), 2, k))], axis=2)
        if "c" in calib:
            A[:, :, 6 + calib.index("c")] = (proj - pp) / interior["c"]
        if not dist.is_zero:
            v += dist.delta(red)
        if k:
            Jxy, Jpar = dist.jacobian_xy(red), dist.jacobian_params(red)
            for n, name in enumerate(calib):
                if name in ("x0", "y0"):
                    e = 0 if name == "x0" else 1
                    A[:, :, 6 + n] = -Jxy[:, :, e]
                    A[:, e, 6 + n] += 1.0
                elif name != "c":
                    A[:, :, 6 + n] = Jpar[:, :, _DIST.index(name)]
        Ap = np.ascontiguousarray(J[:, :, 6:])
        if partial:
            Ap *= colmask[i][:, None, :]
        return v, A, Ap

    def normals(v, A, Ap, pts):
        """Reduced normal equations, accumulated in blocks: 6 × 6 (+ k) per image, 3 × 3 per
        point, 3 × 6 per observation of a new point (its image–point coupling)."""
        lv = -v[:, :, None]
        W = A.transpose(0, 2, 1) @ np.concatenate([A, lv], axis=2)
        W = np.add.reduceat(W[by_image], image_start, axis=0)  # (M, 6 + k, 7 + k)
        Nyy, by = np.zeros((ny, ny)), np.zeros(ny)
        np.add.at(Nyy, (cols[:, :, None], cols[:, None, :]), W[:, :, :-1])
        np.add.at(by, cols, W[:, :, -1])
        Wp = Ap[m].transpose(0, 2, 1) @ np.concatenate([Ap[m], A[m], lv[m]], axis=2)
        Sp = np.add.reduceat(Wp[by_point], point_start, axis=0)  # N_pp | N_p,interior | b_p
        Npy = np.zeros((len(free), 3, ny))
        Npy[s[:, None, None], np.arange(3)[:, None], cols[jm, None, :6]] = Wp[:, :, 3:9]
        Npy[:, :, 6 * M:6 * M + k] = Sp[:, :, 9:9 + k]
        if d:
            Npy[:, :, 6 * M + k:] = _inner_constraints(pts).reshape(P, 3, 7)[free]
        bp, Npp = Sp[:, :, -1], Sp[:, :, :3]
        if partial or observed:
            Npp = Npp + diag_extra[:, :, None] * np.eye(3)
            bp = bp - wts * (pts[free] - control_obs)
        _check_point_blocks(Npp, free)
        Ninv = np.linalg.inv(Npp)
        T = Ninv @ Npy  # (Pf, 3, ny)
        K = Nyy - Npy.reshape(-1, ny).T @ T.reshape(-1, ny)
        rhs = by - T.reshape(-1, ny).T @ bp.ravel()
        return K, rhs, Ninv, T, bp

    def solve_reduced(K, rhs=None):
        """K⁻¹·rhs by LU on the scaled K_s if two inverse iterations put its condition
        ‖K_s‖_F·‖K_s⁻¹‖ below 1e10; else (and for rhs None) the SVD check, then K⁻¹(·rhs)."""
        scale = 1.0 / np.sqrt(np.where(np.abs(np.diag(K)) > 0, np.abs(np.diag(K)), 1.0))
        Ks = K * scale[:, None] * scale[None, :]
        if rhs is not None:
            try:
                Z = np.linalg.solve(Ks, np.column_stack([scale * rhs, probe]))
                Z2 = np.linalg.solve(Ks, Z[:, 1:] / np.linalg.norm(Z[:, 1:], axis=0))
                if (np.linalg.norm(Ks) * np.max(np.linalg.norm(Z2, axis=0)) < 1e10
                        and np.all(np.isfinite(Z[:, 0]))):
                    return scale * Z[:, 0]
            except np.linalg.LinAlgError:
                pass
        sv = np.linalg.svd(Ks, compute_uv=False)
        if sv[-1] <= 1e-12 * sv[0]:
            what = ("the inner constraints do not remove the defect" if d else
                    "the control points do not fix the datum")
            raise DatumError(f"the reduced normal matrix is singular (condition "
                             f"{sv[0] / max(sv[-1], 1e-300):.3g}): {what}, or the geometry is "
                             "degenerate (e.g. self-calibration parameters not determined)")
        Kinv = scale[:, None] * np.linalg.inv(Ks) * scale[None, :]
        return Kinv if rhs is None else Kinv @ rhs

    def vtpv_control(pts):
        return float(np.sum(wts * (pts[free] - control_obs) ** 2)) if observed else 0.0

    history, converged, it = [], False, 0
    for it in range(1, max_iter + 1):
        try:
            v, A, Ap = linearise(ext, pts, interior)
        except PointBehindCameraError as exc:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: {exc}") from None
        K, rhs, Ninv, T, bp = normals(v, A, Ap, pts)
        dy = solve_reduced(K, rhs)
        dp = (Ninv @ bp[:, :, None])[:, :, 0] - T @ dy
        if not (np.all(np.isfinite(dy)) and np.all(np.isfinite(dp))):
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: non-finite step")
        de = dy[:6 * M].reshape(M, 6)
        ext = ext + de
        pts_before = pts
        pts = pts.copy()
        pts[free] += dp
        for n, name in enumerate(calib):
            interior[name] += dy[6 * M + n]
        dl = max(float(np.max(np.abs(de[:, :3]))), float(np.max(np.abs(dp), initial=0.0)))
        da = float(np.max(np.abs(de[:, 3:])))
        rec = IterationRecord(it, float(np.sum(v**2)) + vtpv_control(pts_before), dl, da)
        history.append(rec)
        if callback is not None:
            callback(rec)
        if dl <= tol * extent and da <= tol:
            converged = True
            break
        if dl > 1e6 * extent:
            raise ConvergenceError(f"bundle adjustment diverged in iteration {it}: an update of "
                                   f"{dl:.3g} object units")
    if not converged and check:
        raise ConvergenceError(f"bundle adjustment did not converge to tol={tol:g} in {max_iter} "
                               f"iterations (last length update {dl:.3g}, angle update {da:.3g}); "
                               "pass check=False to get the last iterate")
    try:
        v, A, Ap = linearise(ext, pts, interior)
    except PointBehindCameraError as exc:
        raise ConvergenceError(f"bundle adjustment ended with {exc}") from None
    K, rhs, Ninv, T, bp = normals(v, A, Ap, pts)
    Kinv = solve_reduced(K)  # the covariance: once, after convergence
    # diag(A Q A^T) per observation: g = a_y − a_p T_i, q = g K⁻¹ gᵀ + a_p N_ii⁻¹ a_pᵀ
    G = -(Ap @ np.concatenate([T, np.zeros((1, 3, ny))])[slot[i]])  # slot −1: control, 0
    G[np.arange(len(xy))[:, None, None], np.arange(2)[:, None], cols[j, None, :]] += A
    qhat = ((G.reshape(-1, ny) @ Kinv) * G.reshape(-1, ny)).sum(axis=1).reshape(-1, 2)
    qhat[m] += ((Ap[m] @ Ninv[s]) * Ap[m]).sum(axis=2)
    qvv = np.clip(1.0 - qhat, 0.0, 1.0)
    sigma0 = float(np.sqrt((np.sum(v**2) + vtpv_control(pts)) / r)) if r > 0 else float("nan")
    s2 = sigma0**2 if r > 0 else float("nan")
    ext_cov = s2 * np.stack([Kinv[6 * a:6 * a + 6, 6 * a:6 * a + 6] for a in range(M)])
    pcov = np.zeros((P, 3, 3))
    Qpp = Ninv + T @ Kinv @ T.transpose(0, 2, 1)
    if partial:
        Qpp *= colmask[free][:, :, None] * colmask[free][:, None, :]
    pcov[free] = s2 * Qpp
    icov = s2 * Kinv[6 * M:6 * M + k, 6 * M:6 * M + k]
    # control observations: v_c, q_vv,c = 1/p − Q_cc, r_c = p·q_vv,c
    cres, cqvv, crn = np.zeros((P, 3)), np.zeros((P, 3)), np.zeros((P, 3))
    if weighted.any():
        unseen = ctrl & weighted.any(axis=1)  # known, in no image: a priori σ², no redundancy
        pcov[unseen] = s2 * np.einsum("pi,ij->pij", np.where(weighted[unseen], (
            sig[unseen] / sigma_image) ** 2, 0.0), np.eye(3))
        w = wts > 0
        with np.errstate(divide="ignore"):
            q = np.where(w, 1.0 / np.where(w, wts, 1.0) - np.einsum("pii->pi", Qpp), 0.0)
        cqvv[free] = np.maximum(q, 0.0)
        crn[free] = np.clip(wts * q, 0.0, 1.0)
        cres[free] = np.where(w, pts[free] - control_obs, 0.0)
    dist = Distortion(r0=r0, **{n: interior[n] for n in _DIST})
    return BundleResult(ext, pts, float(interior["c"]), float(interior["x0"]),
                        float(interior["y0"]), dist, calib,
                        sigma0, n_obs, u, d, r, v, qvv, qvv.copy(), ext_cov, pcov, icov, it,
                        converged, tuple(history), n_control_observations=n_c,
                        control_sigma=sig, sigma_image=sigma_image, control_residuals=cres,
                        control_qvv=cqvv, control_redundancy_numbers=crn)
