"""The mosaic of the real aerial images (chapter 12): tie-point residuals reproduced, with
bounds taken from the data — the ORB measurement precision on a known warp of the same
images — not from a run; and :mod:`photolib.image_mosaic` on inputs with a known answer."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib import image_mosaic as im
from photolib.data import DataPackageMissing

npr = pytest.importorskip("photolib.nb.products_real")
pytest.importorskip("cv2")


@pytest.fixture(scope="module")
def block():
    try:
        return npr.mosaic_block()
    except DataPackageMissing as exc:  # pragma: no cover - data not installed
        pytest.skip(str(exc))


@pytest.fixture(scope="module")
def precision(block):
    """σ (px per coordinate) of ORB on a known warp of each of the first two images."""
    return [npr.synthetic_precision(img, seed=k)[0] for k, img in enumerate(block["images"][:2])]


# -- the real pairs against the measurement precision ---------------------------------------------

def test_the_orb_precision_is_sub_pixel_and_repeatable(precision):
    # two different images and warps: the same measuring tool gives the same precision (±20 %)
    assert all(0.3 < s < 1.0 for s in precision)
    assert max(precision) / min(precision) < 1.2


def test_fitted_pairs_have_residuals_of_the_measurement_precision(block, precision):
    """σ0 of each projective fit is the ORB precision: the model fits these photographs.

    Both sets are cut at the same RANSAC bound; with ~1000 tie points σ0 has a sampling error
    of 1/√(2r) ≈ 2 %, so 25 % leaves room only for differences of texture between the
    images, not for a model error (relief, lens) of the size of the noise.
    """
    sigma = float(np.mean(precision))
    for fit in block["fits"]:
        assert fit.inliers.sum() > 500
        assert abs(fit.sigma0 / sigma - 1.0) < 0.25, (fit.sigma0, sigma)
        # RMS of |v| (two coordinates) is √2·σ0 up to the redundancy factor (2n − 8)/(2n)
        n = int(fit.inliers.sum())
        assert fit.rms == pytest.approx(fit.sigma0 * np.sqrt(2 * (2 * n - 8) / (2 * n)),
                                        rel=1e-9)


def test_chained_pairs_show_no_drift_beyond_the_noise(block):
    """Pairs that were not fitted (1–3, 1–4, 2–4) see the chain's drift on top of the noise."""
    fitted = {(k, k + 1) for k in range(len(block["fits"]))}
    rms_fit = np.sqrt(np.mean([r["rms"] ** 2 for r in block["residuals"]
                               if (r["i"], r["j"]) in fitted]))
    chained = [r for r in block["residuals"] if (r["i"], r["j"]) not in fitted]
    assert len(chained) >= 3
    for r in chained:
        assert r["rms"] < 1.25 * rms_fit, (r["i"], r["j"], r["rms"], rms_fit)


def test_the_residuals_are_the_transformed_tie_points(block):
    T = block["transforms"]
    for (i, j, pi, pj), r in zip(block["ties"], block["residuals"]):
        assert np.allclose(r["v"], T[i](pi) - T[j](pj), atol=1e-9)
        assert r["max"] >= r["rms"]


def test_opencv_agrees_within_the_measurement_precision(block, precision):
    """cv2.findHomography on the same tie points: a side comparison, within σ at the points."""
    _, _, p1, p2 = block["ties"][0]
    H_cv, mask = npr.opencv_homography(p2, p1, npr.THRESHOLD)
    h = np.column_stack([p2, np.ones(len(p2))]) @ H_cv.T
    d = np.hypot(*(block["fits"][0].transform(p2) - h[:, :2] / h[:, 2:]).T)
    assert np.sqrt(np.mean(d**2)) < min(precision)
    assert mask.mean() > 0.9


def test_the_mosaic_covers_every_image_and_its_seams_follow_the_centres(block):
    mos = im.image_mosaic(block["images"], block["transforms"], pixel_size=2.0)
    used = set(np.unique(mos.source)) - {-1}
    assert used == set(range(len(block["images"])))
    assert np.isfinite(mos.mosaic[mos.source >= 0]).all()
    assert np.isnan(mos.mosaic[mos.source < 0]).all()


# -- photolib.image_mosaic on known answers -------------------------------------------------------

def test_fit_pair_recovers_a_known_projective_transform_despite_mismatches():
    rng = np.random.default_rng(3)
    T = pl.ProjectiveTransform(12.0, 0.98, 0.05, -7.0, -0.04, 1.01, 2e-5, -1e-5)
    src = rng.uniform(0, 600, (300, 2))
    dst = T(src) + rng.normal(0, 0.5, src.shape)
    dst[:30] = rng.uniform(0, 600, (30, 2))
    fit = im.fit_pair(src, dst, threshold=1.5, rng=0)
    assert not fit.inliers[:30].any() and fit.inliers[30:].mean() > 0.95
    assert fit.sigma0 == pytest.approx(0.5, rel=0.15)       # the simulated σ
    grid = np.stack(np.meshgrid(np.linspace(0, 600, 5), np.linspace(0, 600, 5)), -1).reshape(-1, 2)
    assert np.abs(fit.transform(grid) - T(grid)).max() < 0.3


def test_mosaic_of_two_crops_restores_the_image():
    rng = np.random.default_rng(0)
    img = rng.uniform(0, 255, (40, 60))
    a, b = img[:, :40], img[5:, 25:]                 # b's pixel (0, 0) is img's (25, 5)
    shift = pl.AffineTransform(25.0, 1.0, 0.0, 5.0, 0.0, 1.0)
    mos = im.image_mosaic([a, b], im.chain_transforms([shift]))
    assert mos.mosaic.shape == img.shape
    covered = mos.source >= 0
    assert np.allclose(mos.mosaic[covered], img[covered], atol=1e-9)
    assert covered[5:, :].all() and not covered[:5, 40:].any()


def test_fit_pair_refuses_bad_input():
    with pytest.raises(ValueError, match="model"):
        im.fit_pair(np.zeros((10, 2)), np.zeros((10, 2)), model="bilinear")
    with pytest.raises(ValueError, match="too few"):
        im.fit_pair(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="shape"):
        im.fit_pair(np.zeros((10, 2)), np.zeros((9, 2)))
