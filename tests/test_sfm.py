"""Structure from motion in outline (:mod:`photolib.sfm`, chapter 12): each step against an
independent route — the essential matrix of known poses (:func:`photolib.essential_matrix`),
the known truth of a simulated sequence, and OpenCV's essential matrix in its own frames."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib import sfm

D = np.diag([1.0, -1.0, -1.0])


def _pair(seed, n=40, noise=0.0, c=1.0):
    rng = np.random.default_rng(seed)
    X = rng.uniform(-5, 5, (n, 3)) + [0.0, 0.0, -20.0]
    R2 = pl.rotation_opk(*rng.uniform(-0.1, 0.1, 3))
    b = np.r_[1.0, rng.uniform(-0.3, 0.3, 2)]
    xy1 = pl.project(X, np.zeros(3), np.eye(3), c) + rng.normal(0, noise, (n, 2))
    xy2 = pl.project(X, b, R2, c) + rng.normal(0, noise, (n, 2))
    return X, R2, b, xy1, xy2


def _same_up_to_scale(A, B):
    A, B = A / np.linalg.norm(A), B / np.linalg.norm(B)
    return min(np.abs(A - B).max(), np.abs(A + B).max())


@pytest.mark.parametrize("seed", range(4))
def test_eight_point_is_the_essential_matrix_of_the_poses(seed):
    _, R2, b, xy1, xy2 = _pair(seed)
    E = sfm.essential_eight_point(xy1, xy2, 1.0)
    assert _same_up_to_scale(E, pl.essential_matrix(np.zeros(3), np.eye(3), b, R2)) < 1e-9
    assert np.abs(sfm.sampson_distance(E, xy1, xy2, 1.0)).max() < 1e-12


@pytest.mark.parametrize("seed", range(4))
def test_decomposition_gives_the_true_rotation_and_base(seed):
    _, R2, b, xy1, xy2 = _pair(seed)
    E = sfm.essential_eight_point(xy1, xy2, 1.0)
    R, base = sfm.decompose_essential(E, xy1, xy2, 1.0)
    assert np.allclose(R, R2, atol=1e-9)
    assert np.allclose(base, b / np.linalg.norm(b), atol=1e-9)


def test_opencv_essential_matrix_is_ours_in_its_frames():
    """OpenCV's E relates its own camera frames: E_cv ∝ (D·E·D)ᵀ (docs/conventions.md)."""
    cv2 = pytest.importorskip("cv2")
    _, R2, b, xy1, xy2 = _pair(5, n=60, c=800.0)
    E = sfm.essential_eight_point(xy1, xy2, 800.0)
    # OpenCV pixels: x right, y down, principal point at (0, 0); K = diag(800, 800, 1)
    p1, p2 = xy1 * [1.0, -1.0], xy2 * [1.0, -1.0]
    E_cv, _ = cv2.findEssentialMat(p1, p2, np.diag([800.0, 800.0, 1.0]), cv2.RANSAC, 0.999, 1e-3)
    assert _same_up_to_scale(E_cv[:3], (D @ E @ D).T) < 1e-6


def test_orient_pair_rejects_mismatches_and_recovers_the_pose():
    rng = np.random.default_rng(2)
    _, R2, b, xy1, xy2 = _pair(7, n=150, noise=0.5, c=600.0)
    xy2 = xy2.copy()
    xy2[:15] = xy2[rng.permutation(15) + 15]           # 15 mismatches
    po = sfm.orient_pair(xy1, xy2, 600.0, threshold=1.5, rng=0)
    assert not po.inliers[:15].any() and po.inliers[15:].mean() > 0.95
    # within 4 standard deviations of the coplanarity adjustment's own covariance (κ2 and by
    # are strongly correlated when the depth range is small, so κ2 is the weakest angle)
    ro = pl.relative_orientation(xy1[po.inliers], xy2[po.inliers], 600.0, bx=1.0)
    std = np.sqrt(np.diag(ro.covariance))[2:]
    err = np.array(pl.opk_from_rotation(po.R2)) - np.array(pl.opk_from_rotation(R2))
    assert np.all(np.abs(err) < 4 * std), (err, std)
    std_b = np.sqrt(np.diag(ro.covariance))[:2]          # by, bz for bx = 1
    err_b = po.base[1:] / po.base[0] - b[1:] / b[0]
    assert np.all(np.abs(err_b) < 4 * std_b), (err_b, std_b)


def test_chain_poses_of_the_true_relative_orientations_is_the_true_path():
    rng = np.random.default_rng(1)
    poses = [(np.zeros(3), np.eye(3))]
    for _ in range(4):
        X0, R = poses[-1]
        poses.append((X0 + rng.uniform(-2, 2, 3), R @ pl.rotation_opk(*rng.uniform(-.2, .2, 3))))
    rel, scales = [], []
    for (Xa, Ra), (Xb, Rb) in zip(poses, poses[1:]):
        bl = Ra.T @ (Xb - Xa)
        rel.append((Ra.T @ Rb, bl / np.linalg.norm(bl)))
        scales.append(float(np.linalg.norm(bl)))
    for (X0, R), (Xt, Rt) in zip(sfm.chain_poses(rel, scales), poses):
        assert np.allclose(X0, Xt, atol=1e-12) and np.allclose(R, Rt, atol=1e-12)


def test_the_simulated_sequence_is_recovered_to_its_noise():
    """The chapter's pipeline: σ0 within 3 standard errors of the simulated 0.5 px, no
    mismatch kept, and the block equal to the truth after a similarity within 3× the
    precision the adjustment itself predicts (its point covariances)."""
    npr = pytest.importorskip("photolib.nb.products_real")
    out = npr.sfm_pipeline()
    res = out["bundle"]
    sigma = npr.SFM_CAMERA["sigma_px"]
    assert res.converged
    assert abs(res.sigma0 / sigma - 1.0) < 3.0 / np.sqrt(2 * res.redundancy)
    assert out["n_mismatched_kept"] == 0
    m = out["similarity"].m
    predicted = m * np.sqrt(np.mean(np.trace(res.point_covariance, axis1=1, axis2=2)))
    actual = np.sqrt(np.mean(np.sum(out["dX"] ** 2, axis=1)))
    assert actual < 3.0 * predicted, (actual, predicted)


def test_bad_input_is_refused():
    _, _, _, xy1, xy2 = _pair(0)
    with pytest.raises(ValueError, match="≥ 8"):
        sfm.essential_eight_point(xy1[:7], xy2[:7], 1.0)
    with pytest.raises(ValueError, match="coincide"):
        sfm.essential_eight_point(np.zeros((9, 2)), xy2[:9], 1.0)
    with pytest.raises(ValueError, match="method"):
        sfm.orient_pair(xy1, xy2, 1.0, method="five-point")
    with pytest.raises(ValueError, match="c"):
        sfm.image_vectors(xy1, -1.0)
