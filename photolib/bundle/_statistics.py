"""Test distributions of data snooping: Student's t, its upper tail and critical values.

:func:`student_t_cdf` (the normal distribution for ``dof = inf``) from the regularised
incomplete beta function by Lentz's continued fraction, and :func:`critical_value`, the
two-sided critical value of the normal (Baarda's w), Student's t and Pope's τ test, found by
bisection on the upper tail itself so that tiny levels keep their digits. NumPy/``math``
only (no SciPy).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib._validate import as_scalar


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
