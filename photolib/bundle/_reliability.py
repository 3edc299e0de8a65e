"""Baarda's theory of a bundle result: data snooping and internal and external reliability.

:func:`data_snooping` tests every image coordinate for a gross error (the w test with an
a-priori σ, Pope's τ test with σ̂0); :func:`non_centrality` gives δ0 of the w test from α and
β, and :func:`reliability` the minimal detectable blunders (internal reliability) and their
effect on the unknowns (external reliability) from the redundancy numbers of a
:class:`~photolib.bundle.BundleResult`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from photolib._validate import as_scalar
from photolib.bundle._adjustment import bundle_adjustment  # noqa: F401 - the doctests
from photolib.bundle._result import BundleResult
from photolib.bundle._statistics import critical_value
from photolib.collinearity import project  # noqa: F401 - the doctests
from photolib.rotations import rotation_opk  # noqa: F401 - the doctests


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
        stat = result.standardised_residuals
    else:
        sigma = as_scalar(sigma, "sigma", positive=True)
        test, crit = "w", critical_value(alpha, "normal")
        stat = result.standardised_residuals * (result.sigma0 / sigma)
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
