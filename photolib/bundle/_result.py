"""The result of a bundle adjustment: :class:`BundleResult` and its :class:`IterationRecord`.

:class:`BundleResult` holds the adjusted exterior orientations, object points and interior
orientation with their covariances (already scaled by σ0²), the residuals, the diagonal of
``Q_vv`` and the redundancy numbers of the image and the control observations, from which
it derives the standardised residuals τ; ``INTERIOR_PARAMETERS`` names, in their order, the
interior parameters that self-calibration can estimate.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from photolib.distortion import Distortion

#: parameters that self-calibration can estimate, in this order
INTERIOR_PARAMETERS = ("c", "x0", "y0", "A1", "A2", "A3", "B1", "B2", "C1", "C2")
_DIST = ("A1", "A2", "A3", "B1", "B2", "C1", "C2")  # order of Distortion.jacobian_params


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
    def orientations(self) -> tuple:
        """The adjusted exterior orientations as :class:`photolib.ExteriorOrientation`, one per
        image."""
        from photolib.exterior import ExteriorOrientation
        return tuple(ExteriorOrientation.from_params(e) for e in self.exterior)

    @property
    def standardised_residuals(self) -> np.ndarray:
        """τ_k = v_k / (σ̂0 √q_vv,k), (N, 2); NaN where q_vv = 0 (uncontrolled)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.qvv > 1e-12, self.residuals / (self.sigma0 * np.sqrt(
                np.maximum(self.qvv, 1e-300))), np.nan)

    @property
    def control_standardised_residuals(self) -> np.ndarray:
        """τ_c = v_c / (σ̂0 √q_vv,c), (P, 3), for the control coordinates observed with
        0 < σ < ∞; NaN elsewhere."""
        q = self.control_qvv
        if q is None:
            return np.full(self.points.shape, np.nan)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(q > 1e-300, self.control_residuals / (self.sigma0 * np.sqrt(
                np.maximum(q, 1e-300))), np.nan)


    @property
    def standardized_residuals(self) -> np.ndarray:
        """Deprecated spelling of :attr:`standardised_residuals` (the course writes -ise)."""
        _spelling_moved("standardized_residuals", "standardised_residuals")
        return self.standardised_residuals

    @property
    def control_standardized_residuals(self) -> np.ndarray:
        """Deprecated spelling of :attr:`control_standardised_residuals`."""
        _spelling_moved("control_standardized_residuals", "control_standardised_residuals")
        return self.control_standardised_residuals
    @property
    def point_std(self) -> np.ndarray:
        """(P, 3) standard deviations σX, σY, σZ of the object points."""
        return np.sqrt(np.einsum("pii->pi", self.point_covariance))

    def interior(self) -> dict:
        """``{'c': …, 'x0': …, 'y0': …, 'A1': …, …}`` of the adjusted camera."""
        return {"c": float(self.c), "x0": float(self.x0), "y0": float(self.y0)} | {
            k: float(v) for k, v in self.distortion.params.items() if k in _DIST}


def _spelling_moved(old: str, new: str) -> None:
    import warnings
    warnings.warn(f"BundleResult.{old} is now BundleResult.{new} (one spelling: -ise); the "
                  "old name goes in the next release", DeprecationWarning, stacklevel=3)
