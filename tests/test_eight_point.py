"""The three 8-point estimators share one core (photolib.stereo._fundamental, issue 18).

``fundamental_8point`` (OpenCV's order ``x2ᵀ F x1 = 0``), ``estimate_fundamental`` (Luhmann's
``h1ᵀ F h2 = 0``) and ``essential_eight_point`` (reduced image vectors) are wrappers of
``_normalised_eight_point``. Checked against routes that do not use it: OpenCV's
``findFundamentalMat(..., FM_8POINT)``, the epipolar constraint on exact data, the essential
matrix of the true relative pose, and the rank and scale each wrapper promises.
"""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib.fundamental import fundamental_8point
from photolib.sfm import essential_eight_point
from photolib.stereo import estimate_fundamental
from photolib.transforms._base import DegenerateGeometryError

C = 50.0  # camera constant, image unit


def _pair(seed, n, noise=0.0):
    """Image points of n object points in a well-conditioned pair (random base and rotation)."""
    rng = np.random.default_rng(seed)
    X = rng.uniform([-6, -6, -35], [6, 6, -15], (n, 3))
    R2 = pl.rotation_opk(*rng.normal(0.0, 0.1, 3))
    X02 = np.array([4.0, *rng.normal(0.0, 0.5, 2)])
    xy1 = pl.project(X, [0, 0, 0], np.eye(3), C) + rng.normal(0.0, noise, (n, 2))
    xy2 = pl.project(X, X02, R2, C) + rng.normal(0.0, noise, (n, 2))
    return xy1, xy2, X02, R2


def _same_up_to_sign(A, B):
    """Largest difference of A and B, both scaled to unit Frobenius norm, for the better sign."""
    A, B = A / np.linalg.norm(A), B / np.linalg.norm(B)
    return min(np.abs(A - B).max(), np.abs(A + B).max())


def _homogeneous(p):
    return np.column_stack([p, np.ones(len(p))])


@pytest.mark.parametrize("seed", range(6))
def test_fundamental_8point_equals_opencv_fm_8point(seed):
    cv2 = pytest.importorskip("cv2")
    xy1, xy2, _, _ = _pair(seed, 8 + 4 * seed, noise=0.02)
    px1, px2 = xy1 * 100 + [2000, 1500], xy2 * 100 + [2000, 1500]  # pixel-like magnitudes
    F_cv, _ = cv2.findFundamentalMat(px1, px2, cv2.FM_8POINT)
    F = fundamental_8point(px1, px2)
    # the same normalisation (mean distance √2) and least squares: equal to rounding
    assert _same_up_to_sign(F, F_cv) < 1e-8
    assert np.linalg.norm(F) == pytest.approx(1.0, abs=1e-15) and F[2, 2] >= 0
    assert np.linalg.svd(F, compute_uv=False)[2] < 1e-12        # rank 2


@pytest.mark.parametrize("seed", range(6))
def test_epipolar_constraint_and_the_true_matrices_on_exact_data(seed):
    xy1, xy2, X02, R2 = _pair(seed, 10 + 3 * seed)
    E_true = pl.essential_matrix([0, 0, 0], np.eye(3), X02, R2)
    F_true = pl.fundamental_matrix(E_true, C, C)            # Luhmann's order h1ᵀ F h2 = 0
    h1, h2 = _homogeneous(xy1), _homogeneous(xy2)

    F_cv_order = fundamental_8point(xy1, xy2)              # x2ᵀ F x1 = 0
    assert np.abs(np.einsum("ni,ij,nj->n", h2, F_cv_order, h1)).max() < 1e-12
    assert _same_up_to_sign(F_cv_order, F_true.T) < 1e-9

    F_lu = estimate_fundamental(xy1, xy2)                  # h1ᵀ F h2 = 0
    assert np.abs(np.einsum("ni,ij,nj->n", h1, F_lu, h2)).max() < 1e-12
    assert _same_up_to_sign(F_lu, F_true) < 1e-9
    assert np.linalg.norm(F_lu) == pytest.approx(1.0, abs=1e-15)
    assert np.linalg.svd(F_lu, compute_uv=False)[2] < 1e-12

    E = essential_eight_point(xy1, xy2, C)
    a = np.column_stack([xy1, np.full(len(xy1), -C)])     # x* = (x', y', −c)
    b = np.column_stack([xy2, np.full(len(xy2), -C)])
    assert np.abs(np.einsum("ni,ij,nj->n", a, E, b)).max() < 1e-9 * C**2
    assert _same_up_to_sign(E, E_true) < 1e-9
    np.testing.assert_allclose(np.linalg.svd(E, compute_uv=False), [1.0, 1.0, 0.0], atol=1e-12)


def test_the_two_fundamental_orders_are_transposes_on_noisy_data_up_to_normalisation():
    # with noise the two wrappers differ only by their normalisation (mean vs rms distance):
    # both are close to each other's transpose, far closer than to the noise-free F
    xy1, xy2, X02, R2 = _pair(7, 40, noise=0.01)
    F_cv_order, F_lu = fundamental_8point(xy1, xy2), estimate_fundamental(xy1, xy2)
    F_true = pl.fundamental_matrix(pl.essential_matrix([0, 0, 0], np.eye(3), X02, R2), C, C)
    d = _same_up_to_sign(F_cv_order.T, F_lu)
    assert d < 0.1 * _same_up_to_sign(F_lu, F_true)


@pytest.mark.parametrize("estimator, message", [
    (fundamental_8point, "the points of an image coincide"),
    (estimate_fundamental, "all points coincide"),
    (lambda a, b: essential_eight_point(a, b, C), "all image points coincide")])
def test_coincident_points_raise_the_wrappers_own_message(estimator, message):
    xy1, _, _, _ = _pair(0, 9)
    with pytest.raises(DegenerateGeometryError, match=message):
        estimator(xy1, np.tile([1.0, 2.0], (9, 1)))


@pytest.mark.parametrize("estimator, message", [
    (fundamental_8point, "a second null vector"),
    (estimate_fundamental, r"σ8/σ1 = "),
    (lambda a, b: essential_eight_point(a, b, C), "too few distinct rays")])
def test_points_on_a_line_do_not_determine_the_matrix(estimator, message):
    t = np.linspace(-1.0, 1.0, 10)
    line = np.column_stack([t, 0.5 * t + 0.1])
    with pytest.raises(DegenerateGeometryError, match=message):
        estimator(line, 1.3 * line + [0.2, -0.1])
