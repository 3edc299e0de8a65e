"""Test distributions of data snooping: critical values of the normal, Student's t and Pope's τ.

:func:`critical_value`, the two-sided critical value of the normal (Baarda's w), Student's t
and Pope's τ test, from SciPy's distributions (``scipy.stats``, imported on first use): the
inverse upper tail ``isf`` itself, not ``ppf(1 − α/2)``, so that tiny levels keep their
digits. :func:`student_t_cdf` is deprecated (use ``scipy.stats.t.cdf``).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib._validate import as_scalar


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


def _distribution(nu: float):
    """SciPy's standard normal for ``nu = inf``, else Student's t with ν degrees of freedom."""
    from scipy import stats

    return stats.norm() if math.isinf(nu) else stats.t(nu)


def student_t_cdf(t: float, dof: float) -> float:
    r"""CDF of Student's t with ``dof`` degrees of freedom (``dof = inf``: normal); deprecated.

    .. deprecated:: 0.1.0
        Use ``scipy.stats.t.cdf(t, dof)`` (``scipy.stats.norm.cdf(t)`` for the normal); this
        name delegates to it and is removed in the next release.

    .. math:: P(T_ν \le t) = 1 - \tfrac12 I_{ν/(ν+t^2)}(ν/2, 1/2)\quad (t \ge 0)

    Parameters
    ----------
    t : float
        Value of the test statistic (dimensionless, e.g. a standardised residual), finite.
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
    """
    import warnings

    warnings.warn("photolib.student_t_cdf is deprecated and will be removed in the next "
                  "release; use scipy.stats.t.cdf(t, dof) (scipy.stats.norm.cdf(t) for "
                  "dof = inf)", DeprecationWarning, stacklevel=2)
    t = as_scalar(t, "t")
    return float(_distribution(_as_dof(dof)).cdf(t))


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

    taken from SciPy's inverse upper tail, ``scipy.stats.norm.isf(α/2)`` or
    ``scipy.stats.t.isf(α/2, ν)``, checked against the log tail ``logsf`` (where ``isf``
    fails far in the tail, ``logsf(k) = log(α/2)`` is solved for log k instead).

    Raises
    ------
    ValueError
        For ``alpha`` outside (0, 1), an unknown ``test``, ``dof ≤ 0``, ``'tau'`` without
        a finite redundancy r > 1, or a critical value out of floating-point reach (ν < 1 at
        a tiny ``alpha``: ν = 0.5 at α = 1e-300 needs k ≈ 4e599).

    Examples
    --------
    >>> round(critical_value(0.001), 4), round(critical_value(0.05, "t", 5), 4)
    (3.2905, 2.5706)

    The quantile is taken of the upper tail ``P(T > k) = alpha/2`` itself (not of
    ``1 − alpha/2``, which rounds to 1 below 1e-16), so tiny levels keep their digits:

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
    return _upper_quantile(alpha / 2.0, nu)


def _upper_quantile(p: float, nu: float) -> float:
    """k > 0 with ``P(T_ν > k) = p`` (0 < p < ½): SciPy's ``isf``, checked against ``logsf``.

    Far in the tail SciPy's ``isf`` can fail while its log tail still holds (t with ν = 5 at
    p = 5e-301 gives −inf); then ``logsf(k) = log p`` is solved for log k (Brent).
    """
    from scipy.optimize import brentq

    dist = _distribution(nu)
    target = math.log(p)
    k = float(dist.isf(p))
    if math.isfinite(k) and k > 0.0:
        got = float(dist.logsf(k))
        if not math.isfinite(got) or abs(got - target) <= 1e-9 * abs(target):
            return k        # logsf underflows where isf holds (ν = 1 beyond 1e299)
    f = lambda u: float(dist.logsf(math.exp(u))) - target
    u = None
    if f(709.0) < 0.0:                               # e^709: near the largest float
        u = brentq(f, math.log(1e-300), 709.0, xtol=1e-15, rtol=1e-15)
    if u is None or not abs(f(u)) <= 1e-9 * abs(target):
        # ν < 1 at a tiny tail: k beyond the largest float, or beyond ~1e154 where SciPy's
        # logsf of t returns −inf
        raise ValueError(f"the critical value for a tail of {p:g} with dof = {nu:g} is out of "
                         f"floating-point reach: SciPy's logsf(k) = {target:.6g} has no float "
                         f"root k")
    return math.exp(u)
