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
point, 3×6 per observation, the k interior rows), O(N·(6 + k)²); the reduced camera system
has 6×6 blocks only for the image pairs that share a new point and is solved by a dense
Cholesky (LU for a free network) while it is small and by SciPy's sparse LU (SuperLU) when it
is not; its inverse (the covariances) is formed once, after convergence, and the covariance
blocks and redundancy numbers come from it and the block structure
(:mod:`~photolib.bundle._blocks`), never from a matrix over all unknowns. The datum
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
``x' = x'0 − c·kx/N + Δx'(x'_obs − x'0)``. NumPy and SciPy (linear algebra).

Modules: :mod:`~photolib.bundle._adjustment` (the adjustment in named stages),
:mod:`~photolib.bundle._blocks` (layout of the unknowns, normal equations by blocks, the
reduced camera system, covariance blocks),
:mod:`~photolib.bundle._result` (its result), :mod:`~photolib.bundle._inputs` (the checks of
its arguments), :mod:`~photolib.bundle._datum` (inner constraints, datum and geometry
checks), :mod:`~photolib.bundle._pattern` (the pattern of the normal matrix),
:mod:`~photolib.bundle._statistics` (critical values from ``scipy.stats``) and
:mod:`~photolib.bundle._reliability` (data snooping, reliability); every name is importable
from :mod:`photolib.bundle`. ``student_t_cdf`` is deprecated (use ``scipy.stats.t.cdf``): it
still imports from here, warns when called and is not in ``__all__``.
"""

from photolib.bundle._adjustment import bundle_adjustment
from photolib.bundle._datum import (
    POINT_BLOCK_RCOND,  # noqa: F401 - public in the module before the split
    DatumError,
    inner_constraints,
)
from photolib.bundle._pattern import normal_matrix_pattern
from photolib.bundle._reliability import (
    ReliabilityResult,
    SnoopingResult,
    data_snooping,
    non_centrality,
    reliability,
)
from photolib.bundle._result import INTERIOR_PARAMETERS, BundleResult, IterationRecord
from photolib.bundle._statistics import critical_value
from photolib.bundle._statistics import (  # noqa: F401 - deprecated, kept for one release
    student_t_cdf,
)

__all__ = ["BundleResult", "DatumError", "IterationRecord", "ReliabilityResult",
           "SnoopingResult", "INTERIOR_PARAMETERS", "bundle_adjustment", "critical_value",
           "data_snooping", "inner_constraints", "non_centrality", "normal_matrix_pattern",
           "reliability"]
