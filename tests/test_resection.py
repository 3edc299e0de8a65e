"""Space resection against SciPy's least_squares and OpenCV's solvePnP."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import optimize

from photolib import Distortion, exterior_from_opencv_pose, project, rotation_opk
from photolib.resection import space_resection
from photolib.transforms import ConvergenceError

C, X0_TRUE, ANGLES = 24.0, np.array([3.0, -2.0, 35.0]), np.array([0.08, -0.12, 0.6])


def _scene(rng, n=15, planar=False):
    X = rng.uniform([-12, -12, -3], [12, 12, 3], (n, 3))
    if planar:
        X[:, 2] = 0.0
    return X


def _own_projection(q, X, c):
    """Pinhole with R = R_ω·R_φ·R_κ written out here, independent of photolib."""
    om, ph, ka = q[3:]
    Rx = np.array([[1, 0, 0], [0, np.cos(om), -np.sin(om)], [0, np.sin(om), np.cos(om)]])
    Ry = np.array([[np.cos(ph), 0, np.sin(ph)], [0, 1, 0], [-np.sin(ph), 0, np.cos(ph)]])
    Rz = np.array([[np.cos(ka), -np.sin(ka), 0], [np.sin(ka), np.cos(ka), 0], [0, 0, 1]])
    k = (X - q[:3]) @ (Rx @ Ry @ Rz)
    return -c * k[:, :2] / k[:, 2:]


def test_exact_data_recovers_the_orientation():
    rng = np.random.default_rng(40)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C, x0=0.05, y0=-0.03)
    res = space_resection(X, xy, C, x0=0.05, y0=-0.03)
    assert res.converged and res.iterations < 10 and res.redundancy == 24
    assert np.allclose(res.params, np.r_[X0_TRUE, ANGLES], atol=1e-9)
    assert np.max(np.abs(res.residuals)) < 1e-10


def test_noisy_data_matches_scipy_least_squares_and_its_covariance():
    rng = np.random.default_rng(41)
    X = _scene(rng, n=25)
    xy = _own_projection(np.r_[X0_TRUE, ANGLES], X, C) + rng.normal(0, 0.003, (25, 2))
    res = space_resection(X, xy, C)
    ref = optimize.least_squares(lambda q: (_own_projection(q, X, C) - xy).ravel(),
                                 np.r_[X0_TRUE, ANGLES] + 0.01, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.allclose(res.params, ref.x, atol=1e-7)
    s0 = np.sqrt(2 * ref.cost / (50 - 6))
    assert res.sigma0 == pytest.approx(s0, rel=1e-6)
    assert np.allclose(res.covariance, s0**2 * np.linalg.inv(ref.jac.T @ ref.jac), rtol=1e-4)
    assert res.sigma0 == pytest.approx(0.003, rel=0.3)


def test_matches_opencv_solvepnp():
    """OpenCV: K = [[c, 0, x0], [0, c, −y0], [0, 0, 1]], image y flipped, R_cv = diag(1,−1,−1)·Rᵀ."""
    rng = np.random.default_rng(42)
    X = _scene(rng, n=30)
    x0, y0 = 0.1, -0.2
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C, x0, y0) + rng.normal(0, 0.002, (30, 2))
    K = np.array([[C, 0, x0], [0, C, -y0], [0, 0, 1.0]])
    uv = xy * [1.0, -1.0]
    ok, rvec, tvec = cv2.solvePnP(X, uv, K, None, flags=cv2.SOLVEPNP_ITERATIVE)
    assert ok
    rvec, tvec = cv2.solvePnPRefineLM(X, uv, K, None, rvec, tvec,
                                      criteria=(cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 200, 1e-15))
    X0_cv, R_cv = exterior_from_opencv_pose(cv2.Rodrigues(rvec)[0], tvec.ravel())
    res = space_resection(X, xy, C, x0, y0)
    assert np.allclose(res.X0, X0_cv, atol=1e-6)
    assert np.allclose(res.R, R_cv, atol=1e-8)


def test_distortion_is_corrected_at_the_measured_points():
    rng = np.random.default_rng(43)
    X = _scene(rng)
    D = Distortion(A1=-5e-5, B1=2e-6)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C, 0.02, 0.01, distortion=D)
    res = space_resection(X, xy, C, 0.02, 0.01, distortion=D)
    assert np.allclose(res.params, np.r_[X0_TRUE, ANGLES], atol=1e-8)
    without = space_resection(X, xy, C, 0.02, 0.01)
    assert without.sigma0 > 100 * max(res.sigma0, 1e-12)


def test_coplanar_points_need_initial_values():
    rng = np.random.default_rng(44)
    X = _scene(rng, planar=True)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ValueError, match="coplanar.*pass initial"):
        space_resection(X, xy, C)
    res = space_resection(X, xy, C, initial=np.r_[X0_TRUE + [1.0, -1.0, 2.0], ANGLES + 0.05])
    assert np.allclose(res.params, np.r_[X0_TRUE, ANGLES], atol=1e-8)
    with pytest.raises(ValueError, match=r"DLT start needs ≥ 6 points, got 4"):
        space_resection(X[:4], xy[:4], C)
    assert space_resection(X[:3], xy[:3], C, initial=np.r_[X0_TRUE + 0.1, ANGLES + 0.01]).redundancy == 0


def test_divergence_and_non_convergence_raise():
    rng = np.random.default_rng(45)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ConvergenceError, match="diverged|behind the camera"):
        space_resection(X, xy, C, initial=[0.0, 0.0, -40.0, 0.0, 0.0, 0.0])  # below, looking away
    with pytest.raises(ConvergenceError, match="did not converge"):
        space_resection(X, xy, C, initial=np.r_[X0_TRUE + 5, ANGLES + 0.2], max_iter=2)
    res = space_resection(X, xy, C, initial=np.r_[X0_TRUE + 5, ANGLES + 0.2], max_iter=2, check=False)
    assert not res.converged and res.iterations == 2
    # check=False returns the last iterate even when it has points behind its camera
    start = [-10.093, -37.094, 87.181, -0.317, 0.143, 0.393]
    with pytest.raises(ConvergenceError, match="did not converge"):
        space_resection(X, xy, C, initial=start, max_iter=1)
    res = space_resection(X, xy, C, initial=start, max_iter=1, check=False)
    behind = project(X, res.X0, res.R, C, return_valid=True)[1]
    assert not res.converged and not behind.all()
    assert np.isnan(res.residuals[~behind]).all() and np.isfinite(res.residuals[behind]).all()
    assert np.isnan(res.sigma0) and np.isnan(res.covariance).all()


def test_bad_input():
    rng = np.random.default_rng(46)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ValueError, match="c must be > 0"):
        space_resection(X, xy, -C)
    with pytest.raises(ValueError, match=r"X has shape \(15, 2\)"):
        space_resection(X[:, :2], xy, C)
    bad = xy.copy()
    bad[2, 0] = np.nan
    with pytest.raises(ValueError, match=r"xy contains a non-finite value nan at index \(2, 0\)"):
        space_resection(X, bad, C)
    with pytest.raises(ValueError, match=r"initial has shape \(5,\)"):
        space_resection(X, xy, C, initial=np.zeros(5))
    with pytest.raises(ValueError, match="at least 3 points, got 2"):
        space_resection(X[:2], xy[:2], C, initial=np.zeros(6))
    with pytest.raises(TypeError, match="distortion must be"):
        space_resection(X, xy, C, distortion={"A1": 1e-5})


# -- input handling (red-team audit) --------------------------------------------------------------

@pytest.mark.parametrize("kwargs, text", [
    ({"max_iter": 0}, "max_iter must be an integer ≥ 1, got 0"),      # was UnboundLocalError
    ({"max_iter": 0, "check": False}, "max_iter must be an integer ≥ 1, got 0"),
    ({"tol": -1.0}, "tol must be > 0, got -1.0"),                      # ran 50 iterations, then
    ({"tol": np.nan}, "tol must be finite, got nan"),                  # "did not converge"
    ({"initial": "abcdef"}, "initial must be numeric, got 'abcdef'"),
])
def test_iteration_controls_and_start_are_checked(kwargs, text):
    rng = np.random.default_rng(47)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ValueError, match=text):
        space_resection(X, xy, C, **kwargs)


def test_divergence_message_has_no_advice_space_resection_cannot_follow():
    """project's "pass return_valid=True" is not an option of space_resection."""
    rng = np.random.default_rng(45)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ConvergenceError, match=r"diverged in iteration 1: X\[\d+\] = .* is not "
                                               r"in front of the camera") as info:
        space_resection(X, xy, C, initial=[0.0, 0.0, -40.0, 0.0, 0.0, 0.0])
    assert "return_valid" not in str(info.value) and "initial values" in str(info.value)


def test_complex_observations_are_refused():
    rng = np.random.default_rng(48)
    X = _scene(rng)
    xy = project(X, X0_TRUE, rotation_opk(*ANGLES), C)
    with pytest.raises(ValueError, match=r"xy must be real .*got complex values"):
        space_resection(X, xy + 1j, C)
